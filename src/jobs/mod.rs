//! The job model: every long computation of the explorer and the command
//! line (a trajectory, map iterates, a bifurcation diagram, a phase grid,
//! continuation, boundary curves, a work-precision measurement) is defined
//! once here, as a [`Job`] built from its typed [`Spec`], and run by any of
//! three hosts:
//!
//! - the worker ([`crate::worker`]): one generic lane runner, threads and
//!   generations, for the window;
//! - [`run_threads`]: a job to its end on this thread and, for a
//!   [`Job::parallel`] one, helper threads (the command line);
//! - [`Local`]: one thread, units within a time budget per call (a browser
//!   build without threads, and deterministic tests).
//!
//! A job does its work in units ([`Job::step`]) and sends typed [`Update`]s
//! to a [`Sink`]: its partial results as they come, `Progress`, and
//! `Summary` lines. How it ended (`Finished`, with an `Error` before it if it
//! failed) is the host's to send, from the step's result ([`ending`]). A
//! job polls [`Sink::cycle`] before every slip cycle, so a host stops it
//! within one cycle.
//!
//! The plans of the progressive jobs (which unit continues from which)
//! are fixed by the spec and [`Shape`] before any work starts, so every
//! host computes the same numbers, bit for bit, whatever its threads.

pub mod basins;
mod continuation;
mod depends;
mod events;
mod iterate;
mod kinds;
mod local;
mod numerics;
mod orbit;
mod paced;
mod phase;
pub mod plan;
pub mod priority;
mod protocol;
mod schedule;
mod specs;
mod sweep;

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

pub use depends::{Bound, Depends, ParamsKey};
pub use kinds::*;
pub use local::{Local, TimeSlice};
pub use numerics::TIMING_REPEATS;
pub use orbit::{CHUNK_SAMPLES, GRAPH_POINTS, MIN_SPACING};
pub use phase::{COARSE_STRIDE, MAX_CELLS, MAX_STEPS};
pub use plan::{
    PHASE_BLOCK, PlannedCell, PlannedColumn, block_plan, phase_blocks, phase_plan, shard_blocks,
    sweep_plan,
};
pub use protocol::BasinColumn;
pub use protocol::{
    Axis, CascadeFrom, CurveFollow, Generation, GivenCycle, GridCell, IterateOptions,
    ListedAttractor, MAX_GRAPH_POWER, MAX_LISTED, Outcome, PhaseTuning, Timing, Update,
};

use crate::sim::{LANES, SimError};

/// Why a job's update was not taken: its generation is no longer current,
/// or nobody listens any more. Either way the job must stop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    Stale,
    Gone,
}

/// Why a job ended before its end.
#[derive(Debug)]
pub enum JobError {
    /// Cancelled, superseded or nobody listens: end without a word.
    Stop,
    /// The simulation refused or failed: the host reports it.
    Sim(SimError),
    /// Failed; any `Error` update was already sent.
    Failed(String),
}

impl From<Stop> for JobError {
    fn from(_: Stop) -> Self {
        JobError::Stop
    }
}

impl From<SimError> for JobError {
    fn from(e: SimError) -> Self {
        JobError::Sim(e)
    }
}

/// Where a job's updates go, and how it learns that it must stop.
pub trait Sink: Sync {
    /// The generation the job runs under (every update names it).
    fn generation(&self) -> Generation;
    /// The lane the host runs the job on (every update that names a lane
    /// names this one: the host's, not the job's, to say).
    fn lane(&self) -> Lane;
    /// Takes one update; `Err` when the job must stop.
    fn send(&self, update: Update) -> Result<(), Stop>;
    /// Whether the job must stop (cheap; polled while waiting).
    fn stale(&self) -> bool;
    /// Polled before every slip cycle: true when the job must stop instead.
    /// Hosts count these polls (machine-independent work counters).
    fn cycle(&self) -> bool {
        self.stale()
    }
    /// Whether the host wants its thread back now: a job whose unit can
    /// stop part-way (a sweep's column) parks it, returns `Working`, and
    /// resumes it on the next step, with the same result bit for bit. Only
    /// the single-threaded host says yes, at its step's deadline, so that a
    /// page's frame is not held by one long unit.
    fn pause(&self) -> bool {
        false
    }
    /// Whether a heavy piece of a unit (a cycle solve, an interpolant:
    /// milliseconds in one go) should wait for the next step, because much
    /// of this step's time is gone. Like [`Sink::pause`], only the
    /// single-threaded host says yes.
    fn defer_heavy(&self) -> bool {
        false
    }

    /// Whether the host runs the job a slice of time at a time (the
    /// page's single-threaded host, and the pieces bench that measures
    /// it): work that cannot stop part-way for a frame (the Basins
    /// events' location) is left out there, and the view says so.
    fn sliced(&self) -> bool {
        false
    }
}

/// Where a job stands after a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// More units are to come.
    Working,
    /// No unit is left for this caller (others may still be running theirs).
    Done,
}

