//! The map as a verified interpolant: f(θ), for one parameter set and one
//! solver setting, as piecewise Chebyshev series over an interval of the
//! exit arc, built from map evaluations in lanes and checked against the
//! direct map at independent points (docs/interpolant.md).
//!
//! A piece is sampled at 33, 65, then 129 Chebyshev points until its
//! coefficients have decayed below the tolerance; a piece that 129 points
//! do not resolve is split, at a jump of f when its samples show one (the
//! jump is then bracketed by bisection to [`JUMP_WIDTH`] and the bracket
//! left to direct integration), at its middle otherwise. The event's other
//! quantities (the stop, the durations, the peak speed) are tabulated on the
//! same pieces, so that an orbit's kept events carry their slip sizes.
//! Every evaluation outside the verified pieces returns `None`: the caller
//! integrates there instead.

mod orbit;

use std::f64::consts::FRAC_PI_2;

use super::{SimError, Simulator, SlipEvent, cycles_in_lanes};
use crate::model::{elastic_energy, exit_arc, point_from_theta, wrap_angle};
use crate::numerics::chebyshev;

pub use orbit::{InterpolatedOrbit, MapChoice, orbit_interpolated};

/// The width, in θ, to which a jump of f is bracketed; the bracket is
/// integrated directly.
pub const JUMP_WIDTH: f64 = 2e-10;

/// The points a piece is sampled at: 33, then 65, then 129 (nested).
const SAMPLINGS: [usize; 3] = [33, 65, 129];

/// A piece narrower than this that 129 points do not resolve is left to
/// direct integration: a kink of f, say, once it is this well isolated, or
/// the stretches (~1e-4 wide at Fig. 3b's θ ≈ 0.5078 and next to the
/// intermittent point's jump at θ ≈ 0.6248) where the integrated map is
/// rough at the tolerance's scale and no series converges. Narrower, they
/// cost ~10× the evaluations for an even smaller chance that an iterate
/// lands there.
const MIN_PIECE: f64 = 1e-5;

/// Independent points each piece is checked at (fractions of the piece,
/// away from every Chebyshev point it was built on).
const CHECKS: [f64; 4] = [0.061_803, 0.381_966, 0.618_034 + 0.05, 0.927_7];

/// The tabulated quantities of an event, in this order in a piece's table:
/// θ' (as its offset from the arc's centre), f'(θ) (from the series), the
/// stop's x and y, the acceleration's and the slip's durations, the peak
/// speed, the stick's duration.
const FIELDS: usize = 8;

/// What the interpolant is asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterpolantOptions {
    /// The largest error in θ' allowed against the direct map, in radians.
    pub tol: f64,
    /// The most pieces (jump brackets included) the whole interval may take.
    pub max_pieces: usize,
}

impl InterpolantOptions {
    /// The default for a solver setting: θ' to 1e-10, or to an adaptive
    /// method's tolerance where that is tighter (never below 1e-12, about
    /// the noise of the integrated map at the tightest settings); 400
    /// pieces.
    pub fn for_settings(settings: &crate::integrate::SolverSettings) -> Self {
        let tol = if settings.method.is_adaptive() {
            settings.rtol.clamp(1e-12, 1e-10)
        } else {
            1e-10
        };
        InterpolantOptions {
            tol,
            max_pieces: 400,
        }
    }
}

/// Why no interpolant was built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum InterpolantError {
    #[error(
        "the interval [{lo}, {hi}] is not on the exit arc ({arc_lo:.6} < theta < {arc_hi:.6}): the map is defined only there"
    )]
    OffArc {
        lo: f64,
        hi: f64,
        arc_lo: f64,
        arc_hi: f64,
    },
    #[error(
        "the map could not be resolved to {tol:e} within {max_pieces} pieces (still unresolved near theta = {near:.9})"
    )]
    Unresolved {
        tol: f64,
        max_pieces: usize,
        near: f64,
    },
    #[error("a map evaluation failed while building the interpolant: {0}")]
    Cycle(#[from] SimError),
    #[error("interpolant options: {0}")]
    Options(&'static str),
}

/// One piece [a, b] (in θ − ψ): series, or a bracket left to integration.
#[derive(Clone, Debug)]
enum Piece {
    Series {
        a: f64,
        b: f64,
        /// θ' − ψ, chopped: what a plain iterate needs.
        map: Vec<f64>,
        /// The cycle's duration (slip + stick), chopped: what a transient
        /// iterate needs besides θ'.
        cycle: Vec<f64>,
        /// All [`FIELDS`] per coefficient index, unchopped.
        table: Vec<[f64; FIELDS]>,
    },
    Direct {
        a: f64,
        b: f64,
    },
}

impl Piece {
    fn ends(&self) -> (f64, f64) {
        match self {
            Piece::Series { a, b, .. } | Piece::Direct { a, b } => (*a, *b),
        }
    }
}

/// The tabulated event at one onset: what a [`SlipEvent`] needs besides
/// its onset time, and f'(θ).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tabulated {
    pub theta_next: f64,
    /// f'(θ), the derivative of the map's series.
    pub derivative: f64,
    pub stop: [f64; 2],
    pub accel_duration: f64,
    pub slip_duration: f64,
    pub peak_vr: f64,
    pub stick_duration: f64,
}

