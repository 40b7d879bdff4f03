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
use crate::sim::cycles::{CycleFailure, CycleOptions, MAX_STEP, solve_cycle};
use nalgebra::{Matrix2, Vector2};

/// A residual |G| (radians) that the corrector leaves at a step below the
/// location accuracy only where f^p jumps or its slope diverges: a smooth
/// G changes there by less than 1e-8 even with a multiplier of 1e3.
const JUMP: f64 = 1e-4;

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
#[derive(Clone, Debug, PartialEq)]
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
#[derive(Clone, Debug, PartialEq)]
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
}

/// Why a branch ended.
#[derive(Clone, Debug, PartialEq)]
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
#[derive(Clone, Debug, PartialEq)]
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

    /// Why and where the branch ended, as a clause ("reached the end of
    /// the range, at theta-nu = 1.2").
    pub fn stop_message(&self) -> String {
        let at = self
            .points
            .last()
            .map(|p| format!("{} = {}", self.param.name(), p.lambda))
            .unwrap_or_default();
        let why = match &self.stop {
            Stop::Reached => "reached the end of the range".to_string(),
            Stop::Returned => "came back to the start of the range".to_string(),
            Stop::Merged => format!(
                "turned where it merges with the P{} cycle it doubles from",
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
struct Pt {
    x: [f64; 2],
    e: super::Eval,
}

impl Pt {
    fn lambda(&self, scale: f64) -> f64 {
        self.x[1] * scale
    }
    /// The unit tangent ⟂ ∇G = (m − 1, scale·G_λ), oriented along `prev`.
    fn tangent(&self, scale: f64, prev: [f64; 2]) -> [f64; 2] {
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
enum Fail {
    Eval(EvalError),
    NoConvergence(f64),
}

impl Fail {
    fn describe(&self) -> String {
        match self {
            Fail::Eval(e) => e.to_string(),
            Fail::NoConvergence(r) => {
                format!("Newton's corrector did not converge (residual {r:e})")
            }
        }
    }
}

struct Ctx<'a> {
    prob: &'a Problem,
    opts: &'a ContOptions,
    evals: u64,
    /// Why the last step failed (what a branch that ends there ends at).
    last_fail: Option<Fail>,
}

impl Ctx<'_> {
    /// Newton on (G = 0, t·(x − pred) = 0) from `pred`. Returns the last
    /// evaluated point once the step from it is below the tolerance (so the
    /// point's cycle and multiplier are its own).
    fn correct(&mut self, pred: [f64; 2], t: [f64; 2]) -> Result<Pt, Fail> {
        let s = self.opts.scale;
        let mut x = pred;
        let mut last_g = f64::INFINITY;
        let g_floor = 0.5 * CycleOptions::for_settings(&self.prob.settings).tol;
        for _ in 0..self.opts.max_newton {
            let e = self
                .prob
                .eval(x[0], x[1] * s, &mut self.evals)
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

    fn point(&self, p: &Pt, tol: f64) -> BranchPoint {
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
    fn flip(&mut self, p: &Pt) -> Option<super::Flip> {
        let lambda = p.lambda(self.opts.scale);
        let scale = self.opts.scale;
        let g_lambda = p.e.g_lambda;
        super::flip_at(self.prob, lambda, p.x[0], g_lambda, scale, &mut self.evals).ok()
    }

    fn special(&self, kind: SpecialKind, p: &Pt, note: String) -> SpecialPoint {
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
    fn locate(
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
        for _ in 0..80 {
            if closed(sa, sb) {
                break;
            }
            let mut s = sb - fb * (sb - sa) / (fb - fa);
            if !(s > sa.min(sb) && s < sa.max(sb)) {
                s = 0.5 * (sa + sb);
            }
            let pred = [a.x[0] + s * t[0], a.x[1] + s * t[1]];
            let Ok(c) = self.correct(pred, t) else {
                break;
            };
            let fc = test(c.e.multiplier);
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
struct Located {
    /// The closest point to the zero that was corrected.
    pt: Pt,
    /// Whether the test function is zero there (to [`M_ACCURACY`]), rather
    /// than changing sign across a jump or pole of the multiplier.
    real: bool,
    /// |test| there.
    off: f64,
}

/// Follows the p-cycle through `seed` at λ = `from` towards λ = `to`
/// (see the module notes). Fails only when no cycle is found at the start;
/// a branch that fails later ends with [`Stop::Failed`] and keeps what it
/// has. `cancel` is polled once per point.
pub fn continue_branch(
    prob: &Problem,
    from: f64,
    to: f64,
    seed: f64,
    opts: &ContOptions,
    cancel: &dyn Fn() -> bool,
) -> Result<Branch, CycleFailure> {
    continue_branch_reporting(prob, from, to, seed, opts, cancel, &mut |_| {})
}

/// A branch being followed: where it is, and what it has found.
struct Walk<'a, 'b> {
    ctx: Ctx<'a>,
    from: f64,
    to: f64,
    /// +1 when `to` ≥ `from`.
    dir: f64,
    /// The last corrected point and the unit tangent there.
    cur: Pt,
    t: [f64; 2],
    /// Points closer than this are one (for the minimal period).
    tol: f64,
    points: Vec<BranchPoint>,
    special: Vec<SpecialPoint>,
    on_special: &'b mut dyn FnMut(&SpecialPoint),
}

/// What one step of the walk came to.
enum Step {
    /// A point was added: go on (with a longer step if `grow`).
    Next,
    /// The step failed and was halved: try again.
    Retry,
    /// The branch ends.
    Stop(Stop),
}

/// [`continue_branch`], calling `on_special` with each PD, fold, border
/// and jump as it is located (for progress lines).
pub fn continue_branch_reporting(
    prob: &Problem,
    from: f64,
    to: f64,
    seed: f64,
    opts: &ContOptions,
    cancel: &dyn Fn() -> bool,
    on_special: &mut dyn FnMut(&SpecialPoint),
) -> Result<Branch, CycleFailure> {
    let mut walk = Walk::start(prob, from, to, seed, opts, on_special)?;
    let mut h = opts.h0;
    let mut grow = true;
    let stop = loop {
        if cancel() {
            break Stop::Cancelled;
        }
        if walk.points.len() >= opts.max_points {
            break Stop::MaxPoints;
        }
        match walk.step(h) {
            Step::Next => {
                if grow {
                    h = (1.5 * h).min(opts.h_max);
                }
                grow = true;
            }
            Step::Retry => {
                h *= 0.5;
                grow = false;
                if h < opts.h_min {
                    break walk.fail();
                }
            }
            Step::Stop(stop) => break stop,
        }
    };
    Ok(walk.finish(stop))
}

impl<'a, 'b> Walk<'a, 'b> {
    /// The cycle through `seed`, solved and corrected at λ = `from`
    /// exactly.
    fn start(
        prob: &'a Problem,
        from: f64,
        to: f64,
        seed: f64,
        opts: &'a ContOptions,
        on_special: &'b mut dyn FnMut(&SpecialPoint),
    ) -> Result<Self, CycleFailure> {
        let sim = prob.sim(from)?;
        let mut cyc_opts = CycleOptions::for_settings(&prob.settings);
        cyc_opts.tol = cyc_opts.tol.min(opts.newton_tol);
        let cycle = solve_cycle(&sim, seed, prob.period, &cyc_opts)?;
        let mut ctx = Ctx {
            prob,
            opts,
            evals: cycle.map_evals,
            last_fail: None,
        };
        let scale = opts.scale;
        let dir = if to >= from { 1.0 } else { -1.0 };
        let cur = ctx
            .correct([cycle.points[0], from / scale], [0.0, 1.0])
            .map_err(|f| start_failure(f, seed, opts))?;
        let t = cur.tangent(scale, [0.0, dir]);
        // Points closer than 100× the solver's tolerance are one point (as
        // `solve_cycle` decides the minimal period).
        let tol = CycleOptions::for_settings(&prob.settings).tol;
        let mut first = ctx.point(&cur, tol);
        // Exactly the λ asked for, not μ·scale rounded.
        first.lambda = from;
        Ok(Walk {
            ctx,
            from,
            to,
            dir,
            cur,
            t,
            tol,
            points: vec![first],
            special: Vec::new(),
            on_special,
        })
    }

    fn scale(&self) -> f64 {
        self.ctx.opts.scale
    }

    /// Predicts a step h along the tangent, corrects it, clips it to the
    /// range, detects the special points crossed, and records them.
    fn step(&mut self, h: f64) -> Step {
        let Some((n, tn)) = self.predict_correct(h) else {
            return Step::Retry;
        };
        let (n, last) = match self.clip(n) {
            Ok(v) => v,
            Err(()) => return Step::Retry,
        };
        let found = self.detect(&n);
        let mut pd = false;
        for (kind, p, note) in &found {
            let mut sp = self.ctx.special(*kind, p, note.clone());
            if *kind == SpecialKind::PeriodDoubling {
                sp.flip = self.ctx.flip(p);
            }
            (self.on_special)(&sp);
            self.special.push(sp);
            self.points.push(self.ctx.point(p, self.tol));
            pd |= *kind == SpecialKind::PeriodDoubling;
        }
        let mut np = self.ctx.point(&n, self.tol);
        if let Some(target) = last {
            np.lambda = target;
        }
        self.points.push(np);
        // λ turned without a fold: an even-period branch passes the tip of
        // the pitchfork where it is born from the half-period cycle, and
        // would come back as the same cycle with its halves swapped.
        let turned =
            self.t[1] * tn[1] < 0.0 && found.is_empty() && self.ctx.prob.period.is_multiple_of(2);
        self.cur = n;
        self.t = tn;
        if let Some(target) = last {
            return Step::Stop(if target == self.to {
                Stop::Reached
            } else {
                Stop::Returned
            });
        }
        if turned {
            return Step::Stop(Stop::Merged);
        }
        if pd && self.ctx.opts.stop_at_pd {
            return Step::Stop(Stop::PeriodDoubling);
        }
        Step::Next
    }

    /// The corrected point a step h along the tangent, and its tangent;
    /// `None` when the corrector fails, lands more than half a step from
    /// the prediction, or the tangent turns by more than ~18°.
    fn predict_correct(&mut self, h: f64) -> Option<(Pt, [f64; 2])> {
        let (cur, t, scale) = (&self.cur, self.t, self.scale());
        let pred = [cur.x[0] + h * t[0], cur.x[1] + h * t[1]];
        match self.ctx.correct(pred, t) {
            Ok(n) => {
                let tn = n.tangent(scale, t);
                let far = (n.x[0] - pred[0]).hypot(n.x[1] - pred[1]) > 0.5 * h + 1e-12;
                if far || tn[0] * t[0] + tn[1] * t[1] < 0.95 {
                    self.ctx.last_fail = Some(Fail::NoConvergence(n.e.g.abs()));
                    None
                } else {
                    Some((n, tn))
                }
            }
            Err(f) => {
                self.ctx.last_fail = Some(f);
                None
            }
        }
    }

    /// `n`, or the point at the range's end (or its start, after a fold)
    /// when `n` is past it, corrected at exactly that λ, with that λ.
    fn clip(&mut self, n: Pt) -> Result<(Pt, Option<f64>), ()> {
        let scale = self.scale();
        let at = n.lambda(scale);
        let past_end = self.dir * (at - self.to) >= 0.0;
        let behind = self.dir * (at - self.from) < 0.0;
        if !(past_end || behind) {
            return Ok((n, None));
        }
        let target = if past_end { self.to } else { self.from };
        let l0 = self.cur.lambda(scale);
        let w = (target - l0) / (at - l0);
        let th = self.cur.x[0] + w * (n.x[0] - self.cur.x[0]);
        match self.ctx.correct([th, target / scale], [0.0, 1.0]) {
            Ok(c) => Ok((c, Some(target))),
            Err(_) => {
                self.ctx.last_fail = Some(Fail::NoConvergence(f64::NAN));
                Err(())
            }
        }
    }

    /// The PD and fold crossings between the current point and `n`,
    /// located and in order along the step; a crossing that is no zero of
    /// m ± 1 is a [`SpecialKind::Jump`].
    fn detect(&mut self, n: &Pt) -> Vec<(SpecialKind, Pt, String)> {
        let (cur, t) = (self.cur.clone(), self.t);
        let (m0, m1) = (cur.e.multiplier, n.e.multiplier);
        let along = |p: &Pt| (p.x[0] - cur.x[0]) * t[0] + (p.x[1] - cur.x[1]) * t[1];
        let dist = along(n);
        let mut found: Vec<(SpecialKind, Pt, String)> = Vec::new();
        let tests: [(SpecialKind, f64); 2] = [
            (SpecialKind::PeriodDoubling, -1.0),
            (SpecialKind::Fold, 1.0),
        ];
        for (kind, at) in tests {
            if (m0 - at) * (m1 - at) >= 0.0 {
                continue;
            }
            let l = self.ctx.locate(&cur, n, t, dist, |m| m - at);
            if l.real {
                found.push((kind, l.pt, String::new()));
            } else {
                let note = format!(
                    "m goes from {m0:.6} to {m1:.6} across the step but stays |m {} 1| >= {:.2e} away to the location accuracy: a jump or pole of m, not a {}",
                    if at < 0.0 { '+' } else { '-' },
                    l.off,
                    kind.name()
                );
                found.push((SpecialKind::Jump, l.pt, note));
            }
        }
        found.sort_by(|a, b| along(&a.1).total_cmp(&along(&b.1)));
        found
    }

    /// The end when no step down to the shortest works: a border where a
    /// cycle point meets the map's edge or f^p jumps, else a failure.
    fn fail(&mut self) -> Stop {
        let here = self.ctx.special(SpecialKind::End, &self.cur, String::new());
        let note = match self.ctx.last_fail.take() {
            Some(Fail::Eval(e)) if e.is_border() => {
                format!("a cycle point reaches the map's edge {e}")
            }
            // G cannot change by this much over a step shorter than the
            // location accuracy unless f^p jumps there.
            Some(Fail::NoConvergence(r)) if r > JUMP => format!(
                "f^p jumps or its slope diverges: |G| = {r:.1e} a step below the location accuracy away"
            ),
            Some(Fail::NoConvergence(r)) if r.is_nan() => {
                return Stop::Failed("the cycle at the range's end did not converge".into());
            }
            Some(f) => return Stop::Failed(f.describe()),
            None => return Stop::Failed("no step succeeded".into()),
        };
        let border = SpecialPoint {
            kind: SpecialKind::Border,
            note,
            ..here
        };
        (self.on_special)(&border);
        self.special.push(border);
        Stop::Border
    }

    /// The branch, its end point added.
    fn finish(mut self, stop: Stop) -> Branch {
        let note = match &stop {
            Stop::Reached => "the end of the range".to_string(),
            Stop::Returned => "back at the start of the range".to_string(),
            Stop::Merged => "merged with the half-period cycle".to_string(),
            Stop::PeriodDoubling => "its first period doubling".to_string(),
            Stop::Border => "a border".to_string(),
            Stop::Failed(why) => why.clone(),
            Stop::MaxPoints => "the most points".to_string(),
            Stop::Cancelled => "cancelled".to_string(),
        };
        let mut last_point = self.ctx.special(SpecialKind::End, &self.cur, note);
        if let Some(p) = self.points.last() {
            last_point.lambda = p.lambda;
        }
        self.special.push(last_point);
        Branch {
            param: self.ctx.prob.param,
            period: self.ctx.prob.period,
            points: self.points,
            special: self.special,
            stop,
            map_evals: self.ctx.evals,
        }
    }
}

/// A start that Newton could not correct, as the cycle solver's failure.
fn start_failure(f: Fail, seed: f64, opts: &ContOptions) -> CycleFailure {
    match f {
        Fail::Eval(EvalError::Sim(e)) => CycleFailure::Sim(e),
        Fail::Eval(e) => CycleFailure::Discontinuity {
            theta: match e {
                EvalError::NotDifferentiable { theta, .. } | EvalError::OffArc { theta } => theta,
                _ => seed,
            },
        },
        Fail::NoConvergence(r) => CycleFailure::NoConvergence {
            iterations: opts.max_newton,
            residual: r,
        },
    }
}
