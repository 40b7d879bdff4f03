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

use super::branch::SpecialPoint;
use super::{ContParam, EvalError};
use crate::integrate::SolverSettings;
use crate::model::{Params, wrap_angle};
use crate::sim::Simulator;
use crate::sim::cycles::MAX_STEP;
use crate::sim::variational::D_THETA;

/// How many consecutive creeping steps end a direction.
const CREEP_POINTS: usize = 30;

/// Which curve.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum CurveKind {
    /// Period doubling: multiplier −1.
    PeriodDoubling,
    /// Fold: multiplier +1.
    Fold,
}

impl CurveKind {
    /// The multiplier on the curve.
    pub fn target(self) -> f64 {
        match self {
            CurveKind::PeriodDoubling => -1.0,
            CurveKind::Fold => 1.0,
        }
    }

    /// The command line's name: pd or fold.
    pub fn name(self) -> &'static str {
        match self {
            CurveKind::PeriodDoubling => "pd",
            CurveKind::Fold => "fold",
        }
    }
}

/// How the curve is followed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveOptions {
    /// [λ₁ range, λ₂ range]: the box the curve is followed in.
    pub bounds: [[f64; 2]; 2],
    /// The first step, in arclength of (θ, μ₁, μ₂) (μᵢ scaled by the box).
    pub h0: f64,
    /// The longest step.
    pub h_max: f64,
    /// A shorter step that still fails ends that direction.
    pub h_min: f64,
    /// The corrector's convergence: the last Newton step's size …
    pub newton_tol: f64,
    /// … or both |G| and |m − m*| at most this (the multiplier's own
    /// error, ~1e-7 where the map is stiff, can keep the step above any
    /// tighter bound).
    pub residual_tol: f64,
    /// The forward difference's step for the multiplier's gradient.
    pub fd_step: f64,
    /// The most points in each direction.
    pub max_points: usize,
}

impl CurveOptions {
    /// Steps of 1/200 to 1/50 of the box, a corrector to 1e-10 (scaled)
    /// or residuals of 1e-6, at most 2000 points each way.
    pub fn for_box(bounds: [[f64; 2]; 2]) -> Self {
        CurveOptions {
            bounds,
            h0: 5e-3,
            h_max: 2e-2,
            h_min: 1e-7,
            newton_tol: 1e-10,
            residual_tol: 1e-6,
            fd_step: 1e-6,
            max_points: 2000,
        }
    }

    fn scale(&self) -> [f64; 2] {
        self.bounds.map(|b| (b[1] - b[0]).abs().max(1e-300))
    }
}

/// One point of a curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvePoint {
    /// (λ₁, λ₂).
    pub lambda: [f64; 2],
    /// A point θ₀ of the cycle there.
    pub theta: f64,
    /// The multiplier (−1 or +1 to the corrector's accuracy).
    pub multiplier: f64,
}

/// A continued curve: one polyline.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// PD or fold.
    pub kind: CurveKind,
    /// The cycle's period.
    pub period: usize,
    /// (λ₁, λ₂).
    pub params: [ContParam; 2],
    /// The points in order along the curve.
    pub points: Vec<CurvePoint>,
    /// Why each end of the polyline ended (first end, last end).
    pub ends: [String; 2],
    /// Map evaluations spent.
    pub map_evals: u64,
}

struct Ctx<'a> {
    base: Params,
    settings: SolverSettings,
    params: [ContParam; 2],
    period: usize,
    kind: CurveKind,
    opts: &'a CurveOptions,
    scale: [f64; 2],
    evals: u64,
}

/// The Jacobian's two rows, the residual, and the evaluation at a point.
type System = ([[f64; 3]; 2], [f64; 2], Ev);

/// G, the multiplier, and G's gradient in (θ, μ₁, μ₂).
struct Ev {
    g: f64,
    m: f64,
    grad: [f64; 3],
}

