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
            let text = e.to_string();
            let mut lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
            let mut msg = lines
                .next()
                .unwrap_or("invalid arguments")
                .trim_start_matches("error: ")
                .to_string();
            if msg.ends_with(':') {
                // "the following required arguments were not provided:" lists
                // them on the next lines; fold them into this one.
                let names: Vec<&str> = lines
                    .take_while(|l| l.starts_with('-') || l.starts_with('<'))
                    .collect();
                msg = format!("{} {}", msg, names.join(", "));
            }
            eprintln!("error: {msg} (see 'oneblock help')");
            std::process::exit(2);
        }
    };
    if let Err(e) = oneblock::cli::run(cli) {
        eprintln!("error: {e}");
        std::process::exit(e.exit_code());
    }
}
