//! The background simulation worker: the window's host for the jobs of
//! [`crate::jobs`], fed by a bounded crossbeam channel of [`Command`]s and
//! answering on a bounded channel of [`Update`]s. No GUI types: the front
//! end passes a wake-up callback (`ctx.request_repaint`), tests pass a
//! counter.
//!
//! Threads (all named, all joined on shutdown or drop), all started in
//! [`Worker::spawn`]:
//! - `oneblock-worker`: the dispatcher. It reads commands, moves each lane's
//!   generation on (which cancels the running job within one slip cycle)
//!   and hands jobs to the lanes. It never simulates, so it always answers.
//! - `oneblock-<lane>`, one per [`Lane`]: runs its lane's newest job to its
//!   end, one at a time; a parallel job (a sweep, a phase grid) runs on
//!   `sweep_threads` scoped threads `oneblock-<lane>-<i>`. Which job goes on
//!   which lane, and what new parameters do to it, is the job's own
//!   definition ([`Spec::lane`], [`Spec::on_params`]): the worker has no
//!   code for any lane in particular.
//!
//! Ordering (module `gate`): every update of a lane is sent under that lane's
//! lock after re-checking its generation, and the generation only changes
//! under the same lock, so after a `Cancelled` (or a job's
//! `Finished{Cancelled}`) nothing of the older generation follows.

mod command;
mod gate;
mod local;
mod orders;

pub use crate::jobs::priority;

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Duration;

use crossbeam_channel::{Receiver, Sender, TrySendError};

pub use crate::jobs::{
    Axis, BoundarySpec, COARSE_STRIDE, CascadeFrom, ContinuationSpec, CurveFollow, Generation,
    GivenCycle, GridCell, IterateOptions, IterateSpec, Lane, ListedAttractor, MAX_GRAPH_POWER,
    MAX_LISTED, Outcome, PhaseSpec, PhaseTuning, PlannedCell, PlannedColumn, Spec, SweepSpec,
    TIMING_REPEATS, Timing, TrajectorySpec, Update, WorkPrecisionSpec, phase_plan, sweep_plan,
};
pub use command::Command;
pub use local::LocalWorker;

use gate::Gate;

use crate::jobs::{Job, Shape, Sink, Stop, ending, run_threads};
use orders::{Latest, Order};

/// How the worker is set up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorkerConfig {
    /// Capacity of the update channel: a consumer that falls this far behind
    /// blocks the producers (default 256).
    pub update_capacity: usize,
    /// Threads a sweep, or a phase diagram, runs on (default 2, the
    /// machine's two cores).
    pub sweep_threads: usize,
    /// Columns in a sweep's first, coarse pass (default 64, as
    /// [`Shape::default`]; a sweep with fewer columns is all coarse).
    pub coarse_columns: usize,
}

impl Default for WorkerConfig {
    fn default() -> Self {
        WorkerConfig {
            update_capacity: 256,
            sweep_threads: 2,
            coarse_columns: Shape::default().coarse_columns,
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
    /// One gate per lane, in the order of [`Lane::ALL`].
    gates: Vec<Gate>,
    pub stats: Arc<WorkerStats>,
    pub config: WorkerConfig,
}

impl Shared {
    fn gate(&self, lane: Lane) -> &Gate {
        &self.gates[lane.index()]
    }

    /// Stops every job for good.
    fn stop(&self) {
        for g in &self.gates {
            g.stop();
        }
        self.stats.mark_stopped();
    }

    /// The plan shape every progressive job of this worker has.
    fn shape(&self) -> Shape {
        Shape {
            coarse_columns: self.config.coarse_columns,
            ..Shape::default()
        }
    }
}

/// A job's sink in the worker: its lane's gate under its generation.
struct GateSink<'a> {
    gate: &'a Gate,
    generation: Generation,
    stats: &'a WorkerStats,
}

impl Sink for GateSink<'_> {
    fn generation(&self) -> Generation {
        self.generation
    }

    fn lane(&self) -> Lane {
        self.gate.lane
    }

    fn send(&self, update: Update) -> Result<(), Stop> {
        self.gate.send(self.generation, update)
    }

    fn stale(&self) -> bool {
        self.gate.is_stale(self.generation)
    }

    fn cycle(&self) -> bool {
        self.stats.poll(self.gate, self.generation)
    }
}

/// A job queued for a lane.
type Queued = (Generation, Spec);

/// One lane as the dispatcher holds it: where its jobs go, its thread, and
/// why that thread could not start (if it could not).
struct LaneRunner {
    lane: Lane,
    jobs: Option<Sender<Queued>>,
    thread: Option<JoinHandle<()>>,
    broken: Option<String>,
}

impl LaneRunner {
    /// Starts the lane's thread.
    fn spawn(shared: &Arc<Shared>, lane: Lane) -> LaneRunner {
        let (tx, rx) = crossbeam_channel::unbounded::<Queued>();
        let sh = shared.clone();
        let started = start_thread(format!("oneblock-{}", lane.name()), move || {
            lane_loop(&sh, lane, rx)
        });
        let (thread, broken) = match started {
            Ok(t) => (Some(t), None),
            Err(e) => (
                None,
                Some(format!(
                    "the {} lane's thread could not start: {e}",
                    lane.name()
                )),
            ),
        };
        LaneRunner {
            lane,
            jobs: thread.is_some().then_some(tx),
            thread,
            broken,
        }
    }

