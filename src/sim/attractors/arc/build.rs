//! The arc's parts built in bounded pieces: the interpolant's construction
//! (`InterpolantBuild`, a few ms a piece), then each stretch it left to
//! integration sampled, so that a host on a slice of time (the page's
//! frame) can stop between any two and go on with the same map bit for
//! bit.

use super::{ArcError, ArcMap, FINE_TOL, Part, curvature_bound, series_at};
use crate::sim::Simulator;
use crate::sim::interpolant::{InterpolantBuild, InterpolantOptions, MapInterpolant, PieceView};

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
        let map = ArcMap::empty(sim)?;
        let parts = map.parts_build(
            false,
            map.lo,
            map.hi,
            super::COARSE_TOL,
            super::COARSE_EVALUATIONS,
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
        let parts = self.parts_build(true, lo, hi, FINE_TOL, max_evaluations)?;
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
    ) -> Result<PartsBuild, ArcError> {
        let opts = InterpolantOptions {
            tol,
            max_pieces: 400,
            max_evaluations,
        };
        let sim = if fine { self.sim } else { self.coarse };
        let build = InterpolantBuild::start(&sim, self.psi + lo, self.psi + hi, opts, true)?;
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
        let (sim, own) = if b.fine {
            (self.sim, self.own)
        } else {
            (self.coarse, self.own_coarse)
        };
        let eps = b.tol + own;
        let views: Vec<PieceView> = interp.piece_views().collect();
        // The samples of the stretches left to integration share half the
        // build's budget (each 1 to 33).
        let direct = views
            .iter()
            .filter(|v| matches!(v, PieceView::Direct { .. }))
            .count();
        let per = (b.max_evaluations / 2 / direct.max(1)).clamp(3, 33);
        while let Some(v) = views.get(*next) {
            let i = *next;
            *next += 1;
            match *v {
                PieceView::Series {
                    a,
                    b,
                    map,
                    derivative,
                } => {
                    let d: Vec<f64> = derivative.iter().map(|c| c[1]).collect();
                    parts.push(Part::Series {
                        a,
                        b,
                        from: a,
                        to: b,
                        map: map.into(),
                        derivative: d.into(),
                        curvature: curvature_bound(map, a, b),
                        eps,
                    });
                }
                PieceView::Direct { a, b } => {
                    let side = |j: Option<&PieceView>, at: f64| match j {
                        Some(PieceView::Series { a, b, map, .. }) => {
                            Some(series_at(map, *a, *b, at))
                        }
                        _ => None,
                    };
                    let left = side(i.checked_sub(1).and_then(|j| views.get(j)), a);
                    let right = side(views.get(i + 1), b);
                    let samples = self.sampled(&sim, a, b, left, right, per)?;
                    parts.push(Part::Sampled {
                        from: a,
                        to: b,
                        samples: samples.into(),
                        eps,
                    });
                    return Ok(*next < views.len());
                }
            }
        }
        Ok(false)
    }
}
