//! A period-doubling cascade followed branch by branch: P → 2P → 4P …,
//! each level continued from just past the previous level's doubling to
//! its own.
//!
//! The map is one-dimensional, so the critical eigen-direction at a
//! doubling is θ itself: the doubled cycle is seeded at θ* ± ε, a little
//! past the doubling (where the old cycle has a multiplier just below −1
//! and the new one is born with +1), and solved by Newton at period 2p;
//! a seed is kept when the solved cycle's minimal period is 2p.

use super::branch::{Branch, ContOptions, SpecialKind, SpecialPoint, Stop};
use super::pace::solve_cycle;
use super::walk::{Reach, continue_branch_paced};
use super::{Criticality, Flip, Pace, Problem, drive};
use crate::sim::PERIOD_MAX;
use crate::sim::cycles::{CycleFailure, CycleOptions};

/// A followed cascade.
#[derive(Clone, Debug, PartialEq)]
pub struct Cascade {
    /// The branches, one per level, each from its birth to its doubling
    /// (the first as the caller gave it, with [`FirstLevel::Given`]).
    pub branches: Vec<Branch>,
    /// The doublings b₁, b₂, … in order (periods p, 2p, 4p, …).
    pub doublings: Vec<SpecialPoint>,
    /// Why the cascade ended.
    pub stop: String,
}

impl Cascade {
    /// δₙ = (bₙ − bₙ₋₁)/(bₙ₊₁ − bₙ) of the doublings.
    pub fn ratios(&self) -> Vec<f64> {
        let b: Vec<f64> = self.doublings.iter().map(|d| d.lambda).collect();
        feigenbaum_ratios(&b)
    }
}

/// δₙ = (bₙ − bₙ₋₁)/(bₙ₊₁ − bₙ) for n = 1 … len − 2 (empty for fewer than
/// three values).
pub fn feigenbaum_ratios(b: &[f64]) -> Vec<f64> {
    b.windows(3)
        .map(|w| (w[1] - w[0]) / (w[2] - w[1]))
        .collect()
}

/// How far past a doubling the doubled cycle is seeded, as a share of the
/// last gap between doublings: far enough that its points are distinct
/// (they separate like the square root of the distance), near enough to
/// stay well before the next doubling (the gaps shrink about 4.7 times).
const SWITCH_SHARE: f64 = 1e-2;

/// Follows the cascade from the p-cycle through `seed` at λ = `reach.from`
/// towards `reach.to` (see the module notes), until a level has no
/// doubling before `to`, two doublings come closer than 100×
/// `opts.locate_tol` (the δₙ would have no digits left), the period would
/// pass `max_period` (at most [`PERIOD_MAX`]), or a switch fails. Fails
/// only when the first level has no cycle at its start.
pub fn cascade(
    reach: Reach<'_>,
    seed: f64,
    max_period: usize,
    cancel: &dyn Fn() -> bool,
) -> Result<Cascade, CycleFailure> {
    let first = FirstLevel::Seed(seed);
    cascade_reporting(reach, first, max_period, cancel, &mut |_| {})
}

/// [`cascade`] from `first`, calling `on_level` with each level's branch
/// as it ends (for progress lines; a given first level is not reported):
/// the walk of [`cascade_paced`] driven to its end.
pub fn cascade_reporting(
    reach: Reach<'_>,
    first: FirstLevel,
    max_period: usize,
    cancel: &dyn Fn() -> bool,
    on_level: &mut dyn FnMut(&Branch),
) -> Result<Cascade, CycleFailure> {
    let pace = Pace::new();
    let walk = cascade_paced(&pace, reach, first, max_period, on_level);
    drive(&pace, walk, cancel)
}

/// Where a cascade's first level comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum FirstLevel {
    /// Followed from the cycle through this θ.
    Seed(f64),
    /// A branch of the reach's p-cycle from `from` towards `to` that the
    /// caller has already followed (with [`super::continue_branch`] and
    /// the reach's options, past its doubling or not: its first doubling
    /// is the one a cascade's level stops at, so the levels after it are
    /// those a cascade from a seed finds). It is the cascade's first
    /// branch as given, and not reported.
    Given(Branch),
}

