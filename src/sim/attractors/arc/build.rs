//! The arc's parts built in bounded pieces: the interpolant's construction
//! (`InterpolantBuild`, a few ms a piece), then each stretch it left to
//! integration sampled, so that a host on a slice of time (the page's
//! frame) can stop between any two and go on with the same map bit for
//! bit.

use super::{ArcError, ArcMap, FINE_TOL, Node, Part, curvature_bound, nodes, series_at};
use crate::sim::Simulator;
use crate::sim::interpolant::{
    InterpolantBuild, InterpolantOptions, Layout, MapInterpolant, PieceView,
};

/// The whole arc's build in progress ([`ArcMap::build`] runs one to its
/// end).
pub struct ArcBuild {
    map: ArcMap,
    parts: PartsBuild,
    done: bool,
}

impl ArcBuild {
    /// The build at `sim`'s parameters, nothing evaluated yet.
    pub fn start(sim: &Simulator) -> Result<Self, ArcError> {
        Self::start_from(sim, None)
    }

    /// As [`Self::start`], the whole arc's interpolant started from a
    /// neighbouring column's [`ArcMap::layout`] (`InterpolantBuild::start_from`:
    /// the same checks, less work where f has moved little).
    pub fn start_from(sim: &Simulator, layout: Option<&Layout>) -> Result<Self, ArcError> {
        let map = ArcMap::empty(sim)?;
        let parts = map.parts_build(
            false,
            map.lo,
            map.hi,
            super::COARSE_TOL,
            super::COARSE_EVALUATIONS,
            layout,
        )?;
        Ok(ArcBuild {
            map,
            parts,
            done: false,
        })
    }

    /// One piece of the work; whether the map is done. After an error the
    /// build must not be advanced again.
    pub fn advance(&mut self) -> Result<bool, ArcError> {
        if !self.done
            && let Some(parts) = self.map.parts_step(&mut self.parts)?
        {
            self.map.starts = parts.iter().map(Part::from).collect();
            self.map.parts = parts;
            self.done = true;
        }
        Ok(self.done)
    }

    /// The map, once [`Self::advance`] has said it is done.
    pub fn finish(self) -> ArcMap {
        assert!(self.done, "finish follows a done advance");
        self.map
    }
}

/// A stretch being sharpened ([`ArcMap::sharpen_start`]).
pub struct Sharpening {
    lo: f64,
    hi: f64,
    parts: PartsBuild,
}

impl ArcMap {
    /// The build of [lo, hi] again to [`FINE_TOL`] (within
    /// `max_evaluations`), to be run by [`Self::sharpen_step`]; `None`
    /// when there is nothing to sharpen (a stretch already sharp, or off
    /// the covered interval).
    pub fn sharpen_start(
        &self,
        lo: f64,
        hi: f64,
        max_evaluations: usize,
    ) -> Result<Option<Sharpening>, ArcError> {
        let (lo, hi) = (lo.max(self.lo), hi.min(self.hi));
        if !(hi > lo) || self.sharp.iter().any(|s| s[0] <= lo && hi <= s[1]) {
            return Ok(None);
        }
        let parts = self.parts_build(true, lo, hi, FINE_TOL, max_evaluations, None)?;
        Ok(Some(Sharpening { lo, hi, parts }))
    }

    /// One piece of `s`; whether it is done, its parts then replacing the
    /// coarse ones over its stretch.
    pub fn sharpen_step(&mut self, s: &mut Sharpening) -> Result<bool, ArcError> {
        let Some(fine) = self.parts_step(&mut s.parts)? else {
            return Ok(false);
        };
        let (lo, hi) = (s.lo, s.hi);
        let mut parts = Vec::with_capacity(self.parts.len() + fine.len() + 2);
        for p in &self.parts {
            if p.to() <= lo || p.from() >= hi {
                parts.push(p.clone());
                continue;
            }
            if p.from() < lo {
                parts.push(p.clip(p.from(), lo));
            }
            if p.to() > hi {
                parts.push(p.clip(hi, p.to()));
            }
        }
        parts.extend(fine);
        parts.sort_by(|x, y| x.from().total_cmp(&y.from()));
        self.parts = parts;
        self.starts = self.parts.iter().map(Part::from).collect();
        self.sharp.push([lo, hi]);
        Ok(true)
    }
}

/// Points a series part is checked at against the integrated map, beyond
/// the interpolant's own check: between its nodes, three next to each end
/// (where the error of a series peaks when f is steep or singular just
/// beyond the end) and two inside.
const CHECKS_PER_PIECE: usize = 8;

