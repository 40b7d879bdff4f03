//! The phase diagram in (θν, κ) (the paper's Fig. 4): for every cell, the
//! attractor's period, its Lyapunov exponent and the character of its
//! onsets, classified only as far as the numbers allow.
//!
//! Each κ row is a continued sweep along θν (every cell starts from the
//! previous cell's last onset, so it follows one attractor) and the rows run
//! in parallel. A row's result depends only on its own inputs, so the grid is
//! the same whatever the number of threads and whichever thread ran it.
//!
//! A cell stops as soon as its answer is established:
//! - a period p is accepted once the iterates have settled on it
//!   (`super::period::settled_period`: the last max(3p, 24) repeat with
//!   period p within `period_tol`, with no drift across the window and no
//!   proper divisor of p within 10·`period_tol` of passing) and the cycle,
//!   solved by Newton from the next onset (`super::cycles`), attracts: its
//!   exponent ln|m|/p is negative (else the period test is off until the
//!   Lyapunov exponent decides);
//! - when the iterates contract onto a cycle geometrically but slowly (the
//!   ratio of successive p-differences, the multiplier's estimate, is in
//!   [0.5, 1) in magnitude: `super::period::contraction`), that cycle is
//!   solved from Aitken's limit; the cell is periodic at once if it is a
//!   genuine p-cycle, attracts, and the iterates keep approaching it (at
//!   most [`MAX_SOLVES`] unconfirmed solves a cell);
//! - only when the transient ends without a period does the cell pay for
//!   f'(θ) on every iterate: the kept iterates then give the Lyapunov
//!   exponent λ with a batch-means standard error, and the cell is chaotic
//!   once λ − 3·stderr > 0 (checked every 16 kept iterates from 64); the
//!   period tests keep running, so a late periodic orbit is still found;
//! - otherwise the cell is undecided (period 0, class `undecided`).
//!
//! A cell whose left neighbour was chaotic looks for a period for at most
//! `transient_after_chaos` iterates (200) before it starts on λ: inside the
//! chaotic region the transient is most of a grid's cost.
//!
//! A cell with a long budget continues on the map's verified interpolant
//! (`super::interpolant`, [`PhaseOptions::map`]): after its first
//! [`DIRECT_PART`] iterates (or its whole transient, if shorter) it builds
//! the interpolant over their range, when at least [`INTERPOLANT_LEFT`]
//! iterates are left, and iterates the series from there, with f'(θ) from
//! the series too. The tests and solves above are unchanged (the solves
//! still integrate). Where the interpolant is refused the cell integrates.

use rayon::prelude::*;

use super::analysis::{cycle_with_derivative, map_derivative};
use super::attractors::seed_map::hull;
use super::cycles::{CycleOptions, confirm_contraction, near_cycle, solve_counting};
use super::interpolant::{InterpolantOptions, MIN_DIRECT, MapChoice, MapUsed, Stepper};
use super::period::{CONTRACTION_PERIOD_MAX, MIN_WINDOW, contraction, near_period, settled_period};
use super::seeded::{Reach, attractor_count};
use super::stats::mean_and_stderr;
use super::sweep::column_start;
use super::{SimError, Simulator};
use crate::integrate::SolverSettings;
use crate::model::{OnsetCharacter, Params, onset_character};

/// How much work a cell may do and how it is classified.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseOptions {
    /// The most iterates spent looking for a period before the Lyapunov
    /// exponent is computed.
    pub transient: usize,
    /// The most iterates with f'(θ) after the transient (the Lyapunov sample).
    pub keep: usize,
    /// Tolerance of the period test, in radians (see
    /// [`super::OrbitOptions::period_tol_for`]).
    pub period_tol: f64,
    /// Standard errors by which λ must exceed 0 for a cell to be chaotic.
    pub sigmas: f64,
    /// Stop a cell as soon as its class is established. `false` is the brute
    /// force: the whole transient, then `keep` iterates with f'(θ), the period
    /// found on the kept iterates as `oneblock orbit` finds it.
    pub early_exit: bool,
    /// The transient of a cell whose neighbour in the row was chaotic (with
    /// `early_exit`): its attractor most likely is too, and 400 iterates of
    /// looking for a period there are the largest cost of a grid.
    pub transient_after_chaos: usize,
    /// How a cell evaluates the map after its direct part: `Auto` builds
    /// the interpolant when at least [`INTERPOLANT_LEFT`] iterates are left
    /// (the paper's 400 + 128 never are), `Interpolant` whenever any are.
    pub map: MapChoice,
    /// θ₀ spread over the exit arc whose orbits, with the cell's own
    /// attractor, are counted into [`PhaseCell::attractors`] (0: not
    /// counted; `super::seeded::attractor_count`).
    pub seeds: usize,
}

