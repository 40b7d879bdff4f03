//! `oneblock bench-worker` (not yet written).

use clap::Args;

use super::CliError;

#[derive(Debug, Clone, Default, Args)]
pub struct BenchWorkerArgs {}

pub fn run(_args: BenchWorkerArgs) -> Result<(), CliError> {
    Err(CliError::Failed(
        "'bench-worker' is not implemented yet".into(),
    ))
}