/// The cascade's walk, a piece after each map evaluation and a cancel
/// asked once per point: [`cascade_reporting`] drives it to its end at
/// once, a job ([`crate::jobs`]) piece by piece.
pub async fn cascade_paced<R: FnMut(&Branch) + ?Sized>(
    pace: &Pace,
    reach: Reach<'_>,
    first: FirstLevel,
    max_period: usize,
    on_level: &mut R,
) -> Result<Cascade, CycleFailure> {
    let (prob, from, to, opts) = (reach.prob, reach.from, reach.to, reach.opts);
    // (With a given first level the seed is never used.)
    let (seed, mut given) = match first {
        FirstLevel::Seed(seed) => (seed, None),
        FirstLevel::Given(b) => (0.0, Some(b)),
    };
    // The caller has its own branch: only the levels after it are news.
    let report_first = given.is_none();
    let dir = if to >= from { 1.0 } else { -1.0 };
    let mut branches = Vec::new();
    let mut doublings: Vec<SpecialPoint> = Vec::new();
    let (mut start, mut theta, mut period) = (from, seed, prob.period);
    let mut level_opts = ContOptions {
        stop_at_pd: true,
        ..*opts
    };
    let stop = loop {
        let level = prob.with_period(period);
        let followed = match given.take() {
            Some(b) => Ok(b),
            None => follow(pace, &level, [start, to], theta, &level_opts).await,
        };
        let branch = match followed {
            Ok(b) => b,
            Err(e) if branches.is_empty() => return Err(e),
            Err(e) => break format!("the P{period} cycle could not be followed: {e}"),
        };
        if collapsed(&branch, period) {
            branches.push(branch);
            break format!("the P{period} branch collapsed onto a shorter cycle at its start");
        }
        let pd = branch.doublings().next().cloned();
        if report_first || !branches.is_empty() {
            on_level(&branch);
        }
        let message = branch.stop_message();
        let cancelled = branch.stop == Stop::Cancelled;
        branches.push(branch);
        let Some(pd) = pd else {
            break if cancelled {
                "cancelled".into()
            } else {
                format!("no period doubling of the P{period} cycle: it {message}")
            };
        };
        let gap = gap_to(&doublings, &pd, from, to, opts);
        doublings.push(pd.clone());
        if let Some(why) = crowded(doublings.len(), gap, period, max_period, opts) {
            break why;
        }
        let ahead = Reach::new(&level, from, to, opts);
        let end = flip_end(pace, ahead, &pd, gap, on_level, &mut branches).await;
        if let Some(why) = end {
            break why;
        }
        match super::switch::switch(pace, &level, &pd, dir * SWITCH_SHARE * gap).await {
            Ok((l1, th)) => {
                (start, theta, period) = (l1, th, 2 * period);
                level_opts = next_level_options(level_opts, opts, gap);
            }
            Err(why) => break why,
        }
    };
    Ok(Cascade {
        branches,
        doublings,
        stop,
    })
}

/// The branch of `level`'s cycle through `theta` over `[from, to]`, its
/// special points not reported.
async fn follow(
    pace: &Pace,
    level: &Problem,
    [from, to]: [f64; 2],
    theta: f64,
    opts: &ContOptions,
) -> Result<Branch, CycleFailure> {
    let quiet = &mut |_: &SpecialPoint| {};
    continue_branch_paced(pace, Reach::new(level, from, to, opts), theta, quiet).await
}

/// Whether the branch of the `period`-cycle starts on a shorter cycle.
fn collapsed(branch: &Branch, period: usize) -> bool {
    branch
        .points
        .first()
        .is_some_and(|q| q.minimal_period < period)
}

/// How far the cascade's last doubling is from the one before (from the
/// range's nearer end, at least 100× the location accuracy, for the first).
fn gap_to(
    doublings: &[SpecialPoint],
    pd: &SpecialPoint,
    from: f64,
    to: f64,
    opts: &ContOptions,
) -> f64 {
    match doublings.last() {
        Some(prev) => (pd.lambda - prev.lambda).abs(),
        None => (pd.lambda - from)
            .abs()
            .min((to - pd.lambda).abs())
            .max(1e2 * opts.locate_tol),
    }
}

/// Why the cascade ends after its `n`-th doubling, a `gap` past the one
/// before, on the `period`-cycle, if it does: the doublings crowd within
/// 100× the location accuracy (the δₙ would have no digits left), or the
/// next period is above `max_period` (at most [`PERIOD_MAX`]).
fn crowded(
    n: usize,
    gap: f64,
    period: usize,
    max_period: usize,
    opts: &ContOptions,
) -> Option<String> {
    if n >= 2 && gap < 1e2 * opts.locate_tol {
        return Some(format!(
            "the last two doublings are {gap:.1e} apart, within 100x the location accuracy ({:.0e})",
            opts.locate_tol
        ));
    }
    let max = max_period.min(PERIOD_MAX);
    (2 * period > max).then(|| format!("the next period, {}, is above {max}", 2 * period))
}

/// Why the cascade ends at the doubling `pd` of `ahead.prob` (a level:
/// `ahead` is its cycle over the cascade's range, with the cascade's
/// options; `gap` the last gap between doublings) rather than
/// switching to the doubled cycle, if it does. Only a supercritical flip
/// hands the attractor on to the doubled cycle; at a subcritical one that
/// cycle is unstable and lies behind (it is followed to its fold, and
/// added as a level); a supercritical one whose doubled cycle lies behind
/// has no doubling ahead.
async fn flip_end<R: FnMut(&Branch) + ?Sized>(
    pace: &Pace,
    ahead: Reach<'_>,
    pd: &SpecialPoint,
    gap: f64,
    on_level: &mut R,
    branches: &mut Vec<Branch>,
) -> Option<String> {
    let f = pd.flip?;
    let level = ahead.prob;
    let dir = if ahead.to >= ahead.from { 1.0 } else { -1.0 };
    if f.criticality() == Criticality::Subcritical {
        let (why, unstable) = subcritical(pace, ahead, pd, &f, gap).await;
        if let Some(b) = unstable {
            on_level(&b);
            branches.push(b);
        }
        return Some(why);
    }
    if f.criticality() == Criticality::Supercritical && f.side() != dir {
        let period = level.period;
        return Some(format!(
            "the P{period} cycle regains stability at {} = {} (a supercritical flip whose P{} cycle lies behind): no doubling ahead",
            level.param.name(),
            pd.lambda,
            2 * period
        ));
    }
    None
}

