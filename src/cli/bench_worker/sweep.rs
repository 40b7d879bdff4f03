//! `bench-worker`'s sweeps: the Fig. 3b diagram from a sweep command to
//! its first full coarse pass and to its end, a trajectory sent during it
//! to its first chunk, and the core alone on the same columns.

use std::time::{Duration, Instant};

use super::machine::{cpu_seconds, load_average};
use super::{BenchWorkerArgs, recv, say, worker};
use crate::bench::diagram::{fig3b, fig3b_diagram};
use crate::cli::CliError;
use crate::integrate::SolverSettings;
use crate::sim::stats::median;
use crate::sim::{SweepOptions, sweep_columns, theta_nu_grid};
use crate::worker::{Command, Lane, Outcome, TrajectorySpec, Update, sweep_plan};

struct SweepTiming {
    coarse: f64,
    full: f64,
    /// CPU seconds the whole process used meanwhile (all threads), up to
    /// the coarse diagram and up to the full one.
    cpu_coarse: Option<f64>,
    cpu: Option<f64>,
    iterates_per_second: f64,
    column_errors: usize,
}

fn sweep_command(args: &BenchWorkerArgs, settings: SolverSettings, generation: u64) -> Command {
    let mut spec = fig3b_diagram(args.columns, args.transient, args.keep, args.tol);
    spec.settings = settings;
    Command::run(generation, spec)
}

/// One sweep from command to `Finished`, draining as the GUI would.
fn time_sweep(args: &BenchWorkerArgs, settings: SolverSettings) -> Result<SweepTiming, CliError> {
    let w = worker(args);
    let n_coarse = sweep_plan(args.columns, args.coarse(), args.threads)
        .iter()
        .filter(|p| p.coarse)
        .count();
    let t0 = Instant::now();
    let cpu0 = cpu_seconds();
    if !w.send(sweep_command(args, settings, 1)) {
        return Err(CliError::Failed("the worker refused the sweep".into()));
    }
    let (mut coarse_seen, mut coarse, mut ips, mut errors) = (0, None, 0.0, 0);
    let mut cpu_coarse = None;
    let full = loop {
        match recv(&w)? {
            Update::Column { coarse: true, .. } => {
                coarse_seen += 1;
                if coarse_seen == n_coarse {
                    coarse = Some(t0.elapsed().as_secs_f64());
                    cpu_coarse = cpu_seconds().zip(cpu0).map(|(b, a)| b - a);
                }
            }
            Update::Progress {
                iterates_per_second,
                ..
            } => ips = iterates_per_second,
            Update::Error { message, .. } => {
                errors += 1;
                eprintln!("  column error: {message}");
            }
            Update::Finished { outcome, .. } => {
                if let Outcome::Failed(m) = outcome {
                    return Err(CliError::Failed(format!("the sweep failed: {m}")));
                }
                break t0.elapsed().as_secs_f64();
            }
            _ => {}
        }
    };
    let cpu = cpu_seconds().zip(cpu0).map(|(b, a)| b - a);
    w.shutdown();
    Ok(SweepTiming {
        coarse: coarse.unwrap_or(full),
        full,
        cpu_coarse,
        cpu,
        iterates_per_second: ips,
        column_errors: errors,
    })
}

/// Latencies from a `Trajectory` command, sent while a sweep runs, to its
/// first `TrajectoryChunk`.
fn trajectory_latencies(
    args: &BenchWorkerArgs,
    settings: SolverSettings,
    spread: Duration,
) -> Result<Vec<f64>, CliError> {
    let w = worker(args);
    w.send(sweep_command(args, settings, 1));
    let gap = spread / (args.latency_samples as u32 + 1);
    let mut out = Vec::new();
    let mut sweep_done = false;
    for k in 0..args.latency_samples {
        // Keep draining the sweep for a while, as the GUI does every frame.
        let until = Instant::now() + gap;
        while let Some(d) = until.checked_duration_since(Instant::now()) {
            if let Some(Update::Finished {
                lane: Lane::Sweep, ..
            }) = w.recv_timeout(d)
            {
                sweep_done = true;
            }
        }
        let generation = 2 + k as u64;
        let sent = Instant::now();
        w.send(Command::run(
            generation,
            TrajectorySpec {
                params: fig3b().with_theta_nu(1.0),
                settings,
                theta0: None,
                transient: 0,
                spacing: 0.05,
                cycles: Some(5),
                max_samples: None,
            },
        ));
        loop {
            match recv(&w)? {
                Update::TrajectoryChunk { generation: g, .. } if g == generation => {
                    out.push(sent.elapsed().as_secs_f64());
                    break;
                }
                Update::Finished {
                    lane: Lane::Sweep, ..
                } => sweep_done = true,
                Update::Finished {
                    generation: g,
                    outcome: Outcome::Failed(m),
                    ..
                } if g == generation => {
                    return Err(CliError::Failed(format!("the trajectory failed: {m}")));
                }
                _ => {}
            }
        }
    }
    if sweep_done {
        eprintln!("  note: the sweep ended before the last trajectory was sent");
    }
    w.shutdown();
    Ok(out)
}

