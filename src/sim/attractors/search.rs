//! Subdivision: the cell graph analysed level by level, its undecided
//! closed sets (and its basin boundary) halved, a set at its map's floor
//! sharpened, trapped or left as chaotic, until each closed set is decided
//! or the resolution or the cell budget is reached.

mod floor;

use super::classify::{COLUMN_ORBIT, ORBIT, Orbit, clusters, contraction};
use super::graph::{self, CellGraph};
use super::{ArcMap, AttractorError, CellOptions};
use crate::sim::Simulator;
use floor::{Floor, FloorRun};

/// A closed component during subdivision.
pub(super) struct Closed {
    pub(super) cells: Vec<usize>,
    /// (p, u) when its contraction is proved.
    pub(super) proved: Option<(usize, f64)>,
}

/// A cell is made no narrower than this many ε of the map under it (a
/// closed set reaching it is sharpened, or settled; a chaotic set's
/// density has a grid of its own, `density`).
const FLOOR: f64 = 100.0;

/// A basin boundary's cells are halved down to this many ε over the
/// slope of f on them: below, their images are the map's error.
const BOUNDARY_FLOOR: f64 = 4.0;

/// Recurrent cells outside every closed set are subdivided to this
/// many ε: an attractor whose basin is wider than a few of them shows.
const RECURRENT_FLOOR: f64 = 100.0;

/// The most boundary stretches sharpened in one level.
const SHARPEN_PER_LEVEL: usize = 1;

