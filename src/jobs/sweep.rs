//! The sweep job: a progressive bifurcation diagram, a unit a column, on
//! as many threads as its host gives it.
//!
//! The order is fixed in advance by [`sweep_plan`], and so is where each
//! column starts: from the `theta_last` of one named, earlier column (its
//! nearest neighbour among those computed before it), through the core's
//! `column_start`. So the diagram does not depend on thread timing, and a
//! test can recompute every column with the core alone.
//!
//! 1. Coarse pass: `coarse` columns spread over the whole range, split into
//!    [`Shape::chains`] contiguous chains, each continued left to right
//!    (the first column of a chain starts at θ = θν). All of them are sent
//!    before any refinement starts.
//! 2. Fill-in: each gap between coarse columns is bisected level by level;
//!    a new column continues from the nearer end of its sub-gap (the left
//!    one on a tie). Level 1 everywhere, then level 2, and so on, so the
//!    diagram sharpens evenly.
//!
//! Each step takes columns from the job's [`Schedule`], which hands out a
//! column once its parent is done, with the parent's last onset, and steps
//! up to `LANES` ready columns together.
//!
//! A seeded sweep adds to each column every other attractor at its θν,
//! from the exit arc's cell graph (`sim::seeded`).

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Condvar, Mutex};

use super::orbit::{Pacer, paced_progress};
use super::plan::{PlannedColumn, sweep_plan};
use super::protocol::{SweepSpec, Update};
use super::schedule::{PlanItem, Schedule, wait_next};
use super::{Job, JobError, Shape, Sink, Status, lock, panic_message};
use crate::model::{ParamError, Params};
use crate::sim::column_lyapunov::{ExactSim, LyapunovRun};
use crate::sim::interpolant::MapUsed;
use crate::sim::seeded::{SeededColumn, seeded_column};
use crate::sim::{
    Column, ColumnJob, Handover, LANES, LaneEnd, PausedColumn, SimError, Simulator, SweepOptions,
    Yield, column_start, param_grid, run_columns,
};

/// When a sink's host wants its thread back.
struct Yielding<'a>(&'a dyn Sink);

impl Yield for Yielding<'_> {
    fn pause(&self) -> bool {
        self.0.pause()
    }
    fn defer_heavy(&self) -> bool {
        self.0.defer_heavy()
    }
}

impl PlanItem for PlannedColumn {
    fn slot(&self) -> usize {
        self.index
    }

    fn parent(&self) -> Option<usize> {
        self.parent
    }

    fn coarse(&self) -> bool {
        self.coarse
    }
}

/// A sweep's schedule: a done column leaves its last onset for its
/// neighbours, with its slow cycle's period ([`Handover`]; `None` if it
/// failed: they start at θ = θν).
type Columns = Schedule<PlannedColumn, Option<Handover>>;

/// A column running in a lane: its plan entry, its first onset and the
/// period of its neighbour's slow cycle (`Handover`).
type InFlight = (PlannedColumn, (f64, Option<usize>));

/// A column the host asked to pause ([`Sink::pause`]), to be resumed by
/// the next step before anything new starts: part-way through its cycles,
/// or done and part-way through its λ.
enum Parked {
    Running(InFlight, PausedColumn),
    Lyapunov(Delivery),
}

/// A finished column on its way out: what its neighbours continue from,
/// and its λ in progress with the simulator it is computed at (`None`: it
/// has none, e.g. after a failure).
struct Delivery {
    p: PlannedColumn,
    col: Column,
    handover: Option<Handover>,
    lyapunov: Option<(LyapunovRun, ExactSim)>,
}

/// Checks what the columns cannot check for themselves, before any work:
/// finite ends (positive on a log axis) at which the model is valid.
fn validate(s: &SweepSpec) -> Result<(), SimError> {
    let name = s.param.name();
    for v in [s.axis.from, s.axis.to] {
        if !v.is_finite() {
            let range = "the sweep's ends must be finite";
            return Err(ParamError::new(name, v, range).into());
        }
        if s.param.spans_decades() && v <= 0.0 {
            let range = "the sweep's ends must be positive (a log axis)";
            return Err(ParamError::new(name, v, range).into());
        }
    }
    if s.axis.steps == 0 {
        return Err(ParamError::new("columns", 0.0, "must be at least 1").into());
    }
    for v in [s.axis.from, s.axis.to] {
        Simulator::new(s.param.set(&s.params, v), s.settings)?;
    }
    Ok(())
}

