//! `oneblock`: with no arguments opens the window; subcommands run headless.

use clap::Parser;

fn main() {
    let cli = oneblock::cli::Cli::parse();
    if let Err(e) = oneblock::cli::run(cli) {
        eprintln!("error: {e}");
        std::process::exit(e.exit_code());
    }
}
