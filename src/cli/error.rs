//! The command line's error type: bad input maps to exit code 2, a failure
//! of the run to exit code 1.

use crate::output::OutputError;
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
