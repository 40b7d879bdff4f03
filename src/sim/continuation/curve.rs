//! Two-parameter continuation of a period doubling or a fold: the curve
//! in the (λ₁, λ₂) plane where a p-cycle has the multiplier −1 or +1 (the
//! boundaries of the paper's Fig. 4).
//!
//! The unknowns are y = (θ, μ₁, μ₂), μᵢ = λᵢ/scaleᵢ, and the equations
//! G = 0 and m − m* = 0 (m* = −1 or +1). G's row of the Jacobian is exact
//! (chain rule along the cycle); the multiplier's row is a forward
//! difference of the exact multiplier (∂m needs second derivatives of f,
//! which the variational equations do not give): its error of about
//! 1e-3 relative slows Newton to a linear rate of that size, and the
//! residuals themselves, which decide convergence, are exact. The curve is
//! followed by pseudo-arclength along the Jacobian's null vector (the
//! cross product of its rows), both ways from a located start, until it
//! leaves the box of the two ranges.

pub use super::curve_types::{Curve, CurveKind, CurveOf, CurveOptions, CurvePoint};
use super::{ContParam, EvalError, Pace};
use crate::integrate::SolverSettings;
use crate::model::{Params, wrap_angle};
use crate::sim::Simulator;
use crate::sim::cycles::MAX_STEP;
use crate::sim::variational::D_THETA;
use nalgebra::{Matrix3, Vector3};

/// Creeping steps (below [`CREEP`] of the first) looked at by the noise
/// test.
const CREEP_POINTS: usize = 30;
/// A step this share of the first is creeping.
const CREEP: f64 = 1e-3;
/// The change of the multiplier aimed at over a difference step.
const FD_CHANGE: f64 = 1e-3;
/// The shortest and longest difference steps, in (θ, μ₁, μ₂).
const FD_MIN: f64 = 1e-11;
const FD_MAX: f64 = 1e-4;
/// Newton steps per point.
const NEWTON_STEPS: usize = 12;
/// Residuals that end Newton at once (the multiplier's accuracy where the
/// map is smooth).
const TIGHT_RESIDUAL: f64 = 1e-10;
/// A gradient of the multiplier (in (θ, μ₁, μ₂)) beyond which a failing
/// corrector is put down to a jump of f nearby, not to the curve ending.
const STEEP: f64 = 1e4;
/// The tangent's turn aimed at per step, and the most allowed (radians).
const TURN: f64 = 0.1;
const MAX_TURN: f64 = 0.3;

/// A point or direction in (θ, μ₁, μ₂).
pub(super) type V3 = Vector3<f64>;

/// a/|a|, or `None` for a zero or non-finite a.
pub(super) fn normalize(a: V3) -> Option<V3> {
    let n = a.norm();
    (n > 0.0 && n.is_finite()).then(|| a / n)
}

/// a, turned to point the way `prev` does.
fn orient(a: V3, prev: &V3) -> V3 {
    if a.dot(prev) < 0.0 { -a } else { a }
}

/// What every evaluation along a curve shares.
pub(super) struct Ctx<'a> {
    /// Where the walk may pause (after each map evaluation).
    pub(super) pace: &'a Pace,
    base: Params,
    settings: SolverSettings,
    params: [ContParam; 2],
    period: usize,
    kind: CurveKind,
    opts: &'a CurveOptions,
    scale: [f64; 2],
    pub(super) evals: u64,
    /// The difference steps for ∂m, per component of (θ, μ₁, μ₂).
    fd: [f64; 3],
    /// |∇m| at the last evaluated system, for the end's diagnosis.
    steepness: f64,
}

/// The Jacobian's two rows, the residual, and the evaluation at a point.
pub(super) type System = ([V3; 2], [f64; 2], Ev);

/// G, the multiplier, and G's gradient in (θ, μ₁, μ₂).
pub(super) struct Ev {
    /// G.
    pub(super) g: f64,
    /// The multiplier.
    pub(super) m: f64,
    /// G's gradient.
    pub(super) grad: V3,
}

impl<'a> Ctx<'a> {
    /// The context of a curve of `kind` in `params` over `opts`'s box.
    pub(super) fn new(pace: &'a Pace, of: CurveOf, opts: &'a CurveOptions) -> Self {
        let CurveOf {
            base,
            settings,
            params,
            period,
            kind,
        } = of;
        Ctx {
            pace,
            base,
            settings,
            params,
            period,
            kind,
            opts,
            scale: opts.scale(),
            evals: 0,
            fd: [opts.fd_step; 3],
            steepness: 0.0,
        }
    }

