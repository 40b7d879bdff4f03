//! `oneblock trajectory`: the block's path as CSV `t,x,y,u,w,phase`, sampled
//! from the dense output at a settable spacing during slips; a stick phase
//! (a straight line at the surface velocity) contributes its two ends.

use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use clap::Args;

use super::CliError;
use super::common::{
    ModelArgs, SolverArgs, check_out, check_theta, count_in, describe, emit, finite, max_seconds,
    total_iterates, warn_event, warn_validity, with_provenance,
};
use super::run_control::{Limits, Progress, collect_job, job_error};
use super::values::{parse_count, parse_number, short};
use crate::formats::{TRAJECTORY_HEADER, trajectory_rows};
use crate::jobs::{JobError, TrajectorySpec, Update};
use crate::sim::{SimError, Simulator};

/// The smallest sampling spacing accepted: the trajectory job's.
pub use crate::jobs::MIN_SPACING;

/// The most samples (CSV rows) a path may have: they are held in memory
/// until the file is written atomically (~150 bytes each with the text).
pub const MAX_SAMPLES: usize = 2_000_000;

/// The fewest samples a cycle records, whatever the spacing: the slip's
/// onset and stop and the stick's ends (tests/cli_reliability.rs measures
/// it at a spacing longer than any slip).
pub const MIN_SAMPLES_PER_CYCLE: usize = 5;

/// The most cycles recorded: as many as the sample cap can hold at the
/// coarsest spacing. More could never succeed, whatever --spacing.
pub const MAX_EVENTS: usize = MAX_SAMPLES / MIN_SAMPLES_PER_CYCLE;

/// The path of the block over a few cycles.
#[derive(Debug, Clone, Args)]
pub struct TrajectoryArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    #[command(flatten)]
    pub solver: SolverArgs,
    /// θ of the first slip onset, in radians (on the exit arc) [default: θν,
    /// which always is].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub theta0: Option<f64>,
    /// Cycles iterated (not recorded) before the path starts, to reach the
    /// attractor; the recorded path starts at t = 0 (transient + events ≤ 1e12).
    #[arg(long, default_value_t = 0, value_parser = parse_count, allow_hyphen_values = true)]
    pub transient: usize,
    /// Cycles (slip + the stick that follows) recorded, 1 to 400000: a
    /// path holds at most 2e6 samples, and a cycle at least 5.
    #[arg(long, default_value_t = 1, value_parser = parse_count, allow_hyphen_values = true)]
    pub events: usize,
    /// CSV file ("-" = stdout).
    #[arg(long, default_value = "-")]
    pub out: PathBuf,
    /// Time between samples during slips (≥ 1e-6).
    #[arg(long, default_value_t = 0.01, allow_hyphen_values = true, value_parser = parse_number)]
    pub spacing: f64,
    /// Overwrite an existing --out file.
    #[arg(long)]
    pub force: bool,
    /// Stop after this many seconds, in (0, 1e7], writing nothing, exit 1.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub max_seconds: Option<f64>,
}

/// The checked inputs of `trajectory`.
pub struct Plan {
    sim: Simulator,
    theta0: f64,
    events: usize,
    spacing: f64,
    total: u64,
    max_seconds: Option<f64>,
}

/// Checks the flags and the output before any work.
pub fn check(args: &TrajectoryArgs) -> Result<Plan, CliError> {
    let params = args.model.params()?;
    let settings = args.solver.settings()?;
    let events = count_in("events", args.events, MAX_EVENTS)?;
    let total = total_iterates(args.transient, ("events", events), 1)?;
    let spacing = finite("spacing", args.spacing)?;
    if spacing < MIN_SPACING {
        return Err(CliError::Usage(format!(
            "--spacing = {} is out of range: must be a number >= {MIN_SPACING:e}",
            short(spacing)
        )));
    }
    check_out(&args.out, args.force)?;
    let max_seconds = max_seconds(args.max_seconds)?;
    let sim = Simulator::new(params, settings)?;
    let theta0 = check_theta(&sim, "theta0", args.theta0.unwrap_or(params.theta_nu))?;
    Ok(Plan {
        sim,
        theta0,
        events,
        spacing,
        total,
        max_seconds,
    })
}

pub fn run(args: TrajectoryArgs) -> Result<(), CliError> {
    let Plan {
        sim,
        theta0,
        events,
        spacing,
        total,
        max_seconds,
    } = check(&args)?;
    let (params, settings) = (*sim.params(), *sim.settings());
    warn_validity(&params);
    let progress = Progress::new("trajectory", "cycles", total);
    let limits = Limits::start(max_seconds);
    let spec = TrajectorySpec {
        params,
        settings,
        theta0: Some(theta0),
        transient: args.transient,
        spacing,
        cycles: Some(events),
        max_samples: Some(MAX_SAMPLES),
    };
    // The rows are written as the samples come (they are not held twice);
    // the slips are kept.
    let model = describe(sim.params(), sim.settings());
    let csv = Mutex::new(with_provenance(&model, TRAJECTORY_HEADER) + "\n");
    let rows = AtomicUsize::new(0);
    let each = |u: &Update| {
        if let Update::TrajectoryChunk { samples, .. } = u {
            trajectory_rows(&mut csv.lock().unwrap_or_else(|e| e.into_inner()), samples);
            rows.fetch_add(samples.len(), Ordering::Relaxed);
        }
    };
    let slips_only = |u: &Update| matches!(u, Update::Slip { .. });
    let updates = match collect_job(spec.into(), 1, &progress, &limits, &each, slips_only) {
        Err(JobError::Sim(SimError::TooManySamples { .. })) => {
            return Err(CliError::Usage(format!(
                "--spacing = {} with --events = {events} would record more than {MAX_SAMPLES:e} samples: raise --spacing (a cycle records at least {MIN_SAMPLES_PER_CYCLE}, whatever the spacing) or lower --events (nothing was written)",
                short(spacing)
            )));
        }
        r => r.map_err(|e| job_error("trajectory", &limits, e))?,
    };
    let (mut t, mut restarts) = (0.0, 0);
    for u in updates {
        if let Update::Slip { event, .. } = u {
            warn_event(&event);
            t += event.slip_duration + event.stick_duration;
            restarts += usize::from(event.restarted);
        }
    }
    let csv = csv.into_inner().unwrap_or_else(|e| e.into_inner());
    emit(&args.out, csv.as_bytes(), args.force)?;
    eprintln!(
        "trajectory: {}\n  {} cycle(s) after {} transient, {} samples over t in [0, {t}], {} restart(s)",
        describe(&params, &settings),
        events,
        args.transient,
        rows.into_inner(),
        restarts
    );
    Ok(())
}
