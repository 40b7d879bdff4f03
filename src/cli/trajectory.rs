//! `oneblock trajectory`: the block's path as CSV `t,x,y,u,w,phase`, sampled
//! from the dense output at a settable spacing during slips; a stick phase
//! (a straight line at the surface velocity) contributes its two ends.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args;

use super::CliError;
use super::common::{
    ModelArgs, SolverArgs, check_out, check_theta, count_in, describe, emit, finite, total_iterates,
};
use crate::sim::{Sampler, Simulator};

/// The smallest sampling spacing accepted: finer than any plot needs, and a
/// slip of a few time units still yields a bounded number of rows.
pub const MIN_SPACING: f64 = 1e-6;

/// The most cycles recorded: each yields hundreds of rows at the default
/// spacing.
pub const MAX_EVENTS: usize = 1_000_000;

/// The path of the block over a few cycles.
#[derive(Debug, Clone, Args)]
pub struct TrajectoryArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    #[command(flatten)]
    pub solver: SolverArgs,
    /// θ of the first slip onset, in radians (on the exit arc) [default: θν,
    /// which always is].
    #[arg(long, allow_hyphen_values = true)]
    pub theta0: Option<f64>,
    /// Cycles iterated (not recorded) before the path starts, to reach the
    /// attractor; the recorded path starts at t = 0.
    #[arg(long, default_value_t = 0)]
    pub transient: usize,
    /// Cycles (slip + the stick that follows) recorded (1 to 1e6).
    #[arg(long, default_value_t = 1)]
    pub events: usize,
    /// CSV file ("-" = stdout).
    #[arg(long, default_value = "-")]
    pub out: PathBuf,
    /// Time between samples during slips (≥ 1e-6).
    #[arg(long, default_value_t = 0.01, allow_hyphen_values = true)]
    pub spacing: f64,
    /// Overwrite an existing --out file.
    #[arg(long)]
    pub force: bool,
}

pub fn run(args: TrajectoryArgs) -> Result<(), CliError> {
    let params = args.model.params()?;
    let settings = args.solver.settings()?;
    let events = count_in("events", args.events, MAX_EVENTS)?;
    total_iterates(args.transient, ("events", events), 1)?;
    let spacing = finite("spacing", args.spacing)?;
    if spacing < MIN_SPACING {
        return Err(CliError::Usage(format!(
            "--spacing = {spacing} is out of range: must be a number >= {MIN_SPACING:e}"
        )));
    }
    check_out(&args.out, args.force)?;
    let sim = Simulator::new(params, settings)?;
    let mut theta = check_theta(&sim, "theta0", args.theta0.unwrap_or(params.theta_nu))?;

    for _ in 0..args.transient {
        let ev = sim.cycle(theta, 0.0, None)?;
        theta = sim.next_onset(&ev);
    }
    let mut sampler = Sampler::new(spacing);
    let mut t = 0.0;
    let mut restarts = 0;
    for _ in 0..events {
        let ev = sim.cycle(theta, t, Some(&mut sampler))?;
        t += ev.slip_duration + ev.stick_duration;
        restarts += usize::from(ev.restarted);
        theta = sim.next_onset(&ev);
    }

    let samples = sampler.take();
    let mut csv = String::with_capacity(64 * (samples.len() + 1));
    csv.push_str("t,x,y,u,w,phase\n");
    for s in &samples {
        writeln!(
            csv,
            "{},{},{},{},{},{}",
            s.t,
            s.x,
            s.y,
            s.u,
            s.w,
            s.phase.name()
        )
        .ok();
    }
    emit(&args.out, csv.as_bytes(), args.force)?;
    eprintln!(
        "trajectory: {}\n  {} cycle(s) after {} transient, {} samples over t in [0, {t}], {} restart(s)",
        describe(&params, &settings),
        events,
        args.transient,
        samples.len(),
        restarts
    );
    Ok(())
}
