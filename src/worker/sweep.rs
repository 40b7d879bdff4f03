//! The sweep lane: a progressive bifurcation diagram on `sweep_threads`
//! threads.
//!
//! The order is fixed in advance by [`sweep_plan`], and so is where each
//! column starts: from the `theta_last` of one named, earlier column (its
//! nearest neighbour among those computed before it), through the core's
//! `column_start`. So the diagram does not depend on thread timing, and a
//! test can recompute every column with the core alone.
//!
//! 1. Coarse pass: `coarse` columns spread over the whole range, split into
//!    one contiguous chain per thread, each chain continued left to right
//!    (the first column of a chain starts at θ = θν). All of them are sent
//!    before any refinement starts.
//! 2. Fill-in: each gap between coarse columns is bisected level by level;
//!    a new column continues from the nearer end of its sub-gap (the left
//!    one on a tie). Level 1 everywhere, then level 2, and so on, so the
//!    diagram sharpens evenly.
//!
//! The threads take columns from the job's [`Schedule`], which hands out a
//! column once its parent is done, with the parent's last onset; each
//! thread steps up to `LANES` ready columns together.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Condvar, Mutex};

use super::orbit::{JobError, Pacer, run_guarded};
use super::plan::{PlannedColumn, sweep_plan};
use super::protocol::{Command, Generation, Lane, SweepSpec, Update};
use super::schedule::{PlanItem, Schedule, wait_next};
use super::{Shared, lock, panic_message, run_scoped};
use crate::model::ParamError;
use crate::sim::MapChoice;
use crate::sim::interpolant::MapUsed;
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

/// The next column of `sch` that may start, with its neighbour's last onset.
fn next_column(sch: &mut Columns) -> Option<(PlannedColumn, Option<Handover>)> {
    sch.next().ok().map(|(p, seed)| (p, seed.flatten()))
}

/// Runs one sweep-lane command.
pub(crate) fn run(shared: &Shared, cmd: Command) {
    if let Command::Sweep { generation, spec } = cmd {
        run_guarded(&shared.sweep, generation, || {
            sweep(shared, generation, &spec)
        });
    }
}

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

