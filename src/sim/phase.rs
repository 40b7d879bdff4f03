//! The phase diagram in (θν, κ) (the paper's Fig. 4): for every cell, the
//! attractor's period, its Lyapunov exponent and the character of its
//! onsets, classified only as far as the numbers allow.
//!
//! Every cell's orbit starts at θ = θν, as a cell computed alone does; a
//! finished neighbour only lends it its cycle, solved first by Newton's
//! method, so that the cell can stop as soon as its orbit converges onto
//! it ([`continue_cell`], `capture`). The grids' plans fix each cell's
//! neighbour in advance, so a grid is the same whatever the number of
//! threads and whichever thread ran it.
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

mod capture;
mod cells;
mod classify;

use rayon::prelude::*;

use classify::Classifier;

use super::analysis::{cycle_with_derivative, map_derivative};
use super::attractors::{AttractorsRun, CellOptions, Found};
use super::cycles::{Cycle, CycleFailure, CycleOptions, CycleSolve, NearRepeat, confirms};
use super::interpolant::{
    InterpolantOptions, MIN_DIRECT, MapChoice, MapUsed, Stepper, StepperBuild,
};
use super::period::{CONTRACTION_PERIOD_MAX, MIN_WINDOW, PeriodWatch, contraction};
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
    /// Why the attractors were asked for and not counted: the exit arc's
    /// cell graph could not be built (`None` when counted or not asked).
    pub uncounted: Option<String>,
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
            uncounted: None,
        }
    }
}

/// Runs one cell at `params` (its θν and κ) from the onset `theta_start`,
/// all at once ([`CellSteps`] in pieces). `cancel` is polled every cycle; a
/// cancelled cell has error `Cancelled`.
pub fn phase_cell(
    params: Params,
    settings: SolverSettings,
    theta_start: f64,
    opts: &PhaseOptions,
    cancel: &dyn Fn() -> bool,
) -> PhaseCell {
    let mut run = CellSteps::new(params, settings, theta_start, opts, None);
    while !run.advance(cancel) {}
    run.finish().0
}

/// One cell in pieces of a few ms, so that a host on a slice of time (the
/// page's frame) can stop between any two and go on with the same cell
/// bit for bit: its iterates and tests, then, when it is undecided or
/// counts attractors, the exit arc's cell graph.
pub struct CellSteps {
    cell: PhaseCell,
    count: bool,
    stage: Stage,
    /// The cell graph's outcome, when the cell counted attractors.
    found: Option<Found>,
}

enum Stage {
    Classify(Box<Classifier>),
    Tell(Box<AttractorsRun>),
    Done,
}

impl CellSteps {
    /// The cell at `params` from `theta_start`, nothing computed; with
    /// `neighbour` (a point of a finished neighbour's cycle on this cell's
    /// exit arc, and its period) that cycle is solved first
    /// (`capture`).
    pub fn new(
        params: Params,
        settings: SolverSettings,
        theta_start: f64,
        opts: &PhaseOptions,
        neighbour: Option<(f64, usize)>,
    ) -> Self {
        let mut cell = PhaseCell::failed(params.theta_nu, params.kappa, theta_start);
        let sim = Simulator::new(params, settings).and_then(|sim| {
            sim.check_onset(theta_start)?;
            Ok(sim)
        });
        let stage = match sim {
            Ok(sim) => Stage::Classify(Box::new(Classifier::new(
                sim,
                theta_start,
                *opts,
                neighbour,
            ))),
            Err(e) => {
                cell.error = Some(e);
                Stage::Done
            }
        };
        CellSteps {
            cell,
            count: opts.seeds > 0,
            stage,
            found: None,
        }
    }

    /// One piece; whether the cell is done.
    pub fn advance(&mut self, cancel: &dyn Fn() -> bool) -> bool {
        match std::mem::replace(&mut self.stage, Stage::Done) {
            Stage::Classify(mut c) => {
                let r = c.advance(&mut self.cell, cancel);
                if let Some(st) = c.stepper() {
                    self.cell.map = MapUsed::Interpolant(st.summary());
                }
                match r {
                    Ok(false) => self.stage = Stage::Classify(c),
                    Err(e) => {
                        let cell = &mut self.cell;
                        cell.class = CellClass::Failed;
                        cell.lyapunov = None;
                        cell.lyapunov_stderr = None;
                        cell.regime = None;
                        cell.error = Some(e);
                    }
                    Ok(true) => {
                        if self.count || self.cell.class == CellClass::Undecided {
                            // The cell graph on the cell's own simulator.
                            let run = AttractorsRun::new(c.simulator(), &CellOptions::column());
                            self.stage = Stage::Tell(Box::new(run));
                        }
                    }
                }
            }
            Stage::Tell(mut run) => match run.advance(cancel) {
                None => self.stage = Stage::Tell(run),
                Some(found) => {
                    self.found = cells::tell(&mut self.cell, found, self.count);
                }
            },
            Stage::Done => {}
        }
        matches!(self.stage, Stage::Done)
    }

    /// The cell, once [`Self::advance`] has said it is done, and the cell
    /// graph's attractors when it counted them.
    pub fn finish(self) -> (PhaseCell, Option<Found>) {
        (self.cell, self.found)
    }
}

/// What a finished cell leaves for its neighbours.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seed {
    /// Its cycle, when it was periodic: a point of it (the one in the phase
    /// of its last onset) and its period. Neighbours solve it first.
    pub cycle: Option<(f64, usize)>,
    /// Whether it was chaotic (neighbours get the shorter transient).
    pub chaos: bool,
}

impl Seed {
    /// What `cell` leaves for its neighbours (nothing when it failed).
    pub fn of(cell: &PhaseCell) -> Seed {
        let cycle = match (cell.class, &cell.error) {
            (CellClass::Periodic(p), None) => Some((cell.theta_last, p)),
            _ => None,
        };
        Seed {
            cycle,
            chaos: cell.class == CellClass::Chaos,
        }
    }
}

/// The one neighbour rule of every phase grid: the cell at (`kappa`,
/// `theta_nu`) with its finished neighbour's `parent` seed. Its orbit
/// starts at θ = θν, as a cell computed alone does, so that its class is
/// the attractor that orbit reaches; a periodic neighbour's cycle, moved
/// onto the new exit arc, is solved by Newton first and ends the cell as
/// soon as the orbit is seen converging onto it (`capture`); after a
/// chaotic neighbour the transient is the shorter one. All at once
/// ([`continue_steps`] in pieces).
pub fn continue_cell(
    params: Params,
    settings: SolverSettings,
    kappa: f64,
    theta_nu: f64,
    parent: Option<Seed>,
    opts: &PhaseOptions,
    cancel: &dyn Fn() -> bool,
) -> PhaseCell {
    let mut run = continue_steps(params, settings, kappa, theta_nu, parent, opts);
    while !run.advance(cancel) {}
    run.finish().0
}

/// [`continue_cell`]'s cell, nothing computed yet.
pub fn continue_steps(
    params: Params,
    settings: SolverSettings,
    kappa: f64,
    theta_nu: f64,
    parent: Option<Seed>,
    opts: &PhaseOptions,
) -> CellSteps {
    let neighbour = parent
        .and_then(|s| s.cycle)
        .map(|(th, p)| (column_start(kappa, theta_nu, Some(th)), p));
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
    CellSteps::new(p, settings, theta_nu, o, neighbour)
}

/// One κ row: the cells at `theta_nus` in order, each seeded by the
/// previous one ([`continue_cell`]). `on_cell` sees every cell as it is finished. Stops after a
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
