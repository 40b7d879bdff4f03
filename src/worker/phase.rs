//! The phase lane: a progressive phase diagram in (θν, κ) on `sweep_threads`
//! threads, calling the core's `phase_cell` for every cell.
//!
//! As for the bifurcation sweep, the order and each cell's starting neighbour
//! are fixed in advance by [`phase_plan`], so the diagram does not depend on
//! thread timing and a test can recompute every cell with the core alone.
//!
//! 1. Coarse lattice: about every `stride`-th row and column, both ends
//!    included. Each coarse row is a continued chain along θν exactly as the
//!    core's `phase_row` runs one (its first cell from θ = θν), so the coarse
//!    pass equals `phase_grid` on the coarse lattice. All of it is sent
//!    before any refinement starts.
//! 2. Refinement: the gaps between coarse rows and columns are bisected level
//!    by level (a cell's level is the larger of its row's and its column's),
//!    so the whole picture sharpens evenly. A new cell continues from the
//!    nearest cell already computed in its κ row (the core continues along
//!    θν; left on a tie) or, when its row has none yet, from the nearest in
//!    its θν column (lower κ on a tie).
//!
//! A cell continued from a chaotic one gets the shorter transient, as in
//! `phase_row`; one continued from a failed one starts at θ = θν.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::{Duration, Instant};

use super::orbit::{FLUSH_INTERVAL, JobError, Pacer, run_guarded};
use super::protocol::{Axis, Command, Generation, GridCell, Lane, PhaseSpec, Update};
use super::{Shared, lock, panic_message, run_scoped};
use crate::integrate::SolverSettings;
use crate::model::{ParamError, Params};
use crate::sim::phase::{CellClass, PhaseCell, PhaseOptions, phase_cell};
use crate::sim::{SimError, Simulator, column_start, theta_nu_grid};

/// Rows and columns of the coarse lattice: about every this many.
pub const COARSE_STRIDE: usize = 4;
/// `PhaseCells` go out every this many cells, or every `FLUSH_INTERVAL`.
pub const CELL_BATCH: usize = 16;
/// The most rows or columns of a grid (as `oneblock phase`).
pub const MAX_STEPS: usize = 10_000;
/// The most cells of a grid (as `oneblock phase`).
pub const MAX_CELLS: usize = 4_000_000;

/// One cell of a phase plan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlannedCell {
    /// κ row (0 … rows−1).
    pub row: usize,
    /// θν column (0 … columns−1).
    pub column: usize,
    /// The (row, column) whose last onset this cell starts from (`None`:
    /// θ = θν).
    pub parent: Option<(usize, usize)>,
    /// Whether it belongs to the coarse lattice.
    pub coarse: bool,
    /// 0 for the coarse lattice, then the bisection level of the refinement.
    pub level: u32,
}

/// The level of each index 0 … n−1 along one axis: 0 for the coarse
/// indices (about every `stride`-th, both ends included, spread evenly),
/// then the bisection depth between them.
fn axis_levels(n: usize, stride: usize) -> Vec<u32> {
    let mut level = vec![u32::MAX; n];
    if n == 0 {
        return level;
    }
    let m = if n == 1 {
        1
    } else {
        ((n - 1).div_ceil(stride.max(1)) + 1).min(n)
    };
    // A step of (n−1)/(m−1) ≥ 1 keeps the rounded indices distinct.
    let idx: Vec<usize> = if m == 1 {
        vec![0]
    } else {
        (0..m)
            .map(|k| ((k * (n - 1)) as f64 / (m - 1) as f64).round() as usize)
            .collect()
    };
    for &i in &idx {
        level[i] = 0;
    }
    fn bisect(a: usize, b: usize, depth: u32, level: &mut [u32]) {
        if b - a < 2 {
            return;
        }
        let mid = (a + b) / 2;
        level[mid] = depth;
        bisect(a, mid, depth + 1, level);
        bisect(mid, b, depth + 1, level);
    }
    for w in idx.windows(2) {
        bisect(w[0], w[1], 1, &mut level);
    }
    level
}

