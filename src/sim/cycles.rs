//! Periodic orbits solved rather than waited for: Newton's method on
//! g(θ) = wrap(f^p(θ) − θ), whose slope is the chain rule's
//! g'(θ) = Π f'(θᵢ) − 1 over the cycle's points, with a step that is halved
//! whenever it leaves the exit arc or fails to shrink |g| (a jump of f, or
//! a step too long for the linear model). Where convergence is slow the
//! classifiers solve the cycle the orbit is heading for
//! ([`confirm_contraction`]) instead of iterating until it gets there.

use super::period::{Contraction, PERIOD_MAX};
use super::{SimError, Simulator};
use crate::integrate::SolverSettings;
use crate::model::wrap_angle;

mod solve;

pub use solve::CycleSolve;

/// How hard the solver tries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CycleOptions {
    /// Converged once the Newton step |g/g'| is at most `tol`, in radians:
    /// the distance left to the cycle, which near a multiplier of 1 is far
    /// larger than the residual |g|.
    pub tol: f64,
    /// … or once |g| is at most this and no step shrinks it further: the
    /// map's own error, below which no step can be trusted. A residual
    /// below the floor alone does not stop Newton (where f hugs the
    /// identity, m = 0.99998, a residual of 6e-11 is 3e-6 from the cycle).
    pub floor: f64,
    /// The most Newton steps.
    pub max_iter: usize,
    /// The most halvings of one step before the solver gives up on it.
    pub max_halvings: usize,
}

/// The longest Newton step, in radians: past it the linear model of f^p is
/// not trusted (a cycle's basin on the exit arc is rarely wider).
pub const MAX_STEP: f64 = 0.2;

impl CycleOptions {
    /// A step and a residual floor both at the integrator's tolerance (the
    /// map's own error is about the tolerance), within [1e-14, 1e-6]; 1e-10
    /// for the fixed-step methods. 40 steps, 20 halvings each.
    pub fn for_settings(settings: &SolverSettings) -> Self {
        let tol = if settings.method.is_adaptive() {
            settings.rtol.clamp(1e-14, 1e-6)
        } else {
            1e-10
        };
        CycleOptions {
            tol,
            floor: tol,
            max_iter: 40,
            max_halvings: 20,
        }
    }

    /// The budget of a solve a classifier attempts on its own: a step of
    /// 100× and a floor of 10× the tolerance (within [1e-13, 1e-6]: far
    /// below a pixel or a period tolerance), and few steps, so that a seed
    /// that leads nowhere costs little.
    pub fn for_classifier(settings: &SolverSettings) -> Self {
        let tol = Self::for_settings(settings).tol;
        CycleOptions {
            tol: (1e2 * tol).clamp(1e-13, 1e-6),
            floor: (10.0 * tol).clamp(1e-13, 1e-6),
            max_iter: 8,
            max_halvings: 8,
        }
    }
}

/// A solved p-cycle.
#[derive(Clone, Debug, PartialEq)]
pub struct Cycle {
    /// θ₀, f(θ₀), …, f^{p−1}(θ₀), θ₀ the converged Newton iterate.
    pub points: Vec<f64>,
    /// Π f'(θᵢ): the cycle attracts when its magnitude is below 1.
    pub multiplier: f64,
    /// |multiplier| < 1.
    pub stable: bool,
    /// |wrap(f^p(θ₀) − θ₀)|.
    pub residual: f64,
    /// Newton steps taken.
    pub iterations: usize,
    /// The Newton step |g/(m − 1)| at θ₀: the distance left to the cycle
    /// (at most `tol` unless Newton stalled at the map's error).
    pub step: f64,
    /// The smallest q dividing p whose shift maps the points onto themselves
    /// (within 100× the tolerance): p unless Newton found a shorter cycle
    /// traversed p/q times.
    pub minimal_period: usize,
    /// Map evaluations spent (each carries f'(θ) exactly; a central
    /// difference, where f has no derivative, counts 2 more).
    pub map_evals: u64,
    /// Right-hand-side evaluations spent.
    pub rhs_evals: u64,
}

impl Cycle {
    /// p, the period solved for.
    pub fn period(&self) -> usize {
        self.points.len()
    }

    /// The cycle's Lyapunov exponent, ln|multiplier|/p: exact for a
    /// periodic orbit, nothing to average.
    pub fn lyapunov(&self) -> f64 {
        self.multiplier.abs().ln() / self.period() as f64
    }
}