impl ArcMap {
    /// The largest error of the series `map` on [a, b] against the
    /// integrated map at [`CHECKS_PER_PIECE`] points between its nodes.
    fn check_series(
        &mut self,
        sim: &Simulator,
        map: &[f64],
        (a, b): (f64, f64),
    ) -> Result<f64, ArcError> {
        let n = map.len().max(4) - 1;
        let gap = std::f64::consts::PI / n as f64;
        // Angles half-way between Chebyshev nodes, from each end.
        let angles = [0.5, 1.5, 2.5, 0.5 * n as f64 - 0.5, 0.5 * n as f64 + 0.5]
            .into_iter()
            .map(|k| k * gap)
            .chain(
                [0.5, 1.5, 2.5]
                    .into_iter()
                    .map(|k| std::f64::consts::PI - k * gap),
            );
        let us: Vec<f64> = angles
            .take(CHECKS_PER_PIECE)
            .map(|t| 0.5 * (a + b) + 0.5 * (b - a) * t.cos())
            .collect();
        let tasks: Vec<_> = us.iter().map(|u| (sim, self.psi + u, 0.0)).collect();
        let mut worst = 0.0_f64;
        for (r, &u) in crate::sim::cycles_in_lanes(&tasks).into_iter().zip(&us) {
            let e = r?;
            self.spent.0 += 1;
            self.spent.1 += e.rhs_evals;
            let truth = crate::model::wrap_angle(e.theta_next - self.psi);
            worst = worst.max((series_at(map, a, b, u) - truth).abs());
        }
        Ok(worst)
    }
}

/// Verified (and sampled) parts over an interval in progress.
pub(super) struct PartsBuild {
    fine: bool,
    tol: f64,
    max_evaluations: usize,
    stage: Stage,
}

enum Stage {
    /// The interpolant's construction.
    Interpolant(InterpolantBuild),
    /// Its pieces made parts in order, `next` the first not yet made; a
    /// stretch left to integration is sampled, one a piece.
    Stretches {
        interp: MapInterpolant,
        next: usize,
        parts: Vec<Part>,
    },
    /// Handed over.
    Taken,
}

impl ArcMap {
    /// The parts over [lo, hi] at `tol`, to be built by
    /// [`Self::parts_step`]: on the user's solver (`fine`) or the coarse
    /// tier's.
    pub(super) fn parts_build(
        &self,
        fine: bool,
        lo: f64,
        hi: f64,
        tol: f64,
        max_evaluations: usize,
        layout: Option<&Layout>,
    ) -> Result<PartsBuild, ArcError> {
        let opts = InterpolantOptions {
            tol,
            max_pieces: 400,
            max_evaluations,
        };
        let sim = if fine { self.sim } else { self.coarse };
        let (lo, hi) = (self.psi + lo, self.psi + hi);
        let build = match layout {
            Some(l) => InterpolantBuild::start_from(&sim, lo, hi, opts, true, l)?,
            None => InterpolantBuild::start(&sim, lo, hi, opts, true)?,
        };
        Ok(PartsBuild {
            fine,
            tol,
            max_evaluations,
            stage: Stage::Interpolant(build),
        })
    }

    /// One bounded piece of `b`: a piece of the interpolant's
    /// construction, or the parts up to and including the next stretch
    /// left to integration (sampled). The parts once all are made.
    pub(super) fn parts_step(&mut self, b: &mut PartsBuild) -> Result<Option<Vec<Part>>, ArcError> {
        match std::mem::replace(&mut b.stage, Stage::Taken) {
            Stage::Interpolant(mut build) => {
                if !build.advance()? {
                    b.stage = Stage::Interpolant(build);
                    return Ok(None);
                }
                let interp = build.finish();
                if !b.fine {
                    self.layout = interp.layout();
                }
                self.spent.0 += interp.evaluations() as u64;
                self.spent.1 += interp.rhs_evals();
                self.max_error = self.max_error.max(interp.verification().max_map_error);
                let parts = Vec::with_capacity(interp.pieces().0);
                b.stage = Stage::Stretches {
                    interp,
                    next: 0,
                    parts,
                };
                Ok(None)
            }
            Stage::Stretches {
                interp,
                mut next,
                mut parts,
            } => {
                let more = self.make_parts(b, &interp, &mut next, &mut parts)?;
                if !more {
                    return Ok(Some(parts));
                }
                b.stage = Stage::Stretches {
                    interp,
                    next,
                    parts,
                };
                Ok(None)
            }
            Stage::Taken => Ok(None),
        }
    }

