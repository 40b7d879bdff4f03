//! The background simulation worker: all simulation the GUI needs runs here,
//! fed by a bounded crossbeam channel of [`Command`]s and answering on a
//! bounded channel of [`Update`]s. No GUI types: the front end passes a
//! wake-up callback (`ctx.request_repaint`), tests pass a counter.
//!
//! Threads (all named, all joined on shutdown or drop):
//! - `oneblock-worker`: the dispatcher. It reads commands, moves each lane's
//!   generation on (which cancels the running job within one slip cycle)
//!   and hands jobs to the lanes. It never simulates, so it always answers.
//! - `oneblock-orbit`: the orbit lane, one trajectory or map-iterate job at
//!   a time.
//! - `oneblock-sweep`: the sweep lane's coordinator, running each sweep on
//!   `sweep_threads` scoped threads `oneblock-sweep-<i>`.
//! - `oneblock-numerics`: the numerics lane, one work-precision job at a
//!   time (its own lane so that measuring never pauses a view's job).
//! - `oneblock-phase`: the phase lane's coordinator, running each phase
//!   diagram on `sweep_threads` scoped threads `oneblock-phase-<i>`.
//! - `oneblock-continuation`: the continuation lane, one `FindBifurcations`
//!   job at a time; `oneblock-curves`: the curves lane, one `Boundaries`
//!   job at a time (a curve's two directions on two threads).
//!
//! Ordering (module `gate`): every update of a lane is sent under that lane's
//! lock after re-checking its generation, and the generation only changes
//! under the same lock, so after a `Cancelled` (or a job's
//! `Finished{Cancelled}`) nothing of the older generation follows.

mod continuation;
mod gate;
mod numerics;
mod orbit;
mod phase;
mod plan;
pub mod priority;
mod protocol;
mod schedule;
mod sweep;

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Duration;

use crossbeam_channel::{Receiver, Sender, TrySendError};

pub use numerics::TIMING_REPEATS;
pub use phase::{COARSE_STRIDE, Seed, run_cell};
pub use plan::{PlannedCell, PlannedColumn, phase_plan, sweep_plan};
pub use protocol::{
    Axis, BoundarySpec, Command, ContinuationSpec, Generation, GridCell, IterateSpec, Lane,
    MAX_GRAPH_POWER, Outcome, PhaseSpec, SweepSpec, TrajectorySpec, Update, WorkPrecisionSpec,
};

use gate::Gate;

use crate::integrate::SolverSettings;
use crate::model::Params;

/// How the worker is set up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorkerConfig {
    /// Capacity of the update channel: a consumer that falls this far behind
    /// blocks the producers (default 256).
    pub update_capacity: usize,
    /// Threads a sweep, or a phase diagram, runs on (default 2, the
    /// machine's two cores).
    pub sweep_threads: usize,
    /// Columns in a sweep's first, coarse pass (default 64; a sweep with
    /// fewer columns is all coarse).
    pub coarse_columns: usize,
}

impl Default for WorkerConfig {
    fn default() -> Self {
        WorkerConfig {
            update_capacity: 256,
            sweep_threads: 2,
            coarse_columns: 64,
        }
    }
}

/// Capacity of the command channel: commands are small and the dispatcher
/// never simulates, so it only fills if the worker is wedged or gone.
const COMMAND_CAPACITY: usize = 64;

/// Counters for tests and the benchmark: machine-independent measures of
/// how much work ran, and how much ran after a stop.
#[derive(Debug, Default)]
pub struct WorkerStats {
    cycles: AtomicU64,
    /// The cycle count when the worker was first told to stop.
    cycles_at_stop: Mutex<Option<u64>>,
}

impl WorkerStats {
    /// Slip cycles started by all jobs so far (each job polls its
    /// cancellation flag once per cycle; this counts the polls that let a
    /// cycle start).
    pub fn cycles(&self) -> u64 {
        self.cycles.load(Ordering::SeqCst)
    }

    /// Cycles started after the worker was told to stop (shutdown or drop);
    /// `None` while it runs. At most one per job thread, as each job checks
    /// the stop before every cycle.
    pub fn cycles_after_stop(&self) -> Option<u64> {
        let at_stop = *self
            .cycles_at_stop
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        at_stop.map(|c| self.cycles().saturating_sub(c))
    }

    /// Records that a cycle may start for a job of generation `generation`
    /// on `gate`; true when the job must stop instead.
    pub(crate) fn poll(&self, gate: &Gate, generation: Generation) -> bool {
        if gate.is_stale(generation) {
            return true;
        }
        self.cycles.fetch_add(1, Ordering::SeqCst);
        false
    }