/// A bifurcation diagram in progress.
pub(crate) struct SweepJob {
    spec: SweepSpec,
    opts: SweepOptions,
    grid: Vec<f64>,
    sims: Vec<Result<Simulator, SimError>>,
    schedule: Mutex<Columns>,
    ready: Condvar,
    iterates: AtomicU64,
    pacer: Mutex<Pacer>,
    /// The first column that panicked (the sweep goes on, and fails at its end).
    failure: Mutex<Option<String>>,
    /// Columns paused part-way, resumed first by the next step.
    parked: Mutex<Vec<Parked>>,
}

impl SweepJob {
    pub fn new(spec: SweepSpec, shape: Shape) -> Result<Self, JobError> {
        validate(&spec)?;
        let columns = spec.axis.steps;
        let opts = SweepOptions {
            transient: spec.transient,
            keep: spec.keep,
            map: spec.map,
        };
        let grid = param_grid(spec.param, spec.axis.from, spec.axis.to, columns);
        let plan = sweep_plan(columns, shape.coarse_columns, shape.chains);
        let sims = grid
            .iter()
            .map(|&v| Simulator::new(spec.param.set(&spec.params, v), spec.settings))
            .collect();
        Ok(SweepJob {
            spec,
            opts,
            grid,
            sims,
            schedule: Mutex::new(Schedule::new(plan, columns)),
            ready: Condvar::new(),
            iterates: AtomicU64::new(0),
            pacer: Mutex::new(Pacer::new()),
            failure: Mutex::new(None),
            parked: Mutex::new(Vec::new()),
        })
    }

    /// The model's parameters at column `index`.
    fn params_at(&self, index: usize) -> Params {
        self.spec.param.set(&self.spec.params, self.grid[index])
    }

    /// Sends a finished column (or the panic that ended it) and marks it
    /// done in the schedule.
    fn deliver(
        &self,
        p: PlannedColumn,
        start: (f64, Option<usize>),
        col: Result<Column, Box<dyn std::any::Any + Send>>,
        sink: &dyn Sink,
    ) -> Result<(), JobError> {
        let generation = sink.generation();
        let (name, v) = (self.spec.param.name(), self.grid[p.index]);
        let tn = self.params_at(p.index).theta_nu;
        // A failed column is still delivered (with what it kept) after an
        // Error naming it; its neighbours then start afresh from θν.
        let (col, problem) = match col {
            Ok(c) => match &c.error {
                None => (c, None),
                Some(SimError::Cancelled) => return Err(JobError::Stop),
                Some(e) => {
                    let msg = format!(
                        "column {} at {name} = {v} failed after {} kept iterates: {e}",
                        p.index,
                        c.thetas.len()
                    );
                    let parameter = e.parameter();
                    (c, Some((msg, parameter)))
                }
            },
            Err(payload) => {
                let msg = format!(
                    "column {} at {name} = {v} panicked: {}",
                    p.index,
                    panic_message(&*payload)
                );
                *lock(&self.failure) = Some(msg.clone());
                let empty = Column {
                    theta_nu: tn,
                    thetas: vec![],
                    theta_last: start.0,
                    error: None,
                    rhs_evals: 0,
                    slow_period: None,
                    map: MapUsed::Direct,
                };
                (empty, Some((msg, None)))
            }
        };
        let handover = match problem {
            None => col.handover(),
            Some((message, parameter)) => {
                sink.send(Update::Error {
                    generation,
                    lane: sink.lane(),
                    message,
                    parameter,
                })?;
                None
            }
        };
        // λ from the column's own onsets, on this thread: bounded work
        // (one cycle solve, or at most 200 slopes), never the UI's.
        let lyapunov = match (handover, self.sims[p.index].as_ref()) {
            (Some(_), Ok(sim)) => ExactSim::new(sim)
                .ok()
                .map(|exact| (LyapunovRun::new(&col), exact)),
            _ => None,
        };
        let d = Delivery {
            p,
            col,
            handover,
            lyapunov,
        };
        self.send_column(d, sink, false)
    }

