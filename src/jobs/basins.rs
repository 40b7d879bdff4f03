//! The Basins job: every attractor and basin of f over the exit arc
//! (`sim::attractors`, a cell graph, no orbit budget) at each of a range
//! of columns of one parameter (θν for the Basins view and `oneblock
//! figure --view basins`, any of θν, κ, γ, ν, Ω for `oneblock attractors
//! --param`); and the same at the current parameters alone, with a
//! chaotic attractor's density, for the return map's basin band.
//!
//! A unit is one column, any thread takes the next ([`Job::parallel`]).
//! They are handed out coarse first (both ends, the middle, then the
//! quarters, …: [`coarse_first`]), so a diagram sharpens evenly while it
//! fills in. A column starts f's interpolant from its parent's layout
//! (`AttractorsRun::starting_from`: the same checks, about half the
//! work), the parent being fixed by the grid alone ([`parents`]: the
//! nearest column handed out before it), so every host computes the same
//! numbers; a thread whose column's parent is still running waits for it.
//! A column that fails is sent with its error (its children start from
//! nothing); the others go on.

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use super::orbit::{Pacer, paced_progress};
use super::protocol::{Axis, BasinColumn, Update};
use super::{Job, JobError, Sink, Status, lock};
use crate::integrate::SolverSettings;
use crate::model::{ParamError, Params};
use crate::sim::attractors::events::Locator;
use crate::sim::attractors::tracks::identify;
use crate::sim::attractors::{AttractorError, AttractorsRun, CellOptions, Found};
use crate::sim::continuation::ContParam;
use crate::sim::{SimError, Simulator, param_grid};

/// Attractors and basins over `axis`, columns of `param`, at the other
/// parameters of `params` (`param`'s own value there is ignored: it is
/// the axis).
#[derive(Clone, Debug, PartialEq)]
pub struct BasinsSpec {
    /// The model's parameters (κ, γ, ν, Ω).
    pub params: Params,
    /// The solver and its accuracy.
    pub settings: SolverSettings,
    /// The parameter varied along the axis (θν for the Basins view).
    pub param: ContParam,
    /// Its columns: evenly spaced, in log10 of the value for a parameter
    /// that spans decades ([`crate::sim::param_grid`]), as a bifurcation
    /// diagram's.
    pub axis: Axis,
    /// The cell graph asked for: `CellOptions::column()` for a diagram,
    /// `CellOptions::default()` (with a chaotic set's density) for one
    /// point.
    pub cells: CellOptions,
}

/// Attractors and basins at one point, at `params`' own θν, with a
/// chaotic set's density: the return map's band (its own kind of job, as
/// new parameters stop it rather than run it again).
#[derive(Clone, Debug, PartialEq)]
pub struct MapBasinsSpec(pub BasinsSpec);

impl MapBasinsSpec {
    /// One point, at `params`' own θν, with densities.
    pub fn here(params: Params, settings: SolverSettings) -> Self {
        MapBasinsSpec(BasinsSpec {
            params,
            settings,
            param: ContParam::ThetaNu,
            axis: Axis::new(params.theta_nu, params.theta_nu, 1),
            cells: CellOptions::default(),
        })
    }
}

/// The grid's indices, coarse first: 0 and n − 1, then the midpoints of
/// ever finer halvings, each index once.
pub fn coarse_first(n: usize) -> Vec<usize> {
    let mut order = Vec::with_capacity(n);
    let mut seen = vec![false; n];
    let mut push = |i: usize, order: &mut Vec<usize>| {
        if i < n && !seen[i] {
            seen[i] = true;
            order.push(i);
        }
    };
    if n == 0 {
        return order;
    }
    push(0, &mut order);
    push(n - 1, &mut order);
    let mut stride = (n - 1).next_power_of_two().max(1);
    while stride >= 1 {
        (0..n).step_by(stride).for_each(|i| push(i, &mut order));
        if stride == 1 {
            break;
        }
        stride /= 2;
    }
    order
}

/// Each column's parent in `order`: the nearest column that comes before
/// it there (the lower on a tie); none for the first two (the range's
/// ends, built from nothing side by side).
pub fn parents(order: &[usize]) -> Vec<Option<usize>> {
    let mut seen = std::collections::BTreeSet::new();
    let mut parent = vec![None; order.len()];
    for (k, &i) in order.iter().enumerate() {
        if k >= 2 {
            let below = seen.range(..i).next_back().copied();
            let above = seen.range(i..).next().copied();
            parent[i] = match (below, above) {
                (Some(b), Some(a)) if a - i < i - b => Some(a),
                (Some(b), _) => Some(b),
                (None, a) => a,
            };
        }
        seen.insert(i);
    }
    parent
}

