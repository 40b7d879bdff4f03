//! The model's parameters, with validation that names the parameter and its
//! valid range so that the command line and the app can show it as is.

use serde::{Deserialize, Serialize};

/// The dimensionless parameters of the one-block model (docs/model.md, "Units and
/// parameters"). Lengths are in F0/k_y, time in sqrt(m/k_y).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Params {
    /// κ = k_x/k_y, the anisotropy of the two springs (κ > 0).
    pub kappa: f64,
    /// γ = 1/(2ν_f), how fast friction weakens with the relative speed (γ ≥ 0).
    pub gamma: f64,
    /// ν, the pulling speed: magnitude of the surface velocity (ν > 0).
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
#[error("{name} = {value} is out of range: {range}")]
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

impl Params {
    /// Checks every parameter against docs/model.md's ranges.
    pub fn validate(&self) -> Result<(), ParamError> {
        positive("kappa", self.kappa)?;
        if !(self.gamma.is_finite() && self.gamma >= 0.0) {
            return Err(ParamError::new(
                "gamma",
                self.gamma,
                "must be a finite number >= 0",
            ));
        }
        positive("nu", self.nu)?;
        if !self.theta_nu.is_finite() {
            return Err(ParamError::new(
                "theta-nu",
                self.theta_nu,
                "must be a finite angle in radians",
            ));
        }
        positive("omega", self.omega)?;
        // Beyond these the dimensionless model stops meaning anything and the
        // time scales (1/sqrt(κ), 1/ν) leave what f64 step control can span.
        if self.kappa > 1e6 || self.kappa < 1e-6 {
            return Err(ParamError::new(
                "kappa",
                self.kappa,
                "must lie in [1e-6, 1e6]",
            ));
        }
        if self.nu > 1e3 || self.nu < 1e-12 {
            return Err(ParamError::new("nu", self.nu, "must lie in [1e-12, 1e3]"));
        }
        if self.gamma > 1e6 {
            return Err(ParamError::new("gamma", self.gamma, "must lie in [0, 1e6]"));
        }
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
        assert!(Params { gamma: 0.0, ..p }.validate().is_ok());
        assert!(p.validate().is_ok());
    }
}
