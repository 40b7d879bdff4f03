//! The headless command line: one file per subcommand, shared flags in
//! `common`. `main.rs` only parses and dispatches.

pub mod attractors;
mod bench_pieces;
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
pub mod gui;
pub mod map;
pub mod orbit;
mod orbit_stats;
pub mod phase;
pub mod phase_boundaries;
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
    /// Every attractor at one parameter point, from seeds spread over the exit arc, with basin fractions.
    Attractors(attractors::AttractorsArgs),
    /// A cycle followed in a parameter: period doublings, folds, borders; cascades; curves.
    Continue(continue_cmd::ContinueArgs),
    /// The block's path (t, x, y, u, w, phase) sampled for display.
    Trajectory(trajectory::TrajectoryArgs),
    /// Bifurcation diagram data: θ against θν, on both cores.
    Bifurcation(bifurcation::BifurcationArgs),
    /// Times the simulation worker: first coarse diagram, full diagram, trajectory latency.
    BenchWorker(bench_worker::BenchWorkerArgs),
    /// The work-precision chart: map error against cost per iterate for every method (on a four-attractor sample, or on the one attractor the model flags give).
    WorkPrecision(work_precision::WorkPrecisionArgs),
    /// The phase diagram over (θν, κ): period, Lyapunov exponent and class per cell.
    Phase(phase::PhaseArgs),
    /// Opens the window (the default), optionally to take a screenshot and exit.
    Gui(gui::GuiArgs),
    /// One view as an SVG or PNG file, drawn headless by the window's code
    /// (needs the default `gui` feature).
    Figure(figure::FigureArgs),
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
        Some(Command::Phase(a)) => phase::check(a).map(drop),
        Some(Command::Cycle(a)) => cycle::check(a).map(drop),
        Some(Command::Attractors(a)) => attractors::check(a).map(drop),
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
        Some(Command::Figure(a)) => figure::run(a),
    }
}
