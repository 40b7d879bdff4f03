//! A stretch of the arc that no series resolves (a jump's bracket, a rough
//! stretch, the neighbourhood of a point where f' is unbounded, or what a
//! build's budget left over), enclosed from nodes: the integrated map's
//! value and its exact slope (the variational equations) at each node.
//!
//! Between two nodes a < b with values fa, fb and slopes da, db, the chord
//! slope c = (fb − fa)/(b − a) lies between da and db whenever f' is
//! monotone on [a, b] (f convex or concave there). Then f lies between the
//! chord and the larger (convex) or smaller (concave) of the two tangent
//! lines, and |f'| ≤ max(|da|, |db|): an enclosure of f over any [s, t]
//! inside [a, b], and of its slope. That is the one assumption: **between
//! two neighbouring nodes f' is monotone**, and the test above (which any
//! inflection wide enough to be seen between the nodes fails) is how it
//! is checked. Where the test fails, or a node has no slope (f has no
//! derivative there), the interval is **open**: it encloses nothing, the
//! cells over it reach every cell, and it is bisected (a node more) when
//! the cell graph subdivides there. An interval narrower than
//! [`BRANCH_WIDTH`] that fails the test holds at most one jump or kink:
//! the hull of the two nodes' tangent lines across it ([`two_branches`]);
//! one narrower than [`KINK_WIDTH`] whose nodes lack a slope is the hull of
//! its two values widened by their difference: sampled, not bounded, over
//! 1e-9 rad at most.

use crate::model::wrap_angle;
use crate::sim::{SimError, Simulator};

/// Node intervals at most this wide are enclosed by their values' hull
/// widened by their difference (see the module's doc).
pub const KINK_WIDTH: f64 = 1e-9;

/// A node: u, f(u) (both in u = θ − ψ) and f'(u), NaN where f has no
/// derivative.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    pub u: f64,
    pub f: f64,
    pub d: f64,
}

impl Node {
    /// The integrated map and its slope at u.
    pub fn at(sim: &Simulator, psi: f64, u: f64, spent: &mut (u64, u64)) -> Result<Node, SimError> {
        let (ev, d, n) = sim.cycle_slope(psi + u, 0.0)?;
        spent.0 += 1;
        spent.1 += ev.rhs_evals + n;
        Ok(Node {
            u,
            f: wrap_angle(ev.theta_next - psi),
            d: d.unwrap_or(f64::NAN),
        })
    }
}

/// Node intervals at most this wide that fail the test are enclosed as
/// two branches (see [`two_branches`]).
pub const BRANCH_WIDTH: f64 = 1e-6;

/// f over [a.u, b.u] as at most one jump or kink between two branches,
/// each the tangent line from its node across the whole interval: what
/// the nodes allow where the test fails that close together (a jump of f,
/// a grazing; over 1e-6 rad a branch's curvature moves it by 1e-12 at most
/// for |f''| ≤ 1e6).
fn two_branches(a: &Node, b: &Node, own: f64) -> (f64, f64, f64) {
    let w = b.u - a.u;
    let ends = [a.f, a.f + a.d * w, b.f, b.f - b.d * w];
    let lo = ends.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = ends.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (lo - own - 1e-12, hi + own + 1e-12, f64::INFINITY)
}

/// The enclosure of f over [s, t] ⊂ [a.u, b.u] from the nodes a and b,
/// each value known to within `own`: (lo, hi, max |f'|); `None` where the
/// interval is open (see the module's doc).
pub fn between(a: &Node, b: &Node, s: f64, t: f64, own: f64) -> Option<(f64, f64, f64)> {
    let w = b.u - a.u;
    if !(w > 0.0) {
        let (lo, hi) = (a.f.min(b.f), a.f.max(b.f));
        return Some((lo - own, hi + own, f64::INFINITY));
    }
    if w <= KINK_WIDTH {
        let d = (b.f - a.f).abs();
        return Some((
            a.f.min(b.f) - d - own,
            a.f.max(b.f) + d + own,
            f64::INFINITY,
        ));
    }
    if !(a.d.is_finite() && b.d.is_finite()) {
        return None;
    }
    let c = (b.f - a.f) / w;
    // The values' errors move the chord's slope by up to 2 own / w; the
    // slopes carry the integrator's relative error.
    let slack = 2.0 * own / w + 1e-6 * a.d.abs().max(b.d.abs()) + 1e-12;
    if c < a.d.min(b.d) - slack || c > a.d.max(b.d) + slack {
        return (w <= BRANCH_WIDTH).then(|| two_branches(a, b, own));
    }
    let chord = |x: f64| a.f + c * (x - a.u);
    let ta = |x: f64| a.f + a.d * (x - a.u);
    let tb = |x: f64| b.f + b.d * (x - b.u);
    // Where the tangents cross, inside [s, t]: with s and t, where the
    // tangents' envelope (piecewise linear, one kink) has its extremes.
    let cross = if a.d != b.d {
        (b.f - a.f + a.d * a.u - b.d * b.u) / (a.d - b.d)
    } else {
        s
    };
    let xs = [s, t, cross.clamp(s, t)];
    let (c_lo, c_hi) = (chord(s).min(chord(t)), chord(s).max(chord(t)));
    let (lo, hi) = if a.d <= b.d {
        // Convex: above both tangents, below the chord.
        let env = xs
            .iter()
            .map(|&x| ta(x).max(tb(x)))
            .fold(f64::INFINITY, f64::min);
        (env.min(c_lo), c_hi)
    } else {
        // Concave: below both tangents, above the chord.
        let env = xs
            .iter()
            .map(|&x| ta(x).min(tb(x)))
            .fold(f64::NEG_INFINITY, f64::max);
        (c_lo, env.max(c_hi))
    };
    let pad = own + slack * w;
    Some((lo - pad, hi + pad, a.d.abs().max(b.d.abs()) + slack))
}

