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

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Condvar, Mutex};

use super::orbit::{Pacer, paced_progress};
use super::plan::{PlannedColumn, sweep_plan};
use super::protocol::{Lane, SweepSpec, Update};
use super::schedule::{PlanItem, Schedule, wait_next};
use super::{Job, JobError, Shape, Sink, Status, lock, panic_message};
use crate::model::ParamError;
use crate::sim::column_lyapunov::column_lyapunov;
use crate::sim::interpolant::MapUsed;
use crate::sim::seeded::seeded_column;
use crate::sim::{
    Column, ColumnJob, Handover, LANES, SimError, Simulator, SweepOptions, column_start,
    run_columns, theta_nu_grid,
};

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

/// Checks what the columns cannot check for themselves, before any work.
fn validate(s: &SweepSpec) -> Result<(), SimError> {
    for v in [s.theta_nu.from, s.theta_nu.to] {
        if !v.is_finite() {
            let range = "the sweep's ends must be finite angles";
            return Err(ParamError::new("theta-nu", v, range).into());
        }
    }
    if s.theta_nu.steps == 0 {
        return Err(ParamError::new("columns", 0.0, "must be at least 1").into());
    }
    Simulator::new(s.params.with_theta_nu(s.theta_nu.from), s.settings)?;
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
}