/// Why a solve failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CycleFailure {
    #[error("the period must lie in [1, {PERIOD_MAX}], not {0}")]
    BadPeriod(usize),
    #[error("the seed theta = {theta} is not on the exit arc")]
    SeedOffArc { theta: f64 },
    #[error("no convergence: after {iterations} Newton step(s) the residual is still {residual:e}")]
    NoConvergence { iterations: usize, residual: f64 },
    #[error(
        "the cycle crosses a discontinuity of the map near theta = {theta} (f jumps or the slip restarts there, so f is not differentiable)"
    )]
    Discontinuity { theta: f64 },
    #[error(transparent)]
    Sim(#[from] SimError),
}

/// g, g' + 1 and the points of one pass round a candidate cycle
/// ([`solve::Walk`]).
struct Pass {
    g: f64,
    multiplier: f64,
    points: Vec<f64>,
    restarted: bool,
}

/// Solves f^p(θ) = θ by Newton's method from `seed` (see the module notes).
pub fn solve_cycle(
    sim: &Simulator,
    seed: f64,
    p: usize,
    opts: &CycleOptions,
) -> Result<Cycle, CycleFailure> {
    solve_counting(sim, seed, p, opts, &mut (0, 0))
}

/// [`solve_cycle`], adding the map and right-hand-side evaluations it
/// spends to `spent`, whether it succeeds or not.
pub fn solve_counting(
    sim: &Simulator,
    seed: f64,
    p: usize,
    opts: &CycleOptions,
    spent: &mut (u64, u64),
) -> Result<Cycle, CycleFailure> {
    let mut solve = CycleSolve::start(sim, seed, p, opts)?;
    let result = loop {
        if let Some(r) = solve.advance(sim) {
            break r;
        }
    };
    let (maps, rhs) = solve.spent();
    spent.0 += maps;
    spent.1 += rhs;
    result
}

/// The solved cycle at θ₀ = `x` (refused where it passes a restart), its
/// minimal period decided with [`distinct_points`].
#[allow(clippy::too_many_arguments)]
fn finish(
    e: Pass,
    x: f64,
    p: usize,
    opts: &CycleOptions,
    iterations: usize,
    step: f64,
    spent: &(u64, u64),
    before: (u64, u64),
) -> Result<Cycle, CycleFailure> {
    if e.restarted {
        return Err(CycleFailure::Discontinuity { theta: x });
    }
    let distinct = distinct_points(opts.tol, e.multiplier);
    let minimal_period = (1..=p)
        .filter(|q| p.is_multiple_of(*q))
        .find(|&q| (0..p - q).all(|i| wrap_angle(e.points[i + q] - e.points[i]).abs() <= distinct))
        .unwrap_or(p);
    Ok(Cycle {
        stable: e.multiplier.abs() < 1.0,
        multiplier: e.multiplier,
        residual: e.g.abs(),
        points: e.points,
        iterations,
        step,
        minimal_period,
        map_evals: spent.0 - before.0,
        rhs_evals: spent.1 - before.1,
    })
}

/// The cycle an orbit nearly repeats on ([`super::period::near_period`]
/// of `seq`, whose last value is the next onset), solved from that onset:
/// `Some` if it is a genuine p-cycle, attracts, and lies within the
/// recent values' range widened by that range on each side. An orbit
/// leaving an unstable fixed point just past a flip, or approaching a
/// cycle whose multiplier is near 1, nearly repeats long before it
/// settles. The solve's cost is added to `spent`.
pub fn near_cycle(
    sim: &Simulator,
    seq: &[f64],
    opts: &CycleOptions,
    spent: &mut (u64, u64),
) -> Option<Cycle> {
    let near = NearRepeat::of(seq)?;
    solve_counting(sim, near.seed, near.period, opts, spent)
        .ok()
        .filter(|c| near.accepts(c))
}

/// A near repeat of an orbit ([`near_cycle`]): the cycle to solve, and
/// where it must lie.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NearRepeat {
    pub period: usize,
    /// The next onset, where the solve starts.
    pub seed: f64,
    lo: f64,
    hi: f64,
}

