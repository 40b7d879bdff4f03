//! Bifurcation sweeps over θν: each column's orbit starts from the last
//! iterate of the previous column, so a sweep follows one attractor.
//!
//! A column stops integrating once its orbit has settled: when its onsets
//! repeat with a period (`settled_period`), or when they contract onto a
//! cycle too slowly to wait for, which is then solved (`super::cycles`) and
//! confirmed to attract and to be approached. The rest of the column, and
//! the onset its neighbour continues from, are then that cycle's points: a
//! column starts where the attractor is, not where a slow orbit had got to,
//! so no staircase of lagging columns can appear. A column whose neighbour
//! was solved onto a slow cycle solves for that cycle first, from the
//! neighbour's point ([`Handover`]), and continues on it if it attracts.
//!
//! Slow cycles are solved at tol 1e-10 whatever the sweep's own accuracy: a
//! map error ε moves a cycle with multiplier m by ε/|1 − m|, which near
//! m = 1 is many pixels even where ε is far below one.
//!
//! A column that keeps many points ([`SweepOptions::map`]) and has not
//! settled after its transient (at least [`MIN_DIRECT`] direct iterates)
//! builds the map's verified interpolant over the range of its recent
//! onsets and takes the rest of its points from it; where the interpolant
//! is refused, the column goes on integrating.

use super::cycles::Cycle;
use super::interpolant::{MIN_DIRECT, MapChoice, MapUsed};
use super::period::{PERIOD_MAX, PeriodWatch, contraction};
use super::{SimError, Simulator, SlipEvent};
use crate::integrate::SolverSettings;
use crate::model::{Params, project_onto_exit_arc};
use crate::sim::continuation::ContParam;
use heavy::{Heavy, Solving, Tabled};

/// How long each column runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepOptions {
    /// Iterates dropped before any is kept.
    pub transient: usize,
    /// Iterates (points) each column keeps.
    pub keep: usize,
    /// How an unsettled column evaluates the map after its transient:
    /// `Auto` builds the interpolant from [`MapChoice::AUTO_COLUMN_KEEP`] kept points
    /// on, `Interpolant` always, `Direct` never.
    pub map: MapChoice,
}

/// One column of a bifurcation diagram.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    pub theta_nu: f64,
    /// The kept onsets θ (empty if the column failed).
    pub thetas: Vec<f64>,
    /// The onset after the last kept one, where a neighbour continues.
    pub theta_last: f64,
    /// Why the column is empty or short, if it is.
    pub error: Option<SimError>,
    /// Right-hand-side evaluations the column cost.
    pub rhs_evals: u64,
    /// The period of the slow cycle (|multiplier| ≥ 0.5) the column was
    /// solved onto, if it was: its neighbour solves for it first.
    pub slow_period: Option<usize>,
    /// How the column's points after its transient were computed.
    pub map: MapUsed,
}

/// What a finished column hands the neighbour that continues from it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Handover {
    /// Its last onset.
    pub theta: f64,
    /// [`Column::slow_period`].
    pub slow_period: Option<usize>,
}

impl Column {
    /// Where a neighbour continues from; `None` after a failure (the
    /// neighbour then starts afresh from θν).
    pub fn handover(&self) -> Option<Handover> {
        self.error.is_none().then_some(Handover {
            theta: self.theta_last,
            slow_period: self.slow_period,
        })
    }
}

/// The least |multiplier| of a cycle a neighbour solves for first: faster
/// ones are reached by iterating within a few periods.
pub const SLOW_MULTIPLIER: f64 = 0.5;

/// `n` values of θν evenly spaced from `from` to `to` inclusive. Finite
/// ends give finite values: a span too wide for f64 (`to − from` beyond
/// 1.8e308) is interpolated as `from·(1 − s) + to·s` instead.
pub fn theta_nu_grid(from: f64, to: f64, n: usize) -> Vec<f64> {
    let span = to - from;
    match n {
        0 => vec![],
        1 => vec![from],
        _ if span.is_finite() => (0..n)
            .map(|i| from + span * i as f64 / (n - 1) as f64)
            .collect(),
        _ => (0..n)
            .map(|i| {
                let s = i as f64 / (n - 1) as f64;
                from * (1.0 - s) + to * s
            })
            .collect(),
    }
}