impl PhaseOptions {
    /// The paper's budget (400 transient + 128 kept) with the period test tied
    /// to the integrator's tolerance and a 3σ test on λ.
    pub fn for_settings(settings: &SolverSettings) -> Self {
        PhaseOptions {
            transient: 400,
            keep: 128,
            period_tol: if settings.method.is_adaptive() {
                super::OrbitOptions::period_tol_for(settings.rtol)
            } else {
                1e-6
            },
            sigmas: 3.0,
            early_exit: true,
            transient_after_chaos: 200,
            map: MapChoice::Auto,
            seeds: 0,
        }
    }
}

/// The iterates a cell integrates before it may build the interpolant (its
/// whole transient if that is shorter, but at least [`MIN_DIRECT`]): the
/// paper's transient, after which most cells have settled or are chaotic.
pub const DIRECT_PART: usize = 400;
/// The iterates that must be left after the direct part for `Auto` to build
/// the interpolant: its construction costs tens of map evaluations near a
/// slowly approached cycle but 3 000 to 10 000 on a chaotic attractor
/// (measured on the paper's grid), which this many iterates repay.
pub const INTERPOLANT_LEFT: usize = 20_000;

/// What the interpolant may spend, in map evaluations, for a cell with
/// `left` iterates to go: a refusal then costs at most half of what the
/// iterates would have.
fn evaluation_budget(left: usize) -> usize {
    left / 2
}

/// Iterates before the first test for a slow contraction.
pub const MIN_TRANSIENT: usize = 8;
/// The most cycles a cell solves for a slow contraction that the solver
/// does not confirm, and the iterates it waits after each before trying again.
pub const MAX_SOLVES: usize = 4;
const SOLVE_COOLDOWN: usize = 16;
/// Kept iterates before λ is first tested, and between tests.
pub const LYAPUNOV_MIN: usize = 64;
const LYAPUNOV_EVERY: usize = 16;

/// What a cell's attractor is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellClass {
    /// A period-p orbit, p ≤ 64 (1 is the fixed point).
    Periodic(usize),
    /// No period and λ − sigmas·stderr > 0.
    Chaos,
    /// Neither established within the budget.
    Undecided,
    /// A cycle failed (the cell's `error` says why).
    Failed,
}

impl CellClass {
    /// The CSV/legend label: FP, P2, …, chaos, undecided, failed.
    pub fn label(&self) -> String {
        match self {
            CellClass::Periodic(1) => "FP".into(),
            CellClass::Periodic(p) => format!("P{p}"),
            CellClass::Chaos => "chaos".into(),
            CellClass::Undecided => "undecided".into(),
            CellClass::Failed => "failed".into(),
        }
    }

    /// The period, 0 when there is none.
    pub fn period(&self) -> usize {
        match self {
            CellClass::Periodic(p) => *p,
            _ => 0,
        }
    }
}

/// The creep / stick-slip character of an attractor's onsets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AttractorRegime {
    Creep,
    StickSlip,
    Mixed,
}

impl AttractorRegime {
    pub fn name(&self) -> &'static str {
        match self {
            AttractorRegime::Creep => "creep",
            AttractorRegime::StickSlip => "stick-slip",
            AttractorRegime::Mixed => "mixed",
        }
    }

    /// The character of a set of onsets: creep or stick-slip when all agree
    /// (docs/model.md, A(θ) against γ²), mixed otherwise; `None` when empty.
    pub fn of(kappa: f64, gamma: f64, thetas: &[f64]) -> Option<Self> {
        let mut creep = false;
        let mut slip = false;
        for &th in thetas {
            match onset_character(kappa, gamma, th) {
                OnsetCharacter::Creep => creep = true,
                OnsetCharacter::StickSlip => slip = true,
            }
        }
        match (creep, slip) {
            (true, false) => Some(AttractorRegime::Creep),
            (false, true) => Some(AttractorRegime::StickSlip),
            (true, true) => Some(AttractorRegime::Mixed),
            (false, false) => None,
        }
    }
}

