//! The phase job: a progressive phase diagram in (θν, κ), a unit a cell
//! (the core's `phase_cell`, in pieces of a few ms: `CellSteps`), on as
//! many threads as its host gives it.
//!
//! As for the bifurcation sweep, the order and each cell's seeding
//! neighbour are fixed in advance by [`block_plan`], so the diagram does
//! not depend on thread timing and a test can recompute every cell with
//! the core alone. The grid is cut into blocks of 32 × 32 cells, each
//! planned on its own (`phase_plan`: a coarse lattice of about every
//! `COARSE_STRIDE`-th row and column, then the gaps bisected level by
//! level, a cell seeded by the nearest computed one in its row, else in
//! its column), the blocks' cells taken level by level so the whole
//! picture sharpens evenly. No seed crosses a block's edge, so a shard of
//! whole blocks (`PhaseTuning::shard`) computes each of its cells as the
//! whole grid does.
//!
//! Each cell's orbit starts at θ = θν; a periodic neighbour's cycle is
//! solved first and ends the cell once the orbit converges onto it, and a
//! cell seeded by a chaotic one gets the shorter transient
//! (`sim::phase::continue_steps`).
//!
//! Each step takes cells from the job's [`Schedule`], which hands out a
//! cell once its parent is done, with the parent's [`Seed`].

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Condvar, Mutex};
use web_time::Instant;

use super::orbit::{FLUSH_INTERVAL, Pacer, paced_progress};
use super::plan::{PlannedCell, block_plan, phase_blocks, shard_blocks};
use super::protocol::{Axis, GridCell, ListedAttractor, MAX_LISTED, PhaseSpec, Update};
use super::schedule::{PlanItem, Schedule, wait_next};
use super::{Job, JobError, Report, Sink, Status, lock, panic_message};
use crate::model::{ParamError, Params};
use crate::sim::attractors::{Found, Verdict};
use crate::sim::phase::{CellClass, CellSteps, PhaseCell, PhaseOptions, Seed, continue_steps};
use crate::sim::{SimError, Simulator, theta_nu_grid};

/// Rows and columns of the coarse lattice: about every this many.
pub const COARSE_STRIDE: usize = 8;
/// `PhaseCells` go out every this many cells, or every `FLUSH_INTERVAL`.
pub const CELL_BATCH: usize = 16;
/// The most rows or columns of a grid (as `oneblock phase`).
pub const MAX_STEPS: usize = 10_000;
/// The most cells of a grid (as `oneblock phase`).
pub const MAX_CELLS: usize = 4_000_000;

/// A planned cell as the schedule sees it: its slot is its flat index
/// (row·columns + column).
#[derive(Clone, Copy, Debug)]
struct Item {
    cell: PlannedCell,
    columns: usize,
}

impl PlanItem for Item {
    fn slot(&self) -> usize {
        self.cell.row * self.columns + self.cell.column
    }

    fn parent(&self) -> Option<usize> {
        self.cell.parent.map(|(r, c)| r * self.columns + c)
    }

    fn coarse(&self) -> bool {
        self.cell.coarse
    }
}

/// Cells finished and not yet sent.
struct Outbox {
    coarse: Vec<GridCell>,
    fine: Vec<GridCell>,
    last_flush: Instant,
}

