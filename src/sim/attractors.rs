//! Every attractor and basin at one parameter point, from f itself with no
//! orbit budget (docs/attractors.md): set-oriented numerics on the
//! verified interpolant of f over the whole exit arc (Dellnitz–Junge's
//! subdivision, Ulam's method).
//!
//! 1. f is built over the arc as a verified interpolant (`arc`), with its
//!    error bound ε.
//! 2. The arc is covered by cells; a cell has an edge to every cell its
//!    image (the enclosure of f over it, widened by ε) meets (`graph`).
//! 3. The graph's closed strongly connected components hold the
//!    attractors. Each is subdivided until it is proved to be the
//!    trapping region of one stable cycle (a contraction of f^p over its
//!    clusters), or its cells reach the resolution asked for, or the cell
//!    budget runs out; so are the cells that reach more than one of them
//!    (the basin boundary).
//! 4. Then exact (`classify`): a cycle by Newton on the integrated map; a
//!    set that holds no stable cycle, by its invariant density on its
//!    cells (Ulam) and λ = ∫ ln|f'| dμ beside a long orbit's time average.
//!    Where the two disagree, or λ ≤ 0, it is not called chaotic.
//!
//! A cell's basin is the closed component every path from it ends in;
//! cells whose paths end in more than one are the basin boundary at that
//! resolution.

pub mod arc;
mod classify;
mod graph;
pub(crate) mod seed_map;
pub(crate) mod seeds;
pub(crate) mod transient;

pub use arc::{ArcError, ArcMap};
pub use seeds::attractors as seeded_attractors;
pub use seeds::{Attractor as SeedAttractor, KEEP, TRANSIENT, attractors_default, spread_seeds};

use classify::{clusters, contraction, long_orbit, solve, trap, ulam};
use graph::CellGraph;

use super::{SimError, Simulator};
use crate::model::wrap_angle;

/// What the cell graph is asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellOptions {
    /// Equal cells the arc starts with.
    pub initial_cells: usize,
    /// The finest cell width subdivision goes to (radians).
    pub resolution: f64,
    /// The most cells in all.
    pub max_cells: usize,
    /// The most map evaluations the interpolant may take.
    pub max_evaluations: usize,
}

impl Default for CellOptions {
    fn default() -> Self {
        CellOptions {
            initial_cells: 1024,
            resolution: 1e-6,
            max_cells: 1 << 16,
            max_evaluations: 40_000,
        }
    }
}

/// How an attractor's label was decided.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// f^p contracts its closed set onto the cycle: the set holds nothing
    /// else.
    Proved,
    /// A stable cycle (Newton, |m| < 1) in a closed set that the
    /// resolution did not shrink onto it: another attractor may hide in
    /// the rest of the set.
    CycleInSet,
    /// λ > 0 from the density and from the orbit, and they agree.
    Chaotic,
    /// Neither: why, in words.
    Undecided(String),
}

/// The invariant density of a chaotic attractor, on equal bins.
#[derive(Clone, Debug, PartialEq)]
pub struct Density {
    pub from: f64,
    pub to: f64,
    /// Probabilities per bin, summing to 1.
    pub values: Vec<f64>,
}

/// One attractor.
#[derive(Clone, Debug, PartialEq)]
pub struct Attractor {
    /// The period, or `None` for an aperiodic set.
    pub period: Option<usize>,
    /// A cycle's points; an aperiodic set's smallest and largest θ.
    pub points: Vec<f64>,
    /// A cycle's multiplier.
    pub multiplier: Option<f64>,
    /// ln|m|/p for a cycle; the long orbit's time average otherwise.
    pub lyapunov: Option<f64>,
    /// The time average's batch-means standard error.
    pub lyapunov_stderr: Option<f64>,
    /// λ = ∫ ln|f'| dμ from the invariant density (aperiodic sets).
    pub lyapunov_from_density: Option<f64>,
    pub density: Option<Density>,
    /// The basin's share of the arc's length.
    pub basin_fraction: f64,
    /// The closed set of cells, as intervals of θ.
    pub cover: Vec<(f64, f64)>,
    pub verdict: Verdict,
}

/// A stretch of the arc and the attractor it goes to (an index into
/// [`Found::attractors`]), or `None` where it reaches more than one at
/// this resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Basin {
    pub from: f64,
    pub to: f64,
    pub attractor: Option<usize>,
}