/// One cell of the phase diagram.
#[derive(Clone, Debug, PartialEq)]
pub struct PhaseCell {
    pub theta_nu: f64,
    pub kappa: f64,
    pub class: CellClass,
    /// For a periodic orbit: ln of its multiplier over one period, divided by
    /// p (the cycle's exponent); otherwise the mean of ln|f'(θ)| over the kept
    /// iterates. `None` when not computed (a failed cell).
    pub lyapunov: Option<f64>,
    /// The batch-means standard error of an aperiodic cell's λ.
    pub lyapunov_stderr: Option<f64>,
    /// The character of the attractor's onsets (the cycle, or the kept ones).
    pub regime: Option<AttractorRegime>,
    /// Cycles (map evaluations) the cell cost, f'(θ)'s two per use included.
    pub iterates: u64,
    /// Right-hand-side evaluations the cell cost.
    pub rhs_evals: u64,
    /// The onset after the last iterate: where the next cell starts.
    pub theta_last: f64,
    /// Why the cell failed, if it did.
    pub error: Option<SimError>,
    /// How the cell evaluated the map after its direct part.
    pub map: MapUsed,
    /// How many distinct attractors the cell's own and the seeds' orbits
    /// reach ([`PhaseOptions::seeds`]; `None` when not counted).
    pub attractors: Option<usize>,
}

impl PhaseCell {
    /// A cell at (θν, κ) that has computed nothing yet, or never will: class
    /// `Failed` until a result replaces it; the next cell starts at
    /// `theta_last`.
    pub fn failed(theta_nu: f64, kappa: f64, theta_last: f64) -> Self {
        PhaseCell {
            theta_nu,
            kappa,
            class: CellClass::Failed,
            lyapunov: None,
            lyapunov_stderr: None,
            regime: None,
            iterates: 0,
            rhs_evals: 0,
            theta_last,
            error: None,
            map: MapUsed::Direct,
            attractors: None,
        }
    }
}

/// Runs one cell at `params` (its θν and κ) from the onset `theta_start`.
/// `cancel` is polled every cycle; a cancelled cell has error `Cancelled`.
pub fn phase_cell(
    params: Params,
    settings: SolverSettings,
    theta_start: f64,
    opts: &PhaseOptions,
    cancel: &dyn Fn() -> bool,
) -> PhaseCell {
    let mut cell = PhaseCell::failed(params.theta_nu, params.kappa, theta_start);
    match run_cell(&mut cell, params, settings, theta_start, opts, cancel) {
        Err(e) => {
            cell.class = CellClass::Failed;
            cell.lyapunov = None;
            cell.lyapunov_stderr = None;
            cell.regime = None;
            cell.error = Some(e);
        }
        Ok(reach) if opts.seeds > 0 => {
            count_attractors(&mut cell, params, settings, reach, opts, cancel);
        }
        Ok(_) => {}
    }
    cell
}

/// Counts the attractors of a finished cell: its own (`reach`, what its
/// orbit reached) and the seeds', each run with the cell's budget
/// (`super::seeded`). Their cost is the cell's.
fn count_attractors(
    cell: &mut PhaseCell,
    params: Params,
    settings: SolverSettings,
    reach: Option<Reach>,
    opts: &PhaseOptions,
    cancel: &dyn Fn() -> bool,
) {
    let sweep = super::SweepOptions {
        transient: opts.transient,
        keep: opts.keep,
        map: MapChoice::Direct,
    };
    match attractor_count(params, settings, reach, opts.seeds, &sweep, cancel) {
        Ok((n, rhs)) => {
            cell.attractors = Some(n);
            cell.rhs_evals += rhs;
        }
        Err(e) => {
            cell.class = CellClass::Failed;
            cell.error = Some(e);
        }
    }
}

fn run_cell(
    cell: &mut PhaseCell,
    params: Params,
    settings: SolverSettings,
    theta_start: f64,
    opts: &PhaseOptions,
    cancel: &dyn Fn() -> bool,
) -> Result<Option<Reach>, SimError> {
    let sim = Simulator::new(params, settings)?;
    sim.check_onset(theta_start)?;
    let mut stepper = None;
    let r = classify(cell, &sim, theta_start, opts, cancel, &mut stepper);
    if let Some(st) = &stepper {
        cell.map = MapUsed::Interpolant(st.summary());
    }
    r
}

