//! Every attractor at one parameter point (docs/attractors.md): orbits
//! from seeds spread over the exit arc (and from a previous attractor's
//! point, where there is one), each run to its attractor, and the
//! attractors told apart. Two orbits reach the same attractor when their
//! solved cycles coincide to the solver's accuracy, or when their chaotic
//! sets overlap; each attractor's basin fraction is the share of the
//! spread seeds that reach it.

use rayon::prelude::*;

use super::{Orbit, OrbitOptions, Period, SimError, Simulator, default_settings};
use crate::integrate::SolverSettings;
use crate::model::{Params, exit_arc, wrap_angle};

/// Iterates dropped, and kept, per seed (the `orbit` command's defaults).
pub const TRANSIENT: usize = 400;
/// See [`TRANSIENT`].
pub const KEEP: usize = 128;

/// One attractor.
#[derive(Clone, Debug, PartialEq)]
pub struct Attractor {
    /// The period, or `None` for an aperiodic (chaotic) attractor.
    pub period: Option<usize>,
    /// A solved cycle's points; an aperiodic attractor's kept iterates'
    /// smallest and largest θ (the interval its set lies in).
    pub points: Vec<f64>,
    /// A solved cycle's multiplier.
    pub multiplier: Option<f64>,
    /// The Lyapunov exponent: ln|m|/p for a cycle, the mean of ln|f'| over
    /// the kept iterates otherwise.
    pub lyapunov: Option<f64>,
    /// The mean's standard error (none for a cycle, whose exponent is
    /// exact).
    pub lyapunov_stderr: Option<f64>,
    /// The share of the spread seeds that reach it.
    pub basin_fraction: f64,
}

/// The θ₀ of `n` seeds spread over the exit arc at `params`: the midpoints
/// of n equal parts.
pub fn spread_seeds(params: &Params, n: usize) -> Vec<f64> {
    let (lo, hi) = exit_arc(params.kappa, params.theta_nu);
    (0..n)
        .map(|i| lo + (hi - lo) * (i as f64 + 0.5) / n as f64)
        .collect()
}

/// What one seed reached.
enum Reached {
    Cycle {
        period: usize,
        points: Vec<f64>,
        multiplier: f64,
    },
    Aperiodic {
        lo: f64,
        hi: f64,
        lyapunov: Option<f64>,
        stderr: Option<f64>,
    },
}

/// The orbit from `theta0`, to its attractor.
fn reach(
    sim: &Simulator,
    theta0: f64,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Reached, SimError> {
    let opts = OrbitOptions {
        transient: TRANSIENT,
        keep: KEEP,
        lyapunov: false,
        period_tol: OrbitOptions::period_tol_for(sim.settings().rtol),
    };
    let orbit = sim.orbit(theta0, &opts, cancel)?;
    if let (Period::Periodic(_), Some(c)) = (&orbit.period, &orbit.cycle) {
        return Ok(Reached::Cycle {
            period: c.minimal_period,
            points: c.points[..c.minimal_period].to_vec(),
            multiplier: c.multiplier,
        });
    }
    // Aperiodic, or a period whose cycle was not solved: the exponent on
    // more iterates from where the orbit is.
    let more = OrbitOptions {
        transient: 0,
        lyapunov: true,
        ..opts
    };
    let o: Orbit = sim.orbit(orbit.theta_last, &more, cancel)?;
    let th = o.thetas();
    let lo = th.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = th.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Ok(Reached::Aperiodic {
        lo,
        hi,
        lyapunov: o.lyapunov,
        stderr: o.lyapunov_stderr,
    })
}

/// Whether two p-cycles are one: every point of `a` within `tol` of a
/// point of `b`.
fn same_cycle(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.len() == b.len()
        && a.iter()
            .all(|x| b.iter().any(|y| wrap_angle(x - y).abs() <= tol))
}

/// Every attractor at `params` reached from `seeds` seeds spread over the
/// exit arc and from `previous` (a point of the attractor found before,
/// not counted in the basin fractions), in order of decreasing basin
/// fraction. The seeds run in parallel; `cancel` is polled by each orbit.
pub fn attractors(
    params: Params,
    settings: SolverSettings,
    seeds: usize,
    previous: Option<f64>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<Attractor>, SimError> {
    let sim = Simulator::new(params, settings)?;
    let spread = spread_seeds(&params, seeds.max(1));
    let all: Vec<f64> = spread.iter().copied().chain(previous).collect();
    let reached: Vec<Result<Reached, SimError>> =
        all.par_iter().map(|&th| reach(&sim, th, cancel)).collect();
    // Cycles coincide to 1e3× the solver's tolerance (their points are
    // solved by Newton to about the tolerance).
    let tol = 1e3 * super::CycleOptions::for_settings(&settings).tol;
    let mut out: Vec<(Attractor, usize)> = Vec::new();
    for (i, r) in reached.into_iter().enumerate() {
        let counted = usize::from(i < spread.len());
        let r = match r {
            Ok(r) => r,
            // A seed whose orbit fails (off the arc after a restart, or
            // cancelled) reaches nothing that can be named.
            Err(SimError::Cancelled) => return Err(SimError::Cancelled),
            Err(_) => continue,
        };
        let known = out.iter_mut().find(|(a, _)| match (&r, a.period) {
            (Reached::Cycle { period, points, .. }, Some(p)) => {
                *period == p && same_cycle(points, &a.points, tol)
            }
            (Reached::Aperiodic { lo, hi, .. }, None) => *lo <= a.points[1] && *hi >= a.points[0],
            _ => false,
        });
        if let Some((a, n)) = known {
            *n += counted;
            // An overlapping chaotic set widens the interval.
            if let Reached::Aperiodic { lo, hi, .. } = r {
                a.points = vec![a.points[0].min(lo), a.points[1].max(hi)];
            }
            continue;
        }
        let a = match r {
            Reached::Cycle {
                period,
                points,
                multiplier,
            } => Attractor {
                period: Some(period),
                lyapunov: Some(multiplier.abs().ln() / period as f64),
                multiplier: Some(multiplier),
                points,
                lyapunov_stderr: None,
                basin_fraction: 0.0,
            },
            Reached::Aperiodic {
                lo,
                hi,
                lyapunov,
                stderr,
            } => Attractor {
                period: None,
                points: vec![lo, hi],
                multiplier: None,
                lyapunov,
                lyapunov_stderr: stderr,
                basin_fraction: 0.0,
            },
        };
        out.push((a, counted));
    }
    let n = spread.len() as f64;
    let mut found: Vec<Attractor> = out
        .into_iter()
        .map(|(mut a, k)| {
            a.basin_fraction = k as f64 / n;
            a
        })
        .collect();
    found.sort_by(|a, b| b.basin_fraction.total_cmp(&a.basin_fraction));
    Ok(found)
}

/// [`attractors`] with the default solver (DOP853 at 1e-10) and no
/// previous attractor: for tests and examples.
pub fn attractors_default(params: Params, seeds: usize) -> Result<Vec<Attractor>, SimError> {
    attractors(params, default_settings(1e-10), seeds, None, &|| false)
}