/// Checks everything before any work; the error names the field and its
/// valid range.
fn validate(s: &PhaseSpec) -> Result<(), SimError> {
    let Axis {
        from: t0,
        to: t1,
        steps: nt,
    } = s.theta_nu;
    let Axis {
        from: k0,
        to: k1,
        steps: nk,
    } = s.kappa;
    for (name, v) in [("theta-nu-from", t0), ("theta-nu-to", t1)] {
        if !v.is_finite() {
            return Err(ParamError::new(name, v, "must be a finite angle in radians").into());
        }
    }
    for (name, v) in [("kappa-from", k0), ("kappa-to", k1)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(ParamError::new(name, v, "must be a finite number > 0").into());
        }
    }
    for (name, n) in [("theta-nu-steps", nt), ("kappa-steps", nk)] {
        if !(1..=MAX_STEPS).contains(&n) {
            return Err(ParamError::new(name, n as f64, "must lie in [1, 10000]").into());
        }
    }
    if nt * nk > MAX_CELLS {
        let range = "must be at most 4000000 cells with theta-nu-steps";
        return Err(ParamError::new("kappa-steps", nk as f64, range).into());
    }
    if let Some((k, n)) = s.tuning.shard {
        let blocks = phase_blocks(nk, nt).len();
        if !(1..=blocks).contains(&n) || !(1..=n).contains(&k) {
            let range =
                "must be K/N with 1 <= K <= N <= the number of the grid's blocks of 32 x 32 cells";
            return Err(ParamError::new("shard", k as f64, range).into());
        }
    }
    if s.transient > 1_000_000 {
        let range = "must lie in [0, 1000000]";
        return Err(ParamError::new("transient", s.transient as f64, range).into());
    }
    if !(16..=1_000_000).contains(&s.keep) {
        let range =
            "must lie in [16, 1000000] (the Lyapunov exponent's error needs 8 batches of 2)";
        return Err(ParamError::new("keep", s.keep as f64, range).into());
    }
    // The model's own ranges (γ, ν, Ω, κ in [1e-6, 1e3]) and the solver's.
    for (k, t) in [(k0, t0), (k1, t1)] {
        Simulator::new(
            Params {
                kappa: k,
                theta_nu: t,
                ..s.params
            },
            s.settings,
        )
        .map_err(|e| match e {
            // Name the end of the range rather than "kappa".
            SimError::Param(p) if p.name == "kappa" => ParamError::new(
                if k == k0 { "kappa-from" } else { "kappa-to" },
                p.value,
                p.range,
            )
            .into(),
            e => e,
        })?;
    }
    Ok(())
}

/// A phase diagram in progress.
pub(crate) struct PhaseJob {
    spec: PhaseSpec,
    opts: PhaseOptions,
    theta_nus: Vec<f64>,
    kappas: Vec<f64>,
    schedule: Mutex<Schedule<Item, Seed>>,
    ready: Condvar,
    outbox: Mutex<Outbox>,
    iterates: AtomicU64,
    pacer: Mutex<Pacer>,
    /// The first cell that panicked (the grid goes on, and fails at its end).
    failure: Mutex<Option<String>>,
    /// Whether a cell has failed (only the first failure is reported: a
    /// flood of errors would hide the picture).
    failed_once: Mutex<bool>,
    /// Cells paused part-way, resumed before anything new starts.
    parked: Mutex<Vec<(PlannedCell, Box<CellSteps>)>>,
    /// The cells planned: the grid's, or its shard's.
    total: usize,
}

/// A finished cell: itself, its attractors' list, and the error to report.
type Computed = (PhaseCell, Vec<ListedAttractor>, Option<Report>);

impl PhaseJob {
    pub fn new(spec: PhaseSpec) -> Result<Self, JobError> {
        validate(&spec)?;
        let opts = spec.options();
        let (columns, rows) = (spec.theta_nu.steps, spec.kappa.steps);
        let theta_nus = theta_nu_grid(spec.theta_nu.from, spec.theta_nu.to, columns);
        let kappas = theta_nu_grid(spec.kappa.from, spec.kappa.to, rows);
        let blocks = phase_blocks(rows, columns).len();
        let which = match spec.tuning.shard {
            Some((k, n)) => shard_blocks(blocks, k, n),
            None => 0..blocks,
        };
        let plan: Vec<Item> = block_plan(rows, columns, COARSE_STRIDE, which)
            .into_iter()
            .map(|cell| Item { cell, columns })
            .collect();
        let total = plan.len();
        Ok(PhaseJob {
            spec,
            opts,
            theta_nus,
            kappas,
            schedule: Mutex::new(Schedule::new(plan, rows * columns)),
            ready: Condvar::new(),
            outbox: Mutex::new(Outbox {
                coarse: Vec::new(),
                fine: Vec::new(),
                last_flush: Instant::now(),
            }),
            iterates: AtomicU64::new(0),
            pacer: Mutex::new(Pacer::new()),
            failure: Mutex::new(None),
            failed_once: Mutex::new(false),
            parked: Mutex::new(Vec::new()),
            total,
        })
    }

    fn total(&self) -> usize {
        self.total
    }

    /// Sends what is waiting, coarse cells first, under the outbox lock so
    /// that two threads flushing cannot reorder batches.
    fn flush(&self, sink: &dyn Sink) -> Result<(), JobError> {
        let mut ob = lock(&self.outbox);
        for (cells, coarse) in [
            (std::mem::take(&mut ob.coarse), true),
            (std::mem::take(&mut ob.fine), false),
        ] {
            if !cells.is_empty() {
                sink.send(Update::PhaseCells {
                    generation: sink.generation(),
                    cells,
                    coarse,
                })?;
            }
        }
        ob.last_flush = Instant::now();
        Ok(())
    }

