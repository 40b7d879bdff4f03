//! The tip of the pitchfork an even-period branch is born in.
//!
//! A 2q-cycle born at a doubling of a q-cycle is, near its birth, the
//! parabola λ − λ* ∝ (θ − θ*)² in (θ, λ), its halves θᵢ and θᵢ₊q apart
//! by ∝ √|λ − λ*| and its multiplier → +1. At the tip it meets the
//! q-cycle, which is a zero of G for period 2q too: the corrector there
//! may step onto it (the halves merge) or round the tip (the halves come
//! back swapped, and m passes +1 like at a fold). Either is recognised
//! before any fold test by the sign of wrap(θ_q − θ₀), continued along
//! the branch, and the branch ends at the q-cycle's doubling, located on
//! the q-cycle itself.

use super::branch::{BranchPoint, Ctx, Pt, SpecialKind, SpecialPoint};
use crate::model::wrap_angle;

/// wrap(θ_q − θ₀) for a cycle of even period p = 2q (`None` for odd p):
/// zero where its halves merge, and of one sign along a branch from its
/// birth.
pub(super) fn half_gap(points: &[f64]) -> Option<f64> {
    let p = points.len();
    (p >= 2 && p.is_multiple_of(2)).then(|| wrap_angle(points[p / 2] - points[0]))
}

/// Whether the step from `cur` to `n` met the tip: the halves swapped, or
/// merged at `n`, i.e. they are within what the corrector's residual
/// allows. That is 100× the solver's tolerance `tol` (as the minimal
/// period is decided), or more near the tip: the corrector stops at
/// |G| ≈ tol/2, G's error carried through the later slopes, which moves
/// θ by that over |m − 1| → 0, so the half-period cycle can pass for a
/// P2 with halves a few 1e-8 apart. The branch's own halves are apart by
/// ∝ √(1 − m) there, far more until m is within ~1e-7 of 1.
pub(super) fn meets_birth(cur: &Pt, n: &Pt, tol: f64) -> bool {
    let (Some(a), Some(b)) = (half_gap(&cur.e.points), half_gap(&n.e.points)) else {
        return false;
    };
    let mut carried = 1.0;
    let mut amp = 1.0;
    for s in n.e.slopes.iter().rev() {
        carried *= s.abs();
        amp += carried;
    }
    // At most 1e-4: a P2 at a fold of its own (m = +1 too) keeps its
    // halves apart, and one whose halves are within 1e-4 is within
    // ~(1e-4/A)² of a tip in λ anyway.
    let noise = (10.0 * 0.5 * tol * amp / (1.0 - n.e.multiplier).abs()).min(1e-4);
    b.abs() <= noise.max(1e2 * tol) || a * b < 0.0
}

/// The doubling of the half-period cycle at the tip met on the step from
/// `cur` (after `prev`) to `n`: the q-cycle solved at λ of `cur` from the
/// halves' midpoint, a second one past the tip extrapolated from the
/// half-gap (gap² is linear in λ), and m + 1 = 0 located between them on
/// the q-cycle. The special point is that PD (period q, with its flip);
/// `None` where no such bracket is found.
pub(super) async fn locate_tip(
    ctx: &mut Ctx<'_>,
    cur: &Pt,
    prev: Option<&BranchPoint>,
    n: &Pt,
) -> Option<SpecialPoint> {
    let scale = ctx.opts.scale;
    let p = ctx.prob.period;
    let q = p / 2;
    let qprob = ctx.prob.with_period(q);
    let mut qctx = Ctx {
        pace: ctx.pace,
        prob: &qprob,
        opts: ctx.opts,
        evals: 0,
        last_fail: None,
    };
    let found = locate_on(&mut qctx, cur, prev, n, scale).await;
    ctx.evals += qctx.evals;
    found
}

async fn locate_on(
    qctx: &mut Ctx<'_>,
    cur: &Pt,
    prev: Option<&BranchPoint>,
    n: &Pt,
    scale: f64,
) -> Option<SpecialPoint> {
    let along = [0.0, 1.0];
    let gap = half_gap(&cur.e.points)?;
    let mid = cur.x[0] + 0.5 * gap;
    let a = qctx.correct([mid, cur.x[1]], along).await.ok()?;
    let lc = cur.lambda(scale);
    // λ* from gap² linear in λ through `cur` and the point before it (on
    // the same side of the tip), else `n`'s λ.
    let estimate = prev
        .and_then(|b| {
            let g = half_gap(&b.points)?;
            let d = g * g - gap * gap;
            (d.abs() > 0.0).then(|| lc - gap * gap * (b.lambda - lc) / d)
        })
        .filter(|l| l.is_finite() && (l - lc).abs() > 0.0)
        .unwrap_or_else(|| n.lambda(scale));
    // Past the estimate, then along the secant of m + 1 through `a` and
    // the last trial (the P{p} branch's tip and the P{q}'s m = −1 differ
    // by m's error over its slope).
    let side = a.e.multiplier + 1.0;
    let mut lb = lc + 1.5 * (estimate - lc);
    let mut b = None;
    for _ in 0..8 {
        let Ok(c) = qctx.correct([a.x[0], lb / scale], along).await else {
            lb = lc + 0.5 * (lb - lc);
            continue;
        };
        let fc = c.e.multiplier + 1.0;
        if fc * side <= 0.0 {
            b = Some(c);
            break;
        }
        let zero = lc - side * (lb - lc) / (fc - side);
        lb = if zero.is_finite() && (zero - lc) * (lb - lc) > 0.0 {
            lc + 1.5 * (zero - lc)
        } else {
            lc + 4.0 * (lb - lc)
        };
    }
    let b = b?;
    let h = b.x[1] - a.x[1];
    let test = |m: f64| m + 1.0;
    let l = qctx.locate(&a, &b, along, h, test).await;
    if !l.real {
        return None;
    }
    let l = qctx.refine(l, along, test).await;
    let note = format!(
        "the P{} cycle's doubling, where the P{} branch is born",
        qctx.prob.period,
        2 * qctx.prob.period
    );
    let mut sp = qctx.special(SpecialKind::PeriodDoubling, &l.pt, note);
    sp.flip = qctx.flip(&l.pt, &l.samples).await;
    Some(sp)
}
