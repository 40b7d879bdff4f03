//! The stencil of a flip's coefficient c: the half-width H of the
//! differences in θ about θ*, chosen inside the piece of g = f^p that is
//! smooth about θ* (see [`super::flip`] for c itself).
//!
//! f is piecewise smooth: it jumps where an event is met tangentially, and
//! ends at the exit arc's edges. A stencil across a jump gives c with the
//! wrong size or sign, and its error estimate (the second-order value's
//! distance) does not see it. So the stencil is checked along the
//! iterates: at every iterate i, f must be smooth between the cycle's θᵢ
//! and the stencil orbit's θᵢ(±H) (its secant slope within [`SMOOTH`] of
//! the mean of the end slopes: the trapezoid rule, which a jump J between
//! them misses by J/|θᵢ(±H) − θᵢ|). Where it is not, the nearest jump is
//! bisected on f alone, its distance taken back to θ* through the slopes
//! (d/|(fⁱ)'(θ*)|), and H becomes [`SAFETY`] times that; the exit arc's
//! edges count the same way. H is then shrunk further, 4× at a time,
//! while c's truncation error (against the second-order value) is above
//! a tenth of |c| and above what its rounding error would grow to: G's
//! noise enters c divided by H³, M's by H². Where the smooth piece is so
//! narrow that c's rounding error exceeds |c|, c is undecided, and the
//! born cycle decides ([`super::flip`]).

use super::{Eval, EvalError, Pace, Problem, eval_paced};
use crate::model::{exit_arc, wrap_angle};
use crate::sim::Simulator;

/// The step H of the differences in θ for a fixed point (G and M at
/// θ* ± H); a p-cycle's is H/p: g = f^p bends on a scale that shrinks
/// with p (its derivatives grow like products of p slopes). The widest
/// stencil: a jump or border nearer θ* narrows it.
const STEP: f64 = 1e-2;
/// M's error relative to |M|, per map evaluation in the product.
pub(super) const M_NOISE: f64 = 1e-9;
/// G's error per map evaluation, in units of the solver's relative
/// tolerance (a few 1e-8 at ν = 1e-4 and tolerance 1e-10).
const G_NOISE: f64 = 300.0;
/// The share of the distance to the nearest jump or border that the
/// stencil may reach.
const SAFETY: f64 = 0.5;
/// f is smooth between two points when its secant slope is within this
/// share of the larger end slope from their mean.
const SMOOTH: f64 = 0.25;
/// Bisections of the stretch that holds a jump, towards the jump nearest
/// the cycle's point.
const BISECTIONS: usize = 8;
/// The most stencils tried, each two evaluations of f^p.
const TRIALS: usize = 6;
/// How much H shrinks between trials.
const SHRINK: f64 = 4.0;

/// The stencil a flip's coefficient was taken on.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Stencil {
    /// H: c is from G and M at θ* and θ* ± H.
    pub h: f64,
    /// How far from θ* f^p is smooth, as far as the search saw: the
    /// distance to its nearest jump or border (∞ where none lies within
    /// the widest stencil's reach; a session writes ∞ as null).
    #[serde(with = "infinite_as_null")]
    pub piece: f64,
    /// c's rounding error at H (part of its error).
    pub rounding: f64,
}

/// c, its error (truncation and rounding) and the stencil it came from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Estimate {
    pub c: f64,
    pub error: f64,
    pub stencil: Stencil,
}

/// What the cycle's derivatives say about a stencil at θ*: how far each
/// iterate moves per unit of θ* (|(fⁱ)'(θ*)|), the distance to the exit
/// arc's edge in θ*, and the noise of G and M.
struct Reach {
    gains: Vec<f64>,
    arc_edge: f64,
    g_noise: f64,
    m_noise: f64,
}

impl Reach {
    fn of(sim: &Simulator, e0: &Eval) -> Reach {
        let p = e0.points.len();
        let params = sim.params();
        let (psi, half) = exit_arc(params.kappa, params.theta_nu);
        let mut gains = Vec::with_capacity(p);
        let mut gain = 1.0_f64;
        for s in &e0.slopes {
            gains.push(gain);
            gain *= s.abs();
        }
        let arc_edge = e0
            .points
            .iter()
            .zip(&gains)
            .map(|(&t, &k)| (half - wrap_angle(t - psi).abs()) / k)
            .fold(f64::INFINITY, f64::min);
        // The noise of step i reaches G through the slopes after it.
        let (mut after, mut sum) = (1.0_f64, 0.0);
        for s in e0.slopes.iter().rev() {
            sum += after;
            after *= s.abs();
        }
        let per_eval = G_NOISE * sim.settings().rtol.max(1e-14);
        Reach {
            gains,
            arc_edge,
            g_noise: per_eval * sum,
            m_noise: M_NOISE * p as f64 * e0.multiplier.abs(),
        }
    }

