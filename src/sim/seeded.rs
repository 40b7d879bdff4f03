//! Seeded columns and cells (docs/attractors.md): besides the attractor a
//! sweep follows from its neighbour, the orbits from `seeds` θ₀ spread over
//! the exit arc, each run as a sweep column runs (stopping once it has
//! settled onto a cycle), and the attractors they reach told apart. Where
//! attractors coexist (hysteresis), a seeded diagram shows every branch
//! and a seeded phase cell counts them.
//!
//! Two orbits reach the same attractor when both settle onto cycles of the
//! same period whose points coincide to [`SAME_CYCLE`], or when neither
//! settles and the intervals of θ their kept iterates visit overlap. An
//! orbit that settles and one that does not are different attractors.
//!
//! The seeds iterate `SeedMap` (as `oneblock attractors` does): the
//! verified interpolant near the followed attractor and those found so
//! far, direct integration elsewhere; a seed stops once it closes in on a
//! known cycle or repeats. One that contracts too slowly onto a cycle to
//! settle in its budget, and not onto a known one, is run as a sweep column
//! (integrated, its slow cycle solved).

use super::attractors::seed_map::{Fell, Known, SET_STAY, SeedMap, hull};
use super::attractors::{spread_seeds, transient};
use super::period::{PERIOD_MAX, closing_in, contraction};
use super::{Column, SimError, Simulator, SweepOptions, column_start};
use crate::integrate::SolverSettings;
use crate::model::{Params, wrap_angle};

/// How far apart (radians) two settled cycles' points may be and still be
/// one attractor: settled columns repeat their cycle to the sweep's
/// repetition tolerance (at most 1e-6), slowly approached ones are solved
/// to 1e-10, and coexisting cycles of one period lie far further apart.
pub const SAME_CYCLE: f64 = 1e-5;

/// [`SAME_CYCLE`], or ten times the map's tolerance where that is looser
/// (at most 1e-2): on a loose map (the window's diagram runs DP5(4) at
/// 1e-4) the map is not smooth to below its error, and orbits settle onto
/// points of one cycle a few 1e-5 apart (seen at κ = 10, θν = 1.3229),
/// while coexisting cycles still lie tenths of a radian apart.
pub(crate) fn same_tol(settings: &SolverSettings) -> f64 {
    (10.0 * settings.rtol).clamp(SAME_CYCLE, 1e-2)
}

/// The most seeds a column or cell may have.
pub const MAX_SEEDS: usize = 256;

/// What one orbit's kept iterates show.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Reach {
    /// Settled onto this cycle (its p points, as kept).
    Cycle(Vec<f64>),
    /// Not settled: the interval [lo, hi] its kept iterates visit.
    Set(f64, f64),
}

impl Reach {
    /// What `thetas` (one column's kept iterates) reached, `None` if empty.
    /// A cycle they close in on slowly ([`closing_in`]) counts only where
    /// `solves` confirms it from its extrapolated points ([`solves_at`]).
    pub(crate) fn of(
        thetas: &[f64],
        settings: &SolverSettings,
        solves: impl Fn(&[f64]) -> bool,
    ) -> Option<Reach> {
        if thetas.is_empty() {
            return None;
        }
        // The sweep's repetition tolerance, ten times.
        let tol = 10.0 * rep_tol(settings);
        // Every kept iterate repeats with period p: a settled column's
        // kept iterates are its cycle's points, copied.
        let n = thetas.len();
        let repeats = |p: usize| (p..n).all(|i| wrap_angle(thetas[i] - thetas[i - p]).abs() <= tol);
        if let Some(p) = (1..=(n / 2).min(PERIOD_MAX)).find(|&p| repeats(p)) {
            return Some(Reach::Cycle(thetas[n - p..].to_vec()));
        }
        if let Some(cycle) = closing_in(thetas).filter(|c| solves(c)) {
            return Some(Reach::Cycle(cycle));
        }
        let (lo, hi) = hull(thetas);
        Some(Reach::Set(lo, hi))
    }