/// The cells' resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resolution {
    /// The finest and the widest cell.
    pub finest: f64,
    pub widest: f64,
    /// The map's error bound ε the images are widened by.
    pub eps: f64,
    pub cells: usize,
    /// Whether the cell budget stopped subdivision before the resolution
    /// asked for was reached where it was wanted.
    pub budget_hit: bool,
}

/// Everything at one point.
#[derive(Clone, Debug, PartialEq)]
pub struct Found {
    pub attractors: Vec<Attractor>,
    pub basins: Vec<Basin>,
    pub resolution: Resolution,
    /// The share of the arc in no single basin.
    pub boundary_fraction: f64,
    /// Map evaluations (the interpolant's and Newton's) and right-hand
    /// sides.
    pub map_evaluations: u64,
}

/// A closed component during subdivision.
struct Closed {
    cells: Vec<usize>,
    /// (p, u) when its contraction is proved.
    proved: Option<(usize, f64)>,
}

/// A cell is made no narrower than this many ε of the map under it (a
/// closed set reaching it is sharpened, or settled); a chaotic set's
/// cells go on to [`CHAOS_FLOOR`] ε, for its density.
const FLOOR: f64 = 100.0;
const CHAOS_FLOOR: f64 = 20.0;

/// The most map evaluations one sharpened stretch may take.
const SHARPEN_EVALUATIONS: usize = 4_000;

/// Every attractor and basin at `sim`'s parameters (see the module's doc).
pub fn attractors(
    sim: &Simulator,
    opts: &CellOptions,
    cancel: &dyn Fn() -> bool,
) -> Result<Found, AttractorError> {
    let map = ArcMap::build(sim)?;
    let g = CellGraph::uniform(&map, opts.initial_cells.max(2));
    let mut search = Search {
        sim,
        opts,
        map,
        g,
        settled: Vec::new(),
        spent: (0, 0),
        budget_hit: false,
        pending: None,
    };
    let (closed, comps, labels) = loop {
        if cancel() {
            return Err(AttractorError::Sim(SimError::Cancelled));
        }
        if let Some(done) = search.level()? {
            break done;
        }
    };
    let Search {
        map,
        g,
        mut spent,
        budget_hit,
        ..
    } = search;
    let mut found = Vec::with_capacity(closed.len());
    for k in &closed {
        found.push(classify_closed(sim, &map, &g, k, &mut spent)?);
    }
    let (basins, boundary_fraction) = basins(&g, &map, &comps, &labels, &mut found);
    let widths = (0..g.len()).map(|i| g.width(i));
    let (finest, widest) = widths.fold((f64::INFINITY, 0.0_f64), |(a, b), w| (a.min(w), b.max(w)));
    Ok(Found {
        attractors: found,
        basins,
        resolution: Resolution {
            finest,
            widest,
            eps: map.eps(),
            cells: g.len(),
            budget_hit,
        },
        boundary_fraction,
        map_evaluations: map.spent.0 + spent.0,
    })
}

/// The search's state between levels of subdivision.
struct Search<'a> {
    sim: &'a Simulator,
    opts: &'a CellOptions,
    map: ArcMap,
    g: CellGraph,
    /// Closed sets a long orbit showed chaotic at the map's floor (their
    /// hulls): subdivided only to [`CHAOS_FLOOR`].
    settled: Vec<[f64; 2]>,
    spent: (u64, u64),
    budget_hit: bool,
    /// The spans of the closed sets still being subdivided, between
    /// global analyses.
    pending: Option<Vec<[f64; 2]>>,
}

/// The closed sets, the components and their labels, when done.
type Done = (Vec<Closed>, graph::Components, Vec<Option<usize>>);

