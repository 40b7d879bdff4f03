//! A whole boundary in one run: the curve through every located start
//! that is not on a curve already followed (a boundary such as Fig. 4's
//! FP→P2 is crossed twice along θν, and its two arms may not join inside
//! the box), and the points where a curve crosses a line λᵢ = value,
//! corrected there to the multiplier's accuracy (to compare a curve with
//! one-parameter branches).

use super::branch::SpecialPoint;
use super::curve::{Ctx, Curve, CurveOf, CurveOptions, CurvePoint, V3, origin};
use super::{Pace, drive};
use crate::integrate::SolverSettings;
use crate::model::{Params, wrap_angle};
use nalgebra::{Matrix2, Vector2};

/// A start closer than this (in λ, relative to the box) to a crossing of
/// a curve already followed is on that curve.
const SAME_CURVE: f64 = 1e-6;

/// Follows the curve `of` asks for (its `kind` of the p-cycle in
/// (λ₁, λ₂) = `of.params`) through `start`, a special point of that kind
/// located on a branch in λ₁ with λ₂ at `of.base`'s value (see the module
/// notes of [`super::curve`]), the two directions on two threads (which
/// is why it is not [`continue_curve_paced`] driven, as the other
/// synchronous functions are their walk driven: that walk takes the
/// directions in turn). `cancel` is polled once per point.
pub fn continue_curve(
    of: &CurveOf,
    start: &SpecialPoint,
    opts: &CurveOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Curve {
    let (pace, other_pace) = (Pace::new(), Pace::new());
    let (base, y0) = origin(&of.base, of.params, start, opts);
    let mut ctx = Ctx::new(&pace, CurveOf { base, ..*of }, opts);
    let Some(t0) = drive(&pace, ctx.tangent(&y0), &|| false) else {
        return ctx.no_tangent();
    };
    // The two directions are independent: one thread each.
    let mut other = ctx.fork(&other_pace);
    let (back, fwd) = std::thread::scope(|s| {
        let job = s.spawn(|| {
            let r = drive(&other_pace, other.follow(y0, -t0), cancel);
            (r, other.evals)
        });
        let fwd = drive(&pace, ctx.follow(y0, t0), cancel);
        let (back, evals) = job
            .join()
            .unwrap_or_else(|_| ((Vec::new(), "its thread failed".into()), 0));
        ctx.evals += evals;
        (back, fwd)
    });
    drive(&pace, ctx.finish(start, back, fwd), &|| false)
}

/// [`continue_curve`] on one thread, a piece after each map evaluation
/// and a cancel asked once per point: the direction along −t first, then
/// along t (each the same walk as on its own thread).
pub async fn continue_curve_paced(
    pace: &Pace,
    of: &CurveOf,
    start: &SpecialPoint,
    opts: &CurveOptions,
) -> Curve {
    let (base, y0) = origin(&of.base, of.params, start, opts);
    let mut ctx = Ctx::new(pace, CurveOf { base, ..*of }, opts);
    let Some(t0) = ctx.tangent(&y0).await else {
        return ctx.no_tangent();
    };
    let mut other = ctx.fork(pace);
    let back = other.follow(y0, -t0).await;
    let fwd = ctx.follow(y0, t0).await;
    ctx.evals += other.evals;
    ctx.finish(start, back, fwd).await
}

/// Follows the curve `of` asks for through each of `starts` (special
/// points of its kind on one branch in λ₁, at `of.base`'s λ₂), skipping a
/// start that
/// an earlier curve already passes through; see [`continue_curve`].
/// `cancel` is polled once per point; a cancelled run returns the curves
/// so far.
pub fn continue_curves(
    of: &CurveOf,
    starts: &[SpecialPoint],
    opts: &CurveOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Vec<Curve> {
    let mut curves: Vec<Curve> = Vec::new();
    for start in starts {
        if cancel() {
            break;
        }
        let pace = Pace::new();
        let on_one = known(&pace, of, &curves, start, opts);
        let known = drive(&pace, on_one, &|| false);
        if !known {
            curves.push(continue_curve(of, start, opts, cancel));
        }
    }
    curves
}

/// [`continue_curves`] on one thread, a piece after each map evaluation
/// and a cancel asked once per point ([`continue_curve_paced`]).
pub async fn continue_curves_paced(
    pace: &Pace,
    of: &CurveOf,
    starts: &[SpecialPoint],
    opts: &CurveOptions,
) -> Vec<Curve> {
    let mut curves: Vec<Curve> = Vec::new();
    for start in starts {
        if pace.cancelled().await {
            break;
        }
        if !known(pace, of, &curves, start, opts).await {
            curves.push(continue_curve_paced(pace, of, start, opts).await);
        }
    }
    curves
}

/// Whether `start` lies on one of `curves` (where it crosses the line
/// λ₂ = its value in `of`'s base, within [`SAME_CURVE`] of the box).
async fn known(
    pace: &Pace,
    of: &CurveOf,
    curves: &[Curve],
    start: &SpecialPoint,
    opts: &CurveOptions,
) -> bool {
    let scale = opts.scale();
    let level = of.params[1].get(&of.base);
    for c in curves {
        let crossings = crossings_paced(pace, of.of(c), &c.points, opts, 1, level).await;
        if crossings
            .iter()
            .any(|p| (p.lambda[0] - start.lambda).abs() <= SAME_CURVE * scale[0])
        {
            return true;
        }
    }
    false
}

/// Where `curve` crosses λ_axis = `value` (axis 0 or 1), each crossing
/// corrected by Newton on (G, m − m*) in (θ, the other λ) with λ_axis
/// held, to residuals of 1e-12 (or as far as the multiplier's accuracy
/// allows, at most 1e-7): the curve's points there, not a chord's. `base` holds the
/// parameters not on the curve; `opts` the box the curve was followed in.
pub fn curve_crossings(
    base: &Params,
    settings: &SolverSettings,
    curve: &Curve,
    opts: &CurveOptions,
    axis: usize,
    value: f64,
) -> Vec<CurvePoint> {
    let of = CurveOf {
        base: *base,
        settings: *settings,
        params: curve.params,
        period: curve.period,
        kind: curve.kind,
    };
    let pace = Pace::new();
    let walk = crossings_paced(&pace, of, &curve.points, opts, axis, value);
    drive(&pace, walk, &|| false)
}

/// [`curve_crossings`], a piece after each map evaluation.
async fn crossings_paced(
    pace: &Pace,
    of: CurveOf,
    points: &[CurvePoint],
    opts: &CurveOptions,
    axis: usize,
    value: f64,
) -> Vec<CurvePoint> {
    let axis = axis.min(1);
    let other = 1 - axis;
    let mut ctx = Ctx::new(pace, of, opts);
    let scale = ctx.scale();
    let mut out = Vec::new();
    for w in points.windows(2) {
        let (a, b) = (w[0].lambda[axis] - value, w[1].lambda[axis] - value);
        if a * b > 0.0 || a == b {
            continue;
        }
        let f = a / (a - b);
        let mut y = V3::zeros();
        y[0] = w[0].theta + f * wrap_angle(w[1].theta - w[0].theta);
        y[1 + axis] = value / scale[axis];
        y[1 + other] =
            (w[0].lambda[other] + f * (w[1].lambda[other] - w[0].lambda[other])) / scale[other];
        if let Some(p) = refine(&mut ctx, y, other, scale).await {
            out.push(p);
        }
    }
    out
}

/// Newton on (G, m − m*) in (θ, μ_other), the other μ held. The
/// multiplier's own error (1e-11 to 1e-9) is the floor Newton stalls at:
/// the best iterate within [`CROSSING_RESIDUAL`] is kept.
async fn refine(ctx: &mut Ctx<'_>, mut y: V3, other: usize, scale: [f64; 2]) -> Option<CurvePoint> {
    let j = 1 + other;
    let mut best: Option<(f64, CurvePoint)> = None;
    for _ in 0..12 {
        let Ok((rows, r, e)) = ctx.system(&y).await else {
            break;
        };
        let residual = r[0].abs().max(r[1].abs());
        let point = CurvePoint {
            lambda: [y[1] * scale[0], y[2] * scale[1]],
            theta: wrap_angle(y[0]),
            multiplier: e.m,
        };
        if best.as_ref().is_none_or(|b| residual < b.0) {
            best = Some((residual, point));
        }
        if residual <= 1e-12 {
            break;
        }
        // LU with partial pivoting: G's row and m's row differ in size.
        let a = Matrix2::new(rows[0][0], rows[0][j], rows[1][0], rows[1][j]);
        let d = match a.lu().solve(&Vector2::new(r[0], r[1])) {
            Some(d) if d.iter().all(|v| v.is_finite()) => d,
            _ => break,
        };
        y[0] -= d[0];
        y[j] -= d[1];
    }
    best.filter(|b| b.0 <= CROSSING_RESIDUAL).map(|b| b.1)
}

/// The largest residual |G|, |m − m*| a crossing is given with.
const CROSSING_RESIDUAL: f64 = 1e-7;
