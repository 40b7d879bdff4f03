//! `oneblock gui` (not yet written).

use clap::Args;

use super::CliError;

#[derive(Debug, Clone, Default, Args)]
pub struct GuiArgs {}

pub fn run(_args: GuiArgs) -> Result<(), CliError> {
    Err(CliError::Failed("'gui' is not implemented yet".into()))
}
