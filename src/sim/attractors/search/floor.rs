//! A closed set whose cells cannot be made narrower on the map as it is,
//! decided a piece at a time: a long orbit from its middle; a stable
//! cycle in it trapped (on the map as it is, or sharpened round the
//! cycle's points), so that a saddle leaking onto the cycle is no longer
//! closed; otherwise the map sharpened over its hull, or the set left as
//! it is (chaotic).

use super::super::arc::Sharpening;
use super::super::classify::{LongOrbit, Orbit, solve, trap};
use super::super::graph::CellGraph;
use super::super::{ArcMap, AttractorError};
use super::SHARPEN_EVALUATIONS;
use crate::model::wrap_angle;
use crate::sim::Simulator;

/// Iterates of a long orbit on the series a piece (about 1.5 ms).
const ORBIT_PIECE: usize = 1_500;

/// How far round a stable cycle's points the map is sharpened first.
const NEAR_CYCLE: f64 = 1e-3;

/// What became of a closed set at its floor.
pub(super) enum Floor {
    /// Left as it is: chaotic, or nothing more to try (the orbit that
    /// showed it).
    Settled(Orbit),
    /// The map was sharpened over it or a trap was added: look again.
    Changed,
}

/// A closed set whose cells cannot be made narrower on the map as it is
/// (hull: its extent, in u), decided a piece at a time. A long orbit from
/// its middle decides: chaotic, it stays; a stable cycle in it is trapped
/// ([`trap`]: on the map as it is, or else on the map sharpened round the
/// cycle's points), so that the rest of the set (a saddle leaking onto the
/// cycle) is no longer closed; anything else is sharpened once over its
/// hull and subdivided on.
pub(super) struct FloorRun {
    pub(super) hull: [f64; 2],
    /// The spans the level was subdividing when it began (restored when
    /// the set is settled, so that the level goes on where it was).
    pub(super) pending: Option<Vec<[f64; 2]>>,
    stage: FloorStage,
}

enum FloorStage {
    /// The long orbit, [`ORBIT_PIECE`] iterates a piece.
    Orbit(LongOrbit),
    /// The stable cycle it settled on, solved (unless one trapped
    /// already), and the trap tried on the map as it is.
    Cycle(Orbit),
    /// The map sharpened round the cycle's point `next` (`building` it),
    /// then the trap tried again.
    NearCycle {
        orbit: Orbit,
        xs: Vec<f64>,
        next: usize,
        sharpened: bool,
        building: Option<Sharpening>,
    },
    /// The map sharpened over the hull (`building` it).
    Hull {
        orbit: Orbit,
        cycle: Option<Vec<f64>>,
        building: Sharpening,
    },
    Over,
}

impl FloorRun {
    pub(super) fn new(hull: [f64; 2], start: f64, lengths: (usize, usize)) -> Self {
        FloorRun {
            hull,
            pending: None,
            stage: FloorStage::Orbit(LongOrbit::new(start, lengths)),
        }
    }

    /// One piece (the orbit, the solve, a piece of a sharpening); the
    /// outcome once there is one.
    pub(super) fn step(
        &mut self,
        sim: &Simulator,
        map: &mut ArcMap,
        g: &mut CellGraph,
        spent: &mut (u64, u64),
    ) -> Result<Option<Floor>, AttractorError> {
        let (stage, out) = match std::mem::replace(&mut self.stage, FloorStage::Over) {
            FloorStage::Orbit(mut run) => {
                let Some(o) = run.advance(map, ORBIT_PIECE) else {
                    self.stage = FloorStage::Orbit(run);
                    return Ok(None);
                };
                if o.settled.is_none() && o.lyapunov > 0.0 {
                    (FloorStage::Over, Some(Floor::Settled(o)))
                } else {
                    (FloorStage::Cycle(o), None)
                }
            }
            FloorStage::Cycle(orbit) => match new_stable_cycle(sim, map, g, &orbit, spent) {
                Some(xs) if trapped(map, g, &xs) => (FloorStage::Over, Some(Floor::Changed)),
                // The coarse series' curvature bound is too loose for a
                // trap: the map sharpened round the cycle's points only,
                // before its hull.
                Some(xs) => (
                    FloorStage::NearCycle {
                        orbit,
                        xs,
                        next: 0,
                        sharpened: false,
                        building: None,
                    },
                    None,
                ),
                None => self.to_hull(map, g, orbit, None)?,
            },
            FloorStage::NearCycle {
                orbit,
                xs,
                next,
                sharpened,
                building,
            } => self.near_cycle_step(map, g, orbit, xs, (next, sharpened), building)?,
            FloorStage::Hull {
                orbit,
                cycle,
                mut building,
            } => {
                if map.sharpen_step(&mut building)? {
                    self.sharpened_hull(map, g, cycle.as_deref());
                    (FloorStage::Over, Some(Floor::Changed))
                } else {
                    let stage = FloorStage::Hull {
                        orbit,
                        cycle,
                        building,
                    };
                    (stage, None)
                }
            }
            FloorStage::Over => (FloorStage::Over, None),
        };
        self.stage = stage;
        Ok(out)
    }

