//! The model's parameters, with validation that names the parameter and its
//! valid range so that the command line and the app can show it as is.

use std::ops::RangeInclusive;

use serde::{Deserialize, Serialize};

/// κ's valid range. Above 1e3 a slip can stay on the stiff x spring for
/// ever (steady sliding, which the stick-slip map cannot represent); below
/// 1e-6 the time scale 1/sqrt(κ) leaves what step control can span.
pub const KAPPA_RANGE: RangeInclusive<f64> = 1e-6..=1e3;
/// γ's valid range. Below 0.1 friction barely weakens and, at some presets,
/// a slip never stops (steady sliding); above 1e4 friction all but vanishes
/// once the block moves, and a slip runs past any time bound (γ = 1e5 at
/// Fig. 3b). The map cannot represent either.
pub const GAMMA_RANGE: RangeInclusive<f64> = 0.1..=1e4;
/// ν's valid range. Above 0.1 the surface drags the block into steady
/// sliding; below 1e-12 the stick time 1/ν leaves what f64 can time.
pub const NU_RANGE: RangeInclusive<f64> = 1e-12..=0.1;

/// The dimensionless parameters of the one-block model (docs/model.md, "Units and
/// parameters"). Lengths are in F0/k_y, time in sqrt(m/k_y).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Params {
    /// κ = k_x/k_y, the anisotropy of the two springs ([`KAPPA_RANGE`]).
    pub kappa: f64,
    /// γ = 1/(2ν_f), how fast friction weakens with the relative speed
    /// ([`GAMMA_RANGE`]).
    pub gamma: f64,
    /// ν, the pulling speed: magnitude of the surface velocity ([`NU_RANGE`]).
    pub nu: f64,
    /// θν, the direction of the surface velocity, in radians (finite).
    pub theta_nu: f64,
    /// Ω, the "memory" of the friction direction (Ω > 0; the paper uses 50).
    pub omega: f64,
}

impl Default for Params {
    /// The paper's Fig. 3b point: pure stick-slip with a period-doubling cascade.
    fn default() -> Self {
        Params {
            kappa: 18.95,
            gamma: 6.5,
            nu: 1e-3,
            theta_nu: 1.0,
            omega: 50.0,
        }
    }
}

/// An invalid parameter: which one, the value given, and the valid range.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{name} = {} is out of range: {range}", crate::text::short(*value))]
pub struct ParamError {
    /// The parameter's name as the command line spells it (e.g. `kappa`).
    pub name: &'static str,
    /// The offending value.
    pub value: f64,
    /// The valid range in words, e.g. "must be a finite number > 0".
    pub range: &'static str,
}

impl ParamError {
    pub fn new(name: &'static str, value: f64, range: &'static str) -> Self {
        ParamError { name, value, range }
    }
}

/// Checks `value` is finite and strictly positive.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<(), ParamError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(ParamError::new(name, value, "must be a finite number > 0"))
    }
}

/// Checks `value` lies in `range` (NaN does not); `words` says the range
/// and why.
fn within(
    name: &'static str,
    value: f64,
    range: &RangeInclusive<f64>,
    words: &'static str,
) -> Result<(), ParamError> {
    if range.contains(&value) {
        Ok(())
    } else {
        Err(ParamError::new(name, value, words))
    }
}

impl Params {
    /// Checks every parameter against docs/model.md's ranges. The ranges of
    /// κ, γ and ν are those where one map iterate finishes at every preset
    /// (tests/ranges_run.rs); past them slips turn into steady sliding.
    pub fn validate(&self) -> Result<(), ParamError> {
        // A value <= 0 (or not a number) is told so before the range.
        positive("kappa", self.kappa)?;
        within(
            "kappa",
            self.kappa,
            &KAPPA_RANGE,
            "must lie in [1e-6, 1e3] (beyond 1e3 slips turn into steady sliding, which the map cannot represent)",
        )?;
        within(
            "gamma",
            self.gamma,
            &GAMMA_RANGE,
            "must lie in [0.1, 1e4] (below 0.1 slips turn into steady sliding, above 1e4 they barely feel friction and never stop; the map cannot represent either)",
        )?;
        positive("nu", self.nu)?;
        within(
            "nu",
            self.nu,
            &NU_RANGE,
            "must lie in [1e-12, 0.1] (beyond 0.1 slips turn into steady sliding, which the map cannot represent)",
        )?;
        if !self.theta_nu.is_finite() {
            return Err(ParamError::new(
                "theta-nu",
                self.theta_nu,
                "must be a finite angle in radians",
            ));
        }
        positive("omega", self.omega)?;
        if self.omega > 1e8 {
            return Err(ParamError::new("omega", self.omega, "must lie in (0, 1e8]"));
        }
        Ok(())
    }

    /// The surface velocity V = ν (cos θν, sin θν).
    #[inline]
    pub fn velocity(&self) -> [f64; 2] {
        let (s, c) = self.theta_nu.sin_cos();
        [self.nu * c, self.nu * s]
    }

    /// The same parameters with another θν.
    pub fn with_theta_nu(self, theta_nu: f64) -> Self {
        Params { theta_nu, ..self }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_error_shows_a_tiny_value_short() {
        let p = Params {
            nu: 5e-324,
            ..Params::default()
        };
        let m = p.validate().expect_err("out of range").to_string();
        assert!(m.starts_with("nu = 5e-324 is out of range"), "{m}");
        // Its 330 digits written out: over 450 characters.
        assert!(m.len() < 200, "{} characters: {m}", m.len());
    }

    #[test]
    fn rejects_each_bad_value_by_name() {
        let p = Params::default();
        assert_eq!(
            Params { kappa: 0.0, ..p }.validate().unwrap_err().name,
            "kappa"
        );
        assert_eq!(
            Params {
                kappa: f64::NAN,
                ..p
            }
            .validate()
            .unwrap_err()
            .name,
            "kappa"
        );
        assert_eq!(
            Params { gamma: -1.0, ..p }.validate().unwrap_err().name,
            "gamma"
        );
        assert_eq!(Params { nu: -1e-3, ..p }.validate().unwrap_err().name, "nu");
        assert_eq!(
            Params {
                theta_nu: f64::INFINITY,
                ..p
            }
            .validate()
            .unwrap_err()
            .name,
            "theta-nu"
        );
        assert_eq!(
            Params { omega: 0.0, ..p }.validate().unwrap_err().name,
            "omega"
        );
        assert!(p.validate().is_ok());
    }

    /// The messages quote the range the check uses, so they cannot drift.
    #[test]
    fn each_range_message_states_its_range() {
        let p = Params::default();
        for (bad, name, range) in [
            (Params { kappa: 2e3, ..p }, "kappa", &KAPPA_RANGE),
            (Params { gamma: 0.0, ..p }, "gamma", &GAMMA_RANGE),
            (Params { nu: 1.0, ..p }, "nu", &NU_RANGE),
        ] {
            let e = bad.validate().unwrap_err();
            assert_eq!(e.name, name);
            let ends = format!("[{:e}, {:e}]", range.start(), range.end());
            let ends = ends.replace("1e-1,", "0.1,").replace("1e-1]", "0.1]");
            assert!(e.range.contains(&ends), "{} vs {ends}", e.range);
            assert!(e.range.contains("steady sliding"), "{}", e.range);
            for v in [*range.start(), *range.end()] {
                let mut ok = p;
                match name {
                    "kappa" => ok.kappa = v,
                    "gamma" => ok.gamma = v,
                    _ => ok.nu = v,
                }
                assert!(ok.validate().is_ok(), "{name} = {v}");
            }
        }
    }
}