/// The cell's iterates and tests (see the module's doc); the interpolant,
/// once built, is left in `stepper` for the cell's summary.
fn classify<'s>(
    cell: &mut PhaseCell,
    sim: &'s Simulator,
    theta_start: f64,
    opts: &PhaseOptions,
    cancel: &dyn Fn() -> bool,
    stepper: &mut Option<Stepper<'s>>,
) -> Result<Option<Reach>, SimError> {
    let mut run = CellRun::new(sim, theta_start, opts);
    for i in 0..opts.transient + opts.keep {
        if cancel() {
            return Err(SimError::Cancelled);
        }
        run.switch_map(cell, i, stepper);
        run.iterate(cell, i, stepper)?;
        cell.theta_last = run.theta;
        if !opts.early_exit || i + 1 < MIN_TRANSIENT {
            continue;
        }
        if run.settled(cell)? || run.contracting(cell, i) || run.chaotic(cell)? {
            return Ok(run.reach());
        }
    }
    run.finish(cell)?;
    Ok(run.reach())
}

/// A cell in progress: its iterates (all of them: the tests read the
/// transient's end), the kept iterates' ln|f'(θ)|, the next onset, and
/// what the tests have tried so far.
struct CellRun<'s, 'o> {
    sim: &'s Simulator,
    opts: &'o PhaseOptions,
    cycle_opts: CycleOptions,
    thetas: Vec<f64>,
    logs: Vec<f64>,
    /// The next onset (after the last of `thetas`).
    theta: f64,
    /// Differences below this are the map's own error, not a contraction.
    noise: f64,
    solves: usize,
    next_solve: usize,
    /// A settled period whose cycle did not attract: the period test waits
    /// for the kept iterates (the Lyapunov exponent decides).
    unstable_seen: bool,
    /// The period of the last near repeat solved ([`near_period`]), so that
    /// a failed one is not solved again.
    near_tried: Option<usize>,
    /// Map and right-hand-side evaluations of solves not yet charged.
    spent: (u64, u64),
    /// The cycle the cell was found periodic on.
    cycle: Option<Vec<f64>>,
}

impl<'s, 'o> CellRun<'s, 'o> {
    fn new(sim: &'s Simulator, theta_start: f64, opts: &'o PhaseOptions) -> Self {
        CellRun {
            sim,
            opts,
            cycle_opts: CycleOptions::for_classifier(sim.settings()),
            thetas: Vec::with_capacity(opts.transient + opts.keep),
            logs: Vec::with_capacity(opts.keep),
            theta: theta_start,
            noise: 1e-2 * opts.period_tol,
            solves: 0,
            next_solve: MIN_TRANSIENT,
            unstable_seen: false,
            near_tried: None,
            spent: (0, 0),
            cycle: None,
        }
    }

    /// What the cell's orbit reached: its cycle, or the interval its kept
    /// iterates (its last ones, before any are kept) visit.
    fn reach(&self) -> Option<Reach> {
        if let Some(c) = &self.cycle {
            return Some(Reach::Cycle(c.clone()));
        }
        let n = self.thetas.len();
        let kept = &self.thetas[self.opts.transient.min(n / 2)..];
        (!kept.is_empty()).then(|| {
            let (lo, hi) = hull(kept);
            Reach::Set(lo, hi)
        })
    }

    /// Adds the solves' cost to the cell's.
    fn charge(&mut self, cell: &mut PhaseCell) {
        cell.iterates += self.spent.0;
        cell.rhs_evals += self.spent.1;
        self.spent = (0, 0);
    }

    /// The cell is periodic: `cycle`'s period, its onsets' character and
    /// the exponent `lyapunov`.
    fn periodic(&mut self, cell: &mut PhaseCell, cycle: &[f64], lyapunov: f64) {
        self.cycle = Some(cycle.to_vec());
        let p = self.sim.params();
        cell.class = CellClass::Periodic(cycle.len());
        cell.regime = AttractorRegime::of(p.kappa, p.gamma, cycle);
        cell.lyapunov = Some(lyapunov);
    }