    /// Records the count at the first stop (a `Shutdown` and then the drop
    /// both stop the worker; the first one counts).
    fn mark_stopped(&self) {
        let mut at_stop = self
            .cycles_at_stop
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        at_stop.get_or_insert(self.cycles());
    }
}

/// What the dispatcher and the lanes share.
pub(crate) struct Shared {
    pub orbit: Gate,
    pub sweep: Gate,
    pub numerics: Gate,
    pub phase: Gate,
    pub continuation: Gate,
    pub curves: Gate,
    pub stats: Arc<WorkerStats>,
    pub config: WorkerConfig,
}

impl Shared {
    /// Stops every job for good.
    fn stop(&self) {
        self.orbit.stop();
        self.sweep.stop();
        self.numerics.stop();
        self.phase.stop();
        self.continuation.stop();
        self.curves.stop();
        self.stats.mark_stopped();
    }
}

/// The handle the front end holds. Dropping it stops and joins every thread.
pub struct Worker {
    commands: Option<Sender<Command>>,
    updates: Option<Receiver<Update>>,
    shared: Arc<Shared>,
    dispatcher: Option<JoinHandle<()>>,
}

impl Worker {
    /// Starts the worker's threads. `wake` is called after updates are sent
    /// (the GUI passes `ctx.request_repaint`).
    ///
    /// # Panics
    /// If the operating system refuses to start a thread.
    pub fn spawn(config: WorkerConfig, wake: Arc<dyn Fn() + Send + Sync>) -> Worker {
        let config = WorkerConfig {
            update_capacity: config.update_capacity.max(1),
            sweep_threads: config.sweep_threads.max(1),
            coarse_columns: config.coarse_columns.max(1),
        };
        let (cmd_tx, cmd_rx) = crossbeam_channel::bounded(COMMAND_CAPACITY);
        let (up_tx, up_rx) = crossbeam_channel::bounded(config.update_capacity);
        let shared = Arc::new(Shared {
            orbit: Gate::new(Lane::Orbit, up_tx.clone(), wake.clone()),
            sweep: Gate::new(Lane::Sweep, up_tx.clone(), wake.clone()),
            numerics: Gate::new(Lane::Numerics, up_tx.clone(), wake.clone()),
            phase: Gate::new(Lane::Phase, up_tx.clone(), wake.clone()),
            continuation: Gate::new(Lane::Continuation, up_tx.clone(), wake.clone()),
            curves: Gate::new(Lane::Curves, up_tx, wake),
            stats: Arc::new(WorkerStats::default()),
            config,
        });
        let sh = shared.clone();
        let dispatcher = std::thread::Builder::new()
            .name("oneblock-worker".into())
            .spawn(move || dispatch(sh, cmd_rx))
            .expect("cannot start the worker thread");
        Worker {
            commands: Some(cmd_tx),
            updates: Some(up_rx),
            shared,
            dispatcher: Some(dispatcher),
        }
    }

    /// Queues a command without blocking: false if the queue is full or the
    /// worker is gone.
    pub fn send(&self, cmd: Command) -> bool {
        match &self.commands {
            Some(tx) => match tx.try_send(cmd) {
                Ok(()) => true,
                Err(TrySendError::Full(_) | TrySendError::Disconnected(_)) => false,
            },
            None => false,
        }
    }

    /// The next update, if one is queued (never blocks).
    pub fn try_recv(&self) -> Option<Update> {
        self.updates.as_ref()?.try_recv().ok()
    }

    /// The next update, waiting at most `d` (for tests and the benchmark).
    pub fn recv_timeout(&self, d: Duration) -> Option<Update> {
        self.updates.as_ref()?.recv_timeout(d).ok()
    }

    /// Updates currently queued.
    pub fn queued(&self) -> usize {
        self.updates.as_ref().map_or(0, |r| r.len())
    }

    /// The work counters (they outlive the worker).
    pub fn stats(&self) -> Arc<WorkerStats> {
        self.shared.stats.clone()
    }

    /// Sends `Shutdown` and joins every thread.
    pub fn shutdown(mut self) {
        self.stop_and_join();
    }

    fn stop_and_join(&mut self) {
        let Some(handle) = self.dispatcher.take() else {
            return;
        };
        // Jobs see the stop at their next cycle; the update receiver goes
        // first so that any thread blocked on a full channel fails at once.
        self.shared.stop();
        drop(self.updates.take());
        if let Some(tx) = self.commands.take() {
            tx.try_send(Command::Shutdown).ok();
        }
        handle.join().ok();
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        self.stop_and_join();
    }
}

