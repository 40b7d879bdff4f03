//! What each closed set is: a cycle solved on the integrated map (proved,
//! or found in a set the cells did not shrink onto), or a chaotic
//! attractor with its density and λ both ways, or undecided with why.

use super::classify::{COLUMN_ORBIT, ORBIT, Orbit, clusters, long_orbit, solve};
use super::density::{DensityLambda, DensityRun};
use super::graph::CellGraph;
use super::search::Closed;
use super::{ArcMap, Attractor, AttractorError, CellOptions, Density, Verdict};
use crate::model::wrap_angle;
use crate::sim::Simulator;

/// Bins of a chaotic attractor's density.
const DENSITY_BINS: usize = 100;

/// A closed set's attractor (see [`classify`]).
pub(super) fn classify_closed(
    sim: &Simulator,
    map: &ArcMap,
    g: &CellGraph,
    k: &Closed,
    known: &[Orbit],
    opts: &CellOptions,
    spent: &mut (u64, u64),
) -> Result<Judged, AttractorError> {
    let psi = map.psi();
    let cover: Vec<(f64, f64)> = clusters(&k.cells)
        .iter()
        .map(|&(a, b)| (psi + g.bounds[a], psi + g.bounds[b + 1]))
        .collect();
    let inside = |u: f64| {
        let c = g.cell_of(u);
        k.cells.binary_search(&c).is_ok()
    };
    let blank = Attractor {
        period: None,
        points: Vec::new(),
        multiplier: None,
        lyapunov: None,
        lyapunov_stderr: None,
        lyapunov_from_density: None,
        lyapunov_density_error: None,
        density: None,
        basin_fraction: 0.0,
        iterates: Vec::new(),
        cover,
        verdict: Verdict::Undecided(String::new()),
    };
    let cycle = |p: usize, u: f64, verdict: Verdict, spent: &mut (u64, u64)| {
        solved(sim, psi, u, p, spent, &inside).map(|(period, points, multiplier, lyapunov)| {
            Attractor {
                period: Some(period),
                iterates: points.clone(),
                points,
                multiplier: Some(multiplier),
                lyapunov: Some(lyapunov),
                verdict,
                ..blank.clone()
            }
        })
    };
    if let Some((p, u)) = k.proved
        && let Some(a) = cycle(p, u, Verdict::Proved, spent)
    {
        return Ok(Judged::Done(Box::new(a)));
    }
    // An orbit that ended in the set at its floor, or one from its middle
    // cell.
    let orbit = match known.iter().find(|o| inside(o.last)) {
        Some(o) => o.clone(),
        None => {
            let lengths = if opts.density { ORBIT } else { COLUMN_ORBIT };
            long_orbit(map, g.mid(k.cells[k.cells.len() / 2]), lengths)?
        }
    };
    if let Some((p, u)) = orbit.settled.or_else(|| loosely_settled(&orbit))
        && let Some(a) = cycle(p, u, Verdict::CycleInSet, spent)
    {
        return Ok(Judged::Done(Box::new(a)));
    }
    let blank = Attractor {
        iterates: orbit.tail.iter().map(|u| psi + u).collect(),
        ..blank
    };
    Ok(if opts.density {
        Judged::Density(Box::new(Pending::new(g, &k.cells, orbit, opts, blank, psi)))
    } else {
        Judged::Done(Box::new(by_orbit(map, g, &k.cells, &orbit, blank)))
    })
}

/// An orbit that did not settle to 1e-9: its period to 1e-5 with its
/// last point, a candidate for Newton on the integrated map, which
/// decides. The orbit can approach a cycle with m near ±1 too slowly to
/// settle, and its time average of ln|f'| over the approach may even come
/// out positive (κ = 10, θν = 1.37075: a P2 with m = 0.9989 drifting by
/// 3e-7 a step gave λ = +2e-4 ± 1e-5 and was called chaotic).
fn loosely_settled(orbit: &Orbit) -> Option<(usize, f64)> {
    crate::sim::period::settled_period(&orbit.tail, 1e-5).map(|p| (p, orbit.last))
}

/// A closed set judged: its attractor, or a chaotic candidate whose
/// density is still to be computed ([`Pending`]).
pub(super) enum Judged {
    Done(Box<Attractor>),
    Density(Box<Pending>),
}

/// A closed set with no stable cycle found, its density being computed a
/// piece at a time: its hull (θ), the orbit that showed it.
pub(super) struct Pending {
    pub(super) run: DensityRun,
    hull: [f64; 2],
    orbit: Orbit,
    blank: Attractor,
}

/// A closed set with no stable cycle found, told by its orbit alone (a
/// diagram's column): chaotic where λ > 0 by more than four standard
/// errors.
fn by_orbit(
    map: &ArcMap,
    g: &CellGraph,
    cells: &[usize],
    orbit: &Orbit,
    blank: Attractor,
) -> Attractor {
    let psi = map.psi();
    let (lo, hi) = (g.bounds[cells[0]], g.bounds[cells[cells.len() - 1] + 1]);
    let verdict = if orbit.lyapunov > 4.0 * orbit.stderr && orbit.lyapunov > 0.0 {
        Verdict::Chaotic
    } else {
        Verdict::Undecided(format!(
            "a closed set with no stable cycle found and lambda = {:.4} +- {:.4} from a {}-iterate orbit",
            orbit.lyapunov, orbit.stderr, COLUMN_ORBIT.1
        ))
    };
    Attractor {
        points: vec![psi + lo, psi + hi],
        lyapunov: Some(orbit.lyapunov),
        lyapunov_stderr: Some(orbit.stderr),
        verdict,
        ..blank
    }
}

