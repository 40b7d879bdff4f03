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

mod build;
pub mod chebyshev;
mod choice;
mod extend;
mod layout;
mod stepper;

use std::f64::consts::FRAC_PI_2;

use super::{SimError, Simulator, SlipEvent};
use crate::model::{elastic_energy, point_from_theta, wrap_angle};

pub use build::InterpolantBuild;
pub use choice::MapChoice;
pub use extend::{Cover, Extension, Reach};
pub use stepper::{InterpolantSummary, MIN_DIRECT, MapTally, MapUsed, Stepper, StepperBuild};

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
pub(crate) const FIELDS: usize = 8;

/// Where a finished build put its pieces, in u = θ − ψ (ψ the arc's
/// centre), increasing: each series' ends and the samples it took, and
/// each stretch left to integration (a jump's bracket, a rough stretch)
/// with 0. A build at nearby parameters starts from it
/// ([`InterpolantBuild::start_from`]): every piece is then decided and
/// checked exactly as in a build from nothing, so only the work changes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Layout(pub Vec<(f64, f64, usize)>);

/// What the interpolant is asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterpolantOptions {
    /// The largest error in θ' allowed against the direct map, in radians.
    pub tol: f64,
    /// The most pieces (jump brackets included) the whole interval may take.
    pub max_pieces: usize,
    /// The most map evaluations construction and extensions may spend (a
    /// caller that would otherwise integrate a few thousand iterates caps
    /// what a refusal can cost); `usize::MAX` for no cap.
    pub max_evaluations: usize,
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
            max_evaluations: usize::MAX,
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
    #[error(
        "the map could not be resolved to {tol:e} within {max_evaluations} map evaluations (still unresolved near theta = {near:.9})"
    )]
    OverBudget {
        tol: f64,
        max_evaluations: usize,
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
    /// Whether pieces left unresolved by the budgets become stretches of
    /// direct integration instead of refusing the build
    /// ([`Self::build_lenient`]).
    lenient: bool,
}

/// A sample: the event's quantities in [`FIELDS`] order (slot 1 unused),
/// and whether the cycle restarted.
type Sample = ([f64; FIELDS], bool);

/// The interval in θ − ψ that `onsets` span (their later two thirds, where
/// an orbit has settled most), padded by `pad_fraction` of its length and
/// at least 1e-3, kept inside the exit arc of centre ψ: (lo, hi, pad).
/// `None` without onsets.
pub(crate) fn onset_span(psi: f64, onsets: &[f64], pad_fraction: f64) -> Option<(f64, f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &th in &onsets[onsets.len() / 3..] {
        let u = wrap_angle(th - psi);
        (lo, hi) = (lo.min(u), hi.max(u));
    }
    if !(lo <= hi) {
        return None;
    }
    let pad = (pad_fraction * (hi - lo)).max(1e-3);
    let edge = FRAC_PI_2 - 1e-9;
    Some(((lo - pad).max(-edge), (hi + pad).min(edge), pad))
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
        Self::build_counting(sim, lo, hi, opts, &mut (0, 0))
    }

    /// [`Self::build`], but where the budgets run out (or no series
    /// converges, next to a point where f' is unbounded) the pieces still
    /// unresolved are left to direct integration instead of refusing the
    /// build: for a caller that encloses f there by sampling
    /// (`sim::attractors::arc`).
    pub fn build_lenient(
        sim: &Simulator,
        lo: f64,
        hi: f64,
        opts: InterpolantOptions,
    ) -> Result<Self, InterpolantError> {
        let mut spent = (0, 0);
        Self::build_with(sim, lo, hi, opts, &mut spent, true)
    }

    /// [`Self::build`], adding the map evaluations and the right-hand-side
    /// evaluations spent to `spent`, also when the build is refused (a
    /// refusal may have cost many).
    pub fn build_counting(
        sim: &Simulator,
        lo: f64,
        hi: f64,
        opts: InterpolantOptions,
        spent: &mut (u64, u64),
    ) -> Result<Self, InterpolantError> {
        Self::build_with(sim, lo, hi, opts, spent, false)
    }

    fn build_with(
        sim: &Simulator,
        lo: f64,
        hi: f64,
        opts: InterpolantOptions,
        spent: &mut (u64, u64),
        lenient: bool,
    ) -> Result<Self, InterpolantError> {
        InterpolantBuild::start(sim, lo, hi, opts, lenient)?.run_counting(spent)
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

    /// Where its pieces lie, for a build at nearby parameters to start
    /// from ([`InterpolantBuild::start_from`]).
    pub fn layout(&self) -> Layout {
        Layout(
            self.pieces
                .iter()
                .map(|p| match p {
                    Piece::Series { a, b, table, .. } => (*a, *b, table.len()),
                    Piece::Direct { a, b } => (*a, *b, 0),
                })
                .collect(),
        )
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

/// One piece of a [`MapInterpolant`] as the cell graph reads it
/// (`sim::attractors::arc`), in u = θ − ψ.
#[derive(Clone, Copy, Debug)]
pub(crate) enum PieceView<'a> {
    /// f(u) − ψ = Σ `map[k]` T_k(x) on [a, b], x = (2u − a − b)/(b − a);
    /// f'(u) = Σ `table[k][1]` T_k(x).
    Series {
        a: f64,
        b: f64,
        map: &'a [f64],
        derivative: &'a [[f64; FIELDS]],
    },
    /// A jump's bracket or a rough stretch, left to direct integration.
    Direct { a: f64, b: f64 },
}

impl MapInterpolant {
    /// The centre ψ of the exit arc the pieces are built around.
    pub fn psi(&self) -> f64 {
        self.psi
    }

    /// The pieces in order along the arc, in u = θ − ψ.
    pub(crate) fn piece_views(&self) -> impl Iterator<Item = PieceView<'_>> {
        self.pieces.iter().map(|p| match p {
            Piece::Series {
                a, b, map, table, ..
            } => PieceView::Series {
                a: *a,
                b: *b,
                map,
                derivative: table,
            },
            Piece::Direct { a, b } => PieceView::Direct { a: *a, b: *b },
        })
    }
}