    /// Whether `self` and `other` are one attractor (see the module's
    /// doc), cycles' points coinciding to `tol` ([`same_tol`]).
    fn same(&self, other: &Reach, tol: f64) -> bool {
        match (self, other) {
            (Reach::Cycle(a), Reach::Cycle(b)) => {
                a.len() == b.len()
                    && a.iter()
                        .all(|x| b.iter().any(|y| wrap_angle(x - y).abs() <= tol))
            }
            (Reach::Set(a0, a1), Reach::Set(b0, b1)) => a0 <= b1 && b0 <= a1,
            _ => false,
        }
    }
}

/// A column of a seeded diagram: the followed column's points and every
/// other attractor's, each point labelled with its attractor.
#[derive(Clone, Debug, PartialEq)]
pub struct SeededColumn {
    /// The followed column's kept iterates, then each further attractor's
    /// points (a cycle's p points, or an unsettled orbit's kept iterates).
    pub thetas: Vec<f64>,
    /// `attractor[i]` labels `thetas[i]`: 0 is the followed attractor,
    /// 1, 2, … the others in the order of their first seed along the arc.
    pub attractor: Vec<u8>,
    /// How many distinct attractors (0 if the followed column is empty).
    pub count: usize,
    /// Right-hand-side evaluations the seeds cost.
    pub rhs_evals: u64,
    /// What each label's attractor is (`reaches[label]`).
    pub(crate) reaches: Vec<Reach>,
    /// How near two cycles' points are taken for one ([`same_tol`]).
    same_tol: f64,
}

/// Whether Newton on `sim`'s map finds a stable cycle from the
/// extrapolated points of an orbit closing in on it (see [`Reach::of`]).
fn solves_at(sim: &Simulator) -> impl Fn(&[f64]) -> bool + '_ {
    |cycle| crate::sim::column_lyapunov::solve_closing(sim, cycle).is_some()
}

/// What a seed reached, and the points a diagram draws for it.
type Reached = (Reach, Vec<f64>);

/// The sweep's repetition tolerance (`ColumnRun::rep_tol`), which the
/// seeds' orbits repeat to.
pub(crate) fn rep_tol(settings: &SolverSettings) -> f64 {
    (100.0 * settings.rtol).clamp(1e-12, 1e-6)
}

/// What a seed settled onto `cycle` reached, told as a sweep column keeping
/// `keep` points tells it (its kept points are the cycle's, copied): so it
/// compares with the followed column like for like (with fewer kept points
/// than two periods, a column's points are a set, not a cycle).
fn on_cycle(cycle: &[f64], keep: usize, settings: &SolverSettings) -> Reached {
    let kept: Vec<f64> = (0..keep).map(|i| cycle[i % cycle.len()]).collect();
    // Copies of a cycle repeat or, with fewer than two periods, are a set:
    // they never close in.
    match Reach::of(&kept, settings, |_| false) {
        Some(r @ Reach::Cycle(_)) => (r, cycle.to_vec()),
        Some(r) => (r, kept),
        None => (Reach::Cycle(cycle.to_vec()), cycle.to_vec()),
    }
}

/// Adds `r`'s neighbourhood to `map`: near each point of a cycle, over a
/// set's hull (worth `worth` evaluations at most).
fn cover(map: &mut SeedMap, r: &Reach, worth: usize) {
    match r {
        Reach::Cycle(c) => {
            for &x in c {
                map.cover_point(x);
            }
        }
        Reach::Set(lo, hi) => map.cover_set(*lo, *hi, worth),
    }
}

/// The seed from θ0 run as a sweep column (integrated, a slow cycle
/// solved): what it reached and the points drawn for it (`None` if it
/// failed), and its cost; `Cancelled` if it was.
fn as_column(
    params: Params,
    settings: SolverSettings,
    theta0: f64,
    opts: &SweepOptions,
    cancel: &dyn Fn() -> bool,
) -> Result<(Option<Reached>, u64), SimError> {
    let col = Column::run(params, settings, params.theta_nu, theta0, opts, cancel);
    match col.error {
        Some(SimError::Cancelled) => return Err(SimError::Cancelled),
        Some(_) => return Ok((None, col.rhs_evals)),
        None => {}
    }
    let sim = Simulator::new(params, settings)?;
    let reached = Reach::of(&col.thetas, &settings, solves_at(&sim)).map(|r| {
        let points = match &r {
            Reach::Cycle(c) => c.clone(),
            Reach::Set(..) => col.thetas.clone(),
        };
        (r, points)
    });
    Ok((reached, col.rhs_evals))
}

