//! `oneblock map` (not yet written).

use clap::Args;

use super::CliError;

#[derive(Debug, Clone, Default, Args)]
pub struct MapArgs {}

pub fn run(_args: MapArgs) -> Result<(), CliError> {
    Err(CliError::Failed("'map' is not implemented yet".into()))
}
