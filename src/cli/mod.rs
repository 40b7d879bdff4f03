//! The headless command line: one file per subcommand, shared flags in
//! `common`. `main.rs` only parses and dispatches.

pub mod attractors;
pub mod bench_worker;
pub mod bifurcation;
pub mod common;
pub mod continue_cmd;
pub mod continue_out;
pub mod cycle;
mod error;
pub mod figure;
#[cfg(feature = "gui")]
mod figure_basins;
#[cfg(feature = "gui")]
mod figure_csv;
mod figure_flags;
mod figure_look;
pub mod gui;
pub mod map;
pub mod orbit;
mod orbit_stats;
pub mod phase;
pub mod phase_boundaries;
mod phase_merge;
mod phase_picture;
pub mod run_control;
pub mod trajectory;
pub mod values;
pub mod work_precision;

use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::{Parser, Subcommand};

pub use error::CliError;

/// Explorer for the two-dimensional one-block earthquake model. With no
/// subcommand it opens the window.
#[derive(Debug, Parser)]
#[command(name = "oneblock", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// One map iterate θ → θ' with the slip event's details.
    Map(map::MapArgs),
    /// An orbit of the map: CSV of kept slip events, period and Lyapunov exponent.
    Orbit(orbit::OrbitArgs),
    /// A period-p cycle solved by Newton's method: its points, multiplier and stability.
    Cycle(cycle::CycleArgs),
    /// Every attractor and basin at one parameter point, or tracked over a parameter range with where each is born and dies, from the exit arc's cell graph.
    Attractors(attractors::AttractorsArgs),
    /// A cycle followed in a parameter: period doublings, folds, borders; cascades; curves.
    Continue(continue_cmd::ContinueArgs),
    /// The block's path (t, x, y, u, w, phase) sampled for display.
    Trajectory(trajectory::TrajectoryArgs),
    /// Bifurcation diagram data: θ against θν (or κ, γ, ν, Ω: --param), on both cores.
    Bifurcation(bifurcation::BifurcationArgs),
    /// Times the jobs: the worker's sweep (first coarse diagram, full diagram, trajectory latency), or a phase grid (--phase), the single-threaded host (--single-thread), every kind in the page's slices (--pieces).
    BenchWorker(bench_worker::BenchWorkerArgs),
    /// The work-precision chart: map error against cost per iterate for every method (on a four-attractor sample, or on the one attractor the model flags give).
    WorkPrecision(work_precision::WorkPrecisionArgs),
    /// The phase diagram over (θν, κ): period, Lyapunov exponent and class per cell.
    Phase(phase::PhaseArgs),
    /// Opens the window (the default), optionally to take a screenshot and exit.
    Gui(gui::GuiArgs),
    /// One view as an SVG, PDF, PNG or GIF file, drawn headless by the window's code
    /// (needs the default `gui` feature).
    // Boxed: its flags are the largest of all (clippy's large_enum_variant).
    Figure(Box<figure::FigureArgs>),
}

/// Parses this process's command line (clap's errors as they are) and
/// records it, with every flag's value, for the `#` lines each CSV begins
/// with ([`crate::provenance`]).
pub fn parse() -> Result<Cli, clap::Error> {
    use clap::{CommandFactory, FromArgMatches};
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    let cmd = Cli::command();
    let matches = cmd.clone().try_get_matches_from(&args)?;
    let cli = Cli::from_arg_matches(&matches)?;
    crate::provenance::record(invocation(&cmd, &args, &matches));
    Ok(cli)
}

/// The command line as a shell would read it back, and every flag of its
/// subcommand with the value it was read as (given, or the default).
fn invocation(
    cmd: &clap::Command,
    args: &[std::ffi::OsString],
    matches: &clap::ArgMatches,
) -> crate::provenance::Invocation {
    use crate::provenance::shell_quote;
    let words: Vec<String> = std::iter::once("oneblock".to_string())
        .chain(
            args.iter()
                .skip(1)
                .map(|a| shell_quote(&a.to_string_lossy())),
        )
        .collect();
    let mut flags = Vec::new();
    if let Some((name, sub)) = matches.subcommand()
        && let Some(sc) = cmd.find_subcommand(name)
    {
        for arg in sc.get_arguments() {
            let (id, Some(long)) = (arg.get_id().as_str(), arg.get_long()) else {
                continue;
            };
            if sub.value_source(id).is_none() {
                continue;
            }
            let values: Vec<String> = sub
                .get_raw(id)
                .map(|v| v.map(|x| shell_quote(&x.to_string_lossy())).collect())
                .unwrap_or_default();
            flags.push(format!("--{long}={}", values.join(",")));
        }
    }
    crate::provenance::Invocation {
        line: words.join(" "),
        flags,
    }
}

