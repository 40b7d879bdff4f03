//! An a-posteriori reliability check for one map iterate: the same cycle is
//! run again at half the step (fixed-step methods) or at 1/64 of the
//! tolerance (adaptive ones), and the difference estimates the error.
//!
//! For a method of order p the global error at step h is C·h^p + O(h^(p+1)),
//! so |θ'(h) − θ'(h/2)| · 2^p/(2^p − 1) estimates the error of θ'(h)
//! (Richardson). Forward Euler fails on the slip equations by growth: each
//! step multiplies an oscillation of frequency ω by √(1 + h²ω²), and the
//! velocity weakening of the friction adds negative damping; a step-doubling
//! estimate sees that growth as a large difference between the two runs, long
//! before the result becomes non-finite. The check costs three times the
//! iterate for a fixed step; the adaptive methods rarely need it (their
//! error is measured in the work-precision chart) but get the same interface.

use crate::integrate::SolverSettings;
use crate::model::{Params, wrap_angle};
use crate::sim::{SimError, Simulator, SlipEvent};

/// A map iterate with its estimated error and whether it exceeds what was
/// asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Checked {
    /// The iterate computed with the given settings.
    pub event: SlipEvent,
    /// Estimated |θ' − θ'_exact|.
    pub est_error: f64,
    /// `est_error` exceeds the accuracy asked for, or the stop landed
    /// outside C (docs/model.md rule 5: in practice a sign of numerical error).
    pub unreliable: bool,
}

/// The settings of the check run: half the step, or 1/64 of the tolerance.
pub fn refined(settings: &SolverSettings) -> SolverSettings {
    let mut s = *settings;
    if s.method.is_adaptive() {
        s.rtol = (s.rtol / 64.0).max(1e-14);
        s.atol = (s.atol / 64.0).max(1e-16);
    } else {
        s.step *= 0.5;
        s.max_steps = s.max_steps.saturating_mul(2);
    }
    s
}

/// One cycle from θ with `settings`, checked against a refined run;
/// flagged unreliable when the estimated error exceeds `accuracy`.
///
/// A failure of either run is returned as the error it is (a fixed step too
/// large for the events is `SimError::StepTooLarge`).
pub fn checked_cycle(
    params: Params,
    settings: SolverSettings,
    theta: f64,
    accuracy: f64,
) -> Result<Checked, SimError> {
    let event = Simulator::new(params, settings)?.cycle(theta, 0.0, None)?;
    let fine = Simulator::new(params, refined(&settings))?.cycle(theta, 0.0, None)?;
    let diff = wrap_angle(event.theta_next - fine.theta_next).abs();
    let est_error = if settings.method.is_adaptive() {
        diff
    } else {
        let q = 2f64.powi(settings.method.order() as i32);
        diff * q / (q - 1.0)
    };
    let unreliable = !(est_error <= accuracy) || event.restarted || fine.restarted;
    Ok(Checked {
        event,
        est_error,
        unreliable,
    })
}
