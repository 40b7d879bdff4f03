//! Subdivision: the cell graph analysed level by level, its undecided
//! closed sets (and its basin boundary) halved, a set at its map's floor
//! sharpened, trapped or left as chaotic, until each closed set is decided
//! or the resolution or the cell budget is reached.

use super::classify::{COLUMN_ORBIT, ORBIT, Orbit, clusters, contraction, long_orbit, solve, trap};
use super::graph::{self, CellGraph};
use super::{ArcMap, AttractorError, CellOptions};
use crate::model::wrap_angle;
use crate::sim::Simulator;

/// A closed component during subdivision.
pub(super) struct Closed {
    pub(super) cells: Vec<usize>,
    /// (p, u) when its contraction is proved.
    pub(super) proved: Option<(usize, f64)>,
}

/// A cell is made no narrower than this many ε of the map under it (a
/// closed set reaching it is sharpened, or settled); a chaotic set's
/// cells go on to [`CHAOS_FLOOR`] ε, for its density.
const FLOOR: f64 = 100.0;
const CHAOS_FLOOR: f64 = 50.0;

/// Recurrent cells outside every closed set are subdivided to this
/// many ε: an attractor whose basin is wider than a few of them shows.
const RECURRENT_FLOOR: f64 = 100.0;

/// How far round a stable cycle's points the map is sharpened first.
const NEAR_CYCLE: f64 = 1e-3;

/// The most map evaluations one sharpened stretch may take.
const SHARPEN_EVALUATIONS: usize = 4_000;

/// The search's state between levels of subdivision.
pub(super) struct Search {
    sim: Simulator,
    opts: CellOptions,
    pub(super) map: ArcMap,
    pub(super) g: CellGraph,
    /// Closed sets left as they are at the map's floor (their hulls, and
    /// the long orbit that showed it): subdivided only to
    /// [`CHAOS_FLOOR`], and the orbit kept for their verdict.
    pub(super) settled: Vec<([f64; 2], Orbit)>,
    pub(super) spent: (u64, u64),
    pub(super) budget_hit: bool,
    /// The spans of the closed sets still being subdivided, between
    /// global analyses.
    pending: Option<Vec<[f64; 2]>>,
}

/// The closed sets, the components and their labels, when done.
pub(super) type Done = (Vec<Closed>, graph::Components, Vec<Option<usize>>);

impl Search {
    pub(super) fn new(sim: Simulator, opts: CellOptions, map: ArcMap, g: CellGraph) -> Self {
        Search {
            sim,
            opts,
            map,
            g,
            settled: Vec::new(),
            spent: (0, 0),
            budget_hit: false,
            pending: None,
        }
    }

    /// One level: the graph analysed, its undecided closed sets and its
    /// boundary marked and subdivided (or the map sharpened, or a trap
    /// added). `Some` when nothing is left to do.
    pub(super) fn level(&mut self) -> Result<Option<Done>, AttractorError> {
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
            let c = comps.comp[v] as usize;
            // The basin boundary, and recurrent cells that leak (an
            // attractor whose neighbourhood is not closed yet may hide
            // there: a weakly stable cycle with a narrow basin).
            let wanted = if reach[c].count_ones() > 1 {
                FLOOR
            } else if comps.recurrent[c] && !comps.terminal[c] {
                RECURRENT_FLOOR
            } else {
                continue;
            };
            if !marked[v] && self.g.width(v) > self.floor(v, wanted) {
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
                .any(|(s, _)| s[0] <= hull[0] && hull[1] <= s[1]);
            let at_its_floor = k.cells.iter().all(|&i| g.width(i) <= self.floor(i, FLOOR));
            if !chaotic && at_its_floor {
                let middle = g.mid(k.cells[k.cells.len() / 2]);
                let lengths = if self.opts.density {
                    ORBIT
                } else {
                    COLUMN_ORBIT
                };
                match at_floor(
                    &self.sim,
                    lengths,
                    &mut self.map,
                    &mut self.g,
                    hull,
                    middle,
                    &mut self.spent,
                )? {
                    Floor::Settled(orbit) => {
                        self.settled.push((hull, orbit));
                        chaotic = true;
                    }
                    Floor::Changed => return Ok(None),
                }
            }
            // A chaotic set goes on to CHAOS_FLOOR ε, for its density.
            let times = if chaotic && self.opts.density {
                CHAOS_FLOOR
            } else {
                FLOOR
            };
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

/// What became of a closed set at its floor.
enum Floor {
    /// Left as it is: chaotic, or nothing more to try (the orbit that
    /// showed it).
    Settled(Orbit),
    /// The map was sharpened over it or a trap was added: look again.
    Changed,
}

/// A closed set whose cells cannot be made narrower on the map as it is
/// (hull: its extent, in u). A long orbit from `start` decides: chaotic,
/// it stays; a stable cycle in it is trapped ([`trap`]: on the map as it
/// is, or else on the map sharpened over the set), so that the rest of the
/// set (a saddle leaking onto the cycle) is no longer closed; anything
/// else is sharpened once and subdivided on.
fn at_floor(
    sim: &Simulator,
    lengths: (usize, usize),
    map: &mut ArcMap,
    g: &mut CellGraph,
    hull: [f64; 2],
    start: f64,
    spent: &mut (u64, u64),
) -> Result<Floor, AttractorError> {
    let o = long_orbit(map, start, lengths)?;
    if o.settled.is_none() && o.lyapunov > 0.0 {
        return Ok(Floor::Settled(o));
    }
    // The stable cycle it settled on, in u, unless one trapped already.
    let cycle: Option<Vec<f64>> = o.settled.and_then(|(p, u)| {
        let c = solve(sim, map.psi(), u, p, spent).filter(|c| c.stable)?;
        let xs: Vec<f64> = c.points[..c.minimal_period]
            .iter()
            .map(|t| wrap_angle(t - map.psi()))
            .collect();
        let known = g
            .cycles
            .iter()
            .any(|c| c.0 == xs.len() && xs.iter().any(|x| (c.1 - x).abs() < 1e-9));
        (!known).then_some(xs)
    });
    if let Some(xs) = &cycle {
        if trapped(map, g, xs) {
            return Ok(Floor::Changed);
        }
        // The coarse series' curvature bound is too loose for a trap: the
        // map sharpened round the cycle's points only, before its hull.
        let mut sharpened = false;
        for &x in xs {
            let (lo, hi) = (x - NEAR_CYCLE, x + NEAR_CYCLE);
            if map.sharpen(lo, hi, SHARPEN_EVALUATIONS / xs.len())? {
                g.refresh(map, lo, hi);
                sharpened = true;
            }
        }
        if sharpened && trapped(map, g, xs) {
            return Ok(Floor::Changed);
        }
    }
    let pad = 1e-3 * (hull[1] - hull[0]) + 1e-6;
    let (lo, hi) = (hull[0] - pad, hull[1] + pad);
    if map.is_sharp(lo, hi) {
        return Ok(Floor::Settled(o));
    }
    map.sharpen(lo, hi, SHARPEN_EVALUATIONS)?;
    g.refresh(map, lo, hi);
    if let Some(xs) = &cycle {
        trapped(map, g, xs);
    }
    Ok(Floor::Changed)
}

/// Adds a trap round the cycle `xs` (in u) to the graph, if one is found
/// on the map as it is.
fn trapped(map: &ArcMap, g: &mut CellGraph, xs: &[f64]) -> bool {
    let Some(pairs) = trap(map, xs) else {
        return false;
    };
    for (from, to) in pairs {
        g.add_trap(map, from, to);
    }
    g.cycles.push((xs.len(), xs[0]));
    true
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