/// The accuracy the seeds' own orbits are run to: an adaptive method's
/// tolerance no tighter than this (about half the cost of an iterate at
/// 1e-10), their interpolants to [`SEED_MAP_TOL`]. A seed's orbit only has
/// to tell which attractor it reaches: one it closes in on or stays in is
/// known already (found to the sweep's accuracy), and one it finds that
/// is not is run again as a sweep column runs, to the full accuracy,
/// before it is counted.
pub const SEED_RTOL: f64 = 1e-7;

/// The error in θ' allowed for the seeds' interpolants: about the loose
/// map's own error at its worst (next to a jump of f), and far below what
/// routing a seed asks (it closes in on a known cycle to 1e-3). Tighter
/// costs more where f is rough (1e-6 took 4 800 evaluations over the
/// intermittent preset's chaotic set against 2 800 at 1e-5).
pub const SEED_MAP_TOL: f64 = 1e-5;

/// The map the seeds run on at `params`: `settings` loosened to
/// [`SEED_RTOL`] (an adaptive method; a fixed-step one as it is).
pub(crate) fn seed_simulator(
    params: Params,
    settings: &SolverSettings,
) -> Result<Simulator, SimError> {
    let loose = if settings.method.is_adaptive() && settings.rtol < SEED_RTOL {
        SolverSettings {
            rtol: SEED_RTOL,
            atol: settings.atol.max(SEED_RTOL),
            ..*settings
        }
    } else {
        *settings
    };
    Simulator::new(params, loose)
}

/// Where the seeds run, and what they are told against.
struct Seeding<'a> {
    params: Params,
    /// The sweep's own settings (a new attractor is confirmed with them).
    settings: SolverSettings,
    opts: &'a SweepOptions,
    cancel: &'a dyn Fn() -> bool,
    /// The attractors known so far: the followed one, then each new one.
    known: Vec<Reach>,
    /// Right-hand-side evaluations of the confirming columns.
    rhs: u64,
}

impl Seeding<'_> {
    /// What a seed whose loose orbit fell as `fell` reached, with the
    /// points a diagram draws for it (`None`: its confirming column
    /// failed). A cycle or set among the known ones is taken as it is;
    /// anything else is run again from the seed's last point as a sweep
    /// column, to the sweep's accuracy.
    fn told(
        &mut self,
        fell: Fell,
        cycles: &[Vec<f64>],
        sets: &[(f64, f64)],
        tol: f64,
    ) -> Result<Option<Reached>, SimError> {
        let keep = self.opts.keep;
        let settings = self.settings;
        let from = match fell {
            Fell::Known(k) => return Ok(Some(on_cycle(&cycles[k], keep, &settings))),
            Fell::InSet(k) => return Ok(Some((Reach::Set(sets[k].0, sets[k].1), vec![]))),
            Fell::Repeats(points) => {
                let r = on_cycle(&points, keep, &settings);
                if self.known.iter().any(|k| k.same(&r.0, same_tol(&settings))) {
                    return Ok(Some(r));
                }
                points[points.len() - 1]
            }
            Fell::Wanders(kept, next) => {
                // Closing in slowly on a known cycle.
                let onto = contraction(&kept, tol).and_then(|c| {
                    let near = |x: &f64| wrap_angle(x - c.limit).abs() <= CLOSE_SLOW;
                    cycles
                        .iter()
                        .find(|cy| cy.len() == c.period && cy.iter().any(near))
                });
                if let Some(cy) = onto {
                    return Ok(Some((Reach::Cycle(cy.clone()), cy.clone())));
                }
                let (lo, hi) = hull(&kept);
                if self.known.iter().any(|k| k.same(&Reach::Set(lo, hi), 0.0)) {
                    return Ok(Some((Reach::Set(lo, hi), kept)));
                }
                next
            }
        };
        let (reached, cost) = as_column(self.params, settings, from, self.opts, self.cancel)?;
        self.rhs += cost;
        Ok(reached)
    }
}