    /// c's rounding error from the differences at H, with g'' = `d2`
    /// (G's noise through g''' over H³ and g'' over H², M's over H²).
    fn rounding(&self, h: f64, d2: f64) -> f64 {
        let (sg, sm) = (self.g_noise, self.m_noise);
        1.8 * sg / (h * h * h) + (2.5 * d2.abs() * sg + 0.6 * sm) / (h * h)
    }
}

/// The coefficient c at θ*, its error and its stencil: G and M at θ* (`at`,
/// evaluated when `None`) and at θ* ± H, H chosen as the module notes
/// say. Counts map evaluations in `evals`.
pub(super) async fn coefficient(
    pace: &Pace,
    prob: &Problem,
    lambda: f64,
    theta: f64,
    at: Option<&Eval>,
    evals: &mut u64,
) -> Result<Estimate, EvalError> {
    let sim = prob.sim(lambda).map_err(EvalError::Sim)?;
    let (param, p) = (prob.param, prob.period);
    let e0 = match at {
        Some(e) if e.slopes.len() == p => e.clone(),
        _ => eval_paced(pace, &sim, param, p, theta, evals).await?,
    };
    let reach = Reach::of(&sim, &e0);
    let mut piece = reach.arc_edge;
    let mut h = (STEP / p as f64).min(SAFETY * piece);
    let mut best: Option<Estimate> = None;
    let mut border = None;
    for _ in 0..TRIALS {
        let sides = match eval_paced(pace, &sim, param, p, theta + h, evals).await {
            Ok(plus) => eval_paced(pace, &sim, param, p, theta - h, evals)
                .await
                .map(|minus| (plus, minus)),
            Err(e) => Err(e),
        };
        let (plus, minus) = match sides {
            Ok(s) => s,
            Err(e) if e.is_border() => {
                (piece, h, border) = (piece.min(h), h / SHRINK, Some(e));
                continue;
            }
            Err(e) => return Err(e),
        };
        if let Some(d) = rough(pace, &sim, &reach, &e0, [&plus, &minus], evals).await {
            piece = piece.min(d);
            h = (SAFETY * d).min(h / 2.0);
            continue;
        }
        let (c, truncation, d2) = from_hermite(h, (e0.g, e0.multiplier), pair(&plus), pair(&minus));
        if !(c.is_finite() && truncation.is_finite()) {
            return Err(EvalError::NonFinite);
        }
        let rounding = reach.rounding(h, d2);
        let est = Estimate {
            c,
            error: truncation + rounding,
            stencil: Stencil { h, piece, rounding },
        };
        if best.is_none_or(|b| est.error < b.error) {
            best = Some(est);
        }
        if truncation <= 0.1 * c.abs() || rounding * SHRINK.powi(3) >= truncation {
            break;
        }
        h /= SHRINK;
    }
    match (best, border) {
        (Some(b), _) => Ok(Estimate {
            stencil: Stencil { piece, ..b.stencil },
            ..b
        }),
        (None, Some(e)) => Err(e),
        (None, None) => Err(EvalError::NonFinite),
    }
}

/// G and M of an evaluation.
fn pair(e: &Eval) -> (f64, f64) {
    (e.g, e.multiplier)
}

/// The distance from θ*, in θ*, of the nearest jump or border of f that
/// the stencil's orbits `sides` (from θ* ± H) cross, if they cross one:
/// at the first iterate of each where f is not smooth between the cycle's
/// point and the orbit's (see the module notes), bisected on f.
async fn rough(
    pace: &Pace,
    sim: &Simulator,
    reach: &Reach,
    e0: &Eval,
    sides: [&Eval; 2],
    evals: &mut u64,
) -> Option<f64> {
    let p = e0.points.len();
    let next = |e: &Eval, i: usize| {
        if i + 1 < p {
            e.points[i + 1]
        } else {
            wrap_angle(e.points[0] + e.g)
        }
    };
    let mut nearest: Option<f64> = None;
    for side in sides {
        let trouble = (0..p).find(|&i| {
            let a = (e0.points[i], next(e0, i), e0.slopes[i]);
            let b = (side.points[i], next(side, i), side.slopes[i]);
            !smooth(a, b, reach.g_noise)
        });
        if let Some(i) = trouble {
            let a = (e0.points[i], next(e0, i), e0.slopes[i]);
            let d = nearest_jump(pace, sim, a, side.points[i], reach.g_noise, evals).await
                / reach.gains[i];
            nearest = Some(nearest.map_or(d, |n: f64| n.min(d)));
        }
    }
    nearest
}