/// The order and starting neighbours of a progressive phase diagram of
/// `rows` × `columns` cells with a coarse lattice of about every `stride`-th
/// row and column (see the module's doc). Every cell appears exactly once,
/// coarse cells first, levels never decrease, and every parent comes before
/// its child.
pub fn phase_plan(rows: usize, columns: usize, stride: usize) -> Vec<PlannedCell> {
    let lr = axis_levels(rows, stride);
    let lc = axis_levels(columns, stride);
    let level = |r: usize, c: usize| lr[r].max(lc[c]);
    let mut plan = Vec::with_capacity(rows * columns);
    for r in 0..rows {
        for c in 0..columns {
            let l = level(r, c);
            // Earlier in the order (level, row, column), on the same row:
            // to the left anything of level ≤ l, to the right only lower.
            let left = (0..c).rev().find(|&k| level(r, k) <= l);
            let right = if l == 0 {
                None
            } else {
                (c + 1..columns).find(|&k| level(r, k) < l)
            };
            let in_row = match (left, right) {
                (Some(a), Some(b)) => Some(if c - a <= b - c { a } else { b }),
                (a, b) => a.or(b),
            };
            let parent = match in_row {
                Some(k) => Some((r, k)),
                // A coarse row's first cell starts from θν, as in phase_row.
                None if l == 0 => None,
                None => {
                    let below = (0..r).rev().find(|&k| level(k, c) <= l);
                    let above = (r + 1..rows).find(|&k| level(k, c) < l);
                    match (below, above) {
                        (Some(a), Some(b)) => Some(if r - a <= b - r { a } else { b }),
                        (a, b) => a.or(b),
                    }
                    .map(|k| (k, c))
                }
            };
            plan.push(PlannedCell {
                row: r,
                column: c,
                parent,
                coarse: l == 0,
                level: l,
            });
        }
    }
    plan.sort_by_key(|p| (p.level, p.row, p.column));
    plan
}

/// Where a finished cell's neighbours continue.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seed {
    /// Its last onset (`None` if it failed: neighbours start at θ = θν).
    pub theta_last: Option<f64>,
    /// Whether it was chaotic (neighbours get the shorter transient).
    pub chaos: bool,
}

impl Seed {
    /// What `cell` leaves for its neighbours, as `phase_row` keeps it.
    pub fn of(cell: &PhaseCell) -> Seed {
        Seed {
            theta_last: cell.error.is_none().then_some(cell.theta_last),
            chaos: cell.class == CellClass::Chaos,
        }
    }
}

/// Runs one cell at (`kappa`, `theta_nu`) continued from `parent` (its seed)
/// exactly as `phase_row` runs the cell after it: the start moved onto the
/// new exit arc, and the shorter transient after a chaotic neighbour.
pub fn run_cell(
    params: Params,
    settings: SolverSettings,
    kappa: f64,
    theta_nu: f64,
    parent: Option<Seed>,
    opts: &PhaseOptions,
    cancel: &dyn Fn() -> bool,
) -> PhaseCell {
    let start = column_start(kappa, theta_nu, parent.and_then(|s| s.theta_last));
    let after_chaos = PhaseOptions {
        transient: opts.transient.min(opts.transient_after_chaos),
        ..*opts
    };
    let o = if parent.is_some_and(|s| s.chaos) && opts.early_exit {
        &after_chaos
    } else {
        opts
    };
    let p = Params {
        kappa,
        theta_nu,
        ..params
    };
    phase_cell(p, settings, start, o, cancel)
}

/// Where each planned cell stands.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Slot {
    Waiting,
    Running,
    Done(Seed),
}

/// The shared to-do list of one phase job.
struct Schedule {
    plan: Vec<PlannedCell>,
    columns: usize,
    slots: Vec<Slot>,
    coarse_left: usize,
    done: usize,
    /// First plan position that may still be waiting.
    scan_from: usize,
}

impl Schedule {
    fn new(plan: Vec<PlannedCell>, rows: usize, columns: usize) -> Self {
        let coarse_left = plan.iter().filter(|p| p.coarse).count();
        Schedule {
            plan,
            columns,
            slots: vec![Slot::Waiting; rows * columns],
            coarse_left,
            done: 0,
            scan_from: 0,
        }
    }