/// How near a slowly contracting seed's extrapolated limit must come to a
/// known cycle's point to be counted as reaching it (the loose map's cycle
/// lies within its error, over 1 − m, of the sweep's).
const CLOSE_SLOW: f64 = 1e-4;

/// What each of `seeds` seeds reached at θν of `params`, with the points a
/// diagram draws for it (a cycle's p points, or an unsettled orbit's kept
/// iterates), given what the followed orbit reached; and what they cost
/// (right-hand-side evaluations). See [`seeds_from`].
fn seed_reaches(
    params: Params,
    settings: SolverSettings,
    followed: Option<&Reach>,
    seeds: usize,
    opts: &SweepOptions,
    cancel: &dyn Fn() -> bool,
) -> Result<(Vec<Reached>, u64), SimError> {
    let known: Vec<Reach> = followed.cloned().into_iter().collect();
    let starts = spread_seeds(&params, seeds);
    seeds_from(params, settings, &known, &starts, opts, cancel)
}

/// What the seeds from `starts` reached at θν of `params`, told against
/// the attractors `known` there (and those found on the way), with the
/// points a diagram draws for each, and what they cost (right-hand-side
/// evaluations). The seeds run on [`SeedMap`] at [`SEED_RTOL`] (see
/// [`Seeding::told`]). `Cancelled` as soon as one is; failed seeds reach
/// nothing that can be named and are left out.
fn seeds_from(
    params: Params,
    settings: SolverSettings,
    known: &[Reach],
    starts: &[f64],
    opts: &SweepOptions,
    cancel: &dyn Fn() -> bool,
) -> Result<(Vec<Reached>, u64), SimError> {
    let sim = seed_simulator(params, &settings)?;
    let mut map = SeedMap::loose(&sim);
    let tol = rep_tol(sim.settings());
    let run = opts.transient.saturating_add(opts.keep);
    // A seed in a known chaotic set stops after SET_STAY iterates there: an
    // interpolant over the set's interval is worth what the seeds left
    // would integrate getting there and staying, a quarter of it at most.
    let worth = |left: usize| left.saturating_mul(run.min(2 * SET_STAY)) / 4;
    let mut seeding = Seeding {
        params,
        settings,
        opts,
        cancel,
        known: known.to_vec(),
        rhs: 0,
    };
    for r in &seeding.known {
        cover(&mut map, r, worth(starts.len()));
    }
    let mut out = Vec::with_capacity(starts.len());
    for (i, &theta0) in starts.iter().enumerate() {
        let (mut cycles, mut sets) = (Vec::new(), Vec::new());
        for r in &seeding.known {
            match r {
                Reach::Cycle(c) => cycles.push(c.clone()),
                Reach::Set(lo, hi) => sets.push((*lo, *hi)),
            }
        }
        let views: Vec<&[f64]> = cycles.iter().map(Vec::as_slice).collect();
        let known = Known {
            cycles: &views,
            sets: &sets,
        };
        let budget = (opts.transient, opts.keep);
        let fell = match map.fall(theta0, budget, tol, known, cancel) {
            Err(SimError::Cancelled) => return Err(SimError::Cancelled),
            Err(_) => continue,
            Ok(fell) => fell,
        };
        let Some((reach, points)) = seeding.told(fell, &cycles, &sets, tol)? else {
            continue;
        };
        let is_new =
            |r: &Reach, known: &[Reach]| !known.iter().any(|k| k.same(r, same_tol(&settings)));
        let (reach, points) = if is_new(&reach, &seeding.known) {
            unless_transient(&sim, reach, points, &cycles, tol, cancel)?
        } else {
            (reach, points)
        };
        if is_new(&reach, &seeding.known) {
            cover(&mut map, &reach, worth(starts.len() - i - 1));
            seeding.known.push(reach.clone());
        }
        out.push((reach, points));
    }
    Ok((out, seeding.rhs + map.rhs_evals))
}

