//! `oneblock`: with no arguments opens the window; subcommands run headless.

use clap::Parser;
use clap::error::ErrorKind;

fn main() {
    let cli = match oneblock::cli::Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => {
            e.exit();
        }
        Err(e) => {
            // clap's usage errors come with a usage block and a hint; the
            // house rule is one line naming the flag, exit code 2.
            eprintln!(
                "error: {} (see 'oneblock help')",
                oneblock::cli::values::escape_controls(&oneblock::cli::usage_line(&e))
            );
            std::process::exit(2);
        }
    };
    if let Err(e) = oneblock::cli::run(cli) {
        // One line, whatever a path or value in it holds.
        eprintln!(
            "error: {}",
            oneblock::cli::values::escape_controls(&e.to_string())
        );
        std::process::exit(e.exit_code());
    }
}