/// `n` values of `param` from `from` to `to`, both ends included: evenly
/// spaced in log10 of the value for a parameter that spans decades
/// ([`ContParam::spans_decades`]; both ends must then be positive), else
/// as [`theta_nu_grid`]. The ends are `from` and `to` exactly.
pub fn param_grid(param: ContParam, from: f64, to: f64, n: usize) -> Vec<f64> {
    // NaN ends are not positive either: the linear grid carries them.
    let positive = from > 0.0 && to > 0.0;
    if !param.spans_decades() || !positive {
        return theta_nu_grid(from, to, n);
    }
    let mut g: Vec<f64> = theta_nu_grid(from.ln(), to.ln(), n)
        .into_iter()
        .map(f64::exp)
        .collect();
    if let (Some(first), true) = (g.first_mut(), n > 0) {
        *first = from;
    }
    if let (Some(last), true) = (g.last_mut(), n > 1) {
        *last = to;
    }
    g
}

/// Where a column at θν starts: the neighbour's last onset moved onto the new
/// exit arc, or θ = θν (always on the arc) when there is none.
pub fn column_start(kappa: f64, theta_nu: f64, neighbour: Option<f64>) -> f64 {
    match neighbour {
        Some(th) if th.is_finite() => project_onto_exit_arc(kappa, theta_nu, th, 1e-6),
        _ => theta_nu,
    }
}

impl Column {
    /// Runs one column at `theta_nu` from `theta_start`; `cancel` is polled
    /// every cycle. A failed cycle ends the column with its error.
    pub fn run(
        params: Params,
        settings: SolverSettings,
        theta_nu: f64,
        theta_start: f64,
        opts: &SweepOptions,
        cancel: &dyn Fn() -> bool,
    ) -> Column {
        Self::run_from(params, settings, theta_nu, theta_start, None, opts, cancel)
    }

    /// [`Column::run`], first solving for a slow cycle of period
    /// `slow_period` from `theta_start` when the neighbour had one.
    pub fn run_from(
        params: Params,
        settings: SolverSettings,
        theta_nu: f64,
        theta_start: f64,
        slow_period: Option<usize>,
        opts: &SweepOptions,
        cancel: &dyn Fn() -> bool,
    ) -> Column {
        let sim = match Simulator::new(params.with_theta_nu(theta_nu), settings) {
            Ok(s) => s,
            Err(e) => return Column::failed(theta_nu, theta_start, e),
        };
        let mut run = ColumnRun::new(&sim, theta_start, slow_period, opts);
        while let Some(theta) = run.next_onset(&sim, cancel) {
            run.take(&sim, sim.cycle(theta, 0.0, None));
        }
        run.finish()
    }

    /// A column that could not start.
    fn failed(theta_nu: f64, theta_start: f64, e: SimError) -> Column {
        Column {
            theta_nu,
            thetas: vec![],
            theta_last: theta_start,
            error: Some(e),
            rhs_evals: 0,
            slow_period: None,
            map: MapUsed::Direct,
        }
    }
}

/// The onsets a column keeps during its transient: enough for
/// [`settled_period`](super::period::settled_period) (the last 3p onsets, p ≤ [`PERIOD_MAX`]) and for
/// [`contraction`] (4p + 1, p ≤ 16), so that memory does not grow with the
/// transient.
const SETTLE_WINDOW: usize = 3 * PERIOD_MAX;

/// A column in progress, one cycle at a time, so that [`Column::run`] and
/// the lanes of [`run_columns`] share the column's logic (the early exit
/// of a settled column, the kept iterates of a failed one). Its memory is
/// proportional to the kept iterates, never to the transient: transient
/// onsets older than [`SETTLE_WINDOW`] are dropped as the column goes.
struct ColumnRun {
    col: Column,
    transient: usize,
    total: usize,
    rep_tol: f64,
    /// onsets[k] is the onset of cycle `first + k`.
    onsets: Vec<f64>,
    /// The period test on `onsets` ([`settled_period`]'s decisions, at
    /// O(1) amortised cost a cycle).
    ///
    /// [`settled_period`]: super::period::settled_period
    watch: Box<PeriodWatch>,
    /// The cycle of `onsets[0]` (never beyond `transient`).
    first: usize,
    done: bool,
    /// Solves of a slow contraction left, and the onset count before which
    /// the next may not start (one that was not confirmed waits a while).
    solves_left: usize,
    next_solve: usize,
    /// The onset count at which an unsettled column turns to the
    /// interpolant (`None`: it does not, or it has tried).
    switch_at: Option<usize>,
    /// Whether it is time to try.
    switch_due: bool,
    /// A cycle solve due before the next cycle ([`Heavy`]), and the one
    /// under way (paused between two map evaluations).
    heavy: Option<Heavy>,
    solving: Option<Box<Solving>>,
    /// The turn to the interpolant under way: its build, then the rest of
    /// the column on it (paused between two pieces).
    tabled: Option<Box<Tabled>>,
    /// The onset count at which `cancel` was last polled on the
    /// interpolant (so that a pause does not poll it twice).
    polled: usize,
}