    /// One piece of the sharpening round the cycle's points `xs` (the
    /// next to sharpen, and whether any was): the next stage, and the
    /// outcome once there is one.
    fn near_cycle_step(
        &self,
        map: &mut ArcMap,
        g: &mut CellGraph,
        orbit: Orbit,
        xs: Vec<f64>,
        (mut next, mut sharpened): (usize, bool),
        building: Option<Sharpening>,
    ) -> Result<(FloorStage, Option<Floor>), AttractorError> {
        let near = |x: f64| (x - NEAR_CYCLE, x + NEAR_CYCLE);
        let building = match building {
            Some(mut b) => {
                if map.sharpen_step(&mut b)? {
                    let (lo, hi) = near(xs[next]);
                    g.refresh(map, lo, hi);
                    sharpened = true;
                    next += 1;
                    None
                } else {
                    Some(b)
                }
            }
            None => match xs.get(next) {
                Some(&x) => {
                    let (lo, hi) = near(x);
                    let b = map.sharpen_start(lo, hi, SHARPEN_EVALUATIONS / xs.len())?;
                    if b.is_none() {
                        next += 1;
                    }
                    b
                }
                None if sharpened && trapped(map, g, &xs) => {
                    return Ok((FloorStage::Over, Some(Floor::Changed)));
                }
                None => {
                    return self.to_hull(map, g, orbit, Some(xs));
                }
            },
        };
        let stage = FloorStage::NearCycle {
            orbit,
            xs,
            next,
            sharpened,
            building,
        };
        Ok((stage, None))
    }

    /// The hull padded a little.
    fn padded_hull(&self) -> (f64, f64) {
        let pad = 1e-3 * (self.hull[1] - self.hull[0]) + 1e-6;
        (self.hull[0] - pad, self.hull[1] + pad)
    }

    /// On to the hull: settled when it is sharp already, else its
    /// sharpening begun (or, with nothing there to sharpen, the images
    /// and the trap looked at again at once).
    fn to_hull(
        &self,
        map: &mut ArcMap,
        g: &mut CellGraph,
        orbit: Orbit,
        cycle: Option<Vec<f64>>,
    ) -> Result<(FloorStage, Option<Floor>), AttractorError> {
        let (lo, hi) = self.padded_hull();
        if map.is_sharp(lo, hi) {
            return Ok((FloorStage::Over, Some(Floor::Settled(orbit))));
        }
        Ok(match map.sharpen_start(lo, hi, SHARPEN_EVALUATIONS)? {
            Some(building) => {
                let stage = FloorStage::Hull {
                    orbit,
                    cycle,
                    building,
                };
                (stage, None)
            }
            None => {
                self.sharpened_hull(map, g, cycle.as_deref());
                (FloorStage::Over, Some(Floor::Changed))
            }
        })
    }

    /// After the hull's sharpening: its cells' images again, and the
    /// cycle's trap tried once more.
    fn sharpened_hull(&self, map: &ArcMap, g: &mut CellGraph, cycle: Option<&[f64]>) {
        let (lo, hi) = self.padded_hull();
        g.refresh(map, lo, hi);
        if let Some(xs) = cycle {
            trapped(map, g, xs);
        }
    }
}

/// The stable cycle the orbit settled on, in u, unless one trapped
/// already.
fn new_stable_cycle(
    sim: &Simulator,
    map: &ArcMap,
    g: &CellGraph,
    o: &Orbit,
    spent: &mut (u64, u64),
) -> Option<Vec<f64>> {
    let (p, u) = o.settled?;
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
