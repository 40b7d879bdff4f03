//! The Basins job: every attractor and basin of f over the exit arc
//! (`sim::attractors`, a cell graph, no orbit budget) at each of a range
//! of columns of one parameter (θν for the Basins view and `oneblock
//! figure --view basins`, any of θν, κ, γ, ν, Ω for `oneblock attractors
//! --param`); and the same at the current parameters alone, with a
//! chaotic attractor's density, for the return map's basin band.
//!
//! A unit is one column, any thread takes the next: the columns are
//! independent (nothing is continued from a neighbour), so the job is
//! [`Job::parallel`] and every host computes the same numbers. They are
//! handed out coarse first (both ends, the middle, then the quarters, …:
//! [`coarse_first`]), so a diagram sharpens evenly while it fills in. A
//! column that fails is sent with its error; the others go on.

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use super::orbit::{Pacer, paced_progress};
use super::protocol::{Axis, BasinColumn, Lane, Update};
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

/// The Basins job in progress.
pub(crate) struct BasinsJob {
    lane: Lane,
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
}

impl BasinsJob {
    /// Checks the spec (finite ends, a column at least, parameters a
    /// simulator takes at both ends) and plans its columns.
    pub fn new(spec: BasinsSpec, lane: Lane) -> Result<Self, JobError> {
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
        Ok(BasinsJob {
            lane,
            order: coarse_first(grid.len()),
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
                let mut run = run.unwrap_or_else(|| AttractorsRun::new(&sim, &self.spec.cells));
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
    /// The tracks and their events over every column, sent as one update
    /// (a range of two columns or more). The thread that finished the
    /// last column locates them, on every core. Not on the
    /// single-threaded host (the page): a continuation or a bisection on
    /// the cell graph cannot stop part-way for the page's frame, so the
    /// page shows tracks without events and says so.
    fn events(&self, sink: &dyn Sink) -> Result<(), JobError> {
        if self.grid.len() < 2 || cfg!(target_arch = "wasm32") {
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
            lane: self.lane,
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
            let Some(column) = self.column(index, run, sink)? else {
                return Ok(Status::Working);
            };
            if let Ok(f) = &column.found
                && let Some(slot) = lock(&self.found).get_mut(index)
            {
                *slot = Some(f.clone());
            }
            sink.send(Update::Basins {
                generation: sink.generation(),
                lane: self.lane,
                column: Box::new(column),
            })?;
            let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
            paced_progress(&self.pacer, self.lane, (done, self.grid.len(), 0), sink)?;
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
    use super::coarse_first;

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
