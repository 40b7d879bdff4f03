//! One-parameter continuation of a p-cycle by pseudo-arclength, with its
//! period doublings, folds and borders located on the way.
//!
//! The unknowns are x = (θ, μ) with μ = λ/scale, so that a step of the
//! arclength moves θ (radians) and λ (its range) by comparable amounts.
//! A step predicts x + h·t along the unit tangent t ⟂ ∇G and corrects by
//! Newton on (G = 0, t·(x − x_pred) = 0), whose 2×2 Jacobian is exact
//! (G_θ = m − 1, G_μ = scale·G_λ) and solved by LU with partial pivoting. Folds are passed because the arclength,
//! not λ, is the parameter.
//!
//! Special points are located by Illinois (regula falsi that halves the
//! retained end's weight) on the arclength s between two branch points:
//! each trial is a corrected point on the hyperplane t·(x − x_a) = s, and
//! the test function is m + 1 (PD) or m − 1 (fold), with m exact. Newton on
//! the augmented system (G = 0, m ± 1 = 0) would need ∂m/∂θ and ∂m/∂λ,
//! second derivatives of f that the variational equations do not give; a
//! bracket on an exact test function converges superlinearly and cannot
//! leave the branch. A border is where the corrector stops finding a
//! differentiable cycle: the step is halved down to a length below the
//! location accuracy.

use super::{ContParam, EvalError, Problem};
use crate::model::wrap_angle;
use crate::sim::cycles::{CycleOptions, MAX_STEP};
use nalgebra::{Matrix2, Vector2};

/// A residual |G| (radians) that the corrector leaves at a step below the
/// location accuracy only where f^p jumps or its slope diverges: a smooth
/// G changes there by less than 1e-8 even with a multiplier of 1e3.
pub(super) const JUMP: f64 = 1e-4;

/// How the branch is followed and its special points located.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContOptions {
    /// λ units per unit of μ (the λ of one unit of arclength).
    pub scale: f64,
    /// The first step, in arclength.
    pub h0: f64,
    /// The longest step.
    pub h_max: f64,
    /// A step shorter than this that still fails ends the branch.
    pub h_min: f64,
    /// The corrector's convergence: the last Newton step's size in (θ, μ).
    pub newton_tol: f64,
    /// The most Newton steps per point.
    pub max_newton: usize,
    /// Special points are located to this, in λ.
    pub locate_tol: f64,
    /// The most branch points.
    pub max_points: usize,
    /// Stop at the first period doubling (a cascade's levels).
    pub stop_at_pd: bool,
}

impl ContOptions {
    /// Steps scaled to the range [from, to]: the first 1/200 of it, none
    /// longer than 1/20; a corrector at the integrator's tolerance (as
    /// `oneblock cycle` uses) and special points located to 1e-10 in λ
    /// (1e-10 relative for a parameter far from 1).
    pub fn for_range(settings: &crate::integrate::SolverSettings, from: f64, to: f64) -> Self {
        let scale = (to - from).abs().max(1e-300);
        let locate_tol = 1e-10 * from.abs().max(to.abs()).clamp(1.0, 1e6);
        let cycle_tol = CycleOptions::for_settings(settings).tol;
        ContOptions {
            scale,
            h0: 5e-3,
            h_max: 5e-2,
            h_min: 0.1 * locate_tol / scale,
            newton_tol: cycle_tol.min(0.1 * locate_tol / scale),
            max_newton: 10,
            locate_tol,
            max_points: 5000,
            stop_at_pd: false,
        }
    }
}

/// One computed point of a branch.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BranchPoint {
    /// The parameter's value.
    pub lambda: f64,
    /// The cycle's points θ₀ … θ_{p−1}, in (−π, π].
    pub points: Vec<f64>,
    /// Π f'(θᵢ).
    pub multiplier: f64,
    /// |multiplier| < 1.
    pub stable: bool,
    /// The smallest shift that maps the points onto themselves.
    pub minimal_period: usize,
}