// Over clippy.toml's 150 lines until issue 27 splits it (listed in
// tests/function_lengths.rs).
#[allow(clippy::too_many_lines)]
fn sweep(shared: &Shared, generation: Generation, s: &SweepSpec) -> Result<(), JobError> {
    validate(s)?;
    let gate = &shared.sweep;
    let threads = shared.config.sweep_threads;
    let columns = s.theta_nu.steps;
    let opts = SweepOptions {
        transient: s.transient,
        keep: s.keep,
        map: MapChoice::Auto,
    };
    let grid = theta_nu_grid(s.theta_nu.from, s.theta_nu.to, columns);
    // Each thread steps up to LANES columns together, so the coarse pass
    // has that many chains per thread.
    let plan = sweep_plan(columns, shared.config.coarse_columns, threads * LANES);
    let schedule: Mutex<Columns> = Mutex::new(Schedule::new(plan, columns));
    let sims: Vec<Result<Simulator, SimError>> = grid
        .iter()
        .map(|&tn| Simulator::new(s.params.with_theta_nu(tn), s.settings))
        .collect();
    let ready = Condvar::new();
    let iterates = AtomicU64::new(0);
    let pacer = Mutex::new(Pacer::new());
    let failure: Mutex<Option<String>> = Mutex::new(None);

    // Sends a finished column (or the panic that ended it) to the front end
    // and marks it done in the schedule.
    let deliver = |p: PlannedColumn,
                   start: (f64, Option<usize>),
                   col: Result<Column, Box<dyn std::any::Any + Send>>|
     -> Result<(), JobError> {
        let tn = grid[p.index];
        // A failed column is still delivered (with what it kept) after
        // an Error naming it; its neighbours then start afresh from θν.
        let (col, problem) = match col {
            Ok(c) => match &c.error {
                None => (c, None),
                Some(SimError::Cancelled) => return Err(JobError::Stop),
                Some(e) => {
                    let msg = format!("column {} (theta-nu = {tn}): {e}", p.index);
                    let parameter = e.parameter();
                    (c, Some((msg, parameter)))
                }
            },
            Err(payload) => {
                let msg = format!(
                    "column {} (theta-nu = {tn}) panicked: {}",
                    p.index,
                    panic_message(&*payload)
                );
                *lock(&failure) = Some(msg.clone());
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
        let theta_last = if problem.is_none() {
            col.handover()
        } else {
            None
        };
        if let Some((message, parameter)) = problem {
            let e = Update::Error {
                generation,
                lane: Lane::Sweep,
                message,
                parameter,
            };
            gate.send(generation, e)?;
        }
        // Iterates this column ran (a failed one counts what it kept).
        let k = (opts.transient + col.thetas.len()) as u64;
        let n = iterates.fetch_add(k, Ordering::Relaxed) + k;
        gate.send(
            generation,
            Update::Column {
                generation,
                index: p.index,
                theta_nu: tn,
                thetas: col.thetas,
                coarse: p.coarse,
            },
        )?;
        let done = {
            let mut sch = lock(&schedule);
            sch.complete(p, theta_last);
            sch.done()
        };
        ready.notify_all();
        let rate = {
            let mut pc = lock(&pacer);
            (pc.due() || done == columns).then(|| pc.rate(n))
        };
        if let Some(iterates_per_second) = rate {
            gate.send(
                generation,
                Update::Progress {
                    generation,
                    lane: Lane::Sweep,
                    fraction: done as f64 / columns as f64,
                    iterates_per_second,
                },
            )?;
        }
        Ok(())
    };
    let cancel = || shared.stats.poll(gate, generation);

    let worker = || -> Result<(), JobError> {
        loop {
            // Wait for a column that may start (or for the end).
            let Some((p, seed)) = wait_next(&schedule, &ready, || gate.is_stale(generation))?
            else {
                return Ok(());
            };
            let first = (p, seed.flatten());
            // Then run it, and whatever else is ready, in lanes; a lane that
            // finds nothing ready retires, and once all have, this loop waits
            // again.
            let mut pending = Some(first);
            let mut in_flight: [Option<InFlight>; LANES] = [None; LANES];
            let mut stop: Option<JobError> = None;
            let lanes = catch_unwind(AssertUnwindSafe(|| {
                run_columns(&opts, &cancel, |lane, finished| {
                    if let (Some(col), Some((p, start))) = (finished, in_flight[lane].take())
                        && stop.is_none()
                    {
                        stop = deliver(p, start, Ok(col)).err();
                    }
                    if stop.is_some() {
                        return None;
                    }
                    let (p, neighbour) = pending
                        .take()
                        .or_else(|| next_column(&mut lock(&schedule)))?;
                    let tn = grid[p.index];
                    let start = column_start(s.params.kappa, tn, neighbour.map(|h| h.theta));
                    let slow_period = neighbour.and_then(|h| h.slow_period);
                    in_flight[lane] = Some((p, (start, slow_period)));
                    #[cfg(test)]
                    tests::inject_panic(p.index);
                    Some(ColumnJob {
                        sim: sims[p.index].as_ref().map_err(Clone::clone),
                        theta_nu: tn,
                        start,
                        slow_period,
                    })
                })
            }));
            if lanes.is_err() {
                // A panic in the lanes: the columns that were in flight are
                // run again one by one, each under its own guard, so that the
                // panic is reported with its column and the others complete
                // (with the values the lanes would have given them).
                for (p, start) in in_flight.into_iter().flatten() {
                    let tn = grid[p.index];
                    let col = catch_unwind(AssertUnwindSafe(|| {
                        #[cfg(test)]
                        tests::inject_panic(p.index);
                        let (theta, slow) = start;
                        Column::run_from(s.params, s.settings, tn, theta, slow, &opts, &cancel)
                    }));
                    deliver(p, start, col)?;
                }
            }
            if let Some(e) = stop {
                return Err(e);
            }
        }
    };

    run_scoped("oneblock-sweep", threads, &worker)?;
    match failure.into_inner().unwrap_or_else(|e| e.into_inner()) {
        // The panic was reported with its column; the sweep went on.
        Some(msg) => Err(JobError::Failed(msg)),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Params;
    use crate::sim::default_settings;
    use crate::worker::{Axis, Outcome, Worker, WorkerConfig};
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
