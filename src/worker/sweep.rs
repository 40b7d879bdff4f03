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

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

use super::orbit::{JobError, Pacer, run_guarded};
use super::protocol::{Command, Generation, Lane, SweepSpec, Update};
use super::{Shared, lock, panic_message, run_scoped};
use crate::model::ParamError;
use crate::sim::{
    Column, ColumnJob, LANES, SimError, Simulator, SweepOptions, column_start, run_columns,
    theta_nu_grid,
};

/// One column of a sweep plan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlannedColumn {
    /// Position in the final grid (0 … columns−1).
    pub index: usize,
    /// The column whose last onset this one starts from (`None`: θ = θν).
    pub parent: Option<usize>,
    /// Whether it belongs to the coarse pass.
    pub coarse: bool,
    /// 0 for the coarse pass, then the bisection level of the fill-in.
    pub level: u32,
}

/// The order and the starting neighbours of a progressive sweep of
/// `columns` columns with a coarse pass of `coarse` columns (at least the
/// two ends, at most `columns`) in `chains` chains. The coarse columns come first (chain
/// heads, then each chain's second column, …), then the fill-in by level
/// and position. Every index appears exactly once, and every parent comes
/// before its child.
pub fn sweep_plan(columns: usize, coarse: usize, chains: usize) -> Vec<PlannedColumn> {
    if columns == 0 {
        return vec![];
    }
    // At least both ends (a single column when that is all there is).
    let m = coarse.clamp(2, columns.max(2)).min(columns);
    // Spread with both ends included; a step of (n−1)/(m−1) ≥ 1 keeps the
    // rounded indices distinct.
    let idx: Vec<usize> = if m == 1 {
        vec![0]
    } else {
        (0..m)
            .map(|k| ((k * (columns - 1)) as f64 / (m - 1) as f64).round() as usize)
            .collect()
    };
    let chains = chains.clamp(1, m);
    let mut chain_of = Vec::with_capacity(m);
    for c in 0..chains {
        let (lo, hi) = (c * m / chains, (c + 1) * m / chains);
        chain_of.push((lo, hi));
    }
    let mut plan = Vec::with_capacity(columns);
    let longest = chain_of.iter().map(|(lo, hi)| hi - lo).max().unwrap_or(0);
    for pos in 0..longest {
        for &(lo, hi) in &chain_of {
            let k = lo + pos;
            if k < hi {
                plan.push(PlannedColumn {
                    index: idx[k],
                    parent: (pos > 0).then(|| idx[k - 1]),
                    coarse: true,
                    level: 0,
                });
            }
        }
    }
    let mut fill = Vec::with_capacity(columns - m);
    fn bisect(a: usize, b: usize, level: u32, out: &mut Vec<PlannedColumn>) {
        if b - a < 2 {
            return;
        }
        let mid = (a + b) / 2;
        let parent = if mid - a <= b - mid { a } else { b };
        out.push(PlannedColumn {
            index: mid,
            parent: Some(parent),
            coarse: false,
            level,
        });
        bisect(a, mid, level + 1, out);
        bisect(mid, b, level + 1, out);
    }
    for w in idx.windows(2) {
        bisect(w[0], w[1], 1, &mut fill);
    }
    fill.sort_by_key(|p| (p.level, p.index));
    plan.extend(fill);
    plan
}

/// Where each planned column stands.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Slot {
    Waiting,
    Running,
    /// Done, with where a neighbour continues (`None` if it failed).
    Done(Option<f64>),
}

/// The shared to-do list of one sweep.
struct Schedule {
    plan: Vec<PlannedColumn>,
    slots: Vec<Slot>,
    coarse_left: usize,
    done: usize,
    /// First plan position that may still be waiting.
    scan_from: usize,
}

impl Schedule {
    fn new(plan: Vec<PlannedColumn>, columns: usize) -> Self {
        let coarse_left = plan.iter().filter(|p| p.coarse).count();
        Schedule {
            plan,
            slots: vec![Slot::Waiting; columns],
            coarse_left,
            done: 0,
            scan_from: 0,
        }
    }

    /// The next column that may start, with its neighbour's last onset.
    /// `Err(true)`: none is ready yet; `Err(false)`: none is left.
    fn next(&mut self) -> Result<(PlannedColumn, Option<f64>), bool> {
        while self.scan_from < self.plan.len()
            && self.slots[self.plan[self.scan_from].index] != Slot::Waiting
        {
            self.scan_from += 1;
        }
        if self.scan_from == self.plan.len() {
            return Err(false);
        }
        for k in self.scan_from..self.plan.len() {
            let p = self.plan[k];
            if !p.coarse && self.coarse_left > 0 {
                break;
            }
            if self.slots[p.index] != Slot::Waiting {
                continue;
            }
            let start = match p.parent {
                None => Some(None),
                Some(q) => match self.slots[q] {
                    Slot::Done(th) => Some(th),
                    _ => None,
                },
            };
            if let Some(th) = start {
                self.slots[p.index] = Slot::Running;
                return Ok((p, th));
            }
        }
        Err(true)
    }