/// f and f' at u ∈ [a.u, b.u] by cubic Hermite interpolation (both slopes
/// known), or on the chord.
pub fn hermite(a: &Node, b: &Node, u: f64) -> (f64, f64) {
    let w = b.u - a.u;
    if !(w > 0.0) {
        return (a.f, if a.d.is_finite() { a.d } else { 0.0 });
    }
    let c = (b.f - a.f) / w;
    if !(a.d.is_finite() && b.d.is_finite()) {
        return (a.f + c * (u - a.u), c);
    }
    let t = ((u - a.u) / w).clamp(0.0, 1.0);
    let (t2, t3) = (t * t, t * t * t);
    let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    let h10 = t3 - 2.0 * t2 + t;
    let h01 = -2.0 * t3 + 3.0 * t2;
    let h11 = t3 - t2;
    let f = h00 * a.f + h10 * w * a.d + h01 * b.f + h11 * w * b.d;
    let d00 = (6.0 * t2 - 6.0 * t) / w;
    let d10 = 3.0 * t2 - 4.0 * t + 1.0;
    let d01 = (-6.0 * t2 + 6.0 * t) / w;
    let d11 = 3.0 * t2 - 2.0 * t;
    let d = d00 * a.f + d10 * a.d + d01 * b.f + d11 * b.d;
    (f, d)
}

/// How far the enclosure of [a.u, b.u] from its two nodes is from the
/// chord (the tangents' crossing against the chord there), or infinite
/// for an open interval: what bisecting it would gain.
pub fn slack(a: &Node, b: &Node, own: f64) -> f64 {
    match between(a, b, a.u, b.u, own) {
        Some((lo, hi, _)) => (hi - lo) - (b.f - a.f).abs(),
        None => f64::INFINITY,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn node(f: &dyn Fn(f64) -> (f64, f64), u: f64) -> Node {
        let (v, d) = f(u);
        Node { u, f: v, d }
    }

    /// The enclosure holds f at fine points for convex, concave and
    /// monotone smooth pieces, and is open across an inflection.
    #[test]
    fn encloses_between_nodes_and_refuses_an_inflection() {
        let fs: [&dyn Fn(f64) -> (f64, f64); 3] = [
            &|x: f64| (x.exp(), x.exp()),
            &|x: f64| (-(x * x) + 3.0 * x, -2.0 * x + 3.0),
            &|x: f64| ((1.0 + x).sqrt(), 0.5 / (1.0 + x).sqrt()),
        ];
        for f in fs {
            let (a, b) = (node(f, 0.1), node(f, 0.9));
            for (s, t) in [(0.1, 0.9), (0.2, 0.3), (0.85, 0.9), (0.4, 0.41)] {
                let (lo, hi, slope) = between(&a, &b, s, t, 0.0).expect("enclosed");
                for k in 0..=100 {
                    let x = s + (t - s) * k as f64 / 100.0;
                    let (v, d) = f(x);
                    assert!(
                        lo - 1e-12 <= v && v <= hi + 1e-12,
                        "{v} not in [{lo}, {hi}]"
                    );
                    assert!(d.abs() <= slope + 1e-12);
                }
            }
        }
        // sin over [−1, 1] has an inflection at 0 its end slopes cannot
        // see only if the chord slope lies outside them.
        let sin: &dyn Fn(f64) -> (f64, f64) = &|x: f64| (x.sin(), x.cos());
        let (a, b) = (node(sin, -1.5), node(sin, 1.5));
        assert!(between(&a, &b, -1.5, 1.5, 0.0).is_none());
    }

    #[test]
    fn hermite_is_exact_on_cubics() {
        let f = |x: f64| (x * x * x - x, 3.0 * x * x - 1.0);
        let (a, b) = (node(&f, -0.5), node(&f, 2.0));
        let (v, d) = hermite(&a, &b, 0.7);
        assert!((v - f(0.7).0).abs() < 1e-12 && (d - f(0.7).1).abs() < 1e-12);
    }
}