    fn slot(&self, r: usize, c: usize) -> Slot {
        self.slots[r * self.columns + c]
    }

    /// The next cell that may start, with its parent's seed.
    /// `Err(true)`: none is ready yet; `Err(false)`: none is left.
    fn next(&mut self) -> Result<(PlannedCell, Option<Seed>), bool> {
        while self.scan_from < self.plan.len() {
            let p = self.plan[self.scan_from];
            if self.slot(p.row, p.column) != Slot::Waiting {
                self.scan_from += 1;
            } else {
                break;
            }
        }
        if self.scan_from == self.plan.len() {
            return Err(false);
        }
        for k in self.scan_from..self.plan.len() {
            let p = self.plan[k];
            // Refinement waits for the whole coarse lattice, so that the
            // picture is complete, if coarse, as early as it can be.
            if !p.coarse && self.coarse_left > 0 {
                break;
            }
            if self.slot(p.row, p.column) != Slot::Waiting {
                continue;
            }
            let start = match p.parent {
                None => Some(None),
                Some((r, c)) => match self.slot(r, c) {
                    Slot::Done(seed) => Some(Some(seed)),
                    _ => None,
                },
            };
            if let Some(seed) = start {
                self.slots[p.row * self.columns + p.column] = Slot::Running;
                return Ok((p, seed));
            }
        }
        Err(true)
    }

    /// Marks `p` done; true if it was the last coarse cell.
    fn complete(&mut self, p: PlannedCell, seed: Seed) -> bool {
        self.slots[p.row * self.columns + p.column] = Slot::Done(seed);
        self.done += 1;
        if p.coarse {
            self.coarse_left -= 1;
            return self.coarse_left == 0;
        }
        false
    }
}

/// Cells finished and not yet sent.
struct Outbox {
    coarse: Vec<GridCell>,
    fine: Vec<GridCell>,
    last_flush: Instant,
}