/// What the a-posteriori check measured.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Verification {
    /// Independent points compared with the direct map.
    pub points: usize,
    /// The largest |θ'_interpolant − θ'_direct| there, in radians.
    pub max_map_error: f64,
    /// The largest error of the other tabulated quantities (the stop, the
    /// durations, the peak speed) there, relative to max(1, |value|). They
    /// are tabulated on θ''s pieces and measured, not refined for.
    pub max_event_error: f64,
    /// Pieces that failed the check and were split again.
    pub failed: usize,
}

/// f on an interval of the exit arc, verified (see the module's doc).
#[derive(Clone, Debug)]
pub struct MapInterpolant {
    sim: Simulator,
    psi: f64,
    opts: InterpolantOptions,
    pieces: Vec<Piece>,
    /// The pieces' left ends, for the search.
    starts: Vec<f64>,
    verification: Verification,
    evaluations: usize,
    rhs_evals: u64,
}

/// A sample: the event's quantities in [`FIELDS`] order (slot 1 unused),
/// and whether the cycle restarted.
type Sample = ([f64; FIELDS], bool);

/// A piece being resolved: its ends and its samples so far.
struct Pending {
    a: f64,
    b: f64,
    samples: Vec<Sample>,
}

impl MapInterpolant {
    /// Builds f over [lo, hi] (radians, on the exit arc: lo < hi, both
    /// strictly inside it).
    pub fn build(
        sim: &Simulator,
        lo: f64,
        hi: f64,
        opts: InterpolantOptions,
    ) -> Result<Self, InterpolantError> {
        if !(opts.tol > 0.0 && opts.max_pieces >= 1) {
            return Err(InterpolantError::Options(
                "tol must be > 0 and max_pieces >= 1",
            ));
        }
        let p = sim.params();
        let (psi, _) = exit_arc(p.kappa, p.theta_nu);
        let mut me = MapInterpolant {
            sim: *sim,
            psi,
            opts,
            pieces: Vec::new(),
            starts: Vec::new(),
            verification: Verification::default(),
            evaluations: 0,
            rhs_evals: 0,
        };
        let (a, b) = me.check_interval(lo, hi)?;
        let new = me.resolve(a, b, opts.max_pieces)?;
        me.insert(new);
        Ok(me)
    }

    /// The interval in θ − ψ, refused when off the arc.
    fn check_interval(&self, lo: f64, hi: f64) -> Result<(f64, f64), InterpolantError> {
        let (a, b) = (lo - self.psi, hi - self.psi);
        let on = |u: f64| u.is_finite() && u > -FRAC_PI_2 && u < FRAC_PI_2;
        if !(on(a) && on(b) && a < b) {
            return Err(InterpolantError::OffArc {
                lo,
                hi,
                arc_lo: self.psi - FRAC_PI_2,
                arc_hi: self.psi + FRAC_PI_2,
            });
        }
        Ok((a, b))
    }