    /// The parts of `interp`'s pieces from `next` up to and including the
    /// next stretch left to integration; whether pieces are left.
    fn make_parts(
        &mut self,
        b: &PartsBuild,
        interp: &MapInterpolant,
        next: &mut usize,
        parts: &mut Vec<Part>,
    ) -> Result<bool, ArcError> {
        let fine = b.fine;
        let (sim, own) = if b.fine {
            (self.sim, self.own)
        } else {
            (self.coarse, self.own_coarse)
        };
        let b_tol = b.tol;
        let views: Vec<PieceView> = interp.piece_views().collect();
        // The samples of the stretches left to integration share half the
        // build's budget (each 1 to 33).
        let direct = views
            .iter()
            .filter(|v| matches!(v, PieceView::Direct { .. }))
            .count();
        let per = (b.max_evaluations / 2 / direct.max(1)).clamp(3, 33);
        // One part a call: a series costs CHECKS_PER_PIECE evaluations, a
        // stretch its nodes.
        let Some(v) = views.get(*next) else {
            return Ok(false);
        };
        let i = *next;
        *next += 1;
        {
            match *v {
                PieceView::Series {
                    a,
                    b,
                    map,
                    derivative,
                } => {
                    let d: Vec<f64> = derivative.iter().map(|c| c[1]).collect();
                    let measured = self.check_series(&sim, map, (a, b))?;
                    parts.push(Part::Series {
                        a,
                        b,
                        from: a,
                        to: b,
                        map: map.into(),
                        derivative: d.into(),
                        curvature: curvature_bound(map, a, b),
                        eps: b_tol.max(2.0 * measured) + own,
                    });
                }
                PieceView::Direct { a, b } => {
                    let neighbours = (
                        i.checked_sub(1).and_then(|j| views.get(j)),
                        views.get(i + 1),
                    );
                    let part = self.direct_part(&sim, (a, b), neighbours, (per, own, fine))?;
                    parts.push(part);
                }
            }
        }
        Ok(*next < views.len())
    }
}

/// A stretch's nodes are added at its build while an interval's
/// enclosure is wider than its chord by more than this (or open) ...
const STRETCH_SLACK: f64 = 1e-4;
/// ... and wider than this; the cell graph refines further where it
/// subdivides ([`ArcMap::add_nodes`]).
const STRETCH_FLOOR: f64 = 1e-6;

impl ArcMap {
    /// The nodes of a stretch left to integration: its ends (one-sided,
    /// from the neighbouring series where there is one) and `n` nodes
    /// across it (a jump's bracket, 2e-10 wide, only its midpoint), then
    /// intervals bisected while they are open or their enclosure is wider
    /// than the chord by more than [`STRETCH_SLACK`], within `most`
    /// evaluations and down to [`STRETCH_FLOOR`].
    fn stretch_nodes(
        &mut self,
        sim: &Simulator,
        (a, b): (f64, f64),
        ends: [Option<Node>; 2],
        most: usize,
        own: f64,
    ) -> Result<Vec<Node>, ArcError> {
        let psi = self.psi;
        let bracket = b - a < 1e-8;
        let n = if bracket {
            1
        } else {
            (((b - a) / 1e-3).ceil() as usize).clamp(3, most.max(3))
        };
        let mut out = Vec::with_capacity(n + 2);
        let mut spent = self.spent;
        let at = |u: f64, spent: &mut (u64, u64)| Node::at(sim, psi, u, spent);
        match ends[0] {
            Some(e) => out.push(e),
            None if !bracket => out.push(at(a, &mut spent)?),
            None => {}
        }
        for k in 0..n {
            let u = if bracket {
                0.5 * (a + b)
            } else {
                a + (b - a) * (k + 1) as f64 / (n + 1) as f64
            };
            out.push(at(u, &mut spent)?);
        }
        match ends[1] {
            Some(e) => out.push(e),
            None if !bracket => out.push(at(b, &mut spent)?),
            None => {}
        }
        let mut budget = most.saturating_mul(4);
        while !bracket && budget > 0 {
            let worst = out
                .windows(2)
                .enumerate()
                .filter(|(_, w)| w[1].u - w[0].u > STRETCH_FLOOR)
                .map(|(k, w)| (k, nodes::slack(&w[0], &w[1], own)))
                .filter(|&(_, s)| s > STRETCH_SLACK)
                .max_by(|x, y| x.1.total_cmp(&y.1));
            let Some((k, _)) = worst else { break };
            let u = 0.5 * (out[k].u + out[k + 1].u);
            out.insert(k + 1, at(u, &mut spent)?);
            budget -= 1;
        }
        self.spent = spent;
        Ok(out)
    }
}

impl ArcMap {
    /// A stretch left to integration as a part enclosed from nodes, its
    /// ends' values and slopes taken from the neighbouring series where
    /// there is one; `(most, own, fine)` as [`Self::stretch_nodes`] and
    /// [`Part::Sampled`] take them.
    fn direct_part(
        &mut self,
        sim: &Simulator,
        (a, b): (f64, f64),
        neighbours: (Option<&PieceView>, Option<&PieceView>),
        (most, own, fine): (usize, f64, bool),
    ) -> Result<Part, ArcError> {
        let side = |j: Option<&PieceView>, at: f64| match j {
            Some(PieceView::Series {
                a,
                b,
                map,
                derivative,
            }) => {
                let d: Vec<f64> = derivative.iter().map(|c| c[1]).collect();
                Some(Node {
                    u: at,
                    f: series_at(map, *a, *b, at),
                    d: series_at(&d, *a, *b, at),
                })
            }
            _ => None,
        };
        let ends = [side(neighbours.0, a), side(neighbours.1, b)];
        let nodes = self.stretch_nodes(sim, (a, b), ends, most, own)?;
        Ok(Part::Sampled {
            from: a,
            to: b,
            nodes,
            own,
            fine,
        })
    }
}