/// The dispatcher loop: runs until `Shutdown` or until the handle is gone.
// Over clippy.toml's 150 lines until issue 27 splits it (listed in
// tests/function_lengths.rs).
#[allow(clippy::too_many_lines)]
fn dispatch(shared: Arc<Shared>, commands: Receiver<Command>) {
    let (orbit_tx, orbit_rx) = crossbeam_channel::unbounded::<Command>();
    let (sweep_tx, sweep_rx) = crossbeam_channel::unbounded::<Command>();
    let sh = shared.clone();
    let orbit_thread = std::thread::Builder::new()
        .name("oneblock-orbit".into())
        .spawn(move || {
            priority::lower_current_thread();
            lane_loop(orbit_rx, |job| orbit::run(&sh, job))
        });
    let sh = shared.clone();
    let sweep_thread = std::thread::Builder::new()
        .name("oneblock-sweep".into())
        .spawn(move || {
            priority::lower_current_thread();
            lane_loop(sweep_rx, |job| sweep::run(&sh, job))
        });
    let (numerics_tx, numerics_rx) = crossbeam_channel::unbounded::<Command>();
    let sh = shared.clone();
    let numerics_thread = std::thread::Builder::new()
        .name("oneblock-numerics".into())
        .spawn(move || {
            priority::lower_current_thread();
            lane_loop(numerics_rx, |job| numerics::run(&sh, job))
        });
    let (phase_tx, phase_rx) = crossbeam_channel::unbounded::<Command>();
    let sh = shared.clone();
    let phase_thread = std::thread::Builder::new()
        .name("oneblock-phase".into())
        .spawn(move || {
            priority::lower_current_thread();
            lane_loop(phase_rx, |job| phase::run(&sh, job))
        });
    let (continuation_tx, continuation_rx) = crossbeam_channel::unbounded::<Command>();
    let sh = shared.clone();
    let continuation_thread = std::thread::Builder::new()
        .name("oneblock-continuation".into())
        .spawn(move || {
            priority::lower_current_thread();
            lane_loop(continuation_rx, |job| continuation::run(&sh, job))
        });
    let (curves_tx, curves_rx) = crossbeam_channel::unbounded::<Command>();
    let sh = shared.clone();
    let curves_thread = std::thread::Builder::new()
        .name("oneblock-curves".into())
        .spawn(move || {
            priority::lower_current_thread();
            lane_loop(curves_rx, |job| continuation::run(&sh, job))
        });

    // Each lane's latest job, for SetParams to run again (a continuation
    // or curves job is not: it is asked for, and a change cancels it).
    let mut last_orbit: Option<Command> = None;
    let mut last_sweep: Option<Command> = None;
    // Cleared by a cancellation: a grid the user stopped is not restarted.
    let mut last_phase: Option<Command> = None;
    while let Ok(cmd) = commands.recv() {
        match cmd {
            Command::Shutdown => break,
            Command::SetParams {
                generation,
                params,
                settings,
            } => {
                if let Some(job) = last_orbit
                    .as_ref()
                    .and_then(|c| with_params(c, generation, params, settings))
                    && shared.orbit.start(generation)
                {
                    last_orbit = Some(job.clone());
                    orbit_tx.send(job).ok();
                }
                if let Some(job) = last_sweep
                    .as_ref()
                    .and_then(|c| with_params(c, generation, params, settings))
                    && shared.sweep.start(generation)
                {
                    last_sweep = Some(job.clone());
                    sweep_tx.send(job).ok();
                }
                // A branch or curve of the old parameters is stale: stop it
                // (it is not run again: it was asked for).
                for g in [&shared.continuation, &shared.curves] {
                    if g.is_running() {
                        gate::cancel(&[g], generation, Some(g.lane));
                    }
                }
                // The grid's axes are κ and θν: only γ, ν, Ω or the solver
                // change it.
                if let Some(job) = last_phase
                    .as_ref()
                    .filter(|c| phase_depends_on_changed(c, params, settings))
                    .and_then(|c| with_params(c, generation, params, settings))
                    && shared.phase.start(generation)
                {
                    last_phase = Some(job.clone());
                    phase_tx.send(job).ok();
                }
            }
            Command::Cancel { generation, lane } => {
                let gates: Vec<&Gate> = match lane {
                    Some(Lane::Orbit) => vec![&shared.orbit],
                    Some(Lane::Sweep) => vec![&shared.sweep],
                    Some(Lane::Numerics) => vec![&shared.numerics],
                    Some(Lane::Continuation) => vec![&shared.continuation],
                    Some(Lane::Curves) => vec![&shared.curves],
                    None => vec![
                        &shared.orbit,
                        &shared.sweep,
                        &shared.numerics,
                        &shared.phase,
                        &shared.continuation,
                        &shared.curves,
                    ],
                    Some(Lane::Phase) => vec![&shared.phase],
                };
                if lane.is_none_or(|l| l == Lane::Phase) {
                    last_phase = None;
                }
                gate::cancel(&gates, generation, lane);
            }
            Command::Sweep { generation, .. } => {
                if shared.sweep.start(generation) {
                    last_sweep = Some(cmd.clone());
                    sweep_tx.send(cmd).ok();
                }
            }
            Command::WorkPrecision { generation, .. } => {
                if shared.numerics.start(generation) {
                    numerics_tx.send(cmd).ok();
                }
            }
            Command::FindBifurcations { generation, .. } => {
                if shared.continuation.start(generation) {
                    continuation_tx.send(cmd).ok();
                }
            }
            Command::Boundaries { generation, .. } => {
                if shared.curves.start(generation) {
                    curves_tx.send(cmd).ok();
                }
            }
            Command::Phase { generation, .. } => {
                if shared.phase.start(generation) {
                    last_phase = Some(cmd.clone());
                    phase_tx.send(cmd).ok();
                }
            }
            Command::Trajectory { generation, .. }
            | Command::Iterate { generation, .. }
            | Command::InjectPanic { generation, .. } => {
                if shared.orbit.start(generation) {
                    if !matches!(cmd, Command::InjectPanic { .. }) {
                        last_orbit = Some(cmd.clone());
                    }
                    orbit_tx.send(cmd).ok();
                }
            }
        }
    }
    shared.stop();
    drop(orbit_tx);
    drop(sweep_tx);
    drop(numerics_tx);
    drop(phase_tx);
    drop(continuation_tx);
    drop(curves_tx);
    for t in [
        orbit_thread,
        sweep_thread,
        numerics_thread,
        phase_thread,
        continuation_thread,
        curves_thread,
    ]
    .into_iter()
    .flatten()
    {
        t.join().ok();
    }
}