    /// Extends the interval to take in θ (with `pad` radians beyond it,
    /// kept inside the arc), within what is left of the piece budget.
    /// Nothing changes when it is refused.
    pub fn extend_to(&mut self, theta: f64, pad: f64) -> Result<(), InterpolantError> {
        let (lo, hi) = self.u_interval();
        let u = wrap_angle(theta - self.psi);
        if !(u > -FRAC_PI_2 && u < FRAC_PI_2) {
            return Err(InterpolantError::OffArc {
                lo: theta,
                hi: theta,
                arc_lo: self.psi - FRAC_PI_2,
                arc_hi: self.psi + FRAC_PI_2,
            });
        }
        let edge = FRAC_PI_2 - 1e-9;
        let (a, b) = if u < lo {
            ((u - pad).max(-edge).min(u), lo)
        } else if u >= hi {
            (hi, (u + pad).min(edge).max(u))
        } else {
            return Ok(());
        };
        let left = self.opts.max_pieces.saturating_sub(self.pieces.len());
        if left == 0 || !(b > a) {
            return Err(InterpolantError::Unresolved {
                tol: self.opts.tol,
                max_pieces: self.opts.max_pieces,
                near: theta,
            });
        }
        let new = self.resolve(a, b, left)?;
        self.insert(new);
        Ok(())
    }

    /// The interval covered, in θ − ψ.
    fn u_interval(&self) -> (f64, f64) {
        let lo = self.pieces.first().map_or(0.0, |p| p.ends().0);
        let hi = self.pieces.last().map_or(0.0, |p| p.ends().1);
        (lo, hi)
    }

    fn insert(&mut self, new: Vec<Piece>) {
        self.pieces.extend(new);
        self.pieces
            .sort_by(|x, y| x.ends().0.total_cmp(&y.ends().0));
        self.starts = self.pieces.iter().map(|p| p.ends().0).collect();
    }

    /// The interval covered, in θ (lo < hi; it may reach past ±π).
    pub fn interval(&self) -> (f64, f64) {
        let (lo, hi) = self.u_interval();
        (self.psi + lo, self.psi + hi)
    }

    /// How many pieces, and how many of them are series.
    pub fn pieces(&self) -> (usize, usize) {
        let series = self
            .pieces
            .iter()
            .filter(|p| matches!(p, Piece::Series { .. }))
            .count();
        (self.pieces.len(), series)
    }

    /// The largest number of coefficients of θ' on a piece.
    pub fn max_degree(&self) -> usize {
        self.pieces
            .iter()
            .map(|p| match p {
                Piece::Series { map, .. } => map.len().saturating_sub(1),
                Piece::Direct { .. } => 0,
            })
            .max()
            .unwrap_or(0)
    }

    /// What the a-posteriori check measured, over all pieces built.
    pub fn verification(&self) -> Verification {
        self.verification
    }

    /// Map evaluations spent building and checking.
    pub fn evaluations(&self) -> usize {
        self.evaluations
    }

    /// Right-hand-side evaluations those map evaluations cost.
    pub fn rhs_evals(&self) -> u64 {
        self.rhs_evals
    }

    /// The simulator (parameters and solver settings) it interpolates.
    pub fn simulator(&self) -> &Simulator {
        &self.sim
    }

    /// The tolerances it was built to.
    pub fn options(&self) -> InterpolantOptions {
        self.opts
    }

    /// The brackets of the jumps (and the other stretches) left to direct
    /// integration, in θ.
    pub fn direct_stretches(&self) -> Vec<(f64, f64)> {
        self.pieces
            .iter()
            .filter_map(|p| match p {
                Piece::Direct { a, b } => Some((self.psi + a, self.psi + b)),
                Piece::Series { .. } => None,
            })
            .collect()
    }

    /// The series piece holding θ and θ's place in it, in [−1, 1].
    #[inline]
    fn locate(&self, theta: f64) -> Option<(&Piece, f64)> {
        let u = wrap_angle(theta - self.psi);
        let i = self.starts.partition_point(|&s| s <= u).checked_sub(1)?;
        let piece = &self.pieces[i];
        let (a, b) = piece.ends();
        if u > b || matches!(piece, Piece::Direct { .. }) {
            return None;
        }
        Some((piece, (2.0 * u - a - b) / (b - a)))
    }

    /// f(θ) from the series; `None` outside the interval or in a stretch
    /// left to direct integration.
    #[inline]
    pub fn map(&self, theta: f64) -> Option<f64> {
        match self.locate(theta)? {
            (Piece::Series { map, .. }, x) => {
                Some(wrap_angle(self.psi + chebyshev::clenshaw(map, x)))
            }
            _ => None,
        }
    }

    /// f(θ) and the cycle's duration (slip + stick) from the series; `None`
    /// where [`Self::map`] is.
    #[inline]
    pub fn step(&self, theta: f64) -> Option<(f64, f64)> {
        match self.locate(theta)? {
            (Piece::Series { map, cycle, .. }, x) => Some((
                wrap_angle(self.psi + chebyshev::clenshaw(map, x)),
                chebyshev::clenshaw(cycle, x),
            )),
            _ => None,
        }
    }

