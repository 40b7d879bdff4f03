//! `oneblock bifurcation` (not yet written).

use clap::Args;

use super::CliError;

#[derive(Debug, Clone, Default, Args)]
pub struct BifurcationArgs {}

pub fn run(_args: BifurcationArgs) -> Result<(), CliError> {
    Err(CliError::Failed(
        "'bifurcation' is not implemented yet".into(),
    ))
}