/// `job` again under `generation` with new parameters, and new solver
/// settings if given (None for commands that are not jobs).
fn with_params(
    job: &Command,
    generation: Generation,
    params: Params,
    settings: Option<SolverSettings>,
) -> Option<Command> {
    let mut job = job.clone();
    let (g, p, s) = match &mut job {
        Command::Trajectory { generation, spec } => {
            (generation, &mut spec.params, &mut spec.settings)
        }
        Command::Iterate { generation, spec } => (generation, &mut spec.params, &mut spec.settings),
        Command::Sweep { generation, spec } => (generation, &mut spec.params, &mut spec.settings),
        Command::Phase { generation, spec } => (generation, &mut spec.params, &mut spec.settings),
        _ => return None,
    };
    (*g, *p) = (generation, params);
    if let Some(settings) = settings {
        *s = settings;
    }
    Some(job)
}

/// Whether a phase job would compute something else with `params` and
/// `settings`: its κ and θν are the grid's axes, so only γ, ν, Ω and the
/// solver count (`settings: None` keeps the job's own solver).
fn phase_depends_on_changed(
    job: &Command,
    params: Params,
    settings: Option<SolverSettings>,
) -> bool {
    match job {
        Command::Phase { spec, .. } => {
            let p = &spec.params;
            (p.gamma, p.nu, p.omega) != (params.gamma, params.nu, params.omega)
                || settings.is_some_and(|n| n != spec.settings)
        }
        _ => false,
    }
}

/// A lane thread: runs the newest queued job, skipping any a newer one has
/// already superseded (the dispatcher finished those as cancelled).
fn lane_loop(jobs: Receiver<Command>, mut run: impl FnMut(Command)) {
    while let Ok(mut job) = jobs.recv() {
        while let Ok(newer) = jobs.try_recv() {
            job = newer;
        }
        run(job);
    }
}

/// Runs `worker` on `threads` scoped threads named `{name}-{i}` and joins
/// them all: the sweep and phase lanes' pools. A thread that cannot start
/// is an error; the first error of any thread is returned (a panic inside
/// `worker` itself is resumed: the jobs catch their own per item).
pub(crate) fn run_scoped<F>(name: &str, threads: usize, worker: &F) -> Result<(), orbit::JobError>
where
    F: Fn() -> Result<(), orbit::JobError> + Sync,
{
    let results: Vec<Result<(), orbit::JobError>> = std::thread::scope(|scope| {
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
                Err(e) => Err(orbit::JobError::Failed(format!(
                    "cannot start a {name} thread: {e}"
                ))),
            })
            .collect()
    });
    results.into_iter().collect()
}

/// A mutex's guard even if a panicking holder poisoned it: the pools'
/// shared state stays consistent (each item is caught and reported).
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