impl Ctx<'_> {
    fn params_at(&self, y: &[f64; 3]) -> Params {
        let p = self.params[0].set(&self.base, y[1] * self.scale[0]);
        self.params[1].set(&p, y[2] * self.scale[1])
    }

    fn eval(&mut self, y: &[f64; 3]) -> Result<Ev, EvalError> {
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
            let [d_theta, p1, p2] =
                d.map_err(|reason| EvalError::NotDifferentiable { theta: th, reason })?;
            d1 = d_theta * d1 + p1;
            d2 = d_theta * d2 + p2;
            m *= d_theta;
            th = ev.theta_next;
        }
        let g = wrap_angle(th - y[0]);
        let grad = [m - 1.0, d1 * self.scale[0], d2 * self.scale[1]];
        if g.is_finite() && grad.iter().all(|x| x.is_finite()) {
            Ok(Ev { g, m, grad })
        } else {
            Err(EvalError::NonFinite)
        }
    }

    /// The Jacobian's two rows and the residual at y.
    fn system(&mut self, y: &[f64; 3]) -> Result<System, EvalError> {
        let e = self.eval(y)?;
        let eta = self.opts.fd_step;
        let mut dm = [0.0; 3];
        for (i, d) in dm.iter_mut().enumerate() {
            let mut z = *y;
            z[i] += eta;
            *d = (self.eval(&z)?.m - e.m) / eta;
        }
        Ok(([e.grad, dm], [e.g, e.m - self.kind.target()], e))
    }

    /// Newton on (G, m − m*, t·(y − pred)) = 0 from `pred`.
    fn correct(&mut self, pred: [f64; 3], t: [f64; 3]) -> Option<(CurvePoint, [f64; 3], [f64; 3])> {
        let mut y = pred;
        for _ in 0..12 {
            let (rows, r, e) = self.system(&y).ok()?;
            let a = [rows[0], rows[1], t];
            let rhs = [r[0], r[1], dot(&t, &sub(&y, &pred))];
            let dy = solve3(&a, &rhs)?;
            let size = dy.iter().map(|v| v.abs()).sum::<f64>();
            let small = r[0].abs().max(r[1].abs()) <= self.opts.residual_tol;
            if size <= self.opts.newton_tol || small {
                let point = CurvePoint {
                    lambda: [y[1] * self.scale[0], y[2] * self.scale[1]],
                    theta: wrap_angle(y[0]),
                    multiplier: e.m,
                };
                return Some((point, y, cross(&rows[0], &rows[1])));
            }
            if dy.iter().any(|v| v.abs() > MAX_STEP) {
                return None;
            }
            y = sub(&y, &dy);
        }
        None
    }

    fn inside(&self, p: &CurvePoint) -> bool {
        (0..2).all(|i| {
            let [a, b] = self.opts.bounds[i];
            p.lambda[i] >= a.min(b) && p.lambda[i] <= a.max(b)
        })
    }

    /// Follows the curve from y along `t` until it leaves the box or fails.
    fn follow(
        &mut self,
        mut y: [f64; 3],
        mut t: [f64; 3],
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> (Vec<CurvePoint>, String) {
        let mut out = Vec::new();
        let mut h = self.opts.h0;
        let mut grow = true;
        let mut creeping = 0;
        loop {
            if cancel() {
                return (out, "cancelled".into());
            }
            if out.len() >= self.opts.max_points {
                let n = out.len();
                return (out, format!("after {n} points"));
            }
            let pred = [y[0] + h * t[0], y[1] + h * t[1], y[2] + h * t[2]];
            let step = self.correct(pred, t).and_then(|(p, yn, tn)| {
                let tn = orient(normalize(tn)?, &t);
                let far = norm(&sub(&yn, &pred)) > 0.5 * h + 1e-12;
                (!far && dot(&tn, &t) > 0.95).then_some((p, yn, tn))
            });
            match step {
                Some((p, yn, tn)) => {
                    out.push(p);
                    // Steps that stay a hundred times shorter than the
                    // first: a cusp, or a stretch where the multiplier's
                    // error is as large as its change over a step.
                    creeping = if h < 1e-2 * self.opts.h0 {
                        creeping + 1
                    } else {
                        0
                    };
                    if creeping >= CREEP_POINTS {
                        return (
                            out,
                            format!(
                                "{CREEP_POINTS} steps in a row below 1e-2 of the first (a cusp, or the multiplier's error as large as its change over a step)"
                            ),
                        );
                    }
                    if !self.inside(&p) {
                        return (out, "left the box of the two ranges".into());
                    }
                    (y, t) = (yn, tn);
                    if grow {
                        h = (1.5 * h).min(self.opts.h_max);
                    }
                    grow = true;
                }
                None => {
                    h *= 0.5;
                    grow = false;
                    if h < self.opts.h_min {
                        let at = out.last().map_or(String::new(), |p: &CurvePoint| {
                            format!(" after ({}, {})", p.lambda[0], p.lambda[1])
                        });
                        return (
                            out,
                            format!(
                                "the corrector failed even at the shortest step{at} (a border, or the curve ends)"
                            ),
                        );
                    }
                }
            }
        }
    }
}