/// A column's interpolant layout, once it is done.
#[derive(Clone, Debug, Default)]
enum Layout {
    #[default]
    Pending,
    /// Done: its layout, none where it failed.
    Done(Option<crate::sim::Layout>),
}

/// The Basins job in progress.
pub(crate) struct BasinsJob {
    spec: BasinsSpec,
    grid: Vec<f64>,
    order: Vec<usize>,
    next: AtomicUsize,
    done: AtomicUsize,
    pacer: Mutex<Pacer>,
    /// A column paused part-way (only the single-threaded host pauses),
    /// resumed by the next step.
    parked: Mutex<Option<(usize, AttractorsRun)>>,
    /// Each column's attractors as they arrive, for the events located
    /// once the last one is in.
    found: Mutex<Vec<Option<Found>>>,
    /// Each column's parent ([`parents`]) and its layout when done, which
    /// a waiting column is woken for.
    parent: Vec<Option<usize>>,
    layouts: Mutex<Vec<Layout>>,
    layout_done: std::sync::Condvar,
}

impl BasinsJob {
    /// Checks the spec (finite ends, a column at least, parameters a
    /// simulator takes at both ends) and plans its columns.
    pub fn new(spec: BasinsSpec) -> Result<Self, JobError> {
        let (param, a) = (spec.param, spec.axis);
        for v in [a.from, a.to] {
            if !v.is_finite() {
                let range = "the basins' range must have finite ends";
                return Err(SimError::from(ParamError::new(param.name(), v, range)).into());
            }
        }
        if a.steps == 0 {
            let e = ParamError::new("columns", 0.0, "must be at least 1");
            return Err(SimError::from(e).into());
        }
        for v in [a.from, a.to] {
            Simulator::new(param.set(&spec.params, v), spec.settings)?;
        }
        let grid = param_grid(param, a.from, a.to, a.steps);
        let order = coarse_first(grid.len());
        Ok(BasinsJob {
            parent: parents(&order),
            layouts: Mutex::new(vec![Layout::Pending; grid.len()]),
            layout_done: std::sync::Condvar::new(),
            order,
            grid,
            spec,
            next: AtomicUsize::new(0),
            done: AtomicUsize::new(0),
            pacer: Mutex::new(Pacer::new()),
            parked: Mutex::new(None),
            found: Mutex::new(vec![None; a.steps]),
        })
    }

    /// Column `index` from where `run` left it (a new run if `None`),
    /// piece by piece until it is done (`Some`) or the host wants its
    /// thread back (`None`, the run parked); `Err` only when the job must
    /// stop.
    fn column(
        &self,
        index: usize,
        run: Option<AttractorsRun>,
        sink: &dyn Sink,
    ) -> Result<Option<BasinColumn>, JobError> {
        let value = self.grid[index];
        let params = self.spec.param.set(&self.spec.params, value);
        let cancel = || sink.cycle();
        let found = match (run, Simulator::new(params, self.spec.settings)) {
            (_, Err(e)) => Err(e.to_string()),
            (run, Ok(sim)) => {
                let mut run = match run {
                    Some(run) => run,
                    None => AttractorsRun::new(&sim, &self.spec.cells)
                        .starting_from(self.parent_layout(index, sink)?),
                };
                loop {
                    match run.advance(&cancel) {
                        None if sink.pause() => {
                            *lock(&self.parked) = Some((index, run));
                            return Ok(None);
                        }
                        None => {}
                        Some(Ok(f)) => break Ok(f),
                        Some(Err(AttractorError::Sim(SimError::Cancelled))) => {
                            return Err(JobError::Stop);
                        }
                        Some(Err(e)) => break Err(e.to_string()),
                    }
                }
            }
        };
        Ok(Some(BasinColumn {
            index,
            value,
            theta_nu: params.theta_nu,
            found,
        }))
    }
}

impl BasinsJob {
    /// Column `index`'s parent's layout, waited for while the parent runs
    /// on another thread (`Stop` if the job must stop meanwhile); none for
    /// a column with no parent or whose parent failed.
    fn parent_layout(
        &self,
        index: usize,
        sink: &dyn Sink,
    ) -> Result<Option<crate::sim::Layout>, JobError> {
        let Some(p) = self.parent.get(index).copied().flatten() else {
            return Ok(None);
        };
        let mut layouts = lock(&self.layouts);
        loop {
            if let Layout::Done(l) = &layouts[p] {
                return Ok(l.clone());
            }
            if sink.stale() {
                return Err(JobError::Stop);
            }
            let wait = std::time::Duration::from_millis(5);
            layouts = match self.layout_done.wait_timeout(layouts, wait) {
                Ok((g, _)) => g,
                Err(poisoned) => poisoned.into_inner().0,
            };
        }
    }