    /// The tabulated event at θ and f'(θ); `None` where [`Self::map`] is.
    #[inline]
    pub fn event(&self, theta: f64) -> Option<Tabulated> {
        let (Piece::Series { map, table, .. }, x) = self.locate(theta)? else {
            return None;
        };
        let v = clenshaw_fields(table, x);
        Some(Tabulated {
            theta_next: wrap_angle(self.psi + chebyshev::clenshaw(map, x)),
            derivative: v[1],
            stop: [v[2], v[3]],
            accel_duration: v[4],
            slip_duration: v[5],
            peak_vr: v[6],
            stick_duration: v[7],
        })
    }

    /// The [`SlipEvent`] of the onset θ at time `onset_time`, from the
    /// tables: no integration, so `rhs_evals` and `steps` are 0.
    pub fn slip_event(&self, theta: f64, onset_time: f64) -> Option<(SlipEvent, f64)> {
        let t = self.event(theta)?;
        let kappa = self.sim.params().kappa;
        let onset = point_from_theta(kappa, theta);
        let (dx, dy) = (t.stop[0] - onset[0], t.stop[1] - onset[1]);
        let ev = SlipEvent {
            theta,
            onset_x: onset[0],
            onset_y: onset[1],
            onset_time,
            accel_duration: t.accel_duration,
            slip_duration: t.slip_duration,
            stop_x: t.stop[0],
            stop_y: t.stop[1],
            slip_distance: dx.hypot(dy),
            peak_vr: t.peak_vr,
            energy_released: elastic_energy(kappa, onset) - elastic_energy(kappa, t.stop),
            stick_duration: t.stick_duration,
            theta_next: t.theta_next,
            restarted: false,
            rhs_evals: 0,
            steps: 0,
        };
        Some((ev, t.derivative))
    }

    /// The samples of the events at the onsets u + ψ, computed in lanes.
    fn sample(&mut self, us: &[f64]) -> Result<Vec<Sample>, InterpolantError> {
        let tasks: Vec<_> = us.iter().map(|u| (&self.sim, self.psi + u, 0.0)).collect();
        self.evaluations += tasks.len();
        let psi = self.psi;
        let mut rhs = 0;
        let out = cycles_in_lanes(&tasks)
            .into_iter()
            .map(|r| {
                let e = r?;
                rhs += e.rhs_evals;
                Ok((
                    [
                        wrap_angle(e.theta_next - psi),
                        0.0,
                        e.stop_x,
                        e.stop_y,
                        e.accel_duration,
                        e.slip_duration,
                        e.peak_vr,
                        e.stick_duration,
                    ],
                    e.restarted,
                ))
            })
            .collect();
        self.rhs_evals += rhs;
        out
    }

    /// Resolves [a, b] (in θ − ψ) into verified pieces, at most `budget`.
    fn resolve(&mut self, a: f64, b: f64, budget: usize) -> Result<Vec<Piece>, InterpolantError> {
        let mut pending = vec![Pending {
            a,
            b,
            samples: Vec::new(),
        }];
        let mut done: Vec<Piece> = Vec::new();
        while !pending.is_empty() {
            if pending.len() + done.len() > budget {
                let narrowest = pending
                    .iter()
                    .min_by(|x, y| (x.b - x.a).total_cmp(&(y.b - y.a)))
                    .map_or(a, |p| 0.5 * (p.a + p.b));
                return Err(InterpolantError::Unresolved {
                    tol: self.opts.tol,
                    max_pieces: self.opts.max_pieces,
                    near: self.psi + narrowest,
                });
            }
            // Every pending piece's next points, in one batch of lanes.
            let mut us = Vec::new();
            let mut wanted = Vec::new();
            for p in &pending {
                let n = next_sampling(p.samples.len());
                let x = chebyshev::points(n);
                let new: Vec<usize> = if p.samples.is_empty() {
                    (0..n).collect()
                } else {
                    (1..n).step_by(2).collect()
                };
                for &j in &new {
                    us.push(0.5 * (p.a + p.b) + 0.5 * (p.b - p.a) * x[j]);
                }
                wanted.push(new.len());
            }
            let mut fresh = self.sample(&us)?.into_iter();
            let mut next = Vec::new();
            for (mut p, count) in pending.into_iter().zip(wanted) {
                let new: Vec<Sample> = fresh.by_ref().take(count).collect();
                p.samples = interleave(std::mem::take(&mut p.samples), new);
                self.settle(p, &mut done, &mut next)?;
            }
            pending = next;
            // The check at independent points: a piece that fails it is
            // split and resolved again.
            let mut checked = Vec::new();
            for piece in done.drain(..) {
                match self.check(&piece)? {
                    true => checked.push(piece),
                    false => {
                        let (pa, pb) = piece.ends();
                        let m = 0.5 * (pa + pb);
                        for (a, b) in [(pa, m), (m, pb)] {
                            pending.push(Pending {
                                a,
                                b,
                                samples: Vec::new(),
                            });
                        }
                    }
                }
            }
            done = checked;
        }
        Ok(done)
    }