    /// Finishes a delivered column's λ and sends the column, or parks it
    /// part-way if the host asks for its thread back (not before one piece
    /// when `fresh`: the first thing in a step).
    fn send_column(&self, mut d: Delivery, sink: &dyn Sink, fresh: bool) -> Result<(), JobError> {
        let generation = sink.generation();
        let p = d.p;
        let v = self.grid[p.index];
        if let (Some((run, exact)), Ok(sim)) = (d.lyapunov.as_mut(), self.sims[p.index].as_ref())
            && !run.advance((sim, exact.get(sim)), &d.col, &Yielding(sink), fresh)
        {
            lock(&self.parked).push(Parked::Lyapunov(d));
            return Ok(());
        }
        let lyapunov = d.lyapunov.as_ref().and_then(|(run, _)| run.result());
        let col = d.col;
        // Iterates this column ran (a failed one counts what it kept).
        let k = (self.opts.transient + col.thetas.len()) as u64;
        let n = self.iterates.fetch_add(k, Ordering::Relaxed) + k;
        match self.seeded(p.index, &col.thetas, d.handover, sink)? {
            Some(seeded) => sink.send(Update::Column {
                generation,
                index: p.index,
                value: v,
                thetas: seeded.thetas,
                coarse: p.coarse,
                rhs_evals: col.rhs_evals + seeded.rhs_evals,
                map: col.map,
                lyapunov,
                attractor: seeded.attractor,
                uncounted: seeded.uncounted,
            })?,
            None => sink.send(Update::Column {
                generation,
                index: p.index,
                value: v,
                thetas: col.thetas,
                coarse: p.coarse,
                rhs_evals: col.rhs_evals,
                map: col.map,
                lyapunov,
                attractor: vec![],
                uncounted: None,
            })?,
        }
        let done = {
            let mut sch = lock(&self.schedule);
            sch.complete(p, d.handover);
            sch.done()
        };
        self.ready.notify_all();
        let columns = self.grid.len();
        paced_progress(&self.pacer, (done, columns, n), sink)
    }

    /// A finished column with the seeds' attractors added and labelled;
    /// `None` when the sweep has no seeds or the column failed (`handover`
    /// is `None`).
    fn seeded(
        &self,
        index: usize,
        thetas: &[f64],
        handover: Option<Handover>,
        sink: &dyn Sink,
    ) -> Result<Option<SeededColumn>, JobError> {
        let seeds = self.spec.seeds;
        let Some(h) = handover.filter(|_| seeds > 0) else {
            return Ok(None);
        };
        let params = self.params_at(index);
        let followed = Column {
            theta_nu: params.theta_nu,
            thetas: thetas.to_vec(),
            theta_last: h.theta,
            error: None,
            rhs_evals: 0,
            slow_period: h.slow_period,
            map: MapUsed::Direct,
        };
        let cancel = || sink.cycle();
        match seeded_column(
            params,
            self.spec.settings,
            &followed,
            seeds,
            self.opts.keep,
            &cancel,
        ) {
            Ok(s) => Ok(Some(s)),
            Err(SimError::Cancelled) => Err(JobError::Stop),
            // Only a cancel ends the seeds early (failed seeds are left out).
            Err(e) => Err(JobError::Sim(e)),
        }
    }

    /// The column of plan entry `p`, to start at `neighbour`'s handover.
    fn column_job(
        &self,
        p: PlannedColumn,
        neighbour: Option<Handover>,
    ) -> (ColumnJob<'_>, InFlight) {
        let params = self.params_at(p.index);
        let tn = params.theta_nu;
        // A chain's head starts at θ0 if given, as if continued from it.
        let from = match (p.parent, self.spec.theta0) {
            (None, Some(theta0)) => Some(theta0),
            _ => neighbour.map(|h| h.theta),
        };
        // Projected onto this column's exit arc (κ's and θν's).
        let start = column_start(params.kappa, tn, from);
        let slow_period = neighbour.and_then(|h| h.slow_period);
        let job = ColumnJob {
            sim: self.sims[p.index].as_ref().map_err(Clone::clone),
            theta_nu: tn,
            start,
            slow_period,
            resume: None,
        };
        (job, (p, (start, slow_period)))
    }

    /// What the last step parked: λs in progress are finished (or parked
    /// again), and the paused columns returned to be resumed.
    fn resume_parked(&self, sink: &dyn Sink) -> Result<Vec<(InFlight, PausedColumn)>, JobError> {
        let parked = std::mem::take(&mut *lock(&self.parked));
        let mut runs = Vec::new();
        for (i, item) in parked.into_iter().enumerate() {
            match item {
                Parked::Lyapunov(d) => self.send_column(d, sink, i == 0)?,
                Parked::Running(flight, run) => runs.push((flight, run)),
            }
        }
        Ok(runs)
    }

    /// Parks paused columns that were not resumed.
    fn park(&self, runs: Vec<(InFlight, PausedColumn)>) {
        let mut parked = lock(&self.parked);
        parked.extend(runs.into_iter().map(|(f, r)| Parked::Running(f, r)));
    }