    /// λ per unit of μ, for each parameter.
    pub(super) fn scale(&self) -> [f64; 2] {
        self.scale
    }

    fn params_at(&self, y: &V3) -> Params {
        let p = self.params[0].set(&self.base, y[1] * self.scale[0]);
        self.params[1].set(&p, y[2] * self.scale[1])
    }

    async fn eval(&mut self, y: &V3) -> Result<Ev, EvalError> {
        let sim = Simulator::new(self.params_at(y), self.settings).map_err(EvalError::Sim)?;
        let mut th = y[0];
        let (mut m, mut d1, mut d2) = (1.0, 0.0, 0.0);
        for _ in 0..self.period {
            if sim.check_onset(th).is_err() {
                return Err(EvalError::OffArc { theta: th });
            }
            let dirs = [
                D_THETA,
                self.params[0].direction(),
                self.params[1].direction(),
            ];
            let (ev, d, _) = sim.cycle_partials(th, 0.0, dirs).map_err(EvalError::Sim)?;
            self.evals += 1;
            self.pace.piece().await;
            let [d_theta, p1, p2] =
                d.map_err(|reason| EvalError::NotDifferentiable { theta: th, reason })?;
            d1 = d_theta * d1 + p1;
            d2 = d_theta * d2 + p2;
            m *= d_theta;
            th = ev.theta_next;
        }
        let g = wrap_angle(th - y[0]);
        let grad = V3::new(m - 1.0, d1 * self.scale[0], d2 * self.scale[1]);
        if g.is_finite() && grad.iter().all(|x| x.is_finite()) {
            Ok(Ev { g, m, grad })
        } else {
            Err(EvalError::NonFinite)
        }
    }

    /// The Jacobian's two rows and the residual at y.
    pub(super) async fn system(&mut self, y: &V3) -> Result<System, EvalError> {
        let e = self.eval(y).await?;
        let mut dm = V3::zeros();
        for i in 0..3 {
            dm[i] = self.dm(y, i, e.m).await?;
        }
        self.steepness = dm.norm();
        Ok(([e.grad, dm], [e.g, e.m - self.kind.target()], e))
    }

    /// ∂m/∂yᵢ by a central difference whose step is chosen so that m
    /// changes by about [`FD_CHANGE`] over it: much less and m's own error
    /// (~1e-8 relative) dominates the quotient, much more and m's
    /// curvature does (near a grazing, m ~ 1/√d changes by orders of
    /// magnitude over a fixed step). The step is kept per component from
    /// point to point and re-chosen at most twice here. Where one side
    /// leaves the map's smooth part, the other side's one-sided quotient.
    async fn dm(&mut self, y: &V3, i: usize, m0: f64) -> Result<f64, EvalError> {
        let mut h = self.fd[i];
        let mut d = 0.0;
        for _ in 0..3 {
            d = self.quotient(y, i, h, m0).await?;
            let want = if d != 0.0 {
                (FD_CHANGE / d.abs()).clamp(FD_MIN, FD_MAX)
            } else {
                FD_MAX
            };
            let close = want > 0.25 * h && want < 4.0 * h;
            h = want;
            if close {
                break;
            }
        }
        self.fd[i] = h;
        Ok(d)
    }

    async fn quotient(&mut self, y: &V3, i: usize, h: f64, m0: f64) -> Result<f64, EvalError> {
        let (mut zp, mut zm) = (*y, *y);
        zp[i] += h;
        zm[i] -= h;
        let plus = self.eval(&zp).await;
        match (plus, self.eval(&zm).await) {
            (Ok(a), Ok(b)) => Ok((a.m - b.m) / (2.0 * h)),
            (Ok(a), Err(_)) => Ok((a.m - m0) / h),
            (Err(_), Ok(b)) => Ok((m0 - b.m) / h),
            (Err(e), Err(_)) => Err(e),
        }
    }

