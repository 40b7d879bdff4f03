//! Every attractor at one parameter point (docs/attractors.md): orbits
//! from seeds spread over the exit arc (and from a previous attractor's
//! point, where there is one), each run to its attractor, and the
//! attractors told apart. Two orbits reach the same attractor when their
//! cycles coincide to the solver's accuracy, or when their chaotic sets
//! overlap; each attractor's basin fraction is the share of the spread
//! seeds that reach it.
//!
//! The first orbit (from the previous point, else the first seed) is
//! integrated as `orbit` runs it. The others iterate [`SeedMap`] on the
//! seeds' loose map (`super::seeded::SEED_RTOL`): its verified interpolant
//! near the attractors already found, direct integration elsewhere; each
//! stops once it closes in on a known cycle, stays in a known chaotic set
//! or repeats. The loose map only routes a seed: a cycle that is not one
//! already found is solved by Newton on the sweep's own map, and a new
//! chaotic set is confirmed by a whole orbit (transient and kept iterates)
//! integrated from the seed's last point, as the first orbit is.

use super::seed_map::{Fell, Known, SeedMap, hull};
use super::transient;

use crate::integrate::SolverSettings;
use crate::model::{Params, exit_arc};
use crate::sim::cycles::{CycleOptions, solve_counting};
use crate::sim::seeded::{rep_tol, same_tol};
use crate::sim::{Orbit, OrbitOptions, Period, SimError, Simulator, default_settings};

pub use super::transient::{KEEP, TRANSIENT, same_cycle};

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

/// The θ₀ of `n` seeds spread over the exit arc ψ − π/2 < θ < ψ + π/2 at
/// `params`: the midpoints of n equal parts.
pub fn spread_seeds(params: &Params, n: usize) -> Vec<f64> {
    let (psi, half) = exit_arc(params.kappa, params.theta_nu);
    (0..n)
        .map(|i| psi - half + 2.0 * half * (i as f64 + 0.5) / n as f64)
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
        /// The orbit's last point (NaN where it was not followed).
        last: f64,
    },
}