/// The options of the level after a doubling: it is about gap/4.7 long,
/// so its steps are in units of `gap`.
fn next_level_options(level_opts: ContOptions, opts: &ContOptions, gap: f64) -> ContOptions {
    let scale = gap;
    ContOptions {
        scale,
        h_min: 0.1 * opts.locate_tol / scale,
        newton_tol: opts.newton_tol.min(0.1 * opts.locate_tol / scale),
        ..level_opts
    }
}

/// At the subcritical flip `pd` of `ahead.prob` (a level, over the
/// cascade's range, with its options): the unstable doubled cycle
/// followed from next to the flip (on the side the normal form puts it)
/// to where it turns, and the words for where the attractor goes.
async fn subcritical(
    pace: &Pace,
    ahead: Reach<'_>,
    pd: &SpecialPoint,
    f: &Flip,
    gap: f64,
) -> (String, Option<Branch>) {
    let (level, from, to, opts) = (ahead.prob, ahead.from, ahead.to, ahead.opts);
    let name = level.param.name();
    let (p, q) = (level.period, 2 * level.period);
    let head = format!(
        "subcritical flip of the P{p} cycle at {name} = {}: past it the attractor jumps away (no P{q} cycle takes over)",
        pd.lambda
    );
    let side = f.side();
    let delta = SWITCH_SHARE * gap;
    let l1 = pd.lambda + side * delta;
    let doubled = level.with_period(q);
    let Some(seed) = unstable_seed(pace, level, pd, f, l1).await else {
        return (
            format!("{head}; the unstable P{q} cycle next to it was not solved"),
            None,
        );
    };
    // Towards the end of the range on the cycle's side.
    let end = if (to - from) * side > 0.0 { to } else { from };
    let o = ContOptions::for_range(&level.settings, l1, end);
    let o = ContOptions {
        locate_tol: opts.locate_tol,
        ..o
    };
    let Ok(b) = follow(pace, &doubled, [l1, end], seed, &o).await else {
        return (
            format!("{head}; the unstable P{q} cycle could not be followed"),
            None,
        );
    };
    let why = match b.of_kind(SpecialKind::Fold).next() {
        Some(fold) => {
            // The branch's points include the located fold itself; its
            // stable stretch beyond the fold, in λ.
            let at = b.points.iter().position(|x| x.lambda == fold.lambda);
            let stable: Vec<f64> = at.map_or(Vec::new(), |i| {
                b.points[i + 1..]
                    .iter()
                    .skip_while(|x| !x.stable)
                    .take_while(|x| x.stable)
                    .map(|x| x.lambda)
                    .collect()
            });
            let lo = stable.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = stable.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            // Past the flip is the side opposite the doubled cycle's.
            let reaches = stable.iter().any(|&l| (l - pd.lambda) * side < 0.0);
            let after = if stable.is_empty() {
                String::new()
            } else {
                format!(
                    "; beyond it the P{q} cycle is stable for {name} in [{lo}, {hi}]{}",
                    if reaches {
                        ", and past the flip the attractor jumps onto it".to_string()
                    } else {
                        ", which does not reach past the flip: there the attractor jumps off these branches".to_string()
                    }
                )
            };
            format!(
                "{head}; the unstable P{q} cycle born there turns at a fold at {name} = {}{after}",
                fold.lambda
            )
        }
        None => format!(
            "{head}; the unstable P{q} cycle born there has no fold before it {}",
            b.stop_message()
        ),
    };
    (why, Some(b))
}

/// A point of the 2p-cycle born at the subcritical flip `pd` of `level`
/// (`f`), solved by Newton at `l1` from the normal form's half-width either
/// side of the flip's point.
async fn unstable_seed(
    pace: &Pace,
    level: &Problem,
    pd: &SpecialPoint,
    f: &Flip,
    l1: f64,
) -> Option<f64> {
    let cyc = CycleOptions::for_settings(&level.settings);
    let q = 2 * level.period;
    let (sim, eta) = (level.sim(l1).ok()?, f.predicted(pd.lambda, l1)?);
    for sign in [1.0, -1.0] {
        let c = solve_cycle(pace, &sim, pd.theta + sign * eta, q, &cyc, &mut (0, 0)).await;
        if let Ok(c) = c
            && c.minimal_period == q
        {
            return Some(c.points[0]);
        }
    }
    None
}