    /// What becomes of a sampled pending piece: a series (to be checked),
    /// more points, or a split.
    fn settle(
        &mut self,
        p: Pending,
        done: &mut Vec<Piece>,
        next: &mut Vec<Pending>,
    ) -> Result<(), InterpolantError> {
        let n = p.samples.len();
        let restarts = p.samples.iter().any(|s| s.1);
        if !restarts && let Some(piece) = self.series(p.a, p.b, &p.samples) {
            done.push(piece);
            return Ok(());
        }
        if n < SAMPLINGS[SAMPLINGS.len() - 1] && !restarts {
            next.push(p);
            return Ok(());
        }
        if p.b - p.a < MIN_PIECE {
            done.push(Piece::Direct { a: p.a, b: p.b });
            return Ok(());
        }
        let x = chebyshev::points(n);
        let at = |j: usize| 0.5 * (p.a + p.b) + 0.5 * (p.b - p.a) * x[j];
        // A jump: one gap between neighbouring samples holds a quarter of
        // the variation, or the restart flag changes there.
        let gaps: Vec<f64> = p
            .samples
            .windows(2)
            .map(|w| {
                let flag = if w[0].1 != w[1].1 { 1.0 } else { 0.0 };
                (w[1].0[0] - w[0].0[0]).abs() + flag
            })
            .collect();
        let total: f64 = gaps.iter().sum();
        let (j, &largest) = gaps
            .iter()
            .enumerate()
            .max_by(|x, y| x.1.total_cmp(y.1))
            .unwrap_or((0, &0.0));
        let mut halves = Vec::new();
        if largest > 0.25 * total && largest > 1e3 * self.opts.tol {
            // Samples run from b down to a.
            let (jl, jr) =
                self.bracket_jump((at(j + 1), p.samples[j + 1]), (at(j), p.samples[j]))?;
            done.push(Piece::Direct { a: jl, b: jr });
            halves.extend([(p.a, jl), (jr, p.b)]);
        } else {
            let m = 0.5 * (p.a + p.b);
            halves.extend([(p.a, m), (m, p.b)]);
        }
        for (a, b) in halves {
            if b > a {
                next.push(Pending {
                    a,
                    b,
                    samples: Vec::new(),
                });
            }
        }
        Ok(())
    }

    /// Narrows [l, r] (in θ − ψ, with their samples) around the jump to
    /// [`JUMP_WIDTH`], keeping the half across which θ' changes most (or
    /// the restart flag changes).
    fn bracket_jump(
        &mut self,
        mut l: (f64, Sample),
        mut r: (f64, Sample),
    ) -> Result<(f64, f64), InterpolantError> {
        let change =
            |x: &Sample, y: &Sample| (x.0[0] - y.0[0]).abs() + if x.1 != y.1 { 10.0 } else { 0.0 };
        while r.0 - l.0 > JUMP_WIDTH {
            let m = 0.5 * (l.0 + r.0);
            if m <= l.0 || m >= r.0 {
                break;
            }
            let sm = self.sample(&[m])?[0];
            if change(&l.1, &sm) >= change(&sm, &r.1) {
                r = (m, sm);
            } else {
                l = (m, sm);
            }
        }
        Ok((l.0, r.0))
    }