/// One computation, run unit by unit by whichever host holds it.
pub trait Job: Send + Sync {
    /// Whether several threads may step it at once: its units are
    /// independent once their parents are done.
    fn parallel(&self) -> bool {
        false
    }
    /// Runs units (at most `width` of them where the job can count them;
    /// `usize::MAX`: as many as are ready), sending their results to `sink`.
    fn step(&self, width: usize, sink: &dyn Sink) -> Result<Status, JobError>;
    /// Called once after every caller's steps returned `Done`: how the job
    /// as a whole ended (a unit that failed on its own may fail it).
    fn finish(&self, _sink: &dyn Sink) -> Result<(), JobError> {
        Ok(())
    }
}

/// The shape of a progressive job's plan: how many columns the sweep's
/// coarse pass has, and in how many chains it runs. Part of what a diagram
/// is, so a host with other threads computes the same one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shape {
    /// Columns in a sweep's first, coarse pass (a sweep with fewer columns
    /// is all coarse).
    pub coarse_columns: usize,
    /// Chains the coarse pass is split into, each continued along θν from
    /// its first column (which starts at θ = θν).
    pub chains: usize,
}

impl Default for Shape {
    /// 64 coarse columns in 2 × [`LANES`] chains: two threads of that
    /// many slip lanes each.
    fn default() -> Self {
        Shape {
            coarse_columns: 64,
            chains: 2 * LANES,
        }
    }
}

/// An error to report: its message and the parameter it names, if any.
pub type Report = (String, Option<&'static str>);

/// How a job that returned `result` (or panicked) ended: the `Error` to send
/// first, if any, and the outcome for `Finished`. `None`: it was stopped,
/// and sends nothing more.
pub fn ending(
    result: std::thread::Result<Result<(), JobError>>,
) -> Option<(Option<Report>, Outcome)> {
    match result {
        Ok(Ok(())) => Some((None, Outcome::Completed)),
        Ok(Err(JobError::Stop | JobError::Sim(SimError::Cancelled))) => None,
        Ok(Err(JobError::Sim(e))) => {
            let msg = e.to_string();
            Some((Some((msg.clone(), e.parameter())), Outcome::Failed(msg)))
        }
        Ok(Err(JobError::Failed(msg))) => Some((None, Outcome::Failed(msg))),
        Err(payload) => {
            let msg = format!("the job panicked: {}", panic_message(&*payload));
            Some((Some((msg.clone(), None)), Outcome::Failed(msg)))
        }
    }
}

/// Runs `job` to its end with the caller's thread and, for a parallel job,
/// `threads − 1` more (named `{name}-{i}`), then its [`Job::finish`]. Panics
/// are the caller's to catch ([`ending`]).
pub fn run_threads(
    job: &dyn Job,
    threads: usize,
    name: &str,
    sink: &dyn Sink,
) -> Result<(), JobError> {
    let drive = || -> Result<(), JobError> {
        while job.step(usize::MAX, sink)? == Status::Working {}
        Ok(())
    };
    if job.parallel() && threads > 1 {
        run_scoped(name, threads, &drive)?;
    } else {
        drive()?;
    }
    job.finish(sink)
}

/// Runs `worker` on `threads` scoped threads named `{name}-{i}` and joins
/// them all. A thread that cannot start is an error; the first error of any
/// thread is returned (a panic inside `worker` is resumed: jobs catch their
/// own per unit).
fn run_scoped<F>(name: &str, threads: usize, worker: &F) -> Result<(), JobError>
where
    F: Fn() -> Result<(), JobError> + Sync,
{
    let results: Vec<Result<(), JobError>> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..threads.max(1))
            .map(|i| {
                std::thread::Builder::new()
                    .name(format!("{name}-{i}"))
                    .spawn_scoped(scope, || {
                        priority::lower_current_thread();
                        worker()
                    })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| match h {
                Ok(h) => h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)),
                Err(e) => Err(JobError::Failed(format!(
                    "cannot start a {name} thread: {e}"
                ))),
            })
            .collect()
    });
    results.into_iter().collect()
}

/// A sink that keeps every update and never goes stale until told: for the
/// command line's hosts and tests. `on_update` sees each update as it comes.
pub struct Collect<F: Fn(&Update) + Sync, S: Fn() -> bool + Sync> {
    /// The lane of the job's kind (the updates name it).
    lane: Lane,
    updates: std::sync::Mutex<Vec<Update>>,
    stopped: AtomicBool,
    /// Whether updates sent after the stop are still taken.
    keep_after_stop: bool,
    /// Which updates are kept once `on_update` has seen them.
    keep: fn(&Update) -> bool,
    cycles: AtomicU64,
    on_update: F,
    stop_when: S,
}

impl<F: Fn(&Update) + Sync, S: Fn() -> bool + Sync> Collect<F, S> {
    /// A sink for a job on `lane` that calls `on_update` for each update
    /// and stops the job once `stop_when` says so (called once before
    /// every slip cycle, so it may count them).
    pub fn new(lane: Lane, on_update: F, stop_when: S) -> Self {
        Collect {
            lane,
            updates: std::sync::Mutex::new(Vec::new()),
            stopped: AtomicBool::new(false),
            keep_after_stop: false,
            keep: |_| true,
            cycles: AtomicU64::new(0),
            on_update,
            stop_when,
        }
    }