    /// Column `index` done (its layout, none where it failed): the
    /// columns waiting for it go on.
    fn layout_finished(&self, index: usize, layout: Option<crate::sim::Layout>) {
        if let Some(slot) = lock(&self.layouts).get_mut(index) {
            *slot = Layout::Done(layout);
        }
        self.layout_done.notify_all();
    }

    /// The tracks and their events over every column, sent as one update
    /// (a range of two columns or more). The thread that finished the
    /// last column locates them, on every core. Not on a host that runs
    /// the job a slice of time at a time (the page, [`Sink::sliced`]): a
    /// continuation or a bisection on the cell graph cannot stop part-way
    /// for the page's frame, so the page shows tracks without events and
    /// says so.
    fn events(&self, sink: &dyn Sink) -> Result<(), JobError> {
        if self.grid.len() < 2 || sink.sliced() {
            return Ok(());
        }
        let found = lock(&self.found).clone();
        let refs: Vec<Option<&Found>> = found.iter().map(Option::as_ref).collect();
        let ids = identify(&refs);
        let locator = Locator {
            base: self.spec.params,
            settings: self.spec.settings,
            param: self.spec.param,
            cells: self.spec.cells,
        };
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        let cancel = || sink.cycle();
        let events = locator.locate(&self.grid, &refs, ids, threads, &cancel);
        if sink.stale() {
            return Err(JobError::Stop);
        }
        sink.send(Update::BasinEvents {
            generation: sink.generation(),
            lane: sink.lane(),
            events: Box::new(events),
        })?;
        Ok(())
    }
}

impl Job for BasinsJob {
    fn parallel(&self) -> bool {
        true
    }

    /// Columns, one after another, until none is left for this caller (or,
    /// on the single-threaded host, until it wants its thread back: a
    /// column pauses between its pieces, the arc's interpolant, each level
    /// of subdivision and each verdict).
    fn step(&self, _width: usize, sink: &dyn Sink) -> Result<Status, JobError> {
        loop {
            let (index, run) = match lock(&self.parked).take() {
                Some((index, run)) => (index, Some(run)),
                None => {
                    let k = self.next.fetch_add(1, Ordering::Relaxed);
                    let Some(&index) = self.order.get(k) else {
                        return Ok(Status::Done);
                    };
                    (index, None)
                }
            };
            let column = match self.column(index, run, sink) {
                Ok(Some(column)) => column,
                Ok(None) => return Ok(Status::Working),
                Err(e) => {
                    self.layout_finished(index, None);
                    return Err(e);
                }
            };
            let layout = column.found.as_ref().ok().map(|f| f.layout.clone());
            self.layout_finished(index, layout);
            if let Ok(f) = &column.found
                && let Some(slot) = lock(&self.found).get_mut(index)
            {
                *slot = Some(f.clone());
            }
            sink.send(Update::Basins {
                generation: sink.generation(),
                lane: sink.lane(),
                column: Box::new(column),
            })?;
            let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
            paced_progress(&self.pacer, (done, self.grid.len(), 0), sink)?;
            if done == self.grid.len() {
                self.events(sink)?;
            }
            if sink.pause() {
                return Ok(Status::Working);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{coarse_first, parents};

    #[test]
    fn a_columns_parent_is_the_nearest_handed_out_before_it() {
        let order = coarse_first(9);
        let p = parents(&order);
        // [0, 8, 4, 2, 6, 1, 3, 5, 7]: the ends have none; 4 is as near
        // 0 as 8 (the lower is taken); then the nearest earlier column.
        assert_eq!(p[0], None);
        assert_eq!(p[8], None);
        assert_eq!(p[4], Some(0));
        assert_eq!(p[2], Some(0));
        assert_eq!(p[6], Some(4));
        assert_eq!(p[1], Some(0));
        assert_eq!(p[3], Some(2));
        assert_eq!(p[7], Some(6));
        // Every parent comes before its child, so the single-threaded
        // host never waits.
        for n in [1, 2, 3, 60, 161] {
            let order = coarse_first(n);
            let p = parents(&order);
            let at: Vec<usize> = {
                let mut at = vec![0; n];
                order.iter().enumerate().for_each(|(k, &i)| at[i] = k);
                at
            };
            for i in 0..n {
                if let Some(q) = p[i] {
                    assert!(at[q] < at[i], "n = {n}: {i}'s parent {q}");
                }
            }
        }
    }

    #[test]
    fn coarse_first_takes_every_index_once_ends_first() {
        for n in [0, 1, 2, 3, 7, 8, 9, 60, 65] {
            let o = coarse_first(n);
            let mut s = o.clone();
            s.sort_unstable();
            assert_eq!(s, (0..n).collect::<Vec<_>>(), "n = {n}");
            if n >= 3 {
                assert_eq!(&o[..2], &[0, n - 1]);
            }
        }
        assert_eq!(coarse_first(9), [0, 8, 4, 2, 6, 1, 3, 5, 7]);
    }
}
