//! `oneblock bench-worker`: times the simulation worker as the GUI uses it,
//! at the paper's Fig. 3b parameters (γ = 6.5, κ = 18.95, ν = 1e-3, Ω = 50,
//! dop853): from a `Sweep` command to the first full coarse diagram and to
//! the full diagram, and from a `Trajectory` command sent mid-sweep to its
//! first chunk. With `--phase N`, instead: from a `Phase` command (N × N
//! cells over the paper's Fig. 4 range, the app's default budget) to the
//! full coarse lattice and to the full grid. Wall-clock figures of this
//! machine, so they live here and in the README, never in tests.

use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::Args;

use std::cell::RefCell;

use super::CliError;
use super::common::max_seconds;
use super::run_control::{Limits, check_stdout, run_bounded, write_stdout};
use super::values::{count_between, parse_count, parse_number, settings_error};
use crate::integrate::{Method, SolverSettings};
use crate::jobs::bench::{fig3b, fig3b_diagram};
use crate::sim::stats::median;
use crate::sim::{SweepOptions, sweep_columns, theta_nu_grid};
use crate::worker::{
    Axis, COARSE_STRIDE, Command, Lane, Outcome, PhaseSpec, PhaseTuning, TrajectorySpec, Update,
    Worker, WorkerConfig, phase_plan, sweep_plan,
};

#[derive(Debug, Clone, Args)]
pub struct BenchWorkerArgs {
    /// Columns of the full diagram over θν ∈ [0, π/2] (1 to 10000).
    #[arg(long, default_value_t = 400, value_parser = parse_count, allow_hyphen_values = true)]
    pub columns: usize,
    /// Columns of the first, coarse pass (1 to --columns).
    #[arg(long, default_value_t = 64, value_parser = parse_count, allow_hyphen_values = true)]
    pub coarse: usize,
    /// Transient iterates per column (0 to 1e5).
    #[arg(long, default_value_t = 300, value_parser = parse_count, allow_hyphen_values = true)]
    pub transient: usize,
    /// Kept iterates per column (1 to 10000).
    #[arg(long, default_value_t = 200, value_parser = parse_count, allow_hyphen_values = true)]
    pub keep: usize,
    /// Tolerance of dop853 (rtol = atol), in [1e-14, 1e-2].
    #[arg(long, default_value_t = 1e-8, allow_hyphen_values = true, value_parser = parse_number)]
    pub tol: f64,
    /// Sweep threads (1 to 64).
    #[arg(long, default_value_t = 2, value_parser = parse_count, allow_hyphen_values = true)]
    pub threads: usize,
    /// Timed sweeps, the median is reported (1 to 100).
    #[arg(long, default_value_t = 3, value_parser = parse_count, allow_hyphen_values = true)]
    pub repeats: usize,
    /// Trajectory commands sent during one more sweep (0 to 1000).
    #[arg(long, default_value_t = 9, value_parser = parse_count, allow_hyphen_values = true)]
    pub latency_samples: usize,
    /// Time an N × N phase diagram (θν ∈ [0, π/2], κ ∈ [1, 42], 400
    /// transient + 128 kept, as the app's default grid) instead of sweeps
    /// (N from 1 to 200).
    #[arg(long, value_parser = parse_count, allow_hyphen_values = true)]
    pub phase: Option<usize>,
    /// Time the diagram on the single-threaded host instead, one unit per
    /// step as the browser build runs it (the native side of web/test's
    /// browser-against-native ratio).
    #[arg(long, conflicts_with = "phase")]
    pub single_thread: bool,
    /// Run every kind of job once on the single-threaded host instead, in
    /// the page's 12 ms compute slices, at the window's defaults (Fig. 3b),
    /// and print per kind its pieces (steps) and the longest piece in ms.
    #[arg(long, conflicts_with_all = ["phase", "single_thread"])]
    pub pieces: bool,
    /// With --pieces: print {"kinds": [{"kind", "pieces", "longest_ms"}]}.
    #[arg(long, requires = "pieces")]
    pub json: bool,
    /// With --pieces: small jobs of every kind (a check in seconds; the
    /// continuation over θν ∈ [1, 1.2] to P4, the boundaries in
    /// [0.9, 1.3] × [17, 21]).
    #[arg(long, requires = "pieces")]
    pub quick: bool,
    /// Give up after this many seconds, in (0, 1e7], printing nothing;
    /// Ctrl+C also stops it.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub max_seconds: Option<f64>,
}

thread_local! {
    /// The report, gathered on the benchmark's thread and printed whole
    /// when it is done: a run stopped by Ctrl+C or --max-seconds prints
    /// nothing of it.
    static REPORT: RefCell<String> = const { RefCell::new(String::new()) };
}

/// One line of the report.
fn say(line: &str) -> Result<(), CliError> {
    REPORT.with(|r| {
        let mut r = r.borrow_mut();
        r.push_str(line);
        r.push('\n');
    });
    Ok(())
}