impl Search<'_> {
    /// One level: the graph analysed, its undecided closed sets and its
    /// boundary marked and subdivided (or the map sharpened, or a trap
    /// added). `Some` when nothing is left to do.
    fn level(&mut self) -> Result<Option<Done>, AttractorError> {
        // While closed sets are undecided, only their cells are analysed:
        // no edge leaves them, and what they hold is all there is.
        if let Some(spans) = self.pending.take() {
            let cells: Vec<usize> = spans
                .iter()
                .flat_map(|s| {
                    let (a, b) = self.g.cells_of(s[0], s[1]);
                    a..=b
                })
                .collect();
            let closed: Vec<Closed> = self
                .g
                .closed_within(&cells)
                .into_iter()
                .map(|cells| closed(&self.g, &self.map, cells))
                .collect();
            let mut marked = vec![false; self.g.len()];
            let Some(extra) = self.mark_closed(&closed, &mut marked)? else {
                return Ok(None);
            };
            if extra > 0 && self.g.len() + extra <= self.opts.max_cells {
                self.pending = Some(self.undecided_spans(&closed, &marked));
                self.g.subdivide(&self.map, &marked);
                return Ok(None);
            }
            self.budget_hit |= extra > 0;
        }
        let (comps, closed, labels) = closed_sets(&self.g, &self.map);
        let mut marked = vec![false; self.g.len()];
        let Some(mut extra) = self.mark_closed(&closed, &mut marked)? else {
            return Ok(None);
        };
        if extra > 0 && !self.budget_hit {
            self.pending = Some(self.undecided_spans(&closed, &marked));
        }
        let reach = self.g.reach(&comps, &labels);
        for v in 0..self.g.len() {
            let ambiguous = reach[comps.comp[v] as usize].count_ones() > 1;
            if ambiguous && !marked[v] && self.g.width(v) > self.floor(v, FLOOR) {
                marked[v] = true;
                extra += 1;
            }
        }
        if extra == 0 {
            return Ok(Some((closed, comps, labels)));
        }
        if self.g.len() + extra > self.opts.max_cells {
            self.budget_hit = true;
            return Ok(Some((closed, comps, labels)));
        }
        self.g.subdivide(&self.map, &marked);
        Ok(None)
    }

    /// The spans (runs of cells) of the closed sets with marked cells.
    fn undecided_spans(&self, closed: &[Closed], marked: &[bool]) -> Vec<[f64; 2]> {
        closed
            .iter()
            .filter(|k| k.cells.iter().any(|&i| marked[i]))
            .flat_map(|k| clusters(&k.cells))
            .map(|(a, b)| [self.g.bounds[a], self.g.bounds[b + 1]])
            .collect()
    }

    /// The narrowest cell i may be made: the resolution asked for, and
    /// `times` ε of the map under it.
    fn floor(&self, i: usize, times: f64) -> f64 {
        self.opts
            .resolution
            .max(times * self.map.eps_at(self.g.mid(i)))
    }

    /// Marks the cells of the closed sets not decided yet; the number
    /// marked, or `None` when the map or the graph changed (a closed set
    /// at its floor was sharpened or trapped) and the level starts again.
    fn mark_closed(
        &mut self,
        closed: &[Closed],
        marked: &mut [bool],
    ) -> Result<Option<usize>, AttractorError> {
        let mut extra = 0;
        for k in closed.iter().filter(|k| k.proved.is_none()) {
            let g = &self.g;
            let hull = [
                g.bounds[k.cells[0]],
                g.bounds[k.cells[k.cells.len() - 1] + 1],
            ];
            let mut chaotic = self
                .settled
                .iter()
                .any(|s| s[0] <= hull[0] && hull[1] <= s[1]);
            let at_its_floor = k.cells.iter().all(|&i| g.width(i) <= self.floor(i, FLOOR));
            if !chaotic && at_its_floor {
                let middle = g.mid(k.cells[k.cells.len() / 2]);
                match at_floor(
                    self.sim,
                    &mut self.map,
                    &mut self.g,
                    hull,
                    middle,
                    &mut self.spent,
                )? {
                    Floor::Settled => {
                        self.settled.push(hull);
                        chaotic = true;
                    }
                    Floor::Changed => return Ok(None),
                }
            }
            // A chaotic set goes on to CHAOS_FLOOR ε, for its density.
            let times = if chaotic { CHAOS_FLOOR } else { FLOOR };
            for &i in &k.cells {
                if self.g.width(i) > self.floor(i, times) {
                    marked[i] = true;
                    extra += 1;
                }
            }
        }
        Ok(Some(extra))
    }
}

/// The basins along the arc (runs of cells with one reachable closed set)
/// and the boundary's share; sets each attractor's basin fraction.
fn basins(
    g: &CellGraph,
    map: &ArcMap,
    comps: &graph::Components,
    labels: &[Option<usize>],
    found: &mut [Attractor],
) -> (Vec<Basin>, f64) {
    let reach = g.reach(comps, labels);
    let psi = map.psi();
    let total = map.hi - map.lo;
    let mut basins: Vec<Basin> = Vec::new();
    let mut share = vec![0.0; found.len()];
    let mut boundary = 0.0;
    for v in 0..g.len() {
        let m = reach[comps.comp[v] as usize];
        let a = (m.count_ones() == 1).then(|| m.trailing_zeros() as usize);
        match a {
            Some(a) if a < share.len() => share[a] += g.width(v),
            _ => boundary += g.width(v),
        }
        let (from, to) = (psi + g.bounds[v], psi + g.bounds[v + 1]);
        match basins.last_mut() {
            Some(b) if b.attractor == a => b.to = to,
            _ => basins.push(Basin {
                from,
                to,
                attractor: a,
            }),
        }
    }
    for (a, s) in found.iter_mut().zip(&share) {
        a.basin_fraction = s / total;
    }
    (basins, boundary / total)
}