/// Checks a parsed command line as `run` does before any work (values,
/// bounds, presets, output paths) without running it: what the property
/// tests drive with arbitrary strings.
pub fn validate(cli: &Cli) -> Result<(), CliError> {
    match &cli.command {
        None => Ok(()),
        Some(Command::Map(a)) => map::check(a).map(drop),
        Some(Command::Orbit(a)) => orbit::check(a).map(drop),
        Some(Command::Trajectory(a)) => trajectory::check(a).map(drop),
        Some(Command::Bifurcation(a)) => bifurcation::check(a).map(drop),
        Some(Command::BenchWorker(a)) => bench_worker::check(a).map(drop),
        Some(Command::WorkPrecision(a)) => work_precision::check(a).map(drop),
        Some(Command::Phase(a)) => phase::check_any(a),
        Some(Command::Cycle(a)) => cycle::check(a).map(drop),
        Some(Command::Attractors(a)) => attractors::check_any(a),
        Some(Command::Continue(a)) => continue_cmd::check(a).map(drop),
        Some(Command::Gui(a)) => gui::check(a).map(drop),
        Some(Command::Figure(a)) => figure::check(a).map(drop),
    }
}

/// A usage error of the parser as one line naming the flag, without the
/// usage block clap adds (the house rule: `--flag: what is wrong`).
pub fn usage_line(e: &clap::Error) -> String {
    let flag = match e.get(ContextKind::InvalidArg) {
        Some(ContextValue::String(s)) => Some(s.split_whitespace().next().unwrap_or(s).to_string()),
        _ => None,
    };
    let value = match e.get(ContextKind::InvalidValue) {
        Some(ContextValue::String(s)) => Some(s.clone()),
        _ => None,
    };
    if let (ErrorKind::ValueValidation, Some(flag), Some(value)) = (e.kind(), &flag, &value) {
        // The parser's own reason is the error's source.
        let reason = std::error::Error::source(e)
            .map(|s| s.to_string())
            .unwrap_or_else(|| "invalid value".into());
        let shown = values::echo(value);
        return format!("{flag} = '{shown}': {reason}");
    }
    if let (ErrorKind::InvalidValue, Some(flag), Some("")) = (e.kind(), &flag, value.as_deref()) {
        // A flag at the end of the line, or followed by another flag.
        return missing_value(flag, e.get(ContextKind::ValidValue));
    }
    if let (ErrorKind::InvalidValue, Some(flag), Some(value), Some(ContextValue::Strings(valid))) =
        (e.kind(), &flag, &value, e.get(ContextKind::ValidValue))
    {
        // A flag with a fixed set of values: the list on the same line.
        return format!(
            "{flag}: unknown value '{}': expected one of {}",
            values::echo(value),
            valid.join(", ")
        );
    }
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
    match flag {
        Some(f) if !msg.contains(&f) => format!("{f}: {msg}"),
        _ => msg,
    }
}

/// The line for `flag` given without its value: the flag, then what it
/// expects (its list of values, else the first sentence of its help).
fn missing_value(flag: &str, valid: Option<&ContextValue>) -> String {
    let expects = match valid {
        Some(ContextValue::Strings(v)) if !v.is_empty() => Some(format!("one of {}", v.join(", "))),
        _ => flag_help(flag),
    };
    match expects {
        Some(x) => format!("{flag} needs a value: {x}"),
        None => format!("{flag} needs a value"),
    }
}

/// The first sentence of the help of `flag` (`--out`) of the subcommand
/// this process was started with.
fn flag_help(flag: &str) -> Option<String> {
    use clap::CommandFactory;
    let long = flag.trim_start_matches('-');
    let cmd = Cli::command();
    let name = std::env::args().skip(1).find(|a| !a.starts_with('-'))?;
    let sub = cmd.find_subcommand(&name)?;
    let arg = sub.get_arguments().find(|a| a.get_long() == Some(long))?;
    let help = arg.get_help()?.to_string();
    let words = help.split_whitespace().collect::<Vec<_>>().join(" ");
    let end = [words.find(". "), words.find("; "), words.find(" [default")]
        .into_iter()
        .flatten()
        .min()
        .unwrap_or(words.len());
    let sentence = words[..end].trim_end_matches('.');
    (!sentence.is_empty()).then(|| sentence.to_string())
}

/// Runs the parsed command line.
pub fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        None => gui::run(gui::GuiArgs::default()),
        Some(Command::Map(a)) => map::run(a),
        Some(Command::Orbit(a)) => orbit::run(a),
        Some(Command::Cycle(a)) => cycle::run(a),
        Some(Command::Attractors(a)) => attractors::run(a),
        Some(Command::Continue(a)) => continue_cmd::run(a),
        Some(Command::Trajectory(a)) => trajectory::run(a),
        Some(Command::Bifurcation(a)) => bifurcation::run(a),
        Some(Command::BenchWorker(a)) => bench_worker::run(a),
        Some(Command::WorkPrecision(a)) => work_precision::run(a),
        Some(Command::Phase(a)) => phase::run(a),
        Some(Command::Gui(a)) => gui::run(a),
        Some(Command::Figure(a)) => figure::run(*a),
    }
}