    /// At iterate `i`, builds the interpolant over the recent iterates when
    /// the cell's direct part ends and enough iterates are left.
    fn switch_map(&mut self, cell: &mut PhaseCell, i: usize, stepper: &mut Option<Stepper<'s>>) {
        let total = self.opts.transient + self.opts.keep;
        let switch = self.opts.transient.clamp(MIN_DIRECT, DIRECT_PART);
        if i != switch
            || !self
                .opts
                .map
                .interpolates_beyond(total - i, INTERPOLANT_LEFT)
        {
            return;
        }
        let iopts = InterpolantOptions {
            max_evaluations: evaluation_budget(total - i),
            ..InterpolantOptions::for_settings(self.sim.settings())
        };
        let recent = &self.thetas[self.thetas.len().saturating_sub(300)..];
        match Stepper::over(self.sim, recent, iopts, &mut self.spent) {
            Ok(s) => *stepper = Some(s),
            Err(e) => cell.map = MapUsed::Refused(e.to_string()),
        }
        self.charge(cell);
    }

    /// Iterate `i`: from the interpolant if there is one, else integrated;
    /// past the transient with f'(θ) too.
    fn iterate(
        &mut self,
        cell: &mut PhaseCell,
        i: usize,
        stepper: &mut Option<Stepper<'_>>,
    ) -> Result<(), SimError> {
        let kept = i >= self.opts.transient;
        self.thetas.push(self.theta);
        if let Some(st) = stepper.as_mut() {
            // The same iterate from the series: f'(θ) from it too.
            self.theta = if kept {
                let (next, d) = st.next_with_derivative(self.theta)?;
                self.logs.push(d.abs().ln());
                next
            } else {
                st.next(self.theta)?
            };
            let (n, rhs) = st.take_cost();
            cell.iterates += n;
            cell.rhs_evals += rhs;
            return Ok(());
        }
        // Past the transient f'(θ) is needed too: it rides along the
        // iterate's own integration (the variational equations), so it
        // adds evaluations, not iterates (two where f has no derivative
        // and the secant stands in).
        let ev = if kept {
            let (ev, d, n) = cycle_with_derivative(self.sim, self.theta, 0.0)?;
            cell.rhs_evals += n;
            self.logs.push(d.abs().ln());
            ev
        } else {
            self.sim.cycle(self.theta, 0.0, None)?
        };
        cell.iterates += 1;
        cell.rhs_evals += ev.rhs_evals;
        self.theta = self.sim.next_onset(&ev);
        Ok(())
    }

    /// The period test: whether the iterates have settled on a period whose
    /// cycle attracts (the cell is then periodic).
    fn settled(&mut self, cell: &mut PhaseCell) -> Result<bool, SimError> {
        let test = !(self.unstable_seen && self.logs.is_empty()) && self.thetas.len() >= MIN_WINDOW;
        let Some(p) = test
            .then(|| settled_period(&self.thetas, self.opts.period_tol))
            .flatten()
        else {
            return Ok(false);
        };
        // The cycle solved from the next onset gives the exponent ln|m|/p;
        // if it cannot be solved, the mean of ln|f'| on its last p
        // iterates does.
        let solved = solve_counting(self.sim, self.theta, p, &self.cycle_opts, &mut self.spent)
            .ok()
            .filter(|c| c.minimal_period == p);
        self.charge(cell);
        let (lc, points) = match solved {
            Some(c) => {
                // The solve started from the next onset: its point 0 is
                // where the next cell continues.
                cell.theta_last = c.points[0];
                (c.lyapunov(), c.points)
            }
            None => {
                let (sim, thetas, logs) = (self.sim, &self.thetas, &self.logs);
                let lc = cycle_exponent(cell, sim, thetas, self.theta, logs, p)?;
                (lc, thetas[thetas.len() - p..].to_vec())
            }
        };
        if lc < 0.0 {
            self.periodic(cell, &points, lc);
            return Ok(true);
        }
        // Repeats within the tolerance but does not attract: not a periodic
        // attractor (e.g. 2^n tiny chaotic bands under a loose tolerance).
        // Let the Lyapunov exponent decide.
        self.unstable_seen = true;
        Ok(false)
    }