/// The start of the note of a branch's end at the doubling it was born in.
pub const MERGED_NOTE: &str = "merged with the P";

/// What a special point is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum SpecialKind {
    /// A period doubling: the multiplier crosses −1.
    PeriodDoubling,
    /// A fold (saddle-node): the multiplier crosses +1 and λ turns.
    Fold,
    /// A cycle point reaches a jump of f, a restart, or the exit arc's edge.
    Border,
    /// The multiplier changes sign about −1 or +1 across a jump or a pole
    /// of m (the cycle passes a point where f' jumps or diverges): no
    /// bifurcation, since m never equals ∓1 there. Kept so that the sign
    /// change is told as what it is.
    Jump,
    /// Where the branch ends (its range's end, or where it stopped).
    End,
}

impl SpecialKind {
    /// The name in points.csv: PD, fold, border, jump, end.
    pub fn name(self) -> &'static str {
        match self {
            SpecialKind::PeriodDoubling => "PD",
            SpecialKind::Fold => "fold",
            SpecialKind::Border => "border",
            SpecialKind::Jump => "jump",
            SpecialKind::End => "end",
        }
    }
}

/// A located special point.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SpecialPoint {
    /// Which.
    pub kind: SpecialKind,
    /// The period of the branch it is on.
    pub period: usize,
    /// The located parameter value.
    pub lambda: f64,
    /// A point of the cycle there (θ₀).
    pub theta: f64,
    /// The multiplier there.
    pub multiplier: f64,
    /// For a border or an end: why the branch ends there.
    pub note: String,
    /// For a period doubling: the flip's normal form (its criticality and
    /// the born cycle's amplitude), when its derivatives could be taken.
    pub flip: Option<super::Flip>,
}

impl SpecialPoint {
    /// "supercritical", "subcritical" or "undecided" for a PD with its
    /// normal form; empty otherwise.
    pub fn criticality_name(&self) -> &'static str {
        self.flip.map_or("", |f| f.criticality().name())
    }

    /// Whether it was located (a PD, fold, jump, border, or the end of a
    /// branch at the doubling it was born in), rather than being the last
    /// computed point: a located point is known to ~1e-10 in λ, a
    /// computed one is exactly where it was computed.
    pub fn is_located(&self) -> bool {
        self.kind != SpecialKind::End || self.note.starts_with(MERGED_NOTE)
    }
}

/// Why a branch ended.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Stop {
    /// It reached the end of its range.
    Reached,
    /// It came back to the start of its range (past a fold).
    Returned,
    /// Its cycle's halves merged: λ turned where the p-cycle meets the
    /// p/2-cycle it doubled from (a period doubling of that one).
    Merged,
    /// At its first period doubling ([`ContOptions::stop_at_pd`]).
    PeriodDoubling,
    /// At a border (see the border point's note).
    Border,
    /// The continuation failed: why.
    Failed(String),
    /// After [`ContOptions::max_points`] points.
    MaxPoints,
    /// The caller cancelled.
    Cancelled,
}

/// A continued branch.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Branch {
    /// The parameter varied.
    pub param: ContParam,
    /// The period.
    pub period: usize,
    /// The computed points, in order along the branch.
    pub points: Vec<BranchPoint>,
    /// The located special points, in order along the branch; the last is
    /// its end.
    pub special: Vec<SpecialPoint>,
    /// Why it ended.
    pub stop: Stop,
    /// Map evaluations spent (each with its derivatives).
    pub map_evals: u64,
}

impl Branch {
    /// The special points of one kind.
    pub fn of_kind(&self, kind: SpecialKind) -> impl Iterator<Item = &SpecialPoint> {
        self.special.iter().filter(move |s| s.kind == kind)
    }

    /// Its own period doublings: those of its period (a branch that met
    /// its birth also lists the half-period cycle's doubling it ends at).
    pub fn doublings(&self) -> impl Iterator<Item = &SpecialPoint> {
        self.of_kind(SpecialKind::PeriodDoubling)
            .filter(move |s| s.period == self.period)
    }