    /// The cell of plan entry `p` from its parent's `seed`, nothing
    /// computed yet.
    fn steps(&self, p: PlannedCell, seed: Option<Seed>) -> Box<CellSteps> {
        let (kappa, tn) = (self.kappas[p.row], self.theta_nus[p.column]);
        let (params, settings) = (self.spec.params, self.spec.settings);
        Box::new(continue_steps(
            params, settings, kappa, tn, seed, &self.opts,
        ))
    }

    /// Runs the cell of plan entry `p` from where `run` left it, piece by
    /// piece under its own guard, until it is done or the host wants its
    /// thread back (`None`: the cell is parked for the next step). Done:
    /// the cell, its attractors' list (see [`Self::listed`]), and the
    /// error to report if any.
    fn compute(
        &self,
        p: PlannedCell,
        mut run: Box<CellSteps>,
        sink: &dyn Sink,
    ) -> Result<Option<Computed>, JobError> {
        let (kappa, tn) = (self.kappas[p.row], self.theta_nus[p.column]);
        let cancel = || sink.cycle();
        let finished = catch_unwind(AssertUnwindSafe(|| {
            #[cfg(test)]
            if p.row * self.theta_nus.len() + p.column
                == tests::PANIC_AT_CELL.load(Ordering::SeqCst)
            {
                panic!(
                    "injected panic in cell {}",
                    p.row * self.theta_nus.len() + p.column
                );
            }
            loop {
                if run.advance(&cancel) {
                    return true;
                }
                if sink.pause() {
                    return false;
                }
            }
        }));
        let where_ = format!(
            "cell (kappa = {kappa}, theta-nu = {tn}; row {}, column {})",
            p.row, p.column
        );
        Ok(Some(match finished {
            Ok(false) => {
                lock(&self.parked).push((p, run));
                return Ok(None);
            }
            Ok(true) => {
                let (c, found) = run.finish();
                match &c.error {
                    None => {
                        let listed = self.listed(&c, found);
                        (c, listed, None)
                    }
                    Some(SimError::Cancelled) => return Err(JobError::Stop),
                    Some(e) => {
                        let first = !std::mem::replace(&mut *lock(&self.failed_once), true);
                        let report = first.then(|| (format!("{where_}: {e}"), e.parameter()));
                        (c, Vec::new(), report)
                    }
                }
            }
            Err(payload) => {
                let msg = format!("{where_} panicked: {}", panic_message(&*payload));
                *lock(&self.failure) = Some(msg.clone());
                (
                    PhaseCell::failed(tn, kappa, tn),
                    Vec::new(),
                    Some((msg, None)),
                )
            }
        }))
    }

    /// A multistable cell's attractors, when the spec asks for them: those
    /// the cell counted (`found`, the exit arc's cell graph at
    /// `CellOptions::column()`), the undecided left out, at most
    /// [`MAX_LISTED`]. Only cells counted with more than one attractor are
    /// listed.
    fn listed(&self, cell: &PhaseCell, found: Option<Found>) -> Vec<ListedAttractor> {
        let multistable = cell.attractors.is_some_and(|n| n > 1);
        match found {
            Some(f) if self.spec.tuning.list_attractors && multistable => f
                .attractors
                .iter()
                .filter(|a| !matches!(a.verdict, Verdict::Undecided(_)))
                .take(MAX_LISTED)
                .map(ListedAttractor::of)
                .collect(),
            _ => Vec::new(),
        }
    }

    /// One cell, resumed from `run`: computed, queued for sending (coarse
    /// before fine), marked done in the schedule, and flushed when a batch
    /// is due. Whether it was done (else it is parked).
    fn one(&self, p: PlannedCell, run: Box<CellSteps>, sink: &dyn Sink) -> Result<bool, JobError> {
        let generation = sink.generation();
        let Some((cell, listed, problem)) = self.compute(p, run, sink)? else {
            return Ok(false);
        };
        let mut seed_out = Seed::of(&cell);
        if cell.class == CellClass::Failed {
            seed_out.cycle = None;
        }
        if let Some((message, parameter)) = problem {
            sink.send(Update::Error {
                generation,
                lane: sink.lane(),
                message,
                parameter,
            })?;
        }
        let n = self.iterates.fetch_add(cell.iterates, Ordering::Relaxed) + cell.iterates;
        // Into the outbox before the schedule hears of it: once the last
        // coarse cell is marked done, every coarse cell is in the outbox,
        // ahead of any refinement cell.
        let queued = {
            let mut ob = lock(&self.outbox);
            let gc = GridCell {
                row: p.row,
                column: p.column,
                cell,
                listed,
            };
            if p.coarse {
                ob.coarse.push(gc);
            } else {
                ob.fine.push(gc);
            }
            (
                ob.coarse.len() + ob.fine.len(),
                ob.last_flush.elapsed() >= FLUSH_INTERVAL,
            )
        };
        let columns = self.theta_nus.len();
        let (done, coarse_done) = {
            let mut sch = lock(&self.schedule);
            let last_coarse = sch.complete(Item { cell: p, columns }, seed_out);
            (sch.done(), last_coarse)
        };
        self.ready.notify_all();
        let total = self.total();
        if queued.0 >= CELL_BATCH || queued.1 || coarse_done || done == total {
            self.flush(sink)?;
        }
        paced_progress(&self.pacer, (done, total, n), sink)?;
        Ok(true)
    }
}

