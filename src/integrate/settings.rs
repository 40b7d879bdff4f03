//! Which method, and how accurately: validated once at the edge.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// The integration methods. Adaptive ones take a tolerance, fixed-step ones
/// a step h.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Method {
    /// Dormand–Prince 5(4) with Shampine's 4th-order dense output.
    Dp54,
    /// Dormand–Prince 8(5,3) with its 7th-order dense output (the default:
    /// cheapest at the default accuracy, see the README's work-precision table).
    Dop853,
    /// Classical 4th-order Runge–Kutta, fixed step, cubic Hermite output.
    Rk4,
    /// Forward Euler, fixed step: kept as the method that fails.
    Euler,
}

impl Method {
    pub const ALL: [Method; 4] = [Method::Dp54, Method::Dop853, Method::Rk4, Method::Euler];

    /// Whether several integrations' steps can be computed together
    /// (`Solver::stages_lanes`): the two adaptive methods.
    pub fn steps_in_lanes(self) -> bool {
        matches!(self, Method::Dop853 | Method::Dp54)
    }

    /// Whether the method controls its step by a tolerance.
    pub fn is_adaptive(self) -> bool {
        matches!(self, Method::Dp54 | Method::Dop853)
    }

    /// The command-line spelling.
    pub fn name(self) -> &'static str {
        match self {
            Method::Dp54 => "dp54",
            Method::Dop853 => "dop853",
            Method::Rk4 => "rk4",
            Method::Euler => "euler",
        }
    }

    /// The order of the propagated solution.
    pub fn order(self) -> u32 {
        match self {
            Method::Dp54 => 5,
            Method::Dop853 => 8,
            Method::Rk4 => 4,
            Method::Euler => 1,
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "dp54" | "dopri5" | "rk45" => Ok(Method::Dp54),
            "dop853" => Ok(Method::Dop853),
            "rk4" => Ok(Method::Rk4),
            "euler" => Ok(Method::Euler),
            _ => Err(format!(
                "unknown method '{s}': expected one of dp54, dop853, rk4, euler"
            )),
        }
    }
}

/// How a slip is integrated and the bounds that keep it from hanging.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolverSettings {
    pub method: Method,
    /// Relative tolerance of the adaptive methods, in [1e-14, 1e-2].
    pub rtol: f64,
    /// Absolute tolerance (on the scaled state: κx, y, √κ v_r,x, v_r,y).
    pub atol: f64,
    /// The step of the fixed-step methods, in (0, 1].
    pub step: f64,
    /// At most this many accepted and rejected steps per slip.
    pub max_steps: u32,
    /// At most this much time per slip (slips last O(1–100)).
    pub max_slip_time: f64,
    /// Approach to the stop (adaptive methods): below v_r = `stop_cutoff`·√rtol
    /// the stop is placed by linear extrapolation (error O(v_r²)).
    pub stop_cutoff: f64,
    /// Approach to the stop: no step aims further than this fraction of the
    /// time v_r/|dv_r/dt| left before the extrapolated stop.
    pub stop_fraction: f64,
    /// Adaptive methods: finish a stiff (creep-sized) slip on its slow
    /// manifold where that is accurate to 1 % of the tolerance
    /// (`Simulator::stiff_stop`). Off, every step is the full field's: for
    /// checking the manifold against it.
    #[serde(default = "stiff_stop_default")]
    pub stiff_stop: bool,
}

fn stiff_stop_default() -> bool {
    true
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            method: Method::Dop853,
            rtol: 1e-10,
            atol: 1e-10,
            step: 1e-3,
            max_steps: 200_000,
            max_slip_time: 1e4,
            stop_cutoff: 1.0,
            stop_fraction: 0.7,
            stiff_stop: true,
        }
    }
}

/// A solver setting out of range, named as on the command line.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{name} = {} is out of range: {range}", crate::text::short(*value))]
pub struct SettingsError {
    pub name: &'static str,
    pub value: f64,
    pub range: &'static str,
}

impl SolverSettings {
    /// Adaptive settings at tolerance `tol` (rtol = atol = tol).
    pub fn adaptive(method: Method, tol: f64) -> Self {
        SolverSettings {
            method,
            rtol: tol,
            atol: tol,
            ..Default::default()
        }
    }

    /// Fixed-step settings with step `h`.
    pub fn fixed(method: Method, h: f64) -> Self {
        SolverSettings {
            method,
            step: h,
            ..Default::default()
        }
    }

    pub fn validate(&self) -> Result<(), SettingsError> {
        let err = |name, value, range| Err(SettingsError { name, value, range });
        if self.method.is_adaptive() {
            if !(self.rtol >= 1e-14 && self.rtol <= 1e-2) {
                return err("tol", self.rtol, "must lie in [1e-14, 1e-2]");
            }
            if !(self.atol >= 1e-16 && self.atol <= 1e-2) {
                return err("atol", self.atol, "must lie in [1e-16, 1e-2]");
            }
        } else if !(self.step > 0.0 && self.step <= 1.0) {
            return err("step", self.step, "must lie in (0, 1]");
        }
        if !(self.stop_cutoff > 0.0 && self.stop_cutoff <= 1e3) {
            return err("stop-cutoff", self.stop_cutoff, "must lie in (0, 1e3]");
        }
        if !(self.stop_fraction > 0.0 && self.stop_fraction < 1.0) {
            return err("stop-fraction", self.stop_fraction, "must lie in (0, 1)");
        }
        if self.max_steps == 0 {
            return err("max-steps", 0.0, "must be at least 1");
        }
        if !(self.max_slip_time > 0.0 && self.max_slip_time.is_finite()) {
            return err(
                "max-slip-time",
                self.max_slip_time,
                "must be a finite number > 0",
            );
        }
        Ok(())
    }
}
