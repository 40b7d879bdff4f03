//! `oneblock bench-worker`: times the simulation worker as the GUI uses it,
//! at the paper's Fig. 3b parameters (γ = 6.5, κ = 18.95, ν = 1e-3, Ω = 50,
//! dop853): from a `Sweep` command to the first full coarse diagram and to
//! the full diagram, and from a `Trajectory` command sent mid-sweep to its
//! first chunk. With `--phase N`, instead: from a `Phase` command (N × N
//! cells over the paper's Fig. 4 range, the app's default budget) to the
//! full coarse lattice and to the full grid. Wall-clock figures of this
//! machine, so they live here and in the README, never in tests.
//!
//! One file per idea: this one the flags, their checks and the report;
//! `sweep` the diagram through the worker (and a trajectory sent during
//! it); `phase` a phase grid through the worker; `machine` what the
//! machine was doing meanwhile (load, CPU time); `pieces` every kind of
//! job in the page's slices (`--pieces`). What they time without the
//! worker (the single-threaded host) is the bench room's,
//! [`crate::bench`].

use std::sync::Arc;
use std::time::Duration;

use clap::Args;

use std::cell::RefCell;

use super::CliError;
use super::common::max_seconds;
use super::run_control::{Limits, check_stdout, run_bounded, write_stdout};
use super::values::{count_between, parse_count, parse_number, settings_error};
use crate::integrate::{Method, SolverSettings};
use crate::worker::{Update, Worker, WorkerConfig};

mod machine;
mod phase;
mod pieces;
mod sweep;

#[derive(Debug, Clone, Args)]
pub struct BenchWorkerArgs {
    /// Columns of the full diagram over θν ∈ [0, π/2] (1 to 10000).
    #[arg(long, default_value_t = 400, value_parser = parse_count, allow_hyphen_values = true)]
    pub columns: usize,
    /// Columns of the first, coarse pass (1 to --columns) [default: 64, or
    /// --columns if fewer].
    #[arg(long, value_parser = parse_count, allow_hyphen_values = true)]
    pub coarse: Option<usize>,
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
            coarse: None,
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

impl BenchWorkerArgs {
    /// The coarse pass's columns: as given, else 64 or --columns if fewer.
    pub fn coarse(&self) -> usize {
        self.coarse.unwrap_or(64.min(self.columns))
    }
}

/// Longer than anything here should take: only a hung worker reaches it.
const HANG: Duration = Duration::from_secs(600);

fn worker(args: &BenchWorkerArgs) -> Worker {
    Worker::spawn(
        WorkerConfig {
            sweep_threads: args.threads,
            coarse_columns: args.coarse(),
            ..WorkerConfig::default()
        },
        Arc::new(|| {}),
    )
}

fn recv(w: &Worker) -> Result<Update, CliError> {
    w.recv_timeout(HANG)
        .ok_or_else(|| CliError::Failed("the worker went silent".into()))
}

/// Checks every count against its bound, and the tolerance, before any work.
pub fn check(args: &BenchWorkerArgs) -> Result<SolverSettings, CliError> {
    count_between("columns", args.columns, 1, 10_000)?;
    count_between("coarse", args.coarse(), 1, args.columns)?;
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
    check_stdout()?;
    Ok(settings)
}

pub fn run(args: BenchWorkerArgs) -> Result<(), CliError> {
    let settings = check(&args)?;
    let limits = Limits::start(max_seconds(args.max_seconds)?);
    check_stdout()?;
    let (done, text) = run_bounded("bench-worker", &limits, move || {
        let done = match args.phase {
            Some(n) => phase::run_phase(&args, settings, n),
            None if args.pieces => {
                pieces::report(args.quick, args.json).and_then(|r| say(r.trim_end()))
            }
            None if args.single_thread => run_single_thread(&args),
            None => sweep::run_sweeps(&args, settings),
        };
        (done, REPORT.with(|r| r.take()))
    })?;
    done?;
    write_stdout(text.as_bytes())
}

/// The diagram timed on the single-threaded host (`--single-thread`).
fn run_single_thread(args: &BenchWorkerArgs) -> Result<(), CliError> {
    let report = crate::bench::diagram::single_thread_report(
        args.columns,
        args.transient,
        args.keep,
        args.tol,
        args.repeats,
    )
    .map_err(CliError::Failed)?;
    say(&report)
}