/// Whether f is smooth between a and b, each (θ, f(θ), f'(θ)): its secant
/// slope within [`SMOOTH`] of the larger end slope (and the noise over the
/// distance) from their mean.
fn smooth(a: (f64, f64, f64), b: (f64, f64, f64), noise: f64) -> bool {
    let dx = b.0 - a.0;
    if dx == 0.0 {
        return true;
    }
    let secant = wrap_angle(b.1 - a.1) / dx;
    let mean = 0.5 * (a.2 + b.2);
    (secant - mean).abs() <= SMOOTH * a.2.abs().max(b.2.abs()) + 2.0 * noise / dx.abs()
}

/// How far from a = (θ, f(θ), f'(θ)) towards `b` f stays smooth: the
/// stretch is bisected [`BISECTIONS`] times, keeping the half nearer a
/// that is not smooth from a (or where f is not evaluated).
async fn nearest_jump(
    pace: &Pace,
    sim: &Simulator,
    a: (f64, f64, f64),
    b: f64,
    noise: f64,
    evals: &mut u64,
) -> f64 {
    let (mut good, mut bad) = (a.0, b);
    let param = super::ContParam::ThetaNu;
    for _ in 0..BISECTIONS {
        let m = 0.5 * (good + bad);
        let ok = eval_paced(pace, sim, param, 1, m, evals)
            .await
            .is_ok_and(|e| smooth(a, (m, wrap_angle(m + e.g), e.multiplier), noise));
        if ok {
            good = m;
        } else {
            bad = m;
        }
    }
    if good == a.0 {
        0.5 * (bad - a.0).abs()
    } else {
        (good - a.0).abs()
    }
}

/// c, its truncation error and g'' from (G, M) at θ*, θ* + h and θ* − h:
/// the quintic through the six values gives g'' and g''' to order h⁴; the
/// error is its distance from c by the three-point differences of M alone
/// (second order).
pub(super) fn from_hermite(
    h: f64,
    at: (f64, f64),
    plus: (f64, f64),
    minus: (f64, f64),
) -> (f64, f64, f64) {
    let ((g0, m0), (gp, mp), (gn, mn)) = (at, plus, minus);
    // In x = θ − θ*, G = Σ aₖxᵏ (k ≤ 5): its even part from the mean of G
    // and the difference of M, its odd part from the difference of G and
    // the mean of M (a₁ = M₀ − 1).
    let even_g = 0.5 * (gp + gn) - g0; // a₂h² + a₄h⁴
    let odd_m = 0.5 * (mp - mn); // 2a₂h + 4a₄h³
    let odd_g = (gp - gn) / (2.0 * h) - (m0 - 1.0); // a₃h² + a₅h⁴
    let even_m = 0.5 * (mp + mn) - m0; // 3a₃h² + 5a₅h⁴
    let d2 = (4.0 * even_g - odd_m * h) / (h * h); // 2a₂
    let d3 = 3.0 * (5.0 * odd_g - even_m) / (h * h); // 6a₃
    let c_of = |d2: f64, d3: f64| 0.25 * d2 * d2 + d3 / 6.0;
    let c = c_of(d2, d3);
    let c3 = c_of(odd_m / h, 2.0 * even_m / (h * h));
    (c, (c - c3).abs(), d2)
}

/// [`Stencil::piece`] in JSON, which has no ∞: +∞ as `null`, and back.
mod infinite_as_null {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
        if *x == f64::INFINITY {
            s.serialize_none()
        } else {
            s.serialize_f64(*x)
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// g(x) = θ* − x + a·x² + b·x³ + Σ higher terms, as G = g − θ and
    /// M = g' at θ* + x.
    fn g_and_m(coef: &[f64], x: f64) -> (f64, f64) {
        let theta_star = 0.4;
        let (mut g, mut m) = (theta_star - x, -1.0);
        for (k, a) in coef.iter().enumerate() {
            let n = (k + 2) as i32;
            g += a * x.powi(n);
            m += f64::from(n) * a * x.powi(n - 1);
        }
        (g - (theta_star + x), m)
    }

    #[test]
    fn the_quintic_is_exact_to_fifth_order_and_its_error_bounds_the_sixth() {
        // c = a² + b = 0.09 + 0.7.
        let quintic = [0.3, 0.7, -2.0, 5.0];
        let h = 0.01;
        let at = |c: &[f64], x| g_and_m(c, x);
        let (c, err, _) = from_hermite(h, at(&quintic, 0.0), at(&quintic, h), at(&quintic, -h));
        assert!((c - 0.79).abs() < 1e-9, "{c}");
        // The three-point value is off by O(h²): the error says so.
        assert!(err > 1e-5 && err < 1e-2, "{err}");
        // With sixth- and seventh-order terms, the quintic's error is of
        // order h⁴, well within the estimate.
        let more = [0.3, 0.7, -2.0, 5.0, 40.0, -90.0];
        let (c, err, _) = from_hermite(h, at(&more, 0.0), at(&more, h), at(&more, -h));
        assert!((c - 0.79).abs() < 1e-5, "{c}");
        assert!((c - 0.79).abs() < err, "{c} ± {err}");
    }
}