    /// The lane job that resumes a paused column.
    fn resumed_job(&self, flight: InFlight, run: PausedColumn) -> ColumnJob<'_> {
        let (p, (start, slow_period)) = flight;
        ColumnJob {
            sim: self.sims[p.index].as_ref().map_err(Clone::clone),
            theta_nu: self.params_at(p.index).theta_nu,
            start,
            slow_period,
            resume: Some(run),
        }
    }

    /// The columns that were in flight when the lanes panicked, run again
    /// one by one, each under its own guard, so that the panic is reported
    /// with its column and the others complete (with the values the lanes
    /// would have given them).
    fn rerun_alone(
        &self,
        in_flight: [Option<InFlight>; LANES],
        sink: &dyn Sink,
    ) -> Result<(), JobError> {
        let cancel = || sink.cycle();
        for (p, start) in in_flight.into_iter().flatten() {
            let params = self.params_at(p.index);
            let tn = params.theta_nu;
            let col = catch_unwind(AssertUnwindSafe(|| {
                #[cfg(test)]
                tests::inject_panic(p.index, self.grid[p.index]);
                let (theta, slow) = start;
                let settings = self.spec.settings;
                Column::run_from(params, settings, tn, theta, slow, &self.opts, &cancel)
            }));
            self.deliver(p, start, col, sink)?;
        }
        Ok(())
    }
}

impl Job for SweepJob {
    fn parallel(&self) -> bool {
        true
    }

    /// Resumes what the last step paused, else waits for a column that
    /// may start (or for the end); then runs it and, in lanes, whatever else
    /// is ready, up to `width` columns. A lane that finds nothing ready
    /// retires; when the host asks for its thread back ([`Sink::pause`]),
    /// the columns in flight are parked for the next step.
    fn step(&self, width: usize, sink: &dyn Sink) -> Result<Status, JobError> {
        let mut resumes = self.resume_parked(sink)?;
        if !lock(&self.parked).is_empty() {
            // A column's λ paused again: the thread goes back at once.
            self.park(resumes);
            return Ok(Status::Working);
        }
        let mut first = None;
        if resumes.is_empty() {
            let Some((p, seed)) = wait_next(&self.schedule, &self.ready, || sink.stale())? else {
                return Ok(Status::Done);
            };
            first = Some((p, seed.flatten()));
        }
        let cancel = || sink.cycle();
        let yielding = Yielding(sink);
        let mut left = width.max(1);
        let mut started = false;
        let mut in_flight: [Option<InFlight>; LANES] = [None; LANES];
        let mut stop: Option<JobError> = None;
        let lanes = catch_unwind(AssertUnwindSafe(|| {
            run_columns(&self.opts, &cancel, &yielding, |lane, ended| {
                match (ended, in_flight[lane].take()) {
                    (Some(LaneEnd::Finished(col)), Some((p, start))) if stop.is_none() => {
                        stop = self.deliver(p, start, Ok(col), sink).err();
                    }
                    (Some(LaneEnd::Paused(run)), Some(flight)) => {
                        lock(&self.parked).push(Parked::Running(flight, run));
                    }
                    _ => {}
                }
                if stop.is_some() || left == 0 || (started && sink.pause()) {
                    return None;
                }
                let job = match resumes.pop() {
                    Some((flight, run)) => {
                        in_flight[lane] = Some(flight);
                        self.resumed_job(flight, run)
                    }
                    None => {
                        let (p, neighbour) = first.take().or_else(|| {
                            lock(&self.schedule)
                                .next()
                                .ok()
                                .map(|(p, seed)| (p, seed.flatten()))
                        })?;
                        let (job, flight) = self.column_job(p, neighbour);
                        in_flight[lane] = Some(flight);
                        #[cfg(test)]
                        tests::inject_panic(p.index, self.grid[p.index]);
                        job
                    }
                };
                left -= 1;
                started = true;
                Some(job)
            })
        }));
        self.park(resumes);
        if lanes.is_err() {
            self.rerun_alone(in_flight, sink)?;
        }
        match stop {
            Some(e) => Err(e),
            None => Ok(Status::Working),
        }
    }

    fn finish(&self, _sink: &dyn Sink) -> Result<(), JobError> {
        match lock(&self.failure).take() {
            // The panic was reported with its column; the sweep went on.
            Some(msg) => Err(JobError::Failed(msg)),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests;
