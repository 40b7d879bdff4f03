//! What can go wrong in a simulation, said with the parameters that caused it.

use crate::integrate::{IntegrateError, SettingsError};
use crate::model::{ParamError, Params};

/// A failed cycle, map iterate or run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SimError {
    #[error(transparent)]
    Param(#[from] ParamError),
    #[error(transparent)]
    Settings(#[from] SettingsError),
    #[error(
        "theta = {theta} is not on the exit arc ({lo:.6} < theta < {hi:.6}) for kappa = {kappa}, theta-nu = {theta_nu}: no stick phase ends there"
    )]
    OffExitArc {
        theta: f64,
        lo: f64,
        hi: f64,
        kappa: f64,
        theta_nu: f64,
    },
    #[error("slip from theta = {theta} ({p}): {source}", p = fmt_params(params))]
    Integrate {
        theta: f64,
        params: Params,
        source: IntegrateError,
    },
    #[error("slip from theta = {theta} ({p}) did not stop within max_slip_time = {max}", p = fmt_params(params))]
    SlipTooLong {
        theta: f64,
        params: Params,
        max: f64,
    },
    #[error(
        "step = {h} is too large to resolve the {event} of the slip from theta = {theta} ({p}); use a smaller --step",
        p = fmt_params(params)
    )]
    StepTooLarge {
        h: f64,
        event: &'static str,
        theta: f64,
        params: Params,
    },
    #[error("the path would hold more than {limit} samples")]
    TooManySamples { limit: usize },
    #[error("the job was cancelled")]
    Cancelled,
}

fn fmt_params(p: &Params) -> String {
    format!(
        "kappa = {}, gamma = {}, nu = {}, theta-nu = {}, omega = {}",
        p.kappa, p.gamma, p.nu, p.theta_nu, p.omega
    )
}

impl SimError {
    /// The parameter or setting the error is about, when it is about one.
    pub fn parameter(&self) -> Option<&'static str> {
        match self {
            SimError::Param(e) => Some(e.name),
            SimError::Settings(e) => Some(e.name),
            SimError::OffExitArc { .. } => Some("theta"),
            SimError::StepTooLarge { .. } => Some("step"),
            _ => None,
        }
    }
}