/// The orbit from `theta0`, integrated to its attractor (with λ over its
/// kept iterates, as `orbit` computes it).
fn reach(sim: &Simulator, theta0: f64, cancel: &dyn Fn() -> bool) -> Result<Reached, SimError> {
    let opts = OrbitOptions {
        transient: TRANSIENT,
        keep: KEEP,
        lyapunov: true,
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
    if orbit.period == Period::Aperiodic {
        return Ok(aperiodic(&orbit));
    }
    aperiodic_from(sim, orbit.theta_last, cancel)
}

/// The chaotic set an orbit's kept iterates visit, with their λ.
fn aperiodic(o: &Orbit) -> Reached {
    let th = o.thetas();
    let (lo, hi) = hull(&th);
    Reached::Aperiodic {
        lo,
        hi,
        lyapunov: o.lyapunov,
        stderr: o.lyapunov_stderr,
        last: o.theta_last,
    }
}

/// An aperiodic (or unsolved periodic) orbit's set and exponent, from
/// [`KEEP`] more integrated iterates from θ.
fn aperiodic_from(
    sim: &Simulator,
    theta: f64,
    cancel: &dyn Fn() -> bool,
) -> Result<Reached, SimError> {
    let opts = OrbitOptions {
        transient: 0,
        keep: KEEP,
        lyapunov: true,
        period_tol: OrbitOptions::period_tol_for(sim.settings().rtol),
    };
    Ok(aperiodic(&sim.orbit(theta, &opts, cancel)?))
}

/// What the seed from θ0 reached, from its orbit on `map`: a cycle among
/// `known` ones is named by its index there, a new one solved by Newton on
/// the direct map; an orbit that does not repeat is settled as `orbit`
/// settles one (a slow cycle solved), or is a chaotic set. A new chaotic
/// set gets its λ from integrated iterates.
fn reach_seeded(
    sim: &Simulator,
    map: &mut SeedMap,
    theta0: f64,
    known: &[Attractor],
    cancel: &dyn Fn() -> bool,
) -> Result<Reached, SimError> {
    let settings = sim.settings();
    let rep_tol = rep_tol(settings);
    let stable: Vec<&Attractor> = stable_cycles(known)
        .into_iter()
        .map(|k| &known[k])
        .collect();
    let cycles: Vec<&[f64]> = stable.iter().map(|a| a.points.as_slice()).collect();
    let sets: Vec<(f64, f64)> = known
        .iter()
        .filter_map(|a| match (a.period, a.points.as_slice()) {
            (None, &[lo, hi]) => Some((lo, hi)),
            _ => None,
        })
        .collect();
    let budget = (TRANSIENT, KEEP);
    let told = Known {
        cycles: &cycles,
        sets: &sets,
    };
    let (kept, next) = match map.fall(theta0, budget, rep_tol, told, cancel)? {
        Fell::InSet(k) => {
            let (lo, hi) = sets[k];
            return Ok(Reached::Aperiodic {
                lo,
                hi,
                lyapunov: None,
                stderr: None,
                last: f64::NAN,
            });
        }
        Fell::Known(k) => {
            let a = stable[k];
            return Ok(Reached::Cycle {
                period: a.points.len(),
                points: a.points.clone(),
                multiplier: a.multiplier.unwrap_or(f64::NAN),
            });
        }
        Fell::Repeats(points) => {
            let p = points.len();
            let same = |a: &&Attractor| {
                a.period == Some(p) && same_cycle(&points, &a.points, same_tol(settings))
            };
            if let Some(a) = known.iter().find(same) {
                return Ok(Reached::Cycle {
                    period: p,
                    points: a.points.clone(),
                    multiplier: a.multiplier.unwrap_or(f64::NAN),
                });
            }
            if let Some(c) = solve_stable(sim, &points) {
                return Ok(c);
            }
            // Repeats on the series but no stable cycle there: integrate.
            return reach(sim, theta0, cancel);
        }
        Fell::Wanders(kept, next) => (kept, next),
    };
    let tol = OrbitOptions::period_tol_for(settings.rtol);
    let settled = sim.settle(&kept, next, &[], tol, &mut (0, 0));
    if let Some(c) = settled.cycle {
        return Ok(Reached::Cycle {
            period: c.minimal_period,
            points: c.points[..c.minimal_period].to_vec(),
            multiplier: c.multiplier,
        });
    }
    let (lo, hi) = hull(&kept);
    let overlaps = |a: &Attractor| a.period.is_none() && lo <= a.points[1] && hi >= a.points[0];
    if known.iter().any(overlaps) {
        return Ok(Reached::Aperiodic {
            lo,
            hi,
            lyapunov: None,
            stderr: None,
            last: next,
        });
    }
    // A new set is confirmed as the first orbit is: a whole orbit on the
    // direct map from the seed's last point, so that chaos that is only a
    // long transient (the loose map's orbit may linger where the direct
    // one escapes, as in a periodic window) ends on its cycle.
    reach(sim, next, cancel)
}

/// The stable cycle of minimal period p Newton solves on `sim`'s map from
/// the last of `points`, a p-cycle's points on a looser map.
fn solve_stable(sim: &Simulator, points: &[f64]) -> Option<Reached> {
    let p = points.len();
    let opts = CycleOptions::for_classifier(sim.settings());
    let c = solve_counting(sim, *points.last()?, p, &opts, &mut (0, 0)).ok()?;
    (c.minimal_period == p && c.stable).then(|| Reached::Cycle {
        period: p,
        points: c.points[..p].to_vec(),
        multiplier: c.multiplier,
    })
}

/// Every attractor at `params` reached from `seeds` seeds spread over the
/// exit arc and from `previous` (a point of the attractor found before,
/// not counted in the basin fractions), in order of decreasing basin
/// fraction. The first orbit (from `previous`, else the first seed) is
/// integrated; the others run on [`SeedMap`] (see the module's doc).
/// `cancel` is polled by each orbit.
pub fn attractors(
    params: Params,
    settings: SolverSettings,
    seeds: usize,
    previous: Option<f64>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<Attractor>, SimError> {
    let sim = Simulator::new(params, settings)?;
    let spread = spread_seeds(&params, seeds.max(1));
    let first_counted = usize::from(previous.is_some());
    let all: Vec<f64> = previous.into_iter().chain(spread.iter().copied()).collect();
    let loose = crate::sim::seeded::seed_simulator(params, &settings)?;
    let mut map = SeedMap::wide(&loose);
    // Cycles coincide to 1e3× the solver's tolerance (their points are
    // solved by Newton to about the tolerance).
    let tol = 1e3 * crate::sim::CycleOptions::for_settings(&settings).tol;
    let rep_tol = rep_tol(&settings);
    let mut found = Found::default();
    for (i, &theta0) in all.iter().enumerate() {
        let counted = usize::from(i >= first_counted);
        let r = if found.attractors.is_empty() {
            reach(&sim, theta0, cancel)
        } else {
            reach_seeded(&sim, &mut map, theta0, &found.attractors, cancel)
        };
        let r = match r {
            Ok(r) => r,
            // A seed whose orbit fails (off the arc after a restart, or
            // cancelled) reaches nothing that can be named.
            Err(SimError::Cancelled) => return Err(SimError::Cancelled),
            Err(_) => continue,
        };
        let Some(r) = found.count(r, counted, tol) else {
            continue;
        };
        let set = match r {
            Reached::Aperiodic { lo, hi, .. } => Some((lo, hi)),
            Reached::Cycle { .. } => None,
        };
        let left = all.len() - i - 1;
        found.add(r, counted, &mut map, left * (TRANSIENT + KEEP) / 4);
        // A new set may hide a window's stable cycle that the seeds, told
        // they have arrived once they stay in the set, would never reach.
        if let Some(set) = set {
            let views = found.stable_views();
            let hidden = transient::hidden_cycle(&loose, set, &views, rep_tol, cancel)?;
            if let Some(c) = hidden.and_then(|points| solve_stable(&sim, &points)) {
                found.add(c, 0, &mut map, 0);
            }
        }
    }
    let (mut found, counts) = found.without_transients(&loose, rep_tol, cancel)?;
    let n = spread.len() as f64;
    for (a, k) in found.iter_mut().zip(counts) {
        a.basin_fraction = k as f64 / n;
    }
    found.sort_by(|a, b| b.basin_fraction.total_cmp(&a.basin_fraction));
    Ok(found)
}

/// The attractors found so far, the spread seeds that reached each, and
/// a chaotic set's orbit's last point (NaN for a cycle: for the escape
/// test).
#[derive(Default)]
struct Found {
    attractors: Vec<Attractor>,
    counts: Vec<usize>,
    lasts: Vec<f64>,
}

impl Found {
    /// Counts `r` (`counted`: 1 for a spread seed) for the attractor among
    /// those found that it is (an overlapping set widens its interval), or
    /// gives it back; cycles are one when their points coincide to `tol`.
    fn count(&mut self, r: Reached, counted: usize, tol: f64) -> Option<Reached> {
        let known = self
            .attractors
            .iter_mut()
            .zip(self.counts.iter_mut())
            .find(|(a, _)| match (&r, a.period) {
                (Reached::Cycle { period, points, .. }, Some(p)) => {
                    *period == p && same_cycle(points, &a.points, tol)
                }
                (Reached::Aperiodic { lo, hi, .. }, None) => {
                    *lo <= a.points[1] && *hi >= a.points[0]
                }
                _ => false,
            });
        let Some((a, n)) = known else {
            return Some(r);
        };
        *n += counted;
        if let Reached::Aperiodic { lo, hi, .. } = r {
            a.points = vec![a.points[0].min(lo), a.points[1].max(hi)];
        }
        None
    }

    /// Adds `r` as a new attractor. Seeds falling towards it from now on
    /// run on its series: near each point of a cycle, or over a chaotic
    /// set's hull (worth `worth` evaluations, a quarter of what the seeds
    /// left would integrate: they cannot stop early there).
    fn add(&mut self, r: Reached, counted: usize, map: &mut SeedMap, worth: usize) {
        let last = match r {
            Reached::Aperiodic { last, .. } => last,
            Reached::Cycle { .. } => f64::NAN,
        };
        let a = attractor(r);
        if a.period.is_some() {
            for &x in &a.points {
                map.cover_point(x);
            }
        } else {
            map.cover_set(a.points[0], a.points[1], worth);
        }
        self.attractors.push(a);
        self.counts.push(counted);
        self.lasts.push(last);
    }

    /// The stable cycles' points.
    fn stable_views(&self) -> Vec<&[f64]> {
        stable_cycles(&self.attractors)
            .into_iter()
            .map(|k| self.attractors[k].points.as_slice())
            .collect()
    }

    /// The attractors and their seed counts without the chaotic sets that
    /// are transients: a set with a stable cycle inside its interval whose
    /// orbit, run on from its last point, ends on one of them (see
    /// [`transient::escapes_to`]). Its seeds count for that cycle.
    fn without_transients(
        self,
        loose: &Simulator,
        rep_tol: f64,
        cancel: &dyn Fn() -> bool,
    ) -> Result<(Vec<Attractor>, Vec<usize>), SimError> {
        let Found {
            attractors: found,
            mut counts,
            lasts,
        } = self;
        let cycles = stable_cycles(&found);
        let mut transient = vec![false; found.len()];
        for (i, a) in found.iter().enumerate() {
            let (None, &[lo, hi]) = (a.period, a.points.as_slice()) else {
                continue;
            };
            let within: Vec<usize> = cycles
                .iter()
                .copied()
                .filter(|&k| transient::inside(&found[k].points, (lo, hi)))
                .collect();
            if within.is_empty() || !lasts[i].is_finite() {
                continue;
            }
            let views: Vec<&[f64]> = within.iter().map(|&k| found[k].points.as_slice()).collect();
            if let Some(j) = transient::escapes_to(loose, lasts[i], &views, rep_tol, cancel)? {
                counts[within[j]] += counts[i];
                transient[i] = true;
            }
        }
        Ok(found
            .into_iter()
            .zip(counts)
            .zip(transient)
            .filter(|(_, t)| !t)
            .map(|(ac, _)| ac)
            .unzip())
    }
}

/// The indices of the stable cycles among `found`.
pub(crate) fn stable_cycles(found: &[Attractor]) -> Vec<usize> {
    (0..found.len())
        .filter(|&k| {
            found[k].period.is_some() && found[k].multiplier.is_some_and(|m| m.abs() < 1.0)
        })
        .collect()
}

/// The attractor a first orbit reached (its basin fraction still 0); a
/// cycle's points in orbit order from its least θ, whichever seed found it.
fn attractor(r: Reached) -> Attractor {
    match r {
        Reached::Cycle {
            period,
            mut points,
            multiplier,
        } => Attractor {
            period: Some(period),
            lyapunov: Some(multiplier.abs().ln() / period as f64),
            multiplier: Some(multiplier),
            points: {
                let least = (0..points.len()).min_by(|&i, &j| points[i].total_cmp(&points[j]));
                points.rotate_left(least.unwrap_or(0));
                points
            },
            lyapunov_stderr: None,
            basin_fraction: 0.0,
        },
        Reached::Aperiodic {
            lo,
            hi,
            lyapunov,
            stderr,
            ..
        } => Attractor {
            period: None,
            points: vec![lo, hi],
            multiplier: None,
            lyapunov,
            lyapunov_stderr: stderr,
            basin_fraction: 0.0,
        },
    }
}

/// [`attractors`] with the default solver (DOP853 at 1e-10) and no
/// previous attractor: for tests and examples.
pub fn attractors_default(params: Params, seeds: usize) -> Result<Vec<Attractor>, SimError> {
    attractors(params, default_settings(1e-10), seeds, None, &|| false)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every seed integrated to its attractor (as `attractors` ran before
    /// [`SeedMap`]): the attractors and basin fractions by an independent
    /// route.
    fn integrated(params: Params, seeds: usize) -> Vec<(Option<usize>, Vec<f64>, f64)> {
        let sim = Simulator::new(params, default_settings(1e-10)).expect("valid");
        let spread = spread_seeds(&params, seeds);
        let mut out: Vec<(Option<usize>, Vec<f64>, f64)> = Vec::new();
        for &th in &spread {
            let (period, points) = match reach(&sim, th, &|| false).expect("runs") {
                Reached::Cycle { period, points, .. } => (Some(period), points),
                Reached::Aperiodic { lo, hi, .. } => (None, vec![lo, hi]),
            };
            let share = 1.0 / seeds as f64;
            let same = |o: &&mut (Option<usize>, Vec<f64>, f64)| {
                o.0 == period
                    && match period {
                        Some(_) => same_cycle(&points, &o.1, 1e-6),
                        None => points[0] <= o.1[1] && points[1] >= o.1[0],
                    }
            };
            match out.iter_mut().find(same) {
                Some(o) => o.2 += share,
                None => out.push((period, points, share)),
            }
        }
        out
    }

    #[test]
    fn the_seeds_on_the_interpolant_find_what_integrating_each_finds() {
        let hysteresis = Params {
            kappa: 10.0,
            gamma: 6.5,
            nu: 1e-3,
            theta_nu: 1.40,
            omega: 50.0,
        };
        let chaos = Params {
            theta_nu: 1.25,
            ..Params::default()
        };
        for params in [hysteresis, chaos] {
            let got = attractors_default(params, 16).expect("runs");
            let want = integrated(params, 16);
            assert_eq!(got.len(), want.len(), "{got:?} vs {want:?}");
            for (p, points, share) in &want {
                let a = got
                    .iter()
                    .find(|a| {
                        a.period == *p && (p.is_none() || same_cycle(&a.points, points, 1e-6))
                    })
                    .unwrap_or_else(|| panic!("{p:?} {points:?} not in {got:?}"));
                assert!((a.basin_fraction - share).abs() < 1e-12, "{a:?} vs {share}");
            }
        }
    }
}