/// Runs one phase-lane command.
pub(crate) fn run(shared: &Shared, cmd: Command) {
    if let Command::Phase { generation, spec } = cmd {
        run_guarded(&shared.phase, generation, || {
            phase(shared, generation, &spec)
        });
    }
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
    if s.transient > 1_000_000 {
        let range = "must lie in [0, 1000000]";
        return Err(ParamError::new("transient", s.transient as f64, range).into());
    }
    if !(16..=1_000_000).contains(&s.keep) {
        let range =
            "must lie in [16, 1000000] (the Lyapunov exponent's error needs 8 batches of 2)";
        return Err(ParamError::new("keep", s.keep as f64, range).into());
    }
    // The model's own ranges (γ, ν, Ω, κ in [1e-6, 1e6]) and the solver's.
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

fn phase(shared: &Shared, generation: Generation, s: &PhaseSpec) -> Result<(), JobError> {
    validate(s)?;
    let gate = &shared.phase;
    let threads = shared.config.sweep_threads;
    let opts = s.options();
    let (columns, rows) = (s.theta_nu.steps, s.kappa.steps);
    let theta_nus = theta_nu_grid(s.theta_nu.from, s.theta_nu.to, columns);
    let kappas = theta_nu_grid(s.kappa.from, s.kappa.to, rows);
    let total = rows * columns;
    let plan = phase_plan(rows, columns, COARSE_STRIDE);
    let schedule = Mutex::new(Schedule::new(plan, rows, columns));
    let ready = Condvar::new();
    let outbox = Mutex::new(Outbox {
        coarse: Vec::new(),
        fine: Vec::new(),
        last_flush: Instant::now(),
    });
    let iterates = AtomicU64::new(0);
    let pacer = Mutex::new(Pacer::new());
    let failure: Mutex<Option<String>> = Mutex::new(None);
    let first_failed_cell = Mutex::new(false);

    // Sends what is waiting, coarse cells first, under the outbox lock so
    // that two threads flushing cannot reorder batches.
    let flush = || -> Result<(), JobError> {
        let mut ob = lock(&outbox);
        for (cells, coarse) in [
            (std::mem::take(&mut ob.coarse), true),
            (std::mem::take(&mut ob.fine), false),
        ] {
            if !cells.is_empty() {
                gate.send(
                    generation,
                    Update::PhaseCells {
                        generation,
                        cells,
                        coarse,
                    },
                )?;
            }
        }
        ob.last_flush = Instant::now();
        Ok(())
    };

    let worker = || -> Result<(), JobError> {
        loop {
            let (p, seed) = {
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
                            // if no cell completes.
                            sch = ready
                                .wait_timeout(sch, Duration::from_millis(20))
                                .map(|(g, _)| g)
                                .unwrap_or_else(|e| e.into_inner().0);
                        }
                    }
                }
            };
            let (kappa, tn) = (kappas[p.row], theta_nus[p.column]);
            let cancel = || shared.stats.poll(gate, generation);
            let cell = catch_unwind(AssertUnwindSafe(|| {
                #[cfg(test)]
                if p.row * columns + p.column == tests::PANIC_AT_CELL.load(Ordering::SeqCst) {
                    panic!("injected panic in cell {}", p.row * columns + p.column);
                }
                run_cell(s.params, s.settings, kappa, tn, seed, &opts, &cancel)
            }));
            let where_ = format!(
                "cell (kappa = {kappa}, theta-nu = {tn}; row {}, column {})",
                p.row, p.column
            );
            let (cell, problem) = match cell {
                Ok(c) => match &c.error {
                    None => (c, None),
                    Some(SimError::Cancelled) => return Err(JobError::Stop),
                    Some(e) => {
                        // The first failure is reported; the rest show as
                        // failed cells in the grid (a flood of errors would
                        // hide the picture).
                        let first = !std::mem::replace(&mut *lock(&first_failed_cell), true);
                        let report = first.then(|| (format!("{where_}: {e}"), e.parameter()));
                        (c, report)
                    }
                },
                Err(payload) => {
                    let msg = format!("{where_} panicked: {}", panic_message(&*payload));
                    *lock(&failure) = Some(msg.clone());
                    let failed = PhaseCell::failed(tn, kappa, tn);
                    (failed, Some((msg, None)))
                }
            };
            let mut seed_out = Seed::of(&cell);
            if cell.class == CellClass::Failed {
                seed_out.theta_last = None;
            }
            if let Some((message, parameter)) = problem {
                gate.send(
                    generation,
                    Update::Error {
                        generation,
                        lane: Lane::Phase,
                        message,
                        parameter,
                    },
                )?;
            }
            let n = iterates.fetch_add(cell.iterates, Ordering::Relaxed) + cell.iterates;
            // Into the outbox before the schedule hears of it: once the last
            // coarse cell is marked done, every coarse cell is in the outbox,
            // ahead of any refinement cell.
            let queued = {
                let mut ob = lock(&outbox);
                let gc = GridCell {
                    row: p.row,
                    column: p.column,
                    cell,
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
            let (done, coarse_done) = {
                let mut sch = lock(&schedule);
                let last_coarse = sch.complete(p, seed_out);
                (sch.done, last_coarse)
            };
            ready.notify_all();
            if queued.0 >= CELL_BATCH || queued.1 || coarse_done || done == total {
                flush()?;
            }
            let rate = {
                let mut pc = lock(&pacer);
                (pc.due() || done == total).then(|| pc.rate(n))
            };
            if let Some(iterates_per_second) = rate {
                gate.send(
                    generation,
                    Update::Progress {
                        generation,
                        lane: Lane::Phase,
                        fraction: done as f64 / total as f64,
                        iterates_per_second,
                    },
                )?;
            }
        }
    };

    run_scoped("oneblock-phase", threads.min(total), &worker)?;
    // Whatever a thread left behind (normally nothing: the last cell flushes).
    flush()?;
    match failure.into_inner().unwrap_or_else(|e| e.into_inner()) {
        // The panic was reported with its cell; the grid went on.
        Some(msg) => Err(JobError::Failed(msg)),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::default_settings;
    use crate::worker::{Outcome, Worker, WorkerConfig};
    use std::collections::HashSet;
    use std::sync::Arc;
    use std::sync::atomic::AtomicUsize;

    /// Fault injection for the phase threads: the cell with this flat index
    /// (row·columns + column) panics (usize::MAX: none). Only this module's
    /// tests set it.
    pub(super) static PANIC_AT_CELL: AtomicUsize = AtomicUsize::new(usize::MAX);

    fn check_plan(rows: usize, columns: usize, stride: usize) {
        let plan = phase_plan(rows, columns, stride);
        let what = format!("{rows} x {columns} stride {stride}");
        assert_eq!(plan.len(), rows * columns, "{what}");
        let cells: HashSet<(usize, usize)> = plan.iter().map(|p| (p.row, p.column)).collect();
        assert_eq!(cells.len(), rows * columns, "each cell once: {what}");
        let n_coarse = plan.iter().filter(|p| p.coarse).count();
        assert!(plan[..n_coarse].iter().all(|p| p.coarse && p.level == 0));
        assert!(plan[n_coarse..].iter().all(|p| !p.coarse && p.level > 0));
        assert!(plan.windows(2).all(|w| w[0].level <= w[1].level), "{what}");
        // The coarse lattice holds the four corners and spans evenly.
        for corner in [
            (0, 0),
            (0, columns - 1),
            (rows - 1, 0),
            (rows - 1, columns - 1),
        ] {
            assert!(
                plan[..n_coarse].iter().any(|p| (p.row, p.column) == corner),
                "{what}: corner {corner:?}"
            );
        }
        let mut coarse_cols: Vec<usize> = plan[..n_coarse]
            .iter()
            .filter(|p| p.row == 0)
            .map(|p| p.column)
            .collect();
        coarse_cols.sort();
        let gaps: Vec<usize> = coarse_cols.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(gaps.iter().all(|&g| g <= stride), "{what}: {gaps:?}");
        // Parents come earlier; coarse parents are the left neighbour in the
        // row; a refinement cell's parent is in its row or column.
        let mut pos = vec![0; rows * columns];
        for (k, p) in plan.iter().enumerate() {
            pos[p.row * columns + p.column] = k;
        }
        for (k, p) in plan.iter().enumerate() {
            match p.parent {
                None => assert!(p.coarse, "{what}: {p:?} has no parent"),
                Some((r, c)) => {
                    assert!(pos[r * columns + c] < k, "{what}: {p:?}");
                    assert!(r == p.row || c == p.column, "{what}: {p:?}");
                    if p.coarse {
                        assert!(r == p.row && c < p.column, "{what}: {p:?}");
                    }
                    if r == p.row {
                        // The nearest earlier cell of the row.
                        let d = c.abs_diff(p.column);
                        let nearer = plan[..k]
                            .iter()
                            .filter(|e| e.row == p.row && e.column.abs_diff(p.column) < d)
                            .count();
                        assert_eq!(nearer, 0, "{what}: {p:?}");
                    } else {
                        // Only when the row had nothing computed before it.
                        assert!(!plan[..k].iter().any(|e| e.row == p.row), "{what}: {p:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn plans_cover_every_cell_once_coarse_first() {
        for rows in [1, 2, 3, 5, 9, 30] {
            for columns in [1, 2, 4, 7, 30, 61] {
                for stride in [1, 2, 4] {
                    check_plan(rows, columns, stride);
                }
            }
        }
        // 30 x 30 at stride 4: a 9 x 9 coarse lattice.
        let plan = phase_plan(30, 30, 4);
        assert_eq!(plan.iter().filter(|p| p.coarse).count(), 81);
    }

    #[test]
    fn a_panicking_cell_is_reported_and_the_grid_goes_on() {
        let w = Worker::spawn(WorkerConfig::default(), Arc::new(|| {}));
        let job = |generation| Command::Phase {
            generation,
            spec: PhaseSpec {
                params: Params::default(),
                settings: default_settings(1e-8),
                theta_nu: Axis::new(0.2, 0.6, 5),
                kappa: Axis::new(2.0, 3.0, 2),
                transient: 40,
                keep: 16,
            },
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