/// What became of a closed set at its floor.
enum Floor {
    /// Left as it is: chaotic, or nothing more to try.
    Settled,
    /// The map was sharpened over it or a trap was added: look again.
    Changed,
}

/// A closed set whose cells cannot be made narrower on the map as it is
/// (hull: its extent, in u). A long orbit from `start` decides: chaotic,
/// it stays; a stable cycle in it is trapped ([`trap`]; on the sharpened
/// map if it is not sharp there yet), so that the rest of the set (a
/// saddle leaking onto the cycle) is no longer closed; anything else is
/// sharpened once and subdivided on.
fn at_floor(
    sim: &Simulator,
    map: &mut ArcMap,
    g: &mut CellGraph,
    hull: [f64; 2],
    start: f64,
    spent: &mut (u64, u64),
) -> Result<Floor, AttractorError> {
    let o = long_orbit(sim, map, start, spent)?;
    if o.settled.is_none() && o.lyapunov > 0.0 {
        return Ok(Floor::Settled);
    }
    let pad = 1e-3 * (hull[1] - hull[0]) + 1e-6;
    let (lo, hi) = (hull[0] - pad, hull[1] + pad);
    let mut sharpened = false;
    if !map.is_sharp(lo, hi) {
        map.sharpen(lo, hi, SHARPEN_EVALUATIONS)?;
        g.refresh(map, lo, hi);
        sharpened = true;
    }
    if let Some((p, u)) = o.settled {
        let c = solve(sim, map.psi(), u, p, spent).filter(|c| c.stable);
        let xs: Option<Vec<f64>> = c.map(|c| {
            c.points[..c.minimal_period]
                .iter()
                .map(|t| wrap_angle(t - map.psi()))
                .collect()
        });
        let known = |xs: &[f64]| {
            g.cycles
                .iter()
                .any(|c| c.0 == xs.len() && xs.iter().any(|x| (c.1 - x).abs() < 1e-9))
        };
        if let Some(xs) = xs.filter(|xs| !known(xs))
            && let Some(pairs) = trap(map, &xs)
        {
            for (from, to) in pairs {
                g.add_trap(map, from, to);
            }
            g.cycles.push((xs.len(), xs[0]));
            return Ok(Floor::Changed);
        }
    }
    Ok(if sharpened {
        Floor::Changed
    } else {
        Floor::Settled
    })
}

/// The cycle whose trap holds every one of `cells`, if one does.
fn in_trap(g: &CellGraph, cells: &[usize]) -> Option<(usize, f64)> {
    if !cells.iter().all(|&i| g.trapped(i)) {
        return None;
    }
    let (lo, hi) = (g.bounds[cells[0]], g.bounds[cells[cells.len() - 1] + 1]);
    g.cycles
        .iter()
        .copied()
        .find(|&(_, u)| {
            // A point of the cycle among the cells.
            lo <= u && u <= hi
        })
        .or_else(|| g.cycles.first().copied())
}

/// The graph's components, its closed ones (each tried for a
/// contraction), and each component's label among the closed ones.
fn closed_sets(
    g: &CellGraph,
    map: &ArcMap,
) -> (graph::Components, Vec<Closed>, Vec<Option<usize>>) {
    let comps = g.components();
    let mut out: Vec<Closed> = Vec::new();
    let mut labels = vec![None; comps.count];
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); comps.count];
    for (v, &c) in comps.comp.iter().enumerate() {
        if comps.terminal[c as usize] {
            members[c as usize].push(v);
        }
    }
    for (c, cells) in members.into_iter().enumerate() {
        if cells.is_empty() {
            continue;
        }
        labels[c] = Some(out.len());
        out.push(closed(g, map, cells));
    }
    (comps, out, labels)
}

/// A closed set's cells, tried for a contraction (or a trap).
fn closed(g: &CellGraph, map: &ArcMap, cells: Vec<usize>) -> Closed {
    let proved = contraction(g, map, &cells)
        .map(|(p, _, u)| (p, u))
        .or_else(|| in_trap(g, &cells));
    Closed { cells, proved }
}