    /// Newton on (G, m − m*, t·(y − pred)) = 0 from `pred`: the point, y
    /// and the tangent there, the Newton steps taken; or why it failed.
    /// Each step solves the bordered 3×3 system by LU with partial
    /// pivoting: G's row and m's row can differ by orders of magnitude
    /// (a multiplier's gradient near a grazing), which Cramer's rule's
    /// cofactors do not survive as well.
    async fn correct(&mut self, pred: V3, t: V3) -> Result<Corrected, Failure> {
        let mut y = pred;
        let mut best: Option<(f64, Corrected)> = None;
        for k in 0..NEWTON_STEPS {
            let (rows, r, e) = self.system(&y).await.map_err(Failure::Eval)?;
            let residual = r[0].abs().max(r[1].abs());
            let point = CurvePoint {
                lambda: [y[1] * self.scale[0], y[2] * self.scale[1]],
                theta: wrap_angle(y[0]),
                multiplier: e.m,
            };
            let here = (point, y, rows[0].cross(&rows[1]), k + 1);
            let a = Matrix3::from_rows(&[rows[0].transpose(), rows[1].transpose(), t.transpose()]);
            let rhs = V3::new(r[0], r[1], t.dot(&(y - pred)));
            let dy = match a.lu().solve(&rhs) {
                Some(dy) if dy.iter().all(|v| v.is_finite()) => dy,
                _ => return Err(Failure::Singular),
            };
            let size = dy.iter().map(|v| v.abs()).sum::<f64>();
            let within = residual <= self.opts.residual_tol;
            if residual <= TIGHT_RESIDUAL || (within && size <= self.opts.newton_tol) {
                return Ok(here);
            }
            if within && best.as_ref().is_none_or(|b| residual < b.0) {
                best = Some((residual, here));
            }
            if dy.iter().any(|v| v.abs() > MAX_STEP) {
                break;
            }
            y -= dy;
        }
        // Where m's own error keeps Newton from its tolerance, the best
        // iterate within the residual bound.
        best.map(|b| b.1).ok_or(Failure::NoConvergence)
    }

    fn inside(&self, p: &CurvePoint) -> bool {
        (0..2).all(|i| {
            let [a, b] = self.opts.bounds[i];
            p.lambda[i] >= a.min(b) && p.lambda[i] <= a.max(b)
        })
    }

    /// Follows the curve from y along `t` until it leaves the box or fails
    /// (a cancel asked once per point).
    pub(super) async fn follow(&mut self, mut y: V3, mut t: V3) -> (Vec<CurvePoint>, String) {
        let mut out: Vec<CurvePoint> = Vec::new();
        // The last creeping points in (θ, μ₁, μ₂), for the noise test.
        let mut creep: Vec<V3> = Vec::new();
        let mut h = self.opts.h0;
        let mut grow = true;
        loop {
            if self.pace.cancelled().await {
                return (out, "cancelled".into());
            }
            if out.len() >= self.opts.max_points {
                let n = out.len();
                return (out, format!("after {n} points"));
            }
            let pred = y + h * t;
            let step = self.correct(pred, t).await.and_then(|(p, yn, tn, k)| {
                let tn = orient(normalize(tn).ok_or(Failure::Singular)?, &t);
                let far = (yn - pred).norm() > 0.5 * h + 1e-12;
                if far || tn.dot(&t) < MAX_TURN.cos() {
                    return Err(Failure::Turned);
                }
                Ok((p, yn, tn, k))
            });
            match step {
                Ok((p, yn, tn, newton)) => {
                    out.push(p);
                    let turn = tn.dot(&t).clamp(-1.0, 1.0).acos();
                    (y, t) = (yn, tn);
                    if !self.inside(&p) {
                        return (out, "left the box of the two ranges".into());
                    }
                    if h < CREEP * self.opts.h0 {
                        creep.push(y);
                        if let Some(why) = noise(&creep) {
                            return (out, why);
                        }
                    } else {
                        creep.clear();
                    }
                    // The next step: a turn of about TURN per step, and
                    // shorter after a slow corrector.
                    let by_turn = if turn > 0.0 { TURN / turn } else { 1.5 };
                    let by_newton = if newton > 4 { 0.7 } else { 1.5 };
                    let factor = by_turn.min(by_newton).clamp(0.5, 1.5);
                    if grow || factor < 1.0 {
                        h = (h * factor).min(self.opts.h_max);
                    }
                    grow = true;
                }
                Err(why) => {
                    h *= 0.5;
                    grow = false;
                    if h < self.opts.h_min {
                        let at = out.last().map_or(String::new(), |p: &CurvePoint| {
                            format!(" after ({}, {})", p.lambda[0], p.lambda[1])
                        });
                        let what = match why {
                            Failure::Eval(e) if e.is_border() => {
                                format!("a border: a cycle point reaches the map's edge {e}")
                            }
                            Failure::Eval(e) => format!("the map failed: {e}"),
                            // Next to a (near) jump of f the multiplier's
                            // gradient explodes, and its error with it.
                            _ if self.steepness > STEEP => format!(
                                "the multiplier turns too steep to follow (|grad m| = {:.1e}: f jumps or nearly jumps next to the cycle); the corrector fails even at the shortest step",
                                self.steepness
                            ),
                            _ => "the corrector failed even at the shortest step".into(),
                        };
                        return (out, format!("{what}{at}"));
                    }
                }
            }
        }
    }
}