/// A seed's chaotic-looking set, unless it is a transient: where one of
/// the known `cycles` lies inside it and the seed's orbit, run on from its
/// last point on the `loose` map, ends on it (see
/// `sim::attractors::transient`), the seed reached that cycle.
fn unless_transient(
    loose: &Simulator,
    reach: Reach,
    points: Vec<f64>,
    cycles: &[Vec<f64>],
    tol: f64,
    cancel: &dyn Fn() -> bool,
) -> Result<Reached, SimError> {
    let (Reach::Set(lo, hi), Some(&last)) = (&reach, points.last()) else {
        return Ok((reach, points));
    };
    let within: Vec<&[f64]> = cycles
        .iter()
        .map(Vec::as_slice)
        .filter(|c| transient::inside(c, (*lo, *hi)))
        .collect();
    if within.is_empty() {
        return Ok((reach, points));
    }
    Ok(
        match transient::escapes_to(loose, last, &within, tol, cancel)? {
            Some(k) => (Reach::Cycle(within[k].to_vec()), within[k].to_vec()),
            None => (reach, points),
        },
    )
}

/// The followed orbit's points labelled 0 and each further attractor's
/// (in the order the seeds first reached them) labelled 1, 2, ….
fn label(
    mine: Option<Reach>,
    thetas: Vec<f64>,
    reached: Vec<Reached>,
    same_tol: f64,
) -> SeededColumn {
    let mut col = SeededColumn {
        attractor: vec![0; thetas.len()],
        thetas,
        count: 0,
        rhs_evals: 0,
        reaches: mine.into_iter().collect(),
        same_tol,
    };
    col.add(reached);
    col
}

impl SeededColumn {
    /// Adds those of `reached` that are none of its attractors, each with
    /// the next label; whether any was added.
    fn add(&mut self, reached: Vec<Reached>) -> bool {
        let before = self.reaches.len();
        for (r, points) in reached {
            let known = self.reaches.iter().any(|k| k.same(&r, self.same_tol));
            if known || self.reaches.len() > u8::MAX as usize {
                continue;
            }
            let label = self.reaches.len() as u8;
            self.thetas.extend_from_slice(&points);
            self.attractor
                .extend(std::iter::repeat_n(label, points.len()));
            self.reaches.push(r);
        }
        self.count = self.reaches.len();
        self.count > before
    }

    /// Where seeds continuing attractor `label` to a neighbouring column
    /// start: each point of a cycle (near a fold its basin there is thin,
    /// and one point may lie outside it), a set's last point drawn.
    fn points_of(&self, label: usize) -> Vec<f64> {
        let labelled = self.thetas.iter().zip(&self.attractor);
        let last = labelled.rev().find(|&(_, &a)| a as usize == label);
        match self.reaches.get(label) {
            Some(Reach::Cycle(c)) => c.clone(),
            Some(Reach::Set(..)) => last.map(|(&t, _)| t).into_iter().collect(),
            None => vec![],
        }
    }

    /// The θ from which seeds at this column (at `params`) continue those
    /// attractors of `neighbour` (the next column's, left or right) that
    /// none of its own continues ([`continues`]), except those `tried`
    /// says were tried already (given their labels).
    pub(crate) fn starts_from(
        &self,
        neighbour: &SeededColumn,
        params: &Params,
        mut tried: impl FnMut(usize) -> bool,
    ) -> Vec<f64> {
        let mut starts = vec![];
        for (label, r) in neighbour.reaches.iter().enumerate() {
            if self.reaches.iter().any(|mine| continues(r, mine)) || tried(label) {
                continue;
            }
            for theta in neighbour.points_of(label) {
                starts.push(column_start(params.kappa, params.theta_nu, Some(theta)));
            }
        }
        starts
    }