/// A closed set that holds no stable cycle found: its density (Ulam),
/// λ from it beside the orbit's, and the verdict they allow.
impl Pending {
    /// The density of the closed set `cells` to be computed, the orbit
    /// `orbit` beside it.
    fn new(
        g: &CellGraph,
        cells: &[usize],
        orbit: Orbit,
        opts: &CellOptions,
        blank: Attractor,
        psi: f64,
    ) -> Self {
        let (lo, hi) = (g.bounds[cells[0]], g.bounds[cells[cells.len() - 1] + 1]);
        let cover: Vec<(f64, f64)> = clusters(cells)
            .iter()
            .map(|&(a, b)| (g.bounds[a], g.bounds[b + 1]))
            .collect();
        Pending {
            run: DensityRun::new(&cover, opts.density_cells, DENSITY_TARGET),
            hull: [psi + lo, psi + hi],
            orbit,
            blank,
        }
    }

    /// The attractor once its density `d` is known: λ from it beside the
    /// orbit's, and the verdict they allow.
    pub(super) fn finish(self, d: DensityLambda) -> Attractor {
        let Pending {
            hull, orbit, blank, ..
        } = self;
        chaotic(hull, &orbit, d, blank)
    }
}

fn chaotic(hull: [f64; 2], orbit: &Orbit, d: DensityLambda, blank: Attractor) -> Attractor {
    let lambda_d = d.lambda;
    let values = binned(&d.mu);
    // Both errors: the density's discretisation error and the orbit's
    // standard error, three of each, and the series' own (1e-3).
    let agree = (lambda_d - orbit.lyapunov).abs() <= 3.0 * (d.error + orbit.stderr) + 1e-3;
    let verdict = if lambda_d > 0.0 && orbit.lyapunov > 4.0 * orbit.stderr && agree {
        Verdict::Chaotic
    } else if !agree {
        Verdict::Undecided(format!(
            "lambda from the density ({lambda_d:.4} +- {:.4}) and from a {}-iterate orbit ({:.4} +- {:.4}) disagree; refine the density with --density-cells",
            d.error, ORBIT.1, orbit.lyapunov, orbit.stderr
        ))
    } else {
        Verdict::Undecided(format!(
            "a closed set with no stable cycle found and lambda = {lambda_d:.4} +- {:.4} from the density, {:.4} +- {:.4} from an orbit: not positive beyond its error; subdivide further with --resolution or --max-cells",
            d.error, orbit.lyapunov, orbit.stderr
        ))
    };
    Attractor {
        period: None,
        points: hull.to_vec(),
        lyapunov: Some(orbit.lyapunov),
        lyapunov_stderr: Some(orbit.stderr),
        lyapunov_from_density: Some(lambda_d),
        lyapunov_density_error: Some(d.error),
        density: Some(Density {
            from: hull[0],
            to: hull[1],
            values,
        }),
        verdict,
        ..blank
    }
}

/// The density's grids are doubled until two doublings in a row move λ by
/// less than this.
const DENSITY_TARGET: f64 = 5e-4;

/// The stable p-cycle through u solved by Newton on the integrated map,
/// if every point lies `inside` the closed set: its minimal period, points,
/// multiplier (of the minimal cycle) and exponent.
fn solved(
    sim: &Simulator,
    psi: f64,
    u: f64,
    p: usize,
    spent: &mut (u64, u64),
    inside: &dyn Fn(f64) -> bool,
) -> Option<(usize, Vec<f64>, f64, f64)> {
    // Newton from the orbit's point, else from a little to either side:
    // a small jump of f between the point and the cycle (the fixed point
    // at κ = 10, θν = 1.41675 sits 4e-8 past one) stalls Newton on the
    // wrong side of it. Whatever converges is checked below all the same.
    let mut c = [0.0, -1e-6, 1e-6, -1e-5, 1e-5]
        .iter()
        .find_map(|d| solve(sim, psi, u + d, p, spent))?;
    if c.minimal_period < p {
        // The minimal cycle's own multiplier (a p-cycle's loses its sign).
        c = solve(
            sim,
            psi,
            wrap_angle(c.points[0] - psi),
            c.minimal_period,
            spent,
        )?;
    }
    let q = c.points.len();
    let ok = c.stable && c.points.iter().all(|&t| inside(wrap_angle(t - psi)));
    ok.then(|| (q, c.points.clone(), c.multiplier, c.lyapunov()))
}

/// A density on a uniform grid as [`DENSITY_BINS`] equal bins over the
/// same interval, summing to 1.
fn binned(mu: &[f64]) -> Vec<f64> {
    let mut values = vec![0.0; DENSITY_BINS];
    let n = mu.len().max(1);
    for (i, &m) in mu.iter().enumerate() {
        values[(i * DENSITY_BINS / n).min(DENSITY_BINS - 1)] += m;
    }
    let s: f64 = values.iter().sum();
    if s > 0.0 {
        values.iter_mut().for_each(|v| *v /= s);
    }
    values
}