    /// Starts `spec` under `generation` (superseding the lane's job), unless
    /// `generation` is stale; a lane whose thread is gone fails the job at
    /// once, saying why. True if the job started.
    fn start(&mut self, shared: &Shared, generation: Generation, spec: Spec) -> bool {
        let gate = shared.gate(self.lane);
        if !gate.start(generation) {
            return false;
        }
        let sent = self
            .jobs
            .as_ref()
            .is_some_and(|tx| tx.send((generation, spec)).is_ok());
        if !sent {
            let why = self
                .broken
                .clone()
                .unwrap_or_else(|| format!("the {} lane has stopped", self.lane.name()));
            gate.finish(generation, Some((why.clone(), None)), Outcome::Failed(why));
        }
        true
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
    /// Starts the worker's threads: the dispatcher and one per lane. `wake`
    /// is called after updates are sent (the GUI passes
    /// `ctx.request_repaint`). A lane whose thread cannot start fails each
    /// job sent to it with an `Error` saying so.
    ///
    /// # Panics
    /// If the operating system refuses to start the dispatcher's thread.
    pub fn spawn(config: WorkerConfig, wake: Arc<dyn Fn() + Send + Sync>) -> Worker {
        let config = WorkerConfig {
            update_capacity: config.update_capacity.max(1),
            sweep_threads: config.sweep_threads.max(1),
            coarse_columns: config.coarse_columns.max(1),
        };
        let (cmd_tx, cmd_rx) = crossbeam_channel::bounded(COMMAND_CAPACITY);
        let (up_tx, up_rx) = crossbeam_channel::bounded(config.update_capacity);
        let shared = Arc::new(Shared {
            gates: Lane::ALL
                .iter()
                .map(|&lane| Gate::new(lane, up_tx.clone(), wake.clone()))
                .collect(),
            stats: Arc::new(WorkerStats::default()),
            config,
        });
        drop(up_tx);
        let lanes: Vec<LaneRunner> = Lane::ALL
            .iter()
            .map(|&lane| LaneRunner::spawn(&shared, lane))
            .collect();
        let sh = shared.clone();
        let dispatcher = start_thread("oneblock-worker".into(), move || {
            dispatch(sh, cmd_rx, lanes)
        })
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

/// Starts one of the worker's threads (the dispatcher and the lanes; a
/// parallel job's pool is started by `jobs::run_threads`), at the lowered
/// priority of background work.
fn start_thread(
    name: String,
    body: impl FnOnce() + Send + 'static,
) -> std::io::Result<JoinHandle<()>> {
    std::thread::Builder::new().name(name).spawn(move || {
        priority::lower_current_thread();
        body()
    })
}

/// The dispatcher loop: runs until `Shutdown` or until the handle is gone,
/// then ends the lanes and joins their threads.
fn dispatch(shared: Arc<Shared>, commands: Receiver<Command>, mut lanes: Vec<LaneRunner>) {
    let mut latest = Latest::default();
    'commands: while let Ok(cmd) = commands.recv() {
        for order in latest.orders(cmd) {
            match order {
                Order::Shutdown => break 'commands,
                Order::Start(generation, spec) => {
                    let runner = &mut lanes[spec.lane().index()];
                    if runner.start(&shared, generation, spec.clone()) {
                        latest.started(&spec);
                    }
                }
                Order::StopRunning(lane, generation) => {
                    let g = shared.gate(lane);
                    if g.is_running() {
                        gate::cancel(&[g], generation, Some(lane));
                    }
                }
                Order::Cancel(of, generation, ack) => {
                    let gates: Vec<&Gate> = of.iter().map(|&l| shared.gate(l)).collect();
                    gate::cancel(&gates, generation, ack);
                }
            }
        }
    }
    shared.stop();
    for lane in &mut lanes {
        drop(lane.jobs.take());
    }
    for lane in lanes {
        if let Some(t) = lane.thread {
            t.join().ok();
        }
    }
}

/// A lane thread: runs the newest queued job, skipping any a newer one has
/// already superseded (the dispatcher finished those as cancelled).
fn lane_loop(shared: &Shared, lane: Lane, jobs: Receiver<Queued>) {
    while let Ok(mut job) = jobs.recv() {
        while let Ok(newer) = jobs.try_recv() {
            job = newer;
        }
        run_job(shared, lane, job);
    }
}

/// Runs one job to its end on its lane, and sends how it ended.
fn run_job(shared: &Shared, lane: Lane, (generation, spec): Queued) {
    let gate = shared.gate(lane);
    if gate.is_stale(generation) {
        return;
    }
    let sink = GateSink {
        gate,
        generation,
        stats: &shared.stats,
    };
    let name = format!("oneblock-{}", lane.name());
    let threads = shared.config.sweep_threads;
    let result = catch_unwind(AssertUnwindSafe(|| {
        let job: Box<dyn Job> = spec.start(shared.shape())?;
        run_threads(job.as_ref(), threads, &name, &sink)
    }));
    if let Some((error, outcome)) = ending(result) {
        gate.finish(generation, error, outcome);
    }
}
