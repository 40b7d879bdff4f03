//! `oneblock trajectory` (not yet written).

use clap::Args;

use super::CliError;

#[derive(Debug, Clone, Default, Args)]
pub struct TrajectoryArgs {}

pub fn run(_args: TrajectoryArgs) -> Result<(), CliError> {
    Err(CliError::Failed(
        "'trajectory' is not implemented yet".into(),
    ))
}
