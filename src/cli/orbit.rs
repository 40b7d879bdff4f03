//! `oneblock orbit` (not yet written).

use clap::Args;

use super::CliError;

#[derive(Debug, Clone, Default, Args)]
pub struct OrbitArgs {}

pub fn run(_args: OrbitArgs) -> Result<(), CliError> {
    Err(CliError::Failed("'orbit' is not implemented yet".into()))
}