    /// [`Collect::new`], but a job stopped by `stop_when` may still send
    /// what it has (a continuation ends its branch where it stopped).
    pub fn keeping(lane: Lane, on_update: F, stop_when: S) -> Self {
        Collect {
            keep_after_stop: true,
            ..Self::new(lane, on_update, stop_when)
        }
    }

    /// Every update so far, in order.
    pub fn into_updates(self) -> Vec<Update> {
        self.updates.into_inner().unwrap_or_else(|e| e.into_inner())
    }

    /// Slip cycles the job started.
    pub fn cycles(&self) -> u64 {
        self.cycles.load(Ordering::Relaxed)
    }

    /// Whether the job was stopped by `stop_when`.
    pub fn stopped(&self) -> bool {
        self.stopped.load(Ordering::Relaxed)
    }
}

impl<F: Fn(&Update) + Sync, S: Fn() -> bool + Sync> Sink for Collect<F, S> {
    fn generation(&self) -> Generation {
        0
    }

    fn lane(&self) -> Lane {
        self.lane
    }

    fn send(&self, update: Update) -> Result<(), Stop> {
        if self.stale() && !self.keep_after_stop {
            return Err(Stop::Stale);
        }
        (self.on_update)(&update);
        if (self.keep)(&update) {
            lock(&self.updates).push(update);
        }
        Ok(())
    }

    fn stale(&self) -> bool {
        self.stopped.load(Ordering::Relaxed)
    }

    fn cycle(&self) -> bool {
        if self.stale() {
            return true;
        }
        if (self.stop_when)() {
            self.stopped.store(true, Ordering::Relaxed);
            return true;
        }
        self.cycles.fetch_add(1, Ordering::Relaxed);
        false
    }
}

/// Runs a job from `spec` to its end on `threads` threads (the command
/// line's host), collecting its updates: `Ok` with them when it completed,
/// the job's error otherwise (`JobError::Stop` when `stop_when` stopped it).
pub fn run_collect(
    spec: Spec,
    threads: usize,
    on_update: impl Fn(&Update) + Sync,
    stop_when: impl Fn() -> bool + Sync,
) -> Result<Vec<Update>, JobError> {
    let sink = Collect::new(spec.lane(), on_update, stop_when);
    run_on(spec, threads, &sink)?;
    Ok(sink.into_updates())
}

/// [`run_collect`] keeping only the updates `keep` says yes to: the rest
/// are seen by `on_update` alone (a trajectory's samples, written as they
/// come, are not held twice).
pub fn run_collect_some(
    spec: Spec,
    threads: usize,
    on_update: impl Fn(&Update) + Sync,
    stop_when: impl Fn() -> bool + Sync,
    keep: fn(&Update) -> bool,
) -> Result<Vec<Update>, JobError> {
    let sink = Collect {
        keep,
        ..Collect::new(spec.lane(), on_update, stop_when)
    };
    run_on(spec, threads, &sink)?;
    Ok(sink.into_updates())
}

/// [`run_collect`] for a job that ends with what it has when stopped (a
/// continuation): every update it sent, the ones after `stop_when` stopped
/// it included, and how it ended (`JobError::Stop` when it was stopped).
pub fn run_kept(
    spec: Spec,
    threads: usize,
    on_update: impl Fn(&Update) + Sync,
    stop_when: impl Fn() -> bool + Sync,
) -> (Vec<Update>, Result<(), JobError>) {
    let sink = Collect::keeping(spec.lane(), on_update, stop_when);
    let ended = run_on(spec, threads, &sink);
    (sink.into_updates(), ended)
}

/// Runs a job from `spec` to its end into `sink`: `Err(JobError::Stop)`
/// when the sink's `stop_when` stopped it.
fn run_on<F, S>(spec: Spec, threads: usize, sink: &Collect<F, S>) -> Result<(), JobError>
where
    F: Fn(&Update) + Sync,
    S: Fn() -> bool + Sync,
{
    let name = format!("oneblock-{}", spec.lane().name());
    let job = spec.start(Shape::default())?;
    let result = catch_unwind(AssertUnwindSafe(|| {
        run_threads(job.as_ref(), threads, &name, sink)
    }));
    match result {
        Ok(Ok(())) if !sink.stopped() => Ok(()),
        Ok(Ok(())) | Ok(Err(JobError::Stop)) => Err(JobError::Stop),
        Ok(Err(JobError::Sim(SimError::Cancelled))) => Err(JobError::Stop),
        Ok(Err(e)) => Err(e),
        Err(payload) => Err(JobError::Failed(format!(
            "the job panicked: {}",
            panic_message(&*payload)
        ))),
    }
}

/// A mutex's guard even if a panicking holder poisoned it: the jobs' shared
/// state stays consistent (each unit is caught and reported).
pub(crate) fn lock<T>(m: &std::sync::Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// The text of a caught panic's payload.
pub(crate) fn panic_message(p: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic payload".to_string()
    }
}
