//! Transient chaos (docs/attractors.md, the seeds' search): inside a periodic
//! window, orbits wander over a chaotic saddle for hundreds of iterates
//! before they reach the window's stable cycle, some for longer than an
//! orbit's budget. Such a set looks like a chaotic attractor, and once it
//! is known, the seeds that stay in it are told they have arrived. Two
//! tests tell it from one: orbits from its edges find a stable cycle
//! hidden in it, and an orbit run on from the set shows whether the set
//! lets it go to a stable cycle inside it.

use super::seed_map::{Fell, Known, SeedMap};
use crate::model::wrap_angle;
use crate::sim::{SimError, Simulator};

/// How long an orbit in a set is run on to see whether the set lets it
/// go: ten orbits' budget (in Fig. 3b's P14 window at θν = 1.23617,
/// direct orbits from θ0 = 0.3 and 0.45 are still on the saddle after
/// 400 iterates, and every one is on the P14 by 4 000).
pub(crate) const ESCAPE: usize = 10 * (TRANSIENT + KEEP);

/// Both tests integrate the seeds' loose map directly: on a set's
/// interpolant (to 1e-4, enough to tell a seed it stays in the set) a
/// narrow window's cycle may not attract (Fig. 3b's P14 at θν = 1.23617
/// does not).
fn direct(loose: &Simulator) -> SeedMap<'_> {
    SeedMap::wide(loose)
}

/// The points a stable cycle hidden in the chaotic-looking set [lo, hi]
/// repeats on (to be solved), if the orbit from its upper edge reaches
/// one that is not among `cycles`: it is run on the `loose` map for
/// [`TRANSIENT`] iterates, told of `cycles` only. The set's extremes are
/// images of f's turning point (where f peaks, and the image of that
/// peak), whose orbit a stable cycle attracts (Singer's theorem, for a
/// map with negative Schwarzian), so a window's cycle that every seed
/// missed is found from there.
pub(crate) fn hidden_cycle(
    loose: &Simulator,
    (_, hi): (f64, f64),
    cycles: &[&[f64]],
    rep_tol: f64,
    cancel: &dyn Fn() -> bool,
) -> Result<Option<Vec<f64>>, SimError> {
    let told = Known { cycles, sets: &[] };
    match direct(loose).fall(hi, (TRANSIENT, 0), rep_tol, told, cancel) {
        Ok(Fell::Repeats(points)) => Ok(Some(points)),
        Err(SimError::Cancelled) => Err(SimError::Cancelled),
        Ok(_) | Err(_) => Ok(None),
    }
}

/// Which of the stable `cycles` inside a set an orbit from `last`, a
/// point of the set, ends on within [`ESCAPE`] iterates on the `loose`
/// map, if any: the set is then a transient on the way to it.
pub(crate) fn escapes_to(
    loose: &Simulator,
    last: f64,
    cycles: &[&[f64]],
    rep_tol: f64,
    cancel: &dyn Fn() -> bool,
) -> Result<Option<usize>, SimError> {
    let told = Known { cycles, sets: &[] };
    match direct(loose).fall(last, (ESCAPE, 0), rep_tol, told, cancel) {
        Ok(Fell::Known(k)) => Ok(Some(k)),
        // It settled before it could be seen closing in: on which?
        Ok(Fell::Repeats(points)) => Ok(cycles
            .iter()
            .position(|c| same_cycle(&points, c, SAME_LOOSE))),
        Err(SimError::Cancelled) => Err(SimError::Cancelled),
        Ok(_) | Err(_) => Ok(None),
    }
}

/// How far the loose map's cycle may lie from the solved one: its error
/// over 1 − m (as `sim::seeded`'s slow closing in).
const SAME_LOOSE: f64 = 1e-4;

/// Whether every point of `cycle` lies in [lo, hi], give or take 5 % of
/// its width: a kept orbit's hull reaches the set's edges only nearly,
/// and a window's cycle passes next to them (they are the turning point's
/// images, which the cycle shadows).
pub(crate) fn inside(cycle: &[f64], (lo, hi): (f64, f64)) -> bool {
    let slack = 0.05 * (hi - lo);
    cycle.iter().all(|x| (lo - slack..=hi + slack).contains(x))
}

/// Iterates dropped, and kept, per seed (the `orbit` command's defaults).
pub const TRANSIENT: usize = 400;
/// See [`TRANSIENT`].
pub const KEEP: usize = 128;

/// Whether two p-cycles are one: every point of `a` within `tol` of a
/// point of `b`.
pub fn same_cycle(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.len() == b.len()
        && a.iter()
            .all(|x| b.iter().any(|y| wrap_angle(x - y).abs() <= tol))
}
