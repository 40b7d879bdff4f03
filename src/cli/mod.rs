//! The headless command line: one file per subcommand, shared flags in
//! `common`. `main.rs` only parses and dispatches.

pub mod bench_worker;
pub mod bifurcation;
pub mod common;
pub mod cycle;
pub mod gui;
pub mod map;
pub mod orbit;
pub mod phase;
pub mod trajectory;
pub mod work_precision;

use clap::{Parser, Subcommand};

pub use common::CliError;

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
    /// The block's path (t, x, y, u, w, phase) sampled for display.
    Trajectory(trajectory::TrajectoryArgs),
    /// Bifurcation diagram data: θ against θν, on both cores.
    Bifurcation(bifurcation::BifurcationArgs),
    /// Times the simulation worker: first coarse diagram, full diagram, trajectory latency.
    BenchWorker(bench_worker::BenchWorkerArgs),
    /// The work-precision chart: map error against cost per iterate for every method.
    WorkPrecision(work_precision::WorkPrecisionArgs),
    /// The phase diagram over (θν, κ): period, Lyapunov exponent and class per cell.
    Phase(phase::PhaseArgs),
    /// Opens the window (the default), optionally to take a screenshot and exit.
    Gui(gui::GuiArgs),
}

/// Runs the parsed command line.
pub fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        None => gui::run(gui::GuiArgs::default()),
        Some(Command::Map(a)) => map::run(a),
        Some(Command::Orbit(a)) => orbit::run(a),
        Some(Command::Cycle(a)) => cycle::run(a),
        Some(Command::Trajectory(a)) => trajectory::run(a),
        Some(Command::Bifurcation(a)) => bifurcation::run(a),
        Some(Command::BenchWorker(a)) => bench_worker::run(a),
        Some(Command::WorkPrecision(a)) => work_precision::run(a),
        Some(Command::Phase(a)) => phase::run(a),
        Some(Command::Gui(a)) => gui::run(a),
    }
}