/// When work running on a host's slice of time stops: before any cycle
/// once the slice is spent ([`Yield::pause`]), before a cycle solve or an
/// interpolant once much of it is ([`Yield::defer_heavy`]). Paused work
/// resumes exactly where it stopped, so neither changes any result.
pub trait Yield {
    fn pause(&self) -> bool;
    fn defer_heavy(&self) -> bool;
}

/// Never stops (a host with threads, or no slices).
pub struct NeverYield;

impl Yield for NeverYield {
    fn pause(&self) -> bool {
        false
    }
    fn defer_heavy(&self) -> bool {
        false
    }
}

/// The most solves of a slow contraction a column attempts.
const MAX_SOLVES: usize = 3;
/// Onsets a column waits after a solve that was not confirmed.
const SOLVE_COOLDOWN: usize = 16;

impl ColumnRun {
    fn new(
        sim: &Simulator,
        theta_start: f64,
        slow_period: Option<usize>,
        opts: &SweepOptions,
    ) -> Self {
        // Saturating: a sum past usize is refused by every caller first,
        // and a saturated total only means a run that never ends by count.
        let total = opts.transient.saturating_add(opts.keep);
        let mut onsets = Vec::with_capacity(opts.keep.min(1 << 20) + SETTLE_WINDOW);
        onsets.push(theta_start);
        let rep_tol = (100.0 * sim.settings().rtol).clamp(1e-12, 1e-6);
        let mut run = ColumnRun {
            col: Column {
                theta_nu: sim.params().theta_nu,
                thetas: Vec::new(),
                theta_last: theta_start,
                error: None,
                rhs_evals: 0,
                slow_period: None,
                map: MapUsed::Direct,
            },
            transient: opts.transient,
            total,
            rep_tol,
            onsets,
            watch: Box::new(PeriodWatch::new(rep_tol)),
            first: 0,
            done: total == 0,
            solves_left: MAX_SOLVES,
            next_solve: 0,
            switch_at: opts
                .map
                .interpolates_beyond(opts.keep, MapChoice::AUTO_COLUMN_KEEP)
                .then_some(opts.transient.max(MIN_DIRECT) + 1),
            switch_due: false,
            heavy: None,
            solving: None,
            tabled: None,
            polled: 0,
        };
        // The neighbour's slow cycle, continued: if it still attracts here,
        // the column is on it from the start (solved before its first cycle).
        if let Some(p) = slow_period
            && !run.done
        {
            run.heavy = Some(Heavy::Handover(p));
        }
        run
    }

    /// Whether a heavy piece of work is to start before the next cycle (a
    /// solve or an interpolant under way is not: it goes on in pieces).
    fn heavy_due(&self) -> bool {
        self.heavy.is_some() || self.switch_due
    }

    /// The column continues on `cycle` from its newest onset, which is
    /// replaced by the cycle's point 0 (solved from it, so in its phase).
    /// Only the onsets from the transient's end on are written out.
    fn follow(&mut self, cycle: &Cycle) {
        let last = self.len() - 1;
        self.onsets.pop();
        let from = last.max(self.transient);
        if from > last {
            self.onsets.clear();
            self.first = from;
        }
        for k in from..=self.total {
            self.onsets.push(cycle.points[(k - last) % cycle.period()]);
        }
        if cycle.multiplier.abs() >= SLOW_MULTIPLIER {
            self.col.slow_period = Some(cycle.period());
        }
        self.done = true;
    }

    /// The number of onsets known so far (cycles 0 ..= len − 1).
    fn len(&self) -> usize {
        self.first + self.onsets.len()
    }

    /// The onsets of cycles `from .. to` (both at or after `first`).
    fn span(&self, from: usize, to: usize) -> &[f64] {
        &self.onsets[from - self.first..to - self.first]
    }

