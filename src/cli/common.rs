//! Flags every simulating subcommand shares, and the error type that maps
//! bad input to exit code 2 and failures to exit code 1.

use std::path::Path;

use clap::Args;

use crate::integrate::{Method, SolverSettings};
use crate::model::Params;
use crate::output::{OutputError, check_writable, write_output};
use crate::sim::SimError;

/// A command-line failure: `Usage` (bad input: exit 2) or `Failed` (exit 1).
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    #[error("{0}")]
    Usage(String),
    #[error("{0}")]
    Failed(String),
}

impl CliError {
    pub fn exit_code(&self) -> i32 {
        match self {
            CliError::Usage(_) => 2,
            CliError::Failed(_) => 1,
        }
    }
}

impl From<SimError> for CliError {
    /// Errors about a parameter, a setting or an off-arc θ are the user's
    /// input; the rest are failures of the run.
    fn from(e: SimError) -> Self {
        match e {
            SimError::Param(_)
            | SimError::Settings(_)
            | SimError::OffExitArc { .. }
            | SimError::StepTooLarge { .. } => CliError::Usage(e.to_string()),
            _ => CliError::Failed(e.to_string()),
        }
    }
}

impl From<OutputError> for CliError {
    fn from(e: OutputError) -> Self {
        CliError::Usage(e.to_string())
    }
}

/// The model's parameters (MODEL.md), angles in radians.
#[derive(Debug, Clone, Args)]
pub struct ModelArgs {
    /// κ = k_x/k_y, the spring anisotropy (> 0).
    #[arg(long, allow_negative_numbers = true)]
    pub kappa: f64,
    /// γ, the friction weakening (≥ 0).
    #[arg(long, allow_negative_numbers = true)]
    pub gamma: f64,
    /// ν, the pulling speed (> 0).
    #[arg(long, allow_negative_numbers = true)]
    pub nu: f64,
    /// θν, the pulling direction in radians.
    #[arg(long = "theta-nu", allow_negative_numbers = true)]
    pub theta_nu: f64,
    /// Ω, the memory of the friction direction (> 0).
    #[arg(long, default_value_t = 50.0, allow_negative_numbers = true)]
    pub omega: f64,
}

impl ModelArgs {
    pub fn params(&self) -> Result<Params, CliError> {
        let p = Params {
            kappa: self.kappa,
            gamma: self.gamma,
            nu: self.nu,
            theta_nu: self.theta_nu,
            omega: self.omega,
        };
        p.validate().map_err(|e| CliError::Usage(e.to_string()))?;
        Ok(p)
    }
}

/// The integration method and its accuracy.
#[derive(Debug, Clone, Args)]
pub struct SolverArgs {
    /// Integration method: dp54, dp853, rk4 or euler.
    #[arg(long, default_value = "dp853")]
    pub method: String,
    /// Tolerance of the adaptive methods (rtol = atol), in [1e-14, 1e-2].
    #[arg(long, allow_negative_numbers = true, conflicts_with = "step")]
    pub tol: Option<f64>,
    /// Step of the fixed-step methods (rk4, euler), in (0, 1].
    #[arg(long, allow_negative_numbers = true)]
    pub step: Option<f64>,
}

impl SolverArgs {
    pub fn settings(&self) -> Result<SolverSettings, CliError> {
        let method: Method = self
            .method
            .parse()
            .map_err(|e: String| CliError::Usage(format!("--method: {e}")))?;
        let s = if method.is_adaptive() {
            if self.step.is_some() {
                return Err(CliError::Usage(format!(
                    "--step applies to rk4 and euler, not {method}; use --tol"
                )));
            }
            SolverSettings::adaptive(method, self.tol.unwrap_or(1e-10))
        } else {
            if self.tol.is_some() {
                return Err(CliError::Usage(format!(
                    "--tol applies to dp54 and dp853, not {method}; use --step"
                )));
            }
            SolverSettings::fixed(method, self.step.unwrap_or(1e-3))
        };
        s.validate()
            .map_err(|e| CliError::Usage(format!("--{e}")))?;
        Ok(s)
    }
}

/// Checks a user-given finite number.
pub fn finite(name: &str, v: f64) -> Result<f64, CliError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(CliError::Usage(format!(
            "--{name} = {v} must be a finite number"
        )))
    }
}

/// Fails early (before any simulation) when `path` cannot be written.
pub fn check_out(path: &Path, force: bool) -> Result<(), CliError> {
    check_writable(path, force).map_err(CliError::from)
}

/// Writes a finished output atomically.
pub fn write_out(path: &Path, bytes: &[u8], force: bool) -> Result<(), CliError> {
    write_output(path, bytes, force).map_err(CliError::from)
}