/// The core alone on this thread, without the worker: the coarse pass's
/// columns as one continued chain (`sweep_columns`). Returns iterates per
/// wall-clock second and per CPU second (the latter is what an idle core
/// would give; the machine may be shared).
fn serial_rate(args: &BenchWorkerArgs, settings: SolverSettings) -> (f64, Option<f64>) {
    let opts = SweepOptions {
        transient: args.transient,
        keep: args.keep,
        map: crate::sim::MapChoice::Direct,
    };
    let grid = theta_nu_grid(0.0, std::f64::consts::FRAC_PI_2, args.columns);
    let coarse: Vec<f64> = sweep_plan(args.columns, args.coarse(), 1)
        .iter()
        .filter(|p| p.coarse)
        .map(|p| grid[p.index])
        .collect();
    let mut sorted = coarse;
    sorted.sort_by(f64::total_cmp);
    let t0 = Instant::now();
    let cpu0 = cpu_seconds();
    let cols = sweep_columns(fig3b(), settings, &sorted, &opts, None, &|| false, |_| {});
    let n: usize = cols.iter().map(|c| args.transient + c.thetas.len()).sum();
    let wall = t0.elapsed().as_secs_f64().max(1e-6);
    // CPU time is counted in hundredths of a second: a shorter run has no
    // CPU rate worth printing.
    let cpu = cpu_seconds()
        .zip(cpu0)
        .map(|(b, a)| b - a)
        .filter(|&c| c >= 0.05);
    (n as f64 / wall, cpu.map(|c| n as f64 / c))
}

/// The sweep benchmark's report.
pub(super) fn run_sweeps(args: &BenchWorkerArgs, settings: SolverSettings) -> Result<(), CliError> {
    say(&format!(
        "bench-worker: Fig. 3b (gamma = 6.5, kappa = 18.95, nu = 1e-3, omega = 50), dop853, tol = {:e}",
        args.tol
    ))?;
    say(&format!(
        "sweep: {} columns x ({} transient + {} kept) over theta-nu in [0, pi/2]; coarse pass {} columns; {} sweep threads; {} logical CPUs",
        args.columns,
        args.transient,
        args.keep,
        args.coarse(),
        args.threads,
        std::thread::available_parallelism().map_or(0, |n| n.get()),
    ))?;
    if let Some(l) = load_average() {
        say(&format!("load average before the run: {l:.2}"))?;
    }
    let (serial_wall, serial_cpu) = serial_rate(args, settings);
    let total = (args.columns * (args.transient + args.keep)) as f64;
    let per_cpu = serial_cpu.unwrap_or(serial_wall);
    say(&format!(
        "core alone (coarse columns, one thread): {serial_wall:.0} iterates per second, {} per CPU second",
        serial_cpu.map_or("?".into(), |r| format!("{r:.0}"))
    ))?;
    say(&format!(
        "  => CPU work: {:.2} s per full diagram, {:.2} s per coarse pass; ideal on {} idle cores: {:.2} s and {:.2} s",
        total / per_cpu,
        total / per_cpu * args.coarse() as f64 / args.columns as f64,
        args.threads,
        total / per_cpu / args.threads as f64,
        total / per_cpu * args.coarse() as f64 / args.columns as f64 / args.threads as f64,
    ))?;
    let mut timings = Vec::new();
    for r in 0..args.repeats {
        let t = time_sweep(args, settings)?;
        say(&format!(
            "  sweep {}: coarse {:.3} s (CPU {}), full {:.3} s (CPU {}), {:.0} iterates/s{}",
            r + 1,
            t.coarse,
            t.cpu_coarse.map_or("?".into(), |c| format!("{c:.2} s")),
            t.full,
            t.cpu.map_or("?".into(), |c| format!("{c:.2} s")),
            t.iterates_per_second,
            if t.column_errors > 0 {
                format!(", {} column errors", t.column_errors)
            } else {
                String::new()
            }
        ))?;
        timings.push(t);
    }
    let coarse = median(&timings.iter().map(|t| t.coarse).collect::<Vec<_>>());
    let full = median(&timings.iter().map(|t| t.full).collect::<Vec<_>>());
    let lat = if args.latency_samples > 0 {
        trajectory_latencies(args, settings, Duration::from_secs_f64(0.8 * full))?
    } else {
        vec![]
    };
    say(&format!(
        "first full coarse diagram: median {coarse:.3} s (target 0.5 s)"
    ))?;
    say(&format!(
        "full diagram:              median {full:.3} s (target 5 s)"
    ))?;
    if !lat.is_empty() {
        let max = lat.iter().copied().fold(0.0, f64::max);
        say(&format!(
            "trajectory first chunk during the sweep: median {:.2} ms, max {:.2} ms over {} commands (target 50 ms)",
            1e3 * median(&lat),
            1e3 * max,
            lat.len()
        ))?;
    }
    Ok(())
}
