//! The bifurcation diagram's axis as the window remembers it: the
//! parameter varied (θν, the paper's, or κ, γ, ν, Ω with the others held
//! at the sliders' values) and, for each of the four others, the range
//! last used, so that switching back and forth keeps each one.

use serde::{Deserialize, Serialize};

use super::is_usable_range;
use crate::model::{GAMMA_RANGE, KAPPA_RANGE, NU_RANGE};
use crate::sim::continuation::ContParam;

/// The largest Ω a range may reach (the model accepts (0, 1e8]).
pub const OMEGA_MAX: f64 = 1e8;

/// The diagram's axis: what varies, and the ranges of the parameters other
/// than θν (θν's is the slider's: [0, π/2], or the full circle).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct DiagramAxis {
    /// The parameter varied along the diagram.
    pub param: ContParam,
    /// κ's range (a log axis).
    pub kappa: (f64, f64),
    /// γ's range (a linear axis).
    pub gamma: (f64, f64),
    /// ν's range (a log axis).
    pub nu: (f64, f64),
    /// Ω's range (a log axis).
    pub omega: (f64, f64),
}

impl Default for DiagramAxis {
    /// θν; κ over the paper's Fig. 4 range, the others over the sliders'.
    fn default() -> Self {
        DiagramAxis {
            param: ContParam::ThetaNu,
            kappa: (1.0, 42.0),
            gamma: (1.0, 10.0),
            nu: (1e-5, 1e-2),
            omega: (1.0, 1000.0),
        }
    }
}

impl DiagramAxis {
    /// The saved range of `p` (`None` for θν, whose range is the slider's).
    pub fn range(&self, p: ContParam) -> Option<(f64, f64)> {
        match p {
            ContParam::ThetaNu => None,
            ContParam::Kappa => Some(self.kappa),
            ContParam::Gamma => Some(self.gamma),
            ContParam::Nu => Some(self.nu),
            ContParam::Omega => Some(self.omega),
        }
    }

    /// Sets the range of `p` (θν's is not kept here: ignored).
    pub fn set_range(&mut self, p: ContParam, r: (f64, f64)) {
        match p {
            ContParam::ThetaNu => {}
            ContParam::Kappa => self.kappa = r,
            ContParam::Gamma => self.gamma = r,
            ContParam::Nu => self.nu = r,
            ContParam::Omega => self.omega = r,
        }
    }

    /// Whether `r` is a range `p` may span: increasing, drawable
    /// ([`is_usable_range`]) and within the model's range of `p`.
    pub fn is_valid_range(p: ContParam, r: (f64, f64)) -> bool {
        let (lo, hi) = match p {
            ContParam::ThetaNu => (-std::f64::consts::PI, std::f64::consts::PI),
            ContParam::Kappa => (*KAPPA_RANGE.start(), *KAPPA_RANGE.end()),
            ContParam::Gamma => (*GAMMA_RANGE.start(), *GAMMA_RANGE.end()),
            ContParam::Nu => (*NU_RANGE.start(), *NU_RANGE.end()),
            // Ω > 0: a log axis' ends must be positive.
            ContParam::Omega => (f64::MIN_POSITIVE, OMEGA_MAX),
        };
        is_usable_range(r) && r.0 >= lo && r.1 <= hi
    }

    /// The same axis with each range the model cannot span back to its
    /// default; whether any was.
    pub fn sanitised(mut self) -> (DiagramAxis, bool) {
        let d = DiagramAxis::default();
        let mut bad = false;
        for p in [
            ContParam::Kappa,
            ContParam::Gamma,
            ContParam::Nu,
            ContParam::Omega,
        ] {
            if let Some(r) = self.range(p)
                && !Self::is_valid_range(p, r)
            {
                self.set_range(p, d.range(p).unwrap_or(r));
                bad = true;
            }
        }
        (self, bad)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_outside_the_model_go_back_to_their_defaults() {
        let axis = DiagramAxis {
            param: ContParam::Kappa,
            kappa: (0.0, 5.0),
            gamma: (2.0, 1.0),
            nu: (1e-4, f64::NAN),
            omega: (1.0, 100.0),
        };
        let (s, bad) = axis.sanitised();
        let d = DiagramAxis::default();
        assert!(bad);
        assert_eq!((s.kappa, s.gamma, s.nu), (d.kappa, d.gamma, d.nu));
        assert_eq!((s.param, s.omega), (ContParam::Kappa, (1.0, 100.0)));
        assert_eq!(d.sanitised(), (d, false));
    }
}