    /// The series of [a, b] from its samples at `points(n)`, when every
    /// quantity is resolved.
    fn series(&self, a: f64, b: f64, samples: &[Sample]) -> Option<Piece> {
        let n = samples.len();
        let column = |f: usize| -> Vec<f64> { samples.iter().map(|s| s.0[f]).collect() };
        let c0 = chebyshev::coefficients(&column(0));
        if !chebyshev::resolved(&c0, self.opts.tol) {
            return None;
        }
        let mut table = vec![[0.0; FIELDS]; n];
        let mut d = chebyshev::derivative(&c0);
        let scale = 2.0 / (b - a);
        d.iter_mut().for_each(|x| *x *= scale);
        for k in 0..n {
            table[k][0] = c0[k];
            table[k][1] = d.get(k).copied().unwrap_or(0.0);
        }
        for f in 2..FIELDS {
            let c = chebyshev::coefficients(&column(f));
            for k in 0..n {
                table[k][f] = c[k];
            }
        }
        let cycle: Vec<f64> = table.iter().map(|c| c[5] + c[7]).collect();
        let big = samples
            .iter()
            .fold(1.0_f64, |m, s| m.max((s.0[5] + s.0[7]).abs()));
        Some(Piece::Series {
            a,
            b,
            map: chebyshev::chop(&c0, self.opts.tol),
            cycle: chebyshev::chop(&cycle, 1e-12 * big),
            table,
        })
    }

    /// Compares a piece with the direct map at [`CHECKS`]; says whether θ'
    /// is within the tolerance there, and records the errors of the pieces
    /// that pass.
    fn check(&mut self, piece: &Piece) -> Result<bool, InterpolantError> {
        let Piece::Series {
            a, b, map, table, ..
        } = piece
        else {
            return Ok(true);
        };
        let us: Vec<f64> = CHECKS.iter().map(|f| a + f * (b - a)).collect();
        let direct = self.sample(&us)?;
        let (mut ok, mut worst, mut worst_event) = (true, 0.0_f64, 0.0_f64);
        for (u, (s, restarted)) in us.iter().zip(direct) {
            let x = (2.0 * u - a - b) / (b - a);
            let v = clenshaw_fields(table, x);
            let map_err = (chebyshev::clenshaw(map, x) - s[0]).abs();
            let mut ev_err: f64 = 0.0;
            for f in 2..FIELDS {
                ev_err = ev_err.max((v[f] - s[f]).abs() / s[f].abs().max(1.0));
            }
            worst = worst.max(map_err);
            worst_event = worst_event.max(ev_err);
            ok &= !restarted && map_err <= self.opts.tol;
        }
        let vf = &mut self.verification;
        if ok {
            vf.points += CHECKS.len();
            vf.max_map_error = vf.max_map_error.max(worst);
            vf.max_event_error = vf.max_event_error.max(worst_event);
        } else {
            vf.failed += 1;
        }
        Ok(ok)
    }
}

/// The next number of points for a piece with `have` samples.
fn next_sampling(have: usize) -> usize {
    SAMPLINGS
        .iter()
        .copied()
        .find(|&n| n > have)
        .unwrap_or(SAMPLINGS[SAMPLINGS.len() - 1])
}

/// The samples at `points(2n − 1)` from those at `points(n)` (the even
/// indices) and the new ones (the odd).
fn interleave(old: Vec<Sample>, new: Vec<Sample>) -> Vec<Sample> {
    if old.is_empty() {
        return new;
    }
    let mut out = Vec::with_capacity(old.len() + new.len());
    let mut new = new.into_iter();
    for (i, s) in old.into_iter().enumerate() {
        if i > 0
            && let Some(m) = new.next()
        {
            out.push(m);
        }
        out.push(s);
    }
    out
}

/// Σ c_k T_k(x) for every field at once (one recurrence, [`FIELDS`] wide).
#[inline]
fn clenshaw_fields(c: &[[f64; FIELDS]], x: f64) -> [f64; FIELDS] {
    let (mut b1, mut b2) = ([0.0; FIELDS], [0.0; FIELDS]);
    let x2 = 2.0 * x;
    for ck in c.iter().skip(1).rev() {
        let mut b = [0.0; FIELDS];
        for f in 0..FIELDS {
            b[f] = ck[f] + x2 * b1[f] - b2[f];
        }
        b2 = b1;
        b1 = b;
    }
    let c0 = c.first().copied().unwrap_or([0.0; FIELDS]);
    let mut out = [0.0; FIELDS];
    for f in 0..FIELDS {
        out[f] = c0[f] + x * b1[f] - b2[f];
    }
    out
}