    /// Why and where the branch ended, as a clause ("reached the end of
    /// the range, at theta-nu = 1.2").
    pub fn stop_message(&self) -> String {
        // The end point's λ: the last computed point's, or the doubling
        // of the cycle it was born from where it met it.
        let at = self
            .special
            .last()
            .filter(|s| s.kind == SpecialKind::End)
            .map(|s| {
                if s.is_located() {
                    // To what it is known (10 significant digits).
                    format!("{:.9e}", s.lambda).parse().unwrap_or(s.lambda)
                } else {
                    s.lambda
                }
            })
            .or(self.points.last().map(|p| p.lambda))
            .map(|l| format!("{} = {}", self.param.name(), l))
            .unwrap_or_default();
        let why = match &self.stop {
            Stop::Reached => "reached the end of the range".to_string(),
            Stop::Returned => "came back to the start of the range".to_string(),
            Stop::Merged => format!(
                "met the P{} cycle it is born from, at that cycle's doubling",
                self.period / 2
            ),
            Stop::PeriodDoubling => "stopped at its first period doubling".to_string(),
            Stop::Border => {
                let note = self
                    .of_kind(SpecialKind::Border)
                    .last()
                    .map(|b| b.note.clone())
                    .unwrap_or_default();
                format!("ended at a border: {note}")
            }
            Stop::Failed(why) => format!("failed: {why}"),
            Stop::MaxPoints => format!("stopped after {} points", self.points.len()),
            Stop::Cancelled => "cancelled".to_string(),
        };
        format!("{why}, at {at}")
    }
}

/// A corrected point: (θ, μ) and G's values there.
#[derive(Clone, Debug)]
pub(super) struct Pt {
    pub(super) x: [f64; 2],
    pub(super) e: super::Eval,
}

impl Pt {
    pub(super) fn lambda(&self, scale: f64) -> f64 {
        self.x[1] * scale
    }
    /// The unit tangent ⟂ ∇G = (m − 1, scale·G_λ), oriented along `prev`.
    pub(super) fn tangent(&self, scale: f64, prev: [f64; 2]) -> [f64; 2] {
        let t = [-scale * self.e.g_lambda, self.e.multiplier - 1.0];
        let n = t[0].hypot(t[1]);
        let t = if n > 0.0 { [t[0] / n, t[1] / n] } else { prev };
        if t[0] * prev[0] + t[1] * prev[1] < 0.0 {
            [-t[0], -t[1]]
        } else {
            t
        }
    }
}

/// Why a correction failed.
pub(super) enum Fail {
    Eval(EvalError),
    NoConvergence(f64),
    /// The corrector landed on a cycle of this smaller minimal period
    /// (past a jump of f^p, where the branch's cycle does not go on).
    OtherCycle(usize),
}

impl Fail {
    pub(super) fn describe(&self) -> String {
        match self {
            Fail::Eval(e) => e.to_string(),
            Fail::NoConvergence(r) => {
                format!("Newton's corrector did not converge (residual {r:e})")
            }
            Fail::OtherCycle(q) => {
                format!("every step lands on a P{q} cycle, not this one")
            }
        }
    }
}

pub(super) struct Ctx<'a> {
    /// Where the walk may pause (after each map evaluation).
    pub(super) pace: &'a super::Pace,
    pub(super) prob: &'a Problem,
    pub(super) opts: &'a ContOptions,
    pub(super) evals: u64,
    /// Why the last step failed (what a branch that ends there ends at).
    pub(super) last_fail: Option<Fail>,
}