impl Job for PhaseJob {
    fn parallel(&self) -> bool {
        true
    }

    /// Up to `width` cells, each waiting for its parent; a cell parked by
    /// the last step first (only the single-threaded host pauses one, in
    /// pieces of a few ms: `sim::phase::CellSteps`).
    fn step(&self, width: usize, sink: &dyn Sink) -> Result<Status, JobError> {
        for _ in 0..width.max(1) {
            let parked = lock(&self.parked).pop();
            let (p, run) = match parked {
                Some(parked) => parked,
                None => {
                    let Some((Item { cell: p, .. }, seed)) =
                        wait_next(&self.schedule, &self.ready, || sink.stale())?
                    else {
                        return Ok(Status::Done);
                    };
                    (p, self.steps(p, seed))
                }
            };
            if !self.one(p, run, sink)? {
                return Ok(Status::Working);
            }
        }
        Ok(Status::Working)
    }

    fn finish(&self, sink: &dyn Sink) -> Result<(), JobError> {
        // Whatever a thread left behind (normally nothing: the last cell
        // flushes).
        self.flush(sink)?;
        match lock(&self.failure).take() {
            // The panic was reported with its cell; the grid went on.
            Some(msg) => Err(JobError::Failed(msg)),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jobs::{Outcome, PhaseTuning};
    use crate::sim::default_settings;
    use crate::worker::{Command, Worker, WorkerConfig};
    use std::collections::HashSet;
    use std::sync::Arc;
    use std::sync::atomic::AtomicUsize;
    use std::time::Duration;

    /// Fault injection for the phase threads: the cell with this flat index
    /// (row·columns + column) panics (usize::MAX: none). Only this module's
    /// tests set it.
    pub(super) static PANIC_AT_CELL: AtomicUsize = AtomicUsize::new(usize::MAX);

    #[test]
    fn a_panicking_cell_is_reported_and_the_grid_goes_on() {
        let w = Worker::spawn(WorkerConfig::default(), Arc::new(|| {}));
        let job = |generation| {
            Command::run(
                generation,
                PhaseSpec {
                    params: Params::default(),
                    settings: default_settings(1e-8),
                    theta_nu: Axis::new(0.2, 0.6, 5),
                    kappa: Axis::new(2.0, 3.0, 2),
                    transient: 40,
                    keep: 16,
                    tuning: PhaseTuning::default(),
                },
            )
        };
        PANIC_AT_CELL.store(7, Ordering::SeqCst);
        assert!(w.send(job(1)));
        let mut cells = HashSet::new();
        let mut errors = vec![];
        let outcome = loop {
            match w.recv_timeout(Duration::from_secs(60)).expect("silent") {
                Update::PhaseCells { cells: cs, .. } => {
                    for c in cs {
                        assert!(cells.insert((c.row, c.column)));
                        let injected = c.row * 5 + c.column == 7;
                        assert_eq!(c.cell.class == CellClass::Failed, injected, "{c:?}");
                    }
                }
                Update::Error { message, .. } => errors.push(message),
                Update::Finished { outcome, .. } => break outcome,
                _ => {}
            }
        };
        PANIC_AT_CELL.store(usize::MAX, Ordering::SeqCst);
        assert_eq!(cells.len(), 10);
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert!(errors[0].contains("row 1, column 2") && errors[0].contains("injected panic"));
        assert!(matches!(outcome, Outcome::Failed(_)));
        assert!(w.send(job(2)));
        let outcome = loop {
            if let Update::Finished { outcome, .. } =
                w.recv_timeout(Duration::from_secs(60)).expect("silent")
            {
                break outcome;
            }
        };
        assert_eq!(outcome, Outcome::Completed);
        w.shutdown();
    }
}