    fn complete(&mut self, p: PlannedColumn, theta_last: Option<f64>) {
        self.slots[p.index] = Slot::Done(theta_last);
        self.done += 1;
        if p.coarse {
            self.coarse_left -= 1;
        }
    }
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

fn sweep(shared: &Shared, generation: Generation, s: &SweepSpec) -> Result<(), JobError> {
    validate(s)?;
    let gate = &shared.sweep;
    let threads = shared.config.sweep_threads;
    let columns = s.theta_nu.steps;
    let opts = SweepOptions {
        transient: s.transient,
        keep: s.keep,
    };
    let grid = theta_nu_grid(s.theta_nu.from, s.theta_nu.to, columns);
    // Each thread steps up to LANES columns together, so the coarse pass
    // has that many chains per thread.
    let plan = sweep_plan(columns, shared.config.coarse_columns, threads * LANES);
    let schedule = Mutex::new(Schedule::new(plan, columns));
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
                   start: f64,
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
                    theta_last: start,
                    error: None,
                    rhs_evals: 0,
                };
                (empty, Some((msg, None)))
            }
        };
        let theta_last = problem.is_none().then_some(col.theta_last);
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
            sch.done
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
            let first = {
                let mut sch = lock(&schedule);
                loop {
                    if gate.is_stale(generation) {
                        return Err(JobError::Stop);
                    }
                    match sch.next() {
                        Ok(next) => break next,
                        Err(false) => return Ok(()),
                        Err(true) => {
                            // A timeout, so that a cancellation is seen even
                            // if no column completes.
                            sch = ready
                                .wait_timeout(sch, Duration::from_millis(20))
                                .map(|(g, _)| g)
                                .unwrap_or_else(|e| e.into_inner().0);
                        }
                    }
                }
            };
            // Then run it, and whatever else is ready, in lanes; a lane that
            // finds nothing ready retires, and once all have, this loop waits
            // again.
            let mut pending = Some(first);
            let mut in_flight: [Option<(PlannedColumn, f64)>; LANES] = [None; LANES];
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
                    let (p, neighbour) = pending.take().or_else(|| lock(&schedule).next().ok())?;
                    let tn = grid[p.index];
                    let start = column_start(s.params.kappa, tn, neighbour);
                    in_flight[lane] = Some((p, start));
                    #[cfg(test)]
                    tests::inject_panic(p.index);
                    Some(ColumnJob {
                        sim: sims[p.index].as_ref().map_err(Clone::clone),
                        theta_nu: tn,
                        start,
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
                        Column::run(s.params, s.settings, tn, start, &opts, &cancel)
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

    /// Fault injection for the sweep threads: the column with this index
    /// panics (usize::MAX: none). Only this module's tests set it.
    static PANIC_AT_COLUMN: AtomicUsize = AtomicUsize::new(usize::MAX);

    pub(super) fn inject_panic(index: usize) {
        if index == PANIC_AT_COLUMN.load(Ordering::SeqCst) {
            panic!("injected panic in column {index}");
        }
    }

    fn check_plan(columns: usize, coarse: usize, chains: usize) {
        let plan = sweep_plan(columns, coarse, chains);
        assert_eq!(plan.len(), columns, "{columns} {coarse} {chains}");
        let idx: HashSet<usize> = plan.iter().map(|p| p.index).collect();
        assert_eq!(idx.len(), columns, "each column once");
        assert!(idx.iter().all(|&i| i < columns));
        let m = coarse.clamp(2, columns.max(2)).min(columns);
        assert!(plan[..m].iter().all(|p| p.coarse && p.level == 0));
        assert!(plan[m..].iter().all(|p| !p.coarse && p.level > 0));
        // The coarse pass spans the range: both ends, even gaps.
        let mut c: Vec<usize> = plan[..m].iter().map(|p| p.index).collect();
        c.sort();
        assert_eq!(c[0], 0);
        if m > 1 {
            assert_eq!(c[m - 1], columns - 1);
            let gaps: Vec<usize> = c.windows(2).map(|w| w[1] - w[0]).collect();
            let (lo, hi) = (
                gaps.iter().min().expect("gaps"),
                gaps.iter().max().expect("gaps"),
            );
            assert!(hi - lo <= 1, "even coarse gaps {gaps:?}");
        }
        // Parents come earlier, and are the nearest earlier column.
        let pos: Vec<usize> = {
            let mut v = vec![0; columns];
            for (k, p) in plan.iter().enumerate() {
                v[p.index] = k;
            }
            v
        };
        let heads = plan.iter().filter(|p| p.parent.is_none()).count();
        assert_eq!(heads, chains.clamp(1, m));
        for (k, p) in plan.iter().enumerate() {
            if let Some(q) = p.parent {
                assert!(pos[q] < k);
                let d = q.abs_diff(p.index);
                let nearer = plan[..k]
                    .iter()
                    .filter(|e| e.coarse || !p.coarse)
                    .map(|e| e.index.abs_diff(p.index))
                    .min()
                    .expect("a parent exists, so an earlier column does");
                if !p.coarse {
                    assert_eq!(d, nearer, "column {} continues from the nearest", p.index);
                }
            }
        }
        // Levels do not decrease.
        assert!(plan.windows(2).all(|w| w[0].level <= w[1].level));
    }

    #[test]
    fn plans_cover_every_column_once_coarse_first() {
        for columns in [1, 2, 3, 7, 10, 64, 65, 100, 400] {
            for coarse in [1, 2, 5, 8, 64, 1000] {
                for chains in [1, 2, 3] {
                    check_plan(columns, coarse, chains);
                }
            }
        }
        assert!(sweep_plan(0, 8, 2).is_empty());
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