impl Ctx<'_> {
    /// Newton on (G = 0, t·(x − pred) = 0) from `pred`. Returns the last
    /// evaluated point once the step from it is below the tolerance (so the
    /// point's cycle and multiplier are its own).
    pub(super) async fn correct(&mut self, pred: [f64; 2], t: [f64; 2]) -> Result<Pt, Fail> {
        let s = self.opts.scale;
        let mut x = pred;
        let mut last_g = f64::INFINITY;
        let g_floor = 0.5 * CycleOptions::for_settings(&self.prob.settings).tol;
        for _ in 0..self.opts.max_newton {
            let e = self
                .prob
                .eval_paced(self.pace, x[0], x[1] * s, &mut self.evals)
                .await
                .map_err(Fail::Eval)?;
            let r = Vector2::new(e.g, t[0] * (x[0] - pred[0]) + t[1] * (x[1] - pred[1]));
            // LU with partial pivoting: G's row (m − 1, scale·G_λ) can be
            // orders of magnitude larger or smaller than the tangent's.
            let jac = Matrix2::new(e.multiplier - 1.0, s * e.g_lambda, t[0], t[1]);
            let dx = match jac.lu().solve(&r) {
                Some(d) if d.iter().all(|v| v.is_finite()) => [d[0], d[1]],
                _ => return Err(Fail::NoConvergence(e.g.abs())),
            };
            // Or G at half the solver's tolerance: G's own error is about
            // that (a P32 cycle sums 32 integrations), and where m is near
            // 1 (a doubled cycle just born) it keeps the step above any
            // tighter bound.
            if dx[0].abs() + dx[1].abs() <= self.opts.newton_tol || e.g.abs() <= g_floor {
                return Ok(Pt { x, e });
            }
            if dx[0].abs() > MAX_STEP || dx[1].abs() > MAX_STEP || e.g.abs() > 4.0 * last_g {
                return Err(Fail::NoConvergence(e.g.abs()));
            }
            last_g = e.g.abs();
            x = [x[0] - dx[0], x[1] - dx[1]];
        }
        Err(Fail::NoConvergence(last_g))
    }

    pub(super) fn point(&self, p: &Pt, tol: f64) -> BranchPoint {
        let m = p.e.multiplier;
        let pts = &p.e.points;
        let n = pts.len();
        let distinct = 1e2 * tol;
        let minimal_period = (1..=n)
            .filter(|q| n.is_multiple_of(*q))
            .find(|&q| (0..n - q).all(|i| wrap_angle(pts[i + q] - pts[i]).abs() <= distinct))
            .unwrap_or(n);
        BranchPoint {
            lambda: p.lambda(self.opts.scale),
            points: pts.iter().map(|&t| wrap_angle(t)).collect(),
            multiplier: m,
            stable: m.abs() < 1.0,
            minimal_period,
        }
    }

    /// The flip's normal form at the located doubling `p` (see
    /// [`super::flip`]); `None` where f^p has no derivatives around it.
    ///
    /// `samples` are (λ, m) at the branch points the location corrected,
    /// the step's ends first: dm/dλ is their slope at the doubling
    /// ([`super::branch_slope`]).
    pub(super) async fn flip(&mut self, p: &Pt, samples: &[(f64, f64)]) -> Option<super::Flip> {
        let lambda = p.lambda(self.opts.scale);
        let dm_dlambda = super::branch_slope(samples, lambda, self.prob.period)?;
        // At the tolerance the point was located with (refine.rs), its
        // centre evaluated again there (the location may have kept the
        // coarse point): G and M at θ* and at θ* ± H from one solver, and
        // the born cycle grown from the same λ*.
        let fine = super::refine::tighter(&self.prob.settings).map(|settings| Problem {
            settings,
            ..*self.prob
        });
        let (prob, at) = match &fine {
            Some(f) => (f, None),
            None => (self.prob, Some(&p.e)),
        };
        super::flip::flip_paced(
            self.pace,
            prob,
            lambda,
            p.x[0],
            at,
            dm_dlambda,
            &mut self.evals,
        )
        .await
        .ok()
    }

    pub(super) fn special(&self, kind: SpecialKind, p: &Pt, note: String) -> SpecialPoint {
        SpecialPoint {
            kind,
            period: self.prob.period,
            lambda: p.lambda(self.opts.scale),
            theta: wrap_angle(p.x[0]),
            multiplier: p.e.multiplier,
            note,
            flip: None,
        }
    }

    /// The zero of `test` between `a` (s = 0) and `b` (s = h) along the
    /// tangent `t` at `a`, by Illinois on s (see the module notes), and
    /// whether it is a zero at all: see [`Located`].
    pub(super) async fn locate(
        &mut self,
        a: &Pt,
        b: &Pt,
        t: [f64; 2],
        h: f64,
        test: impl Fn(f64) -> f64,
    ) -> Located {
        let s_len = self.opts.scale;
        let (mut sa, mut fa) = (0.0, test(a.e.multiplier));
        let (mut sb, mut fb) = (h, test(b.e.multiplier));
        // The test's secant slope over the step (the final bracket's is
        // m's noise over a closed bracket).
        let slope = (fb - fa) / h;
        // The test's true values at the bracket's ends (Illinois halves
        // the retained end's weight, not its value).
        let (mut ta, mut tb) = (fa, fb);
        let mut best = if fa.abs() < fb.abs() {
            a.clone()
        } else {
            b.clone()
        };
        let mut side = 0i8;
        // The bracket is closed in arclength (in λ's units), not in λ: at
        // a fold λ barely moves along the branch while m still does.
        let closed = |sa: f64, sb: f64| (sb - sa).abs() * s_len <= self.opts.locate_tol;
        let mut samples = vec![
            (a.lambda(s_len), a.e.multiplier),
            (b.lambda(s_len), b.e.multiplier),
        ];
        for _ in 0..80 {
            if closed(sa, sb) {
                break;
            }
            let mut s = sb - fb * (sb - sa) / (fb - fa);
            if !(s > sa.min(sb) && s < sa.max(sb)) {
                s = 0.5 * (sa + sb);
            }
            let pred = [a.x[0] + s * t[0], a.x[1] + s * t[1]];
            let Ok(c) = self.correct(pred, t).await else {
                break;
            };
            let fc = test(c.e.multiplier);
            samples.push((c.lambda(s_len), c.e.multiplier));
            if fc.abs() < test(best.e.multiplier).abs() {
                best = c;
            }
            if fc.abs() <= 1e-13 {
                break;
            }
            if (fc > 0.0) == (fb > 0.0) {
                (sb, fb, tb) = (s, fc, fc);
                if side == 1 {
                    fa *= 0.5;
                }
                side = 1;
            } else {
                (sa, fa, ta) = (s, fc, fc);
                if side == -1 {
                    fb *= 0.5;
                }
                side = -1;
            }
        }
        let off = test(best.e.multiplier).abs();
        // A smooth test function is within M_ACCURACY of zero at the
        // located point, or changes by no more than that across the final
        // bracket (a steep m located to the λ accuracy); across a jump or
        // a pole both ends keep their distance from zero.
        let real = off <= M_ACCURACY || (closed(sa, sb) && (ta - tb).abs() <= M_ACCURACY);
        Located {
            pt: best,
            real,
            off,
            samples,
            slope,
        }
    }
}

/// The largest |m ∓ 1| a located PD or fold is reported with (or the
/// largest change of m across its λ interval of the location accuracy):
/// the multiplier is exact to about 1e-9, and Illinois on a smooth test
/// function converges superlinearly to |m ∓ 1| ≲ 1e-10. A sign change
/// that ends further from zero is a jump or a pole of m.
pub const M_ACCURACY: f64 = 1e-5;

/// A zero of a test function located between two branch points.
pub(super) struct Located {
    /// The closest point to the zero that was corrected.
    pub(super) pt: Pt,
    /// Whether the test function is zero there (to [`M_ACCURACY`]), rather
    /// than changing sign across a jump or pole of the multiplier.
    pub(super) real: bool,
    /// |test| there.
    pub(super) off: f64,
    /// (λ, m) at every branch point the location corrected, the bracket's
    /// first ends first (for m's slope at the zero).
    pub(super) samples: Vec<(f64, f64)>,
    /// The test's secant slope in arclength across the step it was
    /// located on.
    pub(super) slope: f64,
}
