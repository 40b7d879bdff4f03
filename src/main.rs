//! `oneblock`: with no arguments opens the window; subcommands run headless.

#[cfg(not(target_arch = "wasm32"))]
use clap::error::ErrorKind;

/// The browser build (web/build.sh): the explorer on the page's canvas.
#[cfg(all(target_arch = "wasm32", feature = "gui"))]
fn main() {
    oneblock::app::web::start();
}

/// A browser build without the window has nothing to run.
#[cfg(all(target_arch = "wasm32", not(feature = "gui")))]
fn main() {}

#[cfg(not(target_arch = "wasm32"))]
fn main() {
    let cli = match oneblock::cli::parse() {
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