    /// Contracting onto a cycle, but slowly: the cycle is solved instead of
    /// waited for; whether it was, and confirmed (the cell is then
    /// periodic).
    fn contracting(&mut self, cell: &mut PhaseCell, i: usize) -> bool {
        if self.solves >= MAX_SOLVES || i + 1 < self.next_solve || self.unstable_seen {
            return false;
        }
        // `contraction` and the confirmation read the last 4p + 1 values,
        // p ≤ 16: a copy of those, not of the whole orbit.
        let from = self
            .thetas
            .len()
            .saturating_sub(4 * CONTRACTION_PERIOD_MAX + 1);
        let mut seq = self.thetas[from..].to_vec();
        seq.push(self.theta);
        let Some(c) = contraction(&seq, self.noise) else {
            return false;
        };
        let confirmed = confirm_contraction(
            self.sim,
            &seq,
            &c,
            &self.cycle_opts,
            self.noise,
            &mut self.spent,
        );
        self.charge(cell);
        if let Some(cycle) = confirmed {
            cell.theta_last = cycle.points[0];
            self.periodic(cell, &cycle.points, cycle.lyapunov());
            return true;
        }
        self.solves += 1;
        self.next_solve = i + 1 + SOLVE_COOLDOWN;
        false
    }

    /// Every [`LYAPUNOV_EVERY`] kept iterates from [`LYAPUNOV_MIN`]: whether
    /// λ exceeds `sigmas` standard errors (the cell is then chaotic, unless
    /// its iterates nearly repeat on a cycle that attracts).
    fn chaotic(&mut self, cell: &mut PhaseCell) -> Result<bool, SimError> {
        let k = self.logs.len();
        if k < LYAPUNOV_MIN || !k.is_multiple_of(LYAPUNOV_EVERY) {
            return Ok(false);
        }
        let (l, se) = mean_and_stderr(&self.logs);
        let (Some(l), Some(se)) = (l, se) else {
            return Ok(false);
        };
        if l - self.opts.sigmas * se <= 0.0 {
            return Ok(false);
        }
        if self.near_cycle(cell)? {
            return Ok(true);
        }
        let p = self.sim.params();
        cell.class = CellClass::Chaos;
        cell.lyapunov = Some(l);
        cell.lyapunov_stderr = Some(se);
        cell.regime = AttractorRegime::of(p.kappa, p.gamma, &self.thetas[self.opts.transient..]);
        Ok(true)
    }

    /// The cycle the iterates nearly repeat on, if it attracts
    /// ([`near_cycle`]): the cell is then periodic. One solve per period.
    fn near_cycle(&mut self, cell: &mut PhaseCell) -> Result<bool, SimError> {
        let from = self.thetas.len().saturating_sub(2 * CONTRACTION_PERIOD_MAX);
        let mut seq = self.thetas[from..].to_vec();
        seq.push(self.theta);
        let Some(p) = near_period(&seq) else {
            return Ok(false);
        };
        if self.near_tried == Some(p) {
            return Ok(false);
        }
        self.near_tried = Some(p);
        let solved = near_cycle(self.sim, &seq, &self.cycle_opts, &mut self.spent);
        self.charge(cell);
        let Some(c) = solved else {
            return Ok(false);
        };
        cell.theta_last = c.points[0];
        self.periodic(cell, &c.points, c.lyapunov());
        Ok(true)
    }

    /// The budget is spent without an early answer: the brute force's
    /// period on the kept iterates, a near repeat's cycle, or λ decides.
    fn finish(&mut self, cell: &mut PhaseCell) -> Result<(), SimError> {
        let opts = self.opts;
        let kept_from = opts.transient.min(self.thetas.len());
        if !opts.early_exit && self.brute_force_period(cell, kept_from) {
            return Ok(());
        }
        let (l, se) = mean_and_stderr(&self.logs);
        let chaos = matches!((l, se), (Some(l), Some(se)) if l - opts.sigmas * se > 0.0);
        // Not chaotic (or not yet tested as such): a cycle the orbit nearly
        // repeats on may be what it is slowly reaching.
        if opts.early_exit && !chaos && self.near_cycle(cell)? {
            return Ok(());
        }
        let p = self.sim.params();
        cell.lyapunov = l;
        cell.lyapunov_stderr = se;
        cell.regime = AttractorRegime::of(p.kappa, p.gamma, &self.thetas[kept_from..]);
        cell.class = if chaos {
            CellClass::Chaos
        } else {
            CellClass::Undecided
        };
        Ok(())
    }