    /// The onset of the next cycle to compute, or `None` once the column
    /// is complete (or cancelled: `cancel` is polled here, once a cycle).
    /// The heavy work due is done first, all of it: a column due to turn
    /// to the interpolant is then complete unless the interpolant was
    /// refused.
    fn next_onset(&mut self, sim: &Simulator, cancel: &dyn Fn() -> bool) -> Option<f64> {
        self.heavy_step(sim, &NeverYield, cancel);
        if self.done {
            return None;
        }
        if cancel() {
            self.col.error = Some(SimError::Cancelled);
            self.done = true;
            return None;
        }
        self.onsets.last().copied()
    }

    /// Takes the result of the cycle from the last onset `next_onset` gave.
    fn take(&mut self, sim: &Simulator, r: Result<SlipEvent, SimError>) {
        let i = self.len() - 1;
        match r {
            Ok(ev) => {
                self.col.rhs_evals += ev.rhs_evals;
                self.onsets.push(sim.next_onset(&ev));
            }
            Err(e) => {
                self.col.error = Some(e);
                // The kept cycles that completed before the failure.
                self.col.thetas = self.span(self.transient.min(i), i).to_vec();
                self.done = true;
                return;
            }
        }
        // A column that has settled onto a short cycle repeats it: the
        // rest of its iterates are the cycle's, to within rep_tol, so
        // they are not integrated again (most columns of a diagram are
        // fixed points or short cycles). Only the iterates from the
        // transient's end on are written out.
        if let Some(p) = self.watch.settled(&self.onsets, self.len()) {
            let n = self.len();
            let cycle: Vec<f64> = self.span(n - p, n).to_vec();
            let from = n.max(self.transient);
            if from > n {
                self.onsets.clear();
                self.first = from;
            }
            for k in from..=self.total {
                self.onsets.push(cycle[(k - (n - p)) % p]);
            }
        } else if self.solves_left > 0 && self.len() >= self.next_solve {
            // Contracting onto a cycle, but slowly: the cycle is solved
            // before the next cycle, and once confirmed the column
            // continues on it. The cycle ends after the solve.
            if let Some(c) = contraction(&self.onsets, self.rep_tol) {
                self.heavy = Some(Heavy::Contraction(c));
                return;
            }
        }
        self.end_cycle();
    }

    /// The bookkeeping after each cycle: forget old transient onsets, end
    /// the column once it has its points, and turn to the interpolant when
    /// due.
    fn end_cycle(&mut self) {
        if !self.done {
            self.forget_transient();
        }
        self.done = self.done || self.len() > self.total;
        if !self.done && self.switch_at.is_some_and(|k| self.len() >= k) {
            self.switch_at = None;
            self.switch_due = true;
        }
    }

    /// Drops transient onsets no longer needed (older than the settle
    /// window), in batches so that the copying stays a small overhead.
    fn forget_transient(&mut self) {
        let keep_from = self.len().saturating_sub(SETTLE_WINDOW).min(self.transient);
        if keep_from >= self.first + 4 * SETTLE_WINDOW {
            self.onsets.drain(..keep_from - self.first);
            self.first = keep_from;
        }
    }

    fn finish(mut self) -> Column {
        if self.col.error.is_none() && self.len() > self.total {
            self.col.thetas = self.span(self.transient, self.total).to_vec();
            self.col.theta_last = self.onsets[self.total - self.first];
        }
        self.col
    }
}

/// A continued sweep over `theta_nus`, in order, starting from `theta0` (or
/// θν). After a failed column the next one starts afresh from θν.
pub fn sweep_columns(
    params: Params,
    settings: SolverSettings,
    theta_nus: &[f64],
    opts: &SweepOptions,
    theta0: Option<f64>,
    cancel: &dyn Fn() -> bool,
    mut on_column: impl FnMut(&Column),
) -> Vec<Column> {
    let mut out = Vec::with_capacity(theta_nus.len());
    let mut prev = theta0.map(|theta| Handover {
        theta,
        slow_period: None,
    });
    for &tn in theta_nus {
        let start = column_start(params.kappa, tn, prev.map(|h| h.theta));
        let slow = prev.and_then(|h| h.slow_period);
        let col = Column::run_from(params, settings, tn, start, slow, opts, cancel);
        prev = col.handover();
        on_column(&col);
        let cancelled = matches!(col.error, Some(SimError::Cancelled));
        out.push(col);
        if cancelled {
            break;
        }
    }
    out
}

mod heavy;
mod lanes;

pub use lanes::{ColumnJob, LaneEnd, PausedColumn, run_columns};

#[cfg(test)]
mod tests;