    /// Runs seeds from `starts` at this column's θν (`params`) against its
    /// attractors and adds what is new (confirmed at full accuracy, as
    /// every seed's is); whether anything was.
    pub(crate) fn extend_from(
        &mut self,
        params: Params,
        settings: SolverSettings,
        starts: &[f64],
        opts: &SweepOptions,
        cancel: &dyn Fn() -> bool,
    ) -> Result<bool, SimError> {
        if starts.is_empty() || self.reaches.is_empty() {
            return Ok(false);
        }
        let (reached, rhs) = seeds_from(params, settings, &self.reaches, starts, opts, cancel)?;
        self.rhs_evals += rhs;
        Ok(self.add(reached))
    }
}

/// How far (radians) an attractor's points may move from one column to the
/// next and still be taken for the same branch by [`continues`]: the
/// columns of a diagram are a few thousandths of a radian of θν apart, and
/// coexisting attractors' points tenths apart.
const BRANCH_STEP: f64 = 0.05;

/// Whether attractor `b` of a column may be the continuation of `a`, its
/// neighbour's: every point of `a` (a set's hull's ends) lies within
/// [`BRANCH_STEP`] of a point of a cycle `b` whose period is a multiple of
/// a cycle `a`'s (the same, or doubled), or of a set `b`'s hull. Only a
/// test for whether a seed is worth running from `a`: a seed that turns
/// out to reach a known attractor adds nothing, so the test leans to
/// running one (a P2 shrinking onto a fixed point at a flip is tried).
fn continues(a: &Reach, b: &Reach) -> bool {
    if let (Reach::Cycle(ca), Reach::Cycle(cb)) = (a, b)
        && cb.len() % ca.len() != 0
    {
        return false;
    }
    let ends = |r: &Reach| match r {
        Reach::Cycle(c) => c.clone(),
        Reach::Set(lo, hi) => vec![*lo, *hi],
    };
    let near = |x: f64| match b {
        Reach::Cycle(c) => c.iter().any(|y| wrap_angle(x - y).abs() <= BRANCH_STEP),
        Reach::Set(lo, hi) => (lo - BRANCH_STEP..=hi + BRANCH_STEP).contains(&x),
    };
    ends(a).into_iter().all(near)
}

/// The followed column `followed` at θν of `params` seeded from `seeds`
/// further θ₀ (see the module's doc). With no seeds it is the followed
/// column alone, labelled 0.
pub fn seeded_column(
    params: Params,
    settings: SolverSettings,
    followed: &Column,
    seeds: usize,
    opts: &SweepOptions,
    cancel: &dyn Fn() -> bool,
) -> Result<SeededColumn, SimError> {
    let sim = Simulator::new(params, settings)?;
    let mine = Reach::of(&followed.thetas, &settings, solves_at(&sim));
    let (reached, rhs_evals) = if seeds == 0 {
        (vec![], 0)
    } else {
        let seeds = seeds.min(MAX_SEEDS);
        seed_reaches(params, settings, mine.as_ref(), seeds, opts, cancel)?
    };
    let mut col = label(mine, followed.thetas.clone(), reached, same_tol(&settings));
    col.rhs_evals = rhs_evals;
    Ok(col)
}

/// How many distinct attractors the orbit that reached `followed` (a phase
/// cell's own: its cycle, or its kept iterates' interval) and the orbits
/// from `seeds` θ₀ spread over the arc reach at `params`, each run with
/// `opts`; and what the seeds cost.
pub(crate) fn attractor_count(
    params: Params,
    settings: SolverSettings,
    followed: Option<Reach>,
    seeds: usize,
    opts: &SweepOptions,
    cancel: &dyn Fn() -> bool,
) -> Result<(usize, u64), SimError> {
    let seeds = seeds.min(MAX_SEEDS);
    let (reached, rhs) = seed_reaches(params, settings, followed.as_ref(), seeds, opts, cancel)?;
    let tol = same_tol(&settings);
    Ok((label(followed, vec![], reached, tol).count, rhs))
}

#[cfg(test)]
mod tests;