/// Follows the `kind` curve of the p-cycle in (λ₁, λ₂) = `params` through
/// `start`, a special point of that kind located on a branch in λ₁ with
/// λ₂ at `base`'s value (see the module notes), the two directions on
/// two threads. `cancel` is polled once per point.
#[allow(clippy::too_many_arguments)]
pub fn continue_curve(
    base: &Params,
    settings: &SolverSettings,
    params: [ContParam; 2],
    period: usize,
    kind: CurveKind,
    start: &SpecialPoint,
    opts: &CurveOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Curve {
    let base = params[0].set(base, start.lambda);
    let scale = opts.scale();
    let mut ctx = Ctx {
        base,
        settings: *settings,
        params,
        period,
        kind,
        opts,
        scale,
        evals: 0,
    };
    let y0 = [
        start.theta,
        start.lambda / scale[0],
        params[1].get(&base) / scale[1],
    ];
    let first = ctx
        .system(&y0)
        .ok()
        .and_then(|(rows, _, _)| normalize(cross(&rows[0], &rows[1])));
    let Some(t0) = first else {
        return Curve {
            kind,
            period,
            params,
            points: Vec::new(),
            ends: ["no tangent at the start".into(), String::new()],
            map_evals: ctx.evals,
        };
    };
    // The two directions are independent: one thread each.
    let mut other = Ctx { evals: 0, ..ctx };
    let ((back, why_back), (fwd, why_fwd)) = std::thread::scope(|s| {
        let job = s.spawn(|| {
            let r = other.follow(y0, [-t0[0], -t0[1], -t0[2]], cancel);
            (r, other.evals)
        });
        let fwd = ctx.follow(y0, t0, cancel);
        let (back, evals) = job
            .join()
            .unwrap_or_else(|_| ((Vec::new(), "its thread failed".into()), 0));
        ctx.evals += evals;
        (back, fwd)
    });
    let mut points: Vec<CurvePoint> = back.into_iter().rev().collect();
    points.push(CurvePoint {
        lambda: [start.lambda, params[1].get(&base)],
        theta: wrap_angle(start.theta),
        multiplier: start.multiplier,
    });
    points.extend(fwd);
    Curve {
        kind,
        period,
        params,
        points,
        ends: [why_back, why_fwd],
        map_evals: ctx.evals,
    }
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm(a: &[f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalize(a: [f64; 3]) -> Option<[f64; 3]> {
    let n = norm(&a);
    (n > 0.0 && n.is_finite()).then(|| a.map(|v| v / n))
}

fn orient(a: [f64; 3], prev: &[f64; 3]) -> [f64; 3] {
    if dot(&a, prev) < 0.0 {
        a.map(|v| -v)
    } else {
        a
    }
}

/// Solves the 3×3 system a·x = b by Cramer's rule (`None` when singular).
fn solve3(a: &[[f64; 3]; 3], b: &[f64; 3]) -> Option<[f64; 3]> {
    let det = |m: &[[f64; 3]; 3]| dot(&m[0], &cross(&m[1], &m[2]));
    let d = det(a);
    if !(d.is_finite() && d != 0.0) {
        return None;
    }
    let mut x = [0.0; 3];
    for (j, xj) in x.iter_mut().enumerate() {
        let mut m = *a;
        for i in 0..3 {
            m[i][j] = b[i];
        }
        *xj = det(&m) / d;
    }
    Some(x)
}