/// The most map evaluations one sharpened stretch may take.
pub(super) const SHARPEN_EVALUATIONS: usize = 4_000;

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
    /// A closed set at its floor being decided, piece by piece: the level
    /// starts again once it is.
    floor: Option<Box<FloorRun>>,
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
            floor: None,
        }
    }

    /// One level: the graph analysed, its undecided closed sets and its
    /// boundary marked and subdivided; or, where a closed set is at its
    /// floor, one piece of its decision ([`FloorRun`]: the map sharpened,
    /// a trap added, or the set settled), after which the level starts
    /// again. `Some` when nothing is left to do.
    pub(super) fn level(&mut self) -> Result<Option<Done>, AttractorError> {
        if let Some(run) = self.floor.take() {
            self.floor_step(run)?;
            return Ok(None);
        }
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
            let Some(extra) = self.mark_closed(&closed, &mut marked) else {
                if let Some(run) = self.floor.as_mut() {
                    run.pending = Some(spans);
                }
                return Ok(None);
            };
            if extra > 0 && self.g.len() + extra <= self.opts.max_cells {
                self.pending = Some(self.undecided_spans(&closed, &marked));
                self.subdivide(&marked)?;
                return Ok(None);
            }
            self.budget_hit |= extra > 0;
        }
        let (comps, closed, labels) = closed_sets(&self.g, &self.map);
        let mut marked = vec![false; self.g.len()];
        let Some(mut extra) = self.mark_closed(&closed, &mut marked) else {
            return Ok(None);
        };
        if extra > 0 && !self.budget_hit {
            self.pending = Some(self.undecided_spans(&closed, &marked));
        }
        let reach = self.g.reach(&comps, &labels);
        if self.sharpen_boundary(&comps, &reach)? {
            return Ok(None);
        }
        extra += self.mark_boundary(&comps, &reach, &mut marked);
        if extra == 0 {
            return Ok(Some((closed, comps, labels)));
        }
        if self.g.len() + extra > self.opts.max_cells {
            self.budget_hit = true;
            return Ok(Some((closed, comps, labels)));
        }
        self.subdivide(&marked)?;
        Ok(None)
    }

    /// Marks the basin boundary's cells and the recurrent cells that leak
    /// (an attractor whose neighbourhood is not closed yet may hide there:
    /// a weakly stable cycle with a narrow basin) while they are wider
    /// than their floors; the number marked.
    fn mark_boundary(
        &self,
        comps: &graph::Components,
        reach: &[u64],
        marked: &mut [bool],
    ) -> usize {
        let mut extra = 0;
        for v in 0..self.g.len() {
            let c = comps.comp[v] as usize;
            let floor = if reach[c].count_ones() > 1 {
                // A boundary cell gains from halving while its image is
                // wider than the map's error: where f is steep (a
                // repelling point, a jump: the boundary's own points) down
                // to the resolution.
                let slope = self.g.images[v].slope.max(1.0);
                self.opts
                    .resolution
                    .max(BOUNDARY_FLOOR * self.map.eps_at(self.g.mid(v)) / slope)
            } else if comps.recurrent[c] && !comps.terminal[c] {
                self.floor(v, RECURRENT_FLOOR)
            } else {
                continue;
            };
            if !marked[v] && self.g.width(v) > floor {
                marked[v] = true;
                extra += 1;
            }
        }
        extra
    }

    /// Sharpens the map round the basin boundary's cells that the coarse
    /// map's error stops short of the resolution (their images are its
    /// error): at most [`SHARPEN_PER_LEVEL`] stretches a level. Whether
    /// any was.
    fn sharpen_boundary(
        &mut self,
        comps: &graph::Components,
        reach: &[u64],
    ) -> Result<bool, AttractorError> {
        let mut spans: Vec<[f64; 2]> = Vec::new();
        for v in 0..self.g.len() {
            if reach[comps.comp[v] as usize].count_ones() < 2 {
                continue;
            }
            let (w, u) = (self.g.width(v), self.g.mid(v));
            let slope = self.g.images[v].slope.max(1.0);
            let stuck = w <= BOUNDARY_FLOOR * self.map.eps_at(u) / slope;
            let pad = 4.0 * w + 1e-6;
            let (lo, hi) = (u - pad, u + pad);
            if !stuck || w <= self.opts.resolution || self.map.is_sharp(lo, hi) {
                continue;
            }
            match spans.last_mut() {
                Some(s) if lo <= s[1] => s[1] = hi,
                _ => spans.push([lo, hi]),
            }
        }
        let mut any = false;
        for s in spans.into_iter().take(SHARPEN_PER_LEVEL) {
            if self.map.sharpen(s[0], s[1], SHARPEN_EVALUATIONS)? {
                self.g.refresh(&self.map, s[0], s[1]);
                any = true;
            }
        }
        Ok(any)
    }

    /// Halves the marked cells, after nodes at their ends and midpoints
    /// where they lie in a stretch left to integration (so that the
    /// halves are enclosed by nodes of their own).
    fn subdivide(&mut self, marked: &[bool]) -> Result<(), AttractorError> {
        let g = &self.g;
        let us: Vec<f64> = (0..g.len())
            .filter(|&i| marked[i])
            .flat_map(|i| [g.bounds[i], g.mid(i), g.bounds[i + 1]])
            .collect();
        self.map.add_nodes(&us)?;
        self.g.subdivide(&self.map, marked);
        Ok(())
    }

    /// Whether a closed set at its floor is being decided.
    pub(super) fn deciding(&self) -> bool {
        self.floor.is_some()
    }

    /// One piece of the decision of a closed set at its floor (`run`); once
    /// it is decided, the level starts again.
    fn floor_step(&mut self, mut run: Box<FloorRun>) -> Result<(), AttractorError> {
        let (map, g) = (&mut self.map, &mut self.g);
        match run.step(&self.sim, map, g, &mut self.spent)? {
            None => self.floor = Some(run),
            // Left as it is: the level again, where it was.
            Some(Floor::Settled(orbit)) => {
                self.settled.push((run.hull, orbit));
                self.pending = run.pending;
            }
            // The map or the graph changed: everything is looked at again.
            Some(Floor::Changed) => {}
        }
        Ok(())
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
    /// marked, or `None` when a closed set is at its floor and not settled
    /// yet: its decision ([`FloorRun`]) is begun, and the level waits for it.
    fn mark_closed(&mut self, closed: &[Closed], marked: &mut [bool]) -> Option<usize> {
        let mut extra = 0;
        for k in closed.iter().filter(|k| k.proved.is_none()) {
            let g = &self.g;
            let hull = [
                g.bounds[k.cells[0]],
                g.bounds[k.cells[k.cells.len() - 1] + 1],
            ];
            let chaotic = self
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
                self.floor = Some(Box::new(FloorRun::new(hull, middle, lengths)));
                return None;
            }
            let times = FLOOR;
            for &i in &k.cells {
                if self.g.width(i) > self.floor(i, times) {
                    marked[i] = true;
                    extra += 1;
                }
            }
        }
        Some(extra)
    }
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
        .or_else(|| g.trap_cycle(&cells));
    Closed { cells, proved }
}