impl Default for BenchWorkerArgs {
    fn default() -> Self {
        BenchWorkerArgs {
            columns: 400,
            coarse: 64,
            transient: 300,
            keep: 200,
            tol: 1e-8,
            threads: 2,
            repeats: 3,
            latency_samples: 9,
            phase: None,
            single_thread: false,
            pieces: false,
            json: false,
            quick: false,
            max_seconds: None,
        }
    }
}

/// Longer than anything here should take: only a hung worker reaches it.
const HANG: Duration = Duration::from_secs(600);

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

fn worker(args: &BenchWorkerArgs) -> Worker {
    Worker::spawn(
        WorkerConfig {
            sweep_threads: args.threads,
            coarse_columns: args.coarse,
            ..WorkerConfig::default()
        },
        Arc::new(|| {}),
    )
}

fn sweep_command(args: &BenchWorkerArgs, settings: SolverSettings, generation: u64) -> Command {
    let mut spec = fig3b_diagram(args.columns, args.transient, args.keep, args.tol);
    spec.settings = settings;
    Command::run(generation, spec)
}

fn recv(w: &Worker) -> Result<Update, CliError> {
    w.recv_timeout(HANG)
        .ok_or_else(|| CliError::Failed("the worker went silent".into()))
}

/// One sweep from command to `Finished`, draining as the GUI would.
fn time_sweep(args: &BenchWorkerArgs, settings: SolverSettings) -> Result<SweepTiming, CliError> {
    let w = worker(args);
    let n_coarse = sweep_plan(args.columns, args.coarse, args.threads)
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

/// One N × N phase grid from command to `Finished`.
struct PhaseTiming {
    /// Seconds to the whole coarse lattice and to the whole grid.
    coarse: f64,
    full: f64,
    /// CPU seconds of the process meanwhile.
    cpu_coarse: Option<f64>,
    cpu: Option<f64>,
    iterates: u64,
    /// Cells per class label, in the order first seen.
    classes: Vec<(String, usize)>,
}

fn time_phase(
    args: &BenchWorkerArgs,
    settings: SolverSettings,
    n: usize,
) -> Result<PhaseTiming, CliError> {
    let w = worker(args);
    let n_coarse = phase_plan(n, n, COARSE_STRIDE)
        .iter()
        .filter(|p| p.coarse)
        .count();
    let t0 = Instant::now();
    let cpu0 = cpu_seconds();
    let sent = w.send(Command::run(
        1,
        PhaseSpec {
            params: fig3b(),
            settings,
            theta_nu: Axis::new(0.0, std::f64::consts::FRAC_PI_2, n),
            kappa: Axis::new(1.0, 42.0, n),
            transient: 400,
            keep: 128,
            tuning: PhaseTuning::default(),
        },
    ));
    if !sent {
        return Err(CliError::Failed("the worker refused the phase grid".into()));
    }
    let (mut seen, mut coarse, mut cpu_coarse, mut iterates) = (0, None, None, 0);
    let mut classes: Vec<(String, usize)> = Vec::new();
    let full = loop {
        match recv(&w)? {
            Update::PhaseCells {
                cells, coarse: c, ..
            } => {
                iterates += cells.iter().map(|c| c.cell.iterates).sum::<u64>();
                for c in &cells {
                    let l = c.cell.class.label();
                    match classes.iter_mut().find(|(k, _)| *k == l) {
                        Some((_, k)) => *k += 1,
                        None => classes.push((l, 1)),
                    }
                }
                if c {
                    seen += cells.len();
                    if seen == n_coarse {
                        coarse = Some(t0.elapsed().as_secs_f64());
                        cpu_coarse = cpu_seconds().zip(cpu0).map(|(b, a)| b - a);
                    }
                }
            }
            Update::Finished { outcome, .. } => {
                if let Outcome::Failed(m) = outcome {
                    return Err(CliError::Failed(format!("the phase grid failed: {m}")));
                }
                break t0.elapsed().as_secs_f64();
            }
            _ => {}
        }
    };
    let cpu = cpu_seconds().zip(cpu0).map(|(b, a)| b - a);
    w.shutdown();
    // FP, then P2, P3, … P10 in numeric order, then chaos and the rest.
    classes.sort_by_key(|(l, _)| class_order(l));
    Ok(PhaseTiming {
        coarse: coarse.unwrap_or(full),
        full,
        cpu_coarse,
        cpu,
        iterates,
        classes,
    })
}

/// Where a class label sorts: the fixed point, the periods by number,
/// then the other labels by name.
fn class_order(label: &str) -> (u8, usize, String) {
    match label {
        "FP" => (0, 1, String::new()),
        l => match l.strip_prefix('P').and_then(|n| n.parse().ok()) {
            Some(p) => (0, p, String::new()),
            None => (1, 0, l.to_string()),
        },
    }
}

fn run_phase(args: &BenchWorkerArgs, settings: SolverSettings, n: usize) -> Result<(), CliError> {
    say(&format!(
        "phase: {n} x {n} cells over theta-nu in [0, pi/2], kappa in [1, 42]; gamma = 6.5, nu = 1e-3, omega = 50; dop853 tol = {:e}; 400 transient + 128 kept; {} threads",
        args.tol, args.threads
    ))?;
    if let Some(l) = load_average() {
        say(&format!("load average before the run: {l:.2}"))?;
    }
    let mut runs = Vec::new();
    for r in 0..args.repeats {
        let t = time_phase(args, settings, n)?;
        let fmt = |c: Option<f64>| c.map_or("?".into(), |c| format!("{c:.2} s"));
        say(&format!(
            "  grid {}: coarse lattice {:.3} s (CPU {}), full {:.3} s (CPU {}), {} iterates; {}",
            r + 1,
            t.coarse,
            fmt(t.cpu_coarse),
            t.full,
            fmt(t.cpu),
            t.iterates,
            t.classes
                .iter()
                .map(|(l, k)| format!("{l} {k}"))
                .collect::<Vec<_>>()
                .join(", "),
        ))?;
        runs.push((t.coarse, t.full));
    }
    say(&format!(
        "phase grid: coarse lattice median {:.3} s, full grid median {:.3} s",
        median(&runs.iter().map(|r| r.0).collect::<Vec<_>>()),
        median(&runs.iter().map(|r| r.1).collect::<Vec<_>>()),
    ))?;
    Ok(())
}

/// CPU time (user + system) of this process so far, from /proc (Linux).
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name, which is in parentheses.
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let utime: f64 = f.get(11)?.parse().ok()?;
    let stime: f64 = f.get(12)?.parse().ok()?;
    // USER_HZ is 100 on every Linux configuration that matters here.
    Some((utime + stime) / 100.0)
}