/// Bins of a chaotic attractor's density.
const DENSITY_BINS: usize = 100;

/// A closed set's attractor (see [`classify`]).
fn classify_closed(
    sim: &Simulator,
    map: &ArcMap,
    g: &CellGraph,
    k: &Closed,
    spent: &mut (u64, u64),
) -> Result<Attractor, AttractorError> {
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
        density: None,
        basin_fraction: 0.0,
        cover,
        verdict: Verdict::Undecided(String::new()),
    };
    let cycle = |p: usize, u: f64, verdict: Verdict, spent: &mut (u64, u64)| {
        solved(sim, psi, u, p, spent, &inside).map(|(period, points, multiplier, lyapunov)| {
            Attractor {
                period: Some(period),
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
        return Ok(a);
    }
    // The set's middle cell by length, as a start.
    let start = g.mid(k.cells[k.cells.len() / 2]);
    let orbit = long_orbit(sim, map, start, spent)?;
    if let Some((p, u)) = orbit.settled
        && let Some(a) = cycle(p, u, Verdict::CycleInSet, spent)
    {
        return Ok(a);
    }
    Ok(chaotic(map, g, &k.cells, &orbit, blank))
}

/// A closed set that holds no stable cycle found: its density (Ulam),
/// λ from it beside the orbit's, and the verdict they allow.
fn chaotic(
    map: &ArcMap,
    g: &CellGraph,
    cells: &[usize],
    orbit: &classify::Orbit,
    blank: Attractor,
) -> Attractor {
    let psi = map.psi();
    let (mu, lambda_d) = ulam(g, map, cells);
    let lo = g.bounds[cells[0]];
    let hi = g.bounds[cells[cells.len() - 1] + 1];
    let values = binned(g, cells, &mu, lo, hi);
    let agree = (lambda_d - orbit.lyapunov).abs() <= 0.02 + 4.0 * orbit.stderr;
    let verdict = if lambda_d > 0.0 && orbit.lyapunov > 0.0 && agree {
        Verdict::Chaotic
    } else if !agree {
        Verdict::Undecided(format!(
            "lambda from the density ({lambda_d:.4}) and from a {}-iterate orbit ({:.4} +- {:.4}) disagree; subdivide further with --resolution or --max-cells",
            classify::ORBIT_KEEP,
            orbit.lyapunov,
            orbit.stderr
        ))
    } else {
        Verdict::Undecided(format!(
            "a closed set with no stable cycle found and lambda = {lambda_d:.4} <= 0 (a drift or gap below the resolution); subdivide further with --resolution or --max-cells"
        ))
    };
    Attractor {
        period: None,
        points: vec![psi + lo, psi + hi],
        lyapunov: Some(orbit.lyapunov),
        lyapunov_stderr: Some(orbit.stderr),
        lyapunov_from_density: Some(lambda_d),
        density: Some(Density {
            from: psi + lo,
            to: psi + hi,
            values,
        }),
        verdict,
        ..blank
    }
}

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
    let mut c = solve(sim, psi, u, p, spent)?;
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

/// A density on cells as [`DENSITY_BINS`] equal bins over [lo, hi],
/// summing to 1.
fn binned(g: &CellGraph, cells: &[usize], mu: &[f64], lo: f64, hi: f64) -> Vec<f64> {
    let mut values = vec![0.0; DENSITY_BINS];
    let bin = (hi - lo) / DENSITY_BINS as f64;
    for (&c, &m) in cells.iter().zip(mu) {
        let (a, b) = (g.bounds[c], g.bounds[c + 1]);
        let (i0, i1) = (
            (((a - lo) / bin) as usize).min(DENSITY_BINS - 1),
            (((b - lo) / bin) as usize).min(DENSITY_BINS - 1),
        );
        for i in i0..=i1 {
            let (x0, x1) = (lo + i as f64 * bin, lo + (i + 1) as f64 * bin);
            let ov = (b.min(x1) - a.max(x0)).max(0.0);
            values[i] += m * ov / (b - a);
        }
    }
    let s: f64 = values.iter().sum();
    values.iter_mut().for_each(|v| *v /= s);
    values
}

/// Why the attractors could not be found.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AttractorError {
    #[error("f could not be built over the exit arc: {0}")]
    Arc(#[from] ArcError),
    #[error("{0}")]
    Sim(#[from] SimError),
}