/// Why a step failed.
enum Failure {
    /// G or m could not be evaluated (a border, or the integration).
    Eval(EvalError),
    /// The Jacobian, with the tangent, is singular.
    Singular,
    /// Newton did not reach the residual bound.
    NoConvergence,
    /// The corrected point is far from the prediction, or the tangent
    /// turned by more than [`MAX_TURN`].
    Turned,
}

/// A corrected point, y, the tangent there, and the Newton steps taken.
type Corrected = (CurvePoint, V3, V3, usize);

/// Whether the creeping points are noise: [`CREEP_POINTS`] of them whose
/// net displacement in (θ, μ₁, μ₂) is under a third of their path, i.e.
/// points that step back and forth (the multiplier's error as large as
/// its change over a step). A cusp of the curve's shadow in (λ₁, λ₂) is
/// no such thing: in (θ, μ₁, μ₂) the curve is smooth there and its points
/// advance, so it is followed through.
fn noise(creep: &[V3]) -> Option<String> {
    if creep.len() < CREEP_POINTS {
        return None;
    }
    let w = &creep[creep.len() - CREEP_POINTS..];
    let path: f64 = w.windows(2).map(|p| (p[1] - p[0]).norm()).sum();
    let net = (w[CREEP_POINTS - 1] - w[0]).norm();
    if net < path / 3.0 {
        Some(format!(
            "noise: {CREEP_POINTS} steps below {CREEP:e} of the first that step back and forth (the multiplier's error is as large as its change over a step)"
        ))
    } else if creep.len() >= 10 * CREEP_POINTS {
        Some(format!(
            "{} steps in a row below {CREEP:e} of the first",
            creep.len()
        ))
    } else {
        None
    }
}

/// The curve's start: `base` with λ₁ at `start`'s, and y there.
pub(super) fn origin(
    base: &Params,
    params: [ContParam; 2],
    start: &super::SpecialPoint,
    opts: &CurveOptions,
) -> (Params, V3) {
    let base = params[0].set(base, start.lambda);
    let scale = opts.scale();
    let y0 = V3::new(
        start.theta,
        start.lambda / scale[0],
        params[1].get(&base) / scale[1],
    );
    (base, y0)
}

impl<'a> Ctx<'a> {
    /// A copy to follow the other direction with, its evaluations counted
    /// apart, pausing at `pace`.
    pub(super) fn fork<'b>(&self, pace: &'b Pace) -> Ctx<'b>
    where
        'a: 'b,
    {
        Ctx {
            pace,
            evals: 0,
            ..*self
        }
    }

    /// The unit tangent at y0 (the cross product of the Jacobian's rows),
    /// or `None` where it has none.
    pub(super) async fn tangent(&mut self, y0: &V3) -> Option<V3> {
        let (rows, _, _) = self.system(y0).await.ok()?;
        normalize(rows[0].cross(&rows[1]))
    }

    /// The curve when there is no tangent at its start.
    pub(super) fn no_tangent(&self) -> Curve {
        Curve {
            kind: self.kind,
            period: self.period,
            params: self.params,
            points: Vec::new(),
            ends: ["no tangent at the start".into(), String::new()],
            map_evals: self.evals,
            generalised_flips: Vec::new(),
        }
    }

    /// The curve from its two halves, `back` (followed along −t0) and
    /// `fwd`, each with why it ended, through `start`; on a PD curve, its
    /// generalised flips.
    pub(super) async fn finish(
        &mut self,
        start: &super::SpecialPoint,
        back: (Vec<CurvePoint>, String),
        fwd: (Vec<CurvePoint>, String),
    ) -> Curve {
        let ((back, why_back), (fwd, why_fwd)) = (back, fwd);
        let mut points: Vec<CurvePoint> = back.into_iter().rev().collect();
        points.push(CurvePoint {
            lambda: [start.lambda, self.params[1].get(&self.base)],
            theta: wrap_angle(start.theta),
            multiplier: start.multiplier,
        });
        points.extend(fwd);
        let mut evals = self.evals;
        let generalised_flips = if self.kind == CurveKind::PeriodDoubling {
            let (base, settings) = (self.base, self.settings);
            super::flip::generalised_flips_paced(
                self.pace,
                &base,
                &settings,
                self.params,
                self.period,
                &points,
                &mut evals,
            )
            .await
        } else {
            Vec::new()
        };
        Curve {
            kind: self.kind,
            period: self.period,
            params: self.params,
            points,
            ends: [why_back, why_fwd],
            map_evals: evals,
            generalised_flips,
        }
    }
}