/// The 1-minute load average (Linux), to tell a busy machine from a slow program.
fn load_average() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
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
    let coarse: Vec<f64> = sweep_plan(args.columns, args.coarse, 1)
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

/// Checks every count against its bound, and the tolerance, before any work.
pub fn check(args: &BenchWorkerArgs) -> Result<SolverSettings, CliError> {
    count_between("columns", args.columns, 1, 10_000)?;
    count_between("coarse", args.coarse, 1, args.columns)?;
    count_between("transient", args.transient, 0, 100_000)?;
    count_between("keep", args.keep, 1, 10_000)?;
    count_between("threads", args.threads, 1, 64)?;
    count_between("repeats", args.repeats, 1, 100)?;
    count_between("latency-samples", args.latency_samples, 0, 1000)?;
    if let Some(n) = args.phase {
        count_between("phase", n, 1, 200)?;
    }
    let settings = SolverSettings::adaptive(Method::Dop853, args.tol);
    settings.validate().map_err(settings_error)?;
    max_seconds(args.max_seconds)?;
    super::run_control::check_stdout()?;
    Ok(settings)
}

pub fn run(args: BenchWorkerArgs) -> Result<(), CliError> {
    let settings = check(&args)?;
    let limits = Limits::start(max_seconds(args.max_seconds)?);
    check_stdout()?;
    let (done, text) = run_bounded("bench-worker", &limits, move || {
        let done = match args.phase {
            Some(n) => run_phase(&args, settings, n),
            None if args.pieces => {
                super::bench_pieces::report(args.quick, args.json).and_then(|r| say(r.trim_end()))
            }
            None if args.single_thread => run_single_thread(&args),
            None => run_sweeps(&args, settings),
        };
        (done, REPORT.with(|r| r.take()))
    })?;
    done?;
    write_stdout(text.as_bytes())
}

/// The diagram timed on the single-threaded host (`--single-thread`).
fn run_single_thread(args: &BenchWorkerArgs) -> Result<(), CliError> {
    let report = crate::jobs::bench::single_thread_report(
        args.columns,
        args.transient,
        args.keep,
        args.tol,
        args.repeats,
    )
    .map_err(CliError::Failed)?;
    say(&report)
}

/// The sweep benchmark's report.
fn run_sweeps(args: &BenchWorkerArgs, settings: SolverSettings) -> Result<(), CliError> {
    say(&format!(
        "bench-worker: Fig. 3b (gamma = 6.5, kappa = 18.95, nu = 1e-3, omega = 50), dop853, tol = {:e}",
        args.tol
    ))?;
    say(&format!(
        "sweep: {} columns x ({} transient + {} kept) over theta-nu in [0, pi/2]; coarse pass {} columns; {} sweep threads; {} logical CPUs",
        args.columns,
        args.transient,
        args.keep,
        args.coarse.min(args.columns),
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
        total / per_cpu * args.coarse.min(args.columns) as f64 / args.columns as f64,
        args.threads,
        total / per_cpu / args.threads as f64,
        total / per_cpu * args.coarse.min(args.columns) as f64
            / args.columns as f64
            / args.threads as f64,
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

#[cfg(test)]
mod tests {
    use super::class_order;

    #[test]
    fn classes_sort_by_period_number_not_by_name() {
        let mut l = vec!["chaos", "P12", "P2", "FP", "P3", "creep?", "P10"];
        l.sort_by_key(|x| class_order(x));
        assert_eq!(l, ["FP", "P2", "P3", "P10", "P12", "chaos", "creep?"]);
    }
}