impl SweepJob {
    pub fn new(spec: SweepSpec, shape: Shape) -> Result<Self, JobError> {
        validate(&spec)?;
        let columns = spec.theta_nu.steps;
        let opts = SweepOptions {
            transient: spec.transient,
            keep: spec.keep,
            map: spec.map,
        };
        let grid = theta_nu_grid(spec.theta_nu.from, spec.theta_nu.to, columns);
        let plan = sweep_plan(columns, shape.coarse_columns, shape.chains);
        let sims = grid
            .iter()
            .map(|&tn| Simulator::new(spec.params.with_theta_nu(tn), spec.settings))
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
        })
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
        let tn = self.grid[p.index];
        // A failed column is still delivered (with what it kept) after an
        // Error naming it; its neighbours then start afresh from θν.
        let (col, problem) = match col {
            Ok(c) => match &c.error {
                None => (c, None),
                Some(SimError::Cancelled) => return Err(JobError::Stop),
                Some(e) => {
                    let msg = format!(
                        "column {} at theta-nu = {tn} failed after {} kept iterates: {e}",
                        p.index,
                        c.thetas.len()
                    );
                    let parameter = e.parameter();
                    (c, Some((msg, parameter)))
                }
            },
            Err(payload) => {
                let msg = format!(
                    "column {} at theta-nu = {tn} panicked: {}",
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
        let problem_free = problem.is_none();
        let theta_last = if problem.is_none() {
            col.handover()
        } else {
            None
        };
        if let Some((message, parameter)) = problem {
            sink.send(Update::Error {
                generation,
                lane: Lane::Sweep,
                message,
                parameter,
            })?;
        }
        // λ from the column's own onsets, on this thread: bounded work
        // (one cycle solve, or at most 200 slopes), never the UI's.
        let lyapunov = match (&problem_free, self.sims[p.index].as_ref()) {
            (true, Ok(sim)) => column_lyapunov(sim, &col),
            _ => None,
        };
        // Iterates this column ran (a failed one counts what it kept).
        let k = (self.opts.transient + col.thetas.len()) as u64;
        let n = self.iterates.fetch_add(k, Ordering::Relaxed) + k;
        let (thetas, attractor, rhs_evals) = self.seeded(tn, col.thetas, theta_last, sink)?;
        sink.send(Update::Column {
            generation,
            index: p.index,
            theta_nu: tn,
            thetas,
            coarse: p.coarse,
            rhs_evals: col.rhs_evals + rhs_evals,
            map: col.map,
            lyapunov,
            attractor,
        })?;
        let done = {
            let mut sch = lock(&self.schedule);
            sch.complete(p, theta_last);
            sch.done()
        };
        self.ready.notify_all();
        let columns = self.grid.len();
        paced_progress(&self.pacer, Lane::Sweep, (done, columns, n), sink)
    }

    /// A finished column's points with the seeds' attractors added and
    /// labelled, and what the seeds cost; as it was (and no labels) when
    /// the sweep has no seeds or the column failed (`handover` is `None`).
    fn seeded(
        &self,
        theta_nu: f64,
        thetas: Vec<f64>,
        handover: Option<Handover>,
        sink: &dyn Sink,
    ) -> Result<(Vec<f64>, Vec<u8>, u64), JobError> {
        let seeds = self.spec.seeds;
        let Some(h) = handover.filter(|_| seeds > 0) else {
            return Ok((thetas, vec![], 0));
        };
        let followed = Column {
            theta_nu,
            thetas,
            theta_last: h.theta,
            error: None,
            rhs_evals: 0,
            slow_period: h.slow_period,
            map: MapUsed::Direct,
        };
        let params = self.spec.params.with_theta_nu(theta_nu);
        let cancel = || sink.cycle();
        match seeded_column(
            params,
            self.spec.settings,
            &followed,
            seeds,
            &self.opts,
            &cancel,
        ) {
            Ok(s) => Ok((s.thetas, s.attractor, s.rhs_evals)),
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
        let tn = self.grid[p.index];
        // A chain's head starts at θ0 if given, as if continued from it.
        let from = match (p.parent, self.spec.theta0) {
            (None, Some(theta0)) => Some(theta0),
            _ => neighbour.map(|h| h.theta),
        };
        let start = column_start(self.spec.params.kappa, tn, from);
        let slow_period = neighbour.and_then(|h| h.slow_period);
        let job = ColumnJob {
            sim: self.sims[p.index].as_ref().map_err(Clone::clone),
            theta_nu: tn,
            start,
            slow_period,
        };
        (job, (p, (start, slow_period)))
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
            let tn = self.grid[p.index];
            let col = catch_unwind(AssertUnwindSafe(|| {
                #[cfg(test)]
                tests::inject_panic(p.index);
                let (theta, slow) = start;
                let (params, settings) = (self.spec.params, self.spec.settings);
                Column::run_from(params, settings, tn, theta, slow, &self.opts, &cancel)
            }));
            self.deliver(p, start, col, sink)?;
        }
        Ok(())
    }
}

impl Job for SweepJob {
    fn lane(&self) -> Lane {
        Lane::Sweep
    }

    fn parallel(&self) -> bool {
        true
    }

    /// Waits for a column that may start (or for the end), then runs it
    /// and, in lanes, whatever else is ready, up to `width` columns; a lane
    /// that finds nothing ready retires.
    fn step(&self, width: usize, sink: &dyn Sink) -> Result<Status, JobError> {
        let Some((p, seed)) = wait_next(&self.schedule, &self.ready, || sink.stale())? else {
            return Ok(Status::Done);
        };
        let cancel = || sink.cycle();
        let mut pending = Some((p, seed.flatten()));
        let mut left = width.max(1);
        let mut in_flight: [Option<InFlight>; LANES] = [None; LANES];
        let mut stop: Option<JobError> = None;
        let lanes = catch_unwind(AssertUnwindSafe(|| {
            run_columns(&self.opts, &cancel, |lane, finished| {
                if let (Some(col), Some((p, start))) = (finished, in_flight[lane].take())
                    && stop.is_none()
                {
                    stop = self.deliver(p, start, Ok(col), sink).err();
                }
                if stop.is_some() || left == 0 {
                    return None;
                }
                let (p, neighbour) = pending.take().or_else(|| {
                    lock(&self.schedule)
                        .next()
                        .ok()
                        .map(|(p, seed)| (p, seed.flatten()))
                })?;
                left -= 1;
                let (job, flight) = self.column_job(p, neighbour);
                in_flight[lane] = Some(flight);
                #[cfg(test)]
                tests::inject_panic(p.index);
                Some(job)
            })
        }));
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
mod tests {
    use super::*;
    use crate::jobs::{Axis, Outcome};
    use crate::model::Params;
    use crate::sim::MapChoice;
    use crate::sim::default_settings;
    use crate::worker::{Command, Worker, WorkerConfig};
    use std::collections::HashSet;
    use std::sync::Arc;
    use std::sync::atomic::AtomicUsize;
    use std::time::Duration;

    /// Fault injection for the sweep threads: the column with this index
    /// panics (usize::MAX: none). Only this module's tests set it.
    static PANIC_AT_COLUMN: AtomicUsize = AtomicUsize::new(usize::MAX);

    pub(super) fn inject_panic(index: usize) {
        if index == PANIC_AT_COLUMN.load(Ordering::SeqCst) {
            panic!("injected panic in column {index}");
        }
    }

    #[test]
    fn a_panicking_column_is_reported_and_the_sweep_goes_on() {
        let w = Worker::spawn(
            WorkerConfig {
                coarse_columns: 4,
                ..WorkerConfig::default()
            },
            Arc::new(|| {}),
        );
        let sweep = |generation| Command::Sweep {
            generation,
            spec: SweepSpec {
                params: Params::default(),
                settings: default_settings(1e-8),
                theta_nu: Axis::new(0.2, 1.4, 10),
                transient: 3,
                keep: 3,
                map: MapChoice::Auto,
                theta0: None,
                seeds: 0,
            },
        };
        PANIC_AT_COLUMN.store(5, Ordering::SeqCst);
        assert!(w.send(sweep(1)));
        let mut columns = HashSet::new();
        let mut errors = vec![];
        let outcome = loop {
            match w.recv_timeout(Duration::from_secs(60)).expect("silent") {
                Update::Column { index, thetas, .. } => {
                    assert!(columns.insert(index));
                    assert_eq!(thetas.is_empty(), index == 5);
                }
                Update::Error { message, .. } => errors.push(message),
                Update::Finished { outcome, .. } => break outcome,
                _ => {}
            }
        };
        PANIC_AT_COLUMN.store(usize::MAX, Ordering::SeqCst);
        assert_eq!(columns.len(), 10);
        assert_eq!(errors.len(), 1);
        assert!(errors[0].contains("column 5") && errors[0].contains("injected panic"));
        assert!(matches!(outcome, Outcome::Failed(_)));
        assert!(w.send(sweep(2)));
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