    /// The brute force's period: found on the kept iterates as `oneblock
    /// orbit` finds it (the cell is then periodic).
    fn brute_force_period(&mut self, cell: &mut PhaseCell, kept_from: usize) -> bool {
        let kept = &self.thetas[kept_from..];
        let s = self.sim.settle(
            kept,
            self.theta,
            &self.logs,
            self.opts.period_tol,
            &mut self.spent,
        );
        self.charge(cell);
        if let Some(c) = s.cycle {
            self.periodic(cell, &c.points, c.lyapunov());
            return true;
        }
        if let super::Period::Periodic(p) = s.period
            && self.logs.len() >= p
        {
            let lc = self.logs[self.logs.len() - p..].iter().sum::<f64>() / p as f64;
            if lc < 0.0 {
                let cycle = self.thetas[self.thetas.len() - p..].to_vec();
                self.periodic(cell, &cycle, lc);
                return true;
            }
        }
        false
    }
}

/// A period-p cycle's exponent from the orbit alone, when the cycle could
/// not be solved: the mean of ln|f'| over the last p iterates (`thetas`,
/// then the next onset `theta`), from the kept iterates' `logs` when there
/// are p of them, else by p derivatives charged to the cell.
fn cycle_exponent(
    cell: &mut PhaseCell,
    sim: &Simulator,
    thetas: &[f64],
    theta: f64,
    logs: &[f64],
    p: usize,
) -> Result<f64, SimError> {
    if logs.len() >= p {
        return Ok(logs[logs.len() - p..].iter().sum::<f64>() / p as f64);
    }
    let mut sum = 0.0;
    for j in 0..p {
        let th = thetas[thetas.len() - p + j];
        let next = if j + 1 < p {
            thetas[thetas.len() - p + j + 1]
        } else {
            theta
        };
        let (d, n) = map_derivative(sim, th, next)?;
        cell.iterates += 1;
        cell.rhs_evals += n;
        sum += d.abs().ln();
    }
    Ok(sum / p as f64)
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
    /// What `cell` leaves for its neighbours.
    pub fn of(cell: &PhaseCell) -> Seed {
        Seed {
            theta_last: cell.error.is_none().then_some(cell.theta_last),
            chaos: cell.class == CellClass::Chaos,
        }
    }
}

/// The one neighbour rule of every phase grid: the cell at (`kappa`,
/// `theta_nu`) continued from `parent` (its seed), its start moved onto the
/// new exit arc, with the shorter transient after a chaotic neighbour; with
/// no parent (or after a failed one), from θ = θν.
pub fn continue_cell(
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

/// One κ row: the cells at `theta_nus` in order, each starting from the
/// previous cell's last onset (the first, and any after a failed cell, from
/// θ = θν). `on_cell` sees every cell as it is finished. Stops after a
/// cancelled cell.
pub fn phase_row(
    params: Params,
    settings: SolverSettings,
    theta_nus: &[f64],
    opts: &PhaseOptions,
    cancel: &dyn Fn() -> bool,
    on_cell: &dyn Fn(&PhaseCell),
) -> Vec<PhaseCell> {
    let mut row = Vec::with_capacity(theta_nus.len());
    let mut prev: Option<Seed> = None;
    for &tn in theta_nus {
        let cell = continue_cell(params, settings, params.kappa, tn, prev, opts, cancel);
        prev = Some(Seed::of(&cell));
        on_cell(&cell);
        let cancelled = matches!(cell.error, Some(SimError::Cancelled));
        row.push(cell);
        if cancelled {
            break;
        }
    }
    row
}

/// The whole grid, rows (one per κ) in parallel on the current rayon pool.
/// Returns the rows in the order of `kappas`, or `Cancelled` if `cancel` fired
/// (nothing half-done is returned).
pub fn phase_grid(
    params: Params,
    settings: SolverSettings,
    kappas: &[f64],
    theta_nus: &[f64],
    opts: &PhaseOptions,
    cancel: &(dyn Fn() -> bool + Sync),
    on_cell: &(dyn Fn(&PhaseCell) + Sync),
) -> Result<Vec<Vec<PhaseCell>>, SimError> {
    let rows: Vec<Vec<PhaseCell>> = kappas
        .par_iter()
        .map(|&k| {
            let p = Params { kappa: k, ..params };
            phase_row(p, settings, theta_nus, opts, cancel, on_cell)
        })
        .collect();
    if rows
        .iter()
        .flatten()
        .any(|c| matches!(c.error, Some(SimError::Cancelled)))
    {
        return Err(SimError::Cancelled);
    }
    Ok(rows)
}