impl NearRepeat {
    /// The near repeat at the end of `seq` (whose last value is the next
    /// onset), if there is one.
    pub fn of(seq: &[f64]) -> Option<Self> {
        let period = super::period::near_period(seq)?;
        let recent = &seq[seq.len() - 2 * super::period::CONTRACTION_PERIOD_MAX..];
        let lo = recent.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = recent.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let margin = hi - lo;
        Some(NearRepeat {
            period,
            seed: *seq.last()?,
            lo: lo - margin,
            hi: hi + margin,
        })
    }

    /// Whether the solved `c` is the cycle it repeats on: a genuine p-cycle
    /// that attracts, within the recent values' range widened by that
    /// range on each side.
    pub fn accepts(&self, c: &Cycle) -> bool {
        c.minimal_period == self.period
            && c.stable
            && c.points.iter().all(|&x| x >= self.lo && x <= self.hi)
    }
}

/// How far apart two points of a solved p-cycle with multiplier `m` must
/// be to count as distinct (deciding its minimal period), for a solve to
/// tolerance `tol`: 100·tol, or more where the points are less certain. An
/// error ε of f^p moves the solved points by ε/|1 − m|, so just past a
/// flip (m near 1, the fixed point traversed twice) they drift apart by
/// far more than the tolerance (3e-8 at m = 1.003 and 1e-10); they are one
/// point to 100·tol/|1 − m|, at most 1e-6 (a genuine doubled cycle that
/// close to its flip cannot be told from the fixed point by any solve;
/// continuation, which needs to, keeps 100·tol).
pub fn distinct_points(tol: f64, m: f64) -> f64 {
    let gap = (1.0 - m).abs();
    (1e2 * tol / gap.min(1.0)).min(1e-6).max(1e2 * tol)
}

/// Whether the end of `seq` keeps approaching `cycle`, whose point 0 is in
/// the phase of the newest value: of the distances e₀ … e₃ of the newest
/// value and of those 1, 2 and 3 periods before it from that point, each
/// is below the one two periods earlier (e₀ < e₂, e₁ < e₃: an approach with
/// a negative multiplier alternates sides, unevenly, so neighbours are not
/// compared), or the newest is already within `noise` of it; and e₃ is
/// within 0.1 rad.
pub fn approaches(cycle: &Cycle, seq: &[f64], noise: f64) -> bool {
    let p = cycle.period();
    let n = seq.len();
    if n < 3 * p + 1 {
        return false;
    }
    let c0 = cycle.points[0];
    let e: [f64; 4] = std::array::from_fn(|k| wrap_angle(seq[n - 1 - k * p] - c0).abs());
    e[3] < 0.1 && (e[0] <= noise || (e[0] < e[2] && e[1] < e[3]))
}

/// The cycle the end of `seq` contracts onto ([`super::contraction`]),
/// solved from Aitken's limit, when it is a genuine p-cycle (not a shorter
/// one traversed several times), attracts, and `seq` keeps approaching it;
/// `None` otherwise (the caller then goes on iterating). The evaluations
/// it spends are added to `spent` (map, right-hand side).
pub fn confirm_contraction(
    sim: &Simulator,
    seq: &[f64],
    c: &Contraction,
    opts: &CycleOptions,
    noise: f64,
    spent: &mut (u64, u64),
) -> Option<Cycle> {
    let cycle = solve_counting(sim, c.limit, c.period, opts, spent).ok()?;
    confirms(&cycle, seq, c, noise).then_some(cycle)
}

/// Whether the solved `cycle` confirms the contraction `c` of `seq`
/// ([`confirm_contraction`]).
pub fn confirms(cycle: &Cycle, seq: &[f64], c: &Contraction, noise: f64) -> bool {
    cycle.minimal_period == c.period && cycle.stable && approaches(cycle, seq, noise)
}

#[cfg(test)]
mod distinct_tests {
    use super::distinct_points;

    #[test]
    fn points_of_a_cycle_with_multiplier_near_one_need_a_wider_gap() {
        // Away from m = 1: 100·tol.
        assert!((distinct_points(1e-10, -0.5) - 1e-8).abs() < 1e-22);
        // The fixed point traversed twice just past a flip (m = 1.003 for
        // f²): its solved points drift 3e-8 apart, and are one point.
        assert!(distinct_points(1e-10, 1.003) > 3e-8);
        // Never wider than 1e-6, nor narrower than 100·tol.
        assert_eq!(distinct_points(1e-10, 1.0), 1e-6);
        assert!((distinct_points(1e-6, 1.0) - 1e-4).abs() < 1e-18);
    }
}
