//! The criticality of a period doubling: the flip's normal-form
//! coefficient from the derivatives of g = f^p at the cycle.
//!
//! Near a flip, g(x) = −(1 + β)x + a·x² + b·x³ + … in x = θ − θ*, with
//! β = −1 − m the multiplier's distance past −1. Its second iterate is
//! x + 2β·x − 2c·x³ + … with c = a² + b = g''²/4 + g'''/6 (= −S/6, S the
//! Schwarzian derivative of g, since g' = −1). For c > 0 the flip is
//! supercritical: a stable 2p-cycle is born on the side where the p-cycle
//! is unstable (β > 0), with half-separation η = √(β/c). For c < 0 it is
//! subcritical: an unstable 2p-cycle lies on the side where the p-cycle is
//! stable, and the attractor jumps away when it loses stability.
//!
//! g' is the exact multiplier M(θ) = Π f'(θᵢ) of the orbit of length p
//! from θ (not a cycle off θ*), and each evaluation gives G = g − θ with
//! it. So two evaluations, at θ* ± H, add four numbers to G and M at θ*
//! (the located point's own): the quintic that takes those six values
//! (Hermite interpolation) gives g'' and g''' with errors of order H⁴.
//! g''' from M alone (the three-point M'' = g''') is second order; the
//! two values of c differ by about the second-order one's error, which is
//! taken as c's (pessimistic, and large wherever g is not smooth over
//! ± H). G's noise (the integrator's, a few 1e-8 at ν = 1e-4) enters the
//! quintic's g''' divided by H³, and M's (1e-9 relative) the three-point
//! values divided by H²; truncation grows like H⁴. H is at most 0.01/p,
//! less where a jump or border of f^p lies nearer θ* or truncation still
//! dominates ([`super::stencil`]): the born cycles of
//! tests/criticality.rs are within 0.2 % of the predicted half-widths,
//! and the estimated error is 1–10 % of |c|. Where the error (truncation
//! and rounding) exceeds |c|, the coefficient does not decide (near a
//! generalised flip, where c changes sign, or where the smooth piece about
//! θ* is too narrow for the differences), and the born cycle does.
//!
//! dm/dλ along the branch costs nothing more: the location of the PD
//! corrected the branch at several λ about λ*, and m at those points is
//! exact. The slope at λ* is the quadratic's through λ* and the two
//! nearest of them that are far enough apart for m's noise (see
//! [`branch_slope`]).

use super::stencil::Stencil;
use super::stencil::{M_NOISE, coefficient};
use super::{Eval, EvalError, Pace, Problem, drive};

/// The largest share of |dm/dλ| that m's noise may take in [`branch_slope`].
const SLOPE_NOISE: f64 = 1e-4;

/// A flip's normal form, at a located period doubling.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Flip {
    /// c = g''²/4 + g'''/6: positive for a supercritical flip.
    pub coefficient: f64,
    /// The coefficient's error: its difference from the second-order
    /// value, and its rounding error.
    pub error: f64,
    /// The stencil it was taken on.
    pub stencil: Stencil,
    /// dm/dλ along the p-cycle's branch at the flip.
    pub dm_dlambda: f64,
    /// The doubled cycle Newton found next to the flip, which confirms
    /// (or, where the coefficient's stencil crossed a jump of f, sets) the
    /// criticality; `None` where none was found on either side.
    pub born: Option<Born>,
}

/// The 2p-cycle found next to a flip.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Born {
    /// The parameter it was solved at.
    pub lambda: f64,
    /// Its point nearest the p-cycle's θ*.
    pub theta: f64,
    /// Its half-separation |θ_p − θ₀|/2.
    pub half_width: f64,
    /// Its multiplier: stable for a supercritical flip, unstable for a
    /// subcritical one.
    pub multiplier: f64,
    /// Whether it lay on the side the coefficient predicted (else the
    /// coefficient was wrong, and was replaced by the one the cycle's
    /// half-width gives).
    pub predicted_side: bool,
}

/// A flip's criticality.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Criticality {
    /// A stable doubled cycle is born where the cycle loses stability.
    Supercritical,
    /// An unstable doubled cycle dies where the cycle loses stability; the
    /// attractor jumps away.
    Subcritical,
    /// |c| is within its error: at or near a generalised flip.
    Undecided,
}

impl Criticality {
    /// The word in the points CSV and the JSON.
    pub fn name(self) -> &'static str {
        match self {
            Criticality::Supercritical => "supercritical",
            Criticality::Subcritical => "subcritical",
            Criticality::Undecided => "undecided",
        }
    }
}

impl Flip {
    /// Super- or subcritical by the coefficient's sign, when it is beyond
    /// its error.
    pub fn criticality(&self) -> Criticality {
        if self.coefficient.abs() <= self.error || self.coefficient == 0.0 {
            Criticality::Undecided
        } else if self.coefficient > 0.0 {
            Criticality::Supercritical
        } else {
            Criticality::Subcritical
        }
    }

    /// A: the born 2p-cycle's half-separation |θ_p − θ₀|/2 is A·√|λ − λ*|
    /// to leading order (η² = β/c with β = −dm/dλ·(λ − λ*)).
    pub fn amplitude(&self) -> f64 {
        (self.dm_dlambda / self.coefficient).abs().sqrt()
    }

    /// The side of λ* the 2p-cycle lies on: +1 above, −1 below (where
    /// β/c > 0).
    pub fn side(&self) -> f64 {
        if -self.dm_dlambda / self.coefficient > 0.0 {
            1.0
        } else {
            -1.0
        }
    }

    /// The predicted half-separation at λ, or `None` on the other side.
    pub fn predicted(&self, lambda_star: f64, lambda: f64) -> Option<f64> {
        let d = lambda - lambda_star;
        (d * self.side() >= 0.0).then(|| self.amplitude() * d.abs().sqrt())
    }
}

/// The flip's normal form at the p-cycle through `theta` at `lambda`, a
/// located period doubling of `prob`: `at` is G and M there (evaluated
/// when `None`), `dm_dlambda` the multiplier's slope along the branch
/// (see [`branch_slope`]). Counts map evaluations in `evals`.
pub fn flip_at(
    prob: &Problem,
    lambda: f64,
    theta: f64,
    at: Option<&Eval>,
    dm_dlambda: f64,
    evals: &mut u64,
) -> Result<Flip, EvalError> {
    let pace = Pace::new();
    let walk = flip_paced(&pace, prob, lambda, theta, at, dm_dlambda, evals);
    drive(&pace, walk, &|| false)
}

/// [`flip_at`], a piece after each map evaluation. (Seven arguments:
/// `flip_at`'s six and the pace.)
pub(super) async fn flip_paced(
    pace: &Pace,
    prob: &Problem,
    lambda: f64,
    theta: f64,
    at: Option<&Eval>,
    dm_dlambda: f64,
    evals: &mut u64,
) -> Result<Flip, EvalError> {
    if !dm_dlambda.is_finite() {
        return Err(EvalError::NonFinite);
    }
    let est = coefficient(pace, prob, lambda, theta, at, evals).await?;
    let flip = Flip {
        coefficient: est.c,
        error: est.error,
        stencil: est.stencil,
        dm_dlambda,
        born: None,
    };
    Ok(confirm(pace, prob, lambda, theta, flip, evals).await)
}

/// The doubled cycle's predicted half-width at the λ it is looked for at
/// (per unit period): small enough for the normal form, large enough
/// that Newton on f^{2p} (whose slope there is about 4β) resolves it.
const BORN_WIDTH: f64 = 1e-4;

/// Confirms a flip's criticality on its doubled cycle: Newton solves the
/// 2p-cycle a small distance to the side the coefficient predicts, and it
/// must exist there with about the predicted half-width and the predicted
/// stability (stable for supercritical). Where it does not (a stencil
/// across a jump of f gets c's sign wrong: κ = 1.5's first flip), the
/// other side is tried with the other stability, and c is taken from the
/// cycle found there (η² = β/c). Each at δ, then δ/16 and δ/256 (a
/// cascade compressed into a narrow range of λ). Where none shows one,
/// the flip is left undecided (the error is set to |c|).
async fn confirm(
    pace: &Pace,
    prob: &Problem,
    lambda: f64,
    theta: f64,
    flip: Flip,
    evals: &mut u64,
) -> Flip {
    let a = flip.amplitude();
    if !(a.is_finite() && a > 0.0) {
        return flip;
    }
    let width = BORN_WIDTH / prob.period as f64;
    let first = (width / a).powi(2).clamp(1e-8, 1e-4) * lambda.abs().max(1.0);
    // Nearer the flip where the doubled cycle has doubled again by then
    // (a cascade compressed into 1e-5 of λ).
    for delta in [first, first / 16.0, first / 256.0] {
        if let Some(confirmed) = confirm_at(pace, prob, lambda, theta, &flip, delta, evals).await {
            return confirmed;
        }
    }
    Flip {
        error: flip.error.max(flip.coefficient.abs()),
        ..flip
    }
}

/// [`confirm`] with the doubled cycle solved a `delta` either side of
/// the flip: the flip it confirms or sets, or `None`. (Seven arguments:
/// [`confirm`]'s six and the `delta` it tries.)
async fn confirm_at(
    pace: &Pace,
    prob: &Problem,
    lambda: f64,
    theta: f64,
    flip: &Flip,
    delta: f64,
    evals: &mut u64,
) -> Option<Flip> {
    let a = flip.amplitude();
    let flip = *flip;
    for predicted in [true, false] {
        let side = if predicted { flip.side() } else { -flip.side() };
        let at = lambda + side * delta;
        let want_stable = if predicted {
            flip.coefficient > 0.0
        } else {
            flip.coefficient < 0.0
        };
        let expected = a * delta.sqrt();
        let Some(born) = born_cycle(pace, prob, at, theta, expected, evals).await else {
            continue;
        };
        let near = if predicted {
            born.half_width > expected / 3.0 && born.half_width < 3.0 * expected
        } else {
            born.half_width < 30.0 * expected
        };
        // A born cycle leaves the flip with m = +1: a cycle with m far
        // from it (beyond 0 or 2) is another one.
        let born_like = (born.multiplier - 1.0).abs() < 1.0;
        if !near || !born_like || (born.multiplier.abs() < 1.0) != want_stable {
            continue;
        }
        let born = Born {
            predicted_side: predicted,
            ..born
        };
        if predicted {
            // The cycle shows the sign: c's error no longer decides it.
            return Some(Flip {
                error: flip.error.min(0.5 * flip.coefficient.abs()),
                born: Some(born),
                ..flip
            });
        }
        // β = −dm/dλ·(λ − λ*) and η² = β/c.
        let c = -flip.dm_dlambda * (at - lambda) / (born.half_width * born.half_width);
        return Some(Flip {
            coefficient: c,
            error: (c - flip.coefficient).abs().min(0.5 * c.abs()),
            born: Some(born),
            ..flip
        });
    }
    None
}

/// The 2p-cycle next to the p-cycle through θ at λ, by Newton from θ
/// shifted by about the expected half-width either way (one that
/// converges onto the p-cycle itself, or far from θ, does not count).
async fn born_cycle(
    pace: &Pace,
    prob: &Problem,
    lambda: f64,
    theta: f64,
    expected: f64,
    evals: &mut u64,
) -> Option<Born> {
    // At the tolerance the doubling was located with (refine.rs): at the
    // solver's own, the 2p-cycle is born where its multiplier's error
    // puts it, as far from λ* as the step δ at a flip whose m is steep.
    let settings = super::refine::tighter(&prob.settings).unwrap_or(prob.settings);
    let sim = Problem { settings, ..*prob }.sim(lambda).ok()?;
    let p = prob.period;
    let opts = crate::sim::CycleOptions::for_settings(sim.settings());
    for k in [
        1.0, -1.0, 2.0, -2.0, 0.5, -0.5, 4.0, -4.0, 8.0, -8.0, 16.0, -16.0,
    ] {
        let mut spent = (0, 0);
        let c =
            super::pace::solve_cycle(pace, &sim, theta + k * expected, 2 * p, &opts, &mut spent)
                .await;
        *evals += spent.0;
        let Ok(c) = c else { continue };
        if c.minimal_period != 2 * p {
            continue;
        }
        let (i, half) = nearest_half(&c.points, theta, p);
        if half > 0.0 && crate::model::wrap_angle(c.points[i] - theta).abs() < 50.0 * expected {
            return Some(Born {
                lambda,
                theta: c.points[i],
                half_width: half,
                multiplier: c.multiplier,
                predicted_side: true,
            });
        }
    }
    None
}

/// A 2p-cycle's point nearest θ and its half-separation from its partner
/// p later: (index, |θ_{i+p} − θᵢ|/2).
pub(super) fn nearest_half(points: &[f64], theta: f64, p: usize) -> (usize, f64) {
    let off = |x: f64| crate::model::wrap_angle(x - theta).abs();
    let i = (0..points.len())
        .min_by(|&x, &y| off(points[x]).total_cmp(&off(points[y])))
        .unwrap_or(0);
    let partner = points[(i + p) % points.len()];
    (i, 0.5 * crate::model::wrap_angle(partner - points[i]).abs())
}

/// dm/dλ at `lambda` along a branch of the p-cycle, from `samples`: (λ, m)
/// at corrected points of the branch, the first two the ends of the step
/// that crossed the flip. The quadratic through the sample nearest
/// `lambda` and the next two nearest that lie apart from the chosen ones
/// by at least δ, where m's noise (1e-9·p) over δ is 1e-4 of the step's
/// slope: its error is of order m'''·δ₁δ₂ (δ₁, δ₂ their distances). With
/// fewer such samples, the secant of the two; `None` without two. Where
/// the slope has the other sign than the step's secant (a long cycle,
/// whose m changes by orders of magnitude within the samples), the
/// secant's is taken, so that the side the doubled cycle is born on is the
/// side the branch shows unstable.
pub fn branch_slope(samples: &[(f64, f64)], lambda: f64, period: usize) -> Option<f64> {
    let [(l0, m0), (l1, m1), ..] = samples else {
        return None;
    };
    let secant = (m1 - m0) / (l1 - l0);
    let noise = M_NOISE * period as f64;
    let apart = if secant.is_finite() && secant != 0.0 {
        noise / (SLOPE_NOISE * secant.abs())
    } else {
        0.0
    };
    let mut by_distance: Vec<(f64, f64)> = samples
        .iter()
        .copied()
        .filter(|(l, m)| l.is_finite() && m.is_finite())
        .collect();
    by_distance.sort_by(|a, b| (a.0 - lambda).abs().total_cmp(&(b.0 - lambda).abs()));
    let mut chosen: Vec<(f64, f64)> = Vec::with_capacity(3);
    for s in by_distance {
        if chosen.len() == 3 {
            break;
        }
        if chosen.iter().all(|c| (c.0 - s.0).abs() > apart) {
            chosen.push(s);
        }
    }
    let slope = match chosen[..] {
        [(x0, y0), (x1, y1), (x2, y2)] => {
            let f01 = (y1 - y0) / (x1 - x0);
            let f12 = (y2 - y1) / (x2 - x1);
            let f012 = (f12 - f01) / (x2 - x0);
            f01 + f012 * ((lambda - x0) + (lambda - x1))
        }
        [(x0, y0), (x1, y1)] => (y1 - y0) / (x1 - x0),
        _ => secant,
    };
    let usable = |s: f64| s.is_finite() && s != 0.0;
    if usable(secant) && usable(slope) && (slope > 0.0) != (secant > 0.0) {
        return Some(secant);
    }
    slope.is_finite().then_some(slope)
}

/// A generalised flip on a PD curve: where the flip's coefficient c
/// changes sign between two neighbouring points of the curve at which the
/// criticality is decided (|c| beyond its error); (λ₁, λ₂) there by linear
/// interpolation of c between them.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GeneralisedFlip {
    /// (λ₁, λ₂) where c is interpolated to 0.
    pub lambda: [f64; 2],
    /// c at the neighbouring decided points, in the curve's order.
    pub coefficients: [f64; 2],
}

/// The generalised flips along a PD curve of the p-cycle (`points` in
/// order; λ₁ is the parameter the flips are computed along): c at every
/// point as [`flip_at`] computes it, and each sign change
/// between consecutive decided points. Counts map evaluations in `evals`.
pub fn generalised_flips(
    base: &crate::model::Params,
    settings: &crate::integrate::SolverSettings,
    params: [super::ContParam; 2],
    period: usize,
    points: &[super::CurvePoint],
    evals: &mut u64,
) -> Vec<GeneralisedFlip> {
    let pace = Pace::new();
    let walk = generalised_flips_paced(&pace, base, settings, params, period, points, evals);
    drive(&pace, walk, &|| false)
}

/// [`generalised_flips`], a piece after each map evaluation. (Seven
/// arguments: `generalised_flips`' six, whose signature the window's
/// code calls, and the pace.)
pub(super) async fn generalised_flips_paced(
    pace: &Pace,
    base: &crate::model::Params,
    settings: &crate::integrate::SolverSettings,
    params: [super::ContParam; 2],
    period: usize,
    points: &[super::CurvePoint],
    evals: &mut u64,
) -> Vec<GeneralisedFlip> {
    let mut decided: Vec<([f64; 2], f64)> = Vec::new();
    for pt in points {
        let prob = Problem {
            base: params[1].set(base, pt.lambda[1]),
            settings: *settings,
            param: params[0],
            period,
        };
        let Ok(est) = coefficient(pace, &prob, pt.lambda[0], pt.theta, None, evals).await else {
            continue;
        };
        if est.c.abs() > est.error {
            decided.push((pt.lambda, est.c));
        }
    }
    decided
        .windows(2)
        .filter(|w| (w[0].1 > 0.0) != (w[1].1 > 0.0))
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let s = a.1 / (a.1 - b.1);
            GeneralisedFlip {
                lambda: [
                    a.0[0] + s * (b.0[0] - a.0[0]),
                    a.0[1] + s * (b.0[1] - a.0[1]),
                ],
                coefficients: [a.1, b.1],
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_branch_slope_is_the_derivative_at_the_zero_despite_noise() {
        // m(λ) = −1 + 3(λ − λ*) − 40(λ − λ*)² + 500(λ − λ*)³; samples as a
        // location leaves them: the step's ends, then trials closing in,
        // the last ones 1e-11 apart with noise of 1e-9 in m.
        let star = 1.2;
        let m = |l: f64| {
            let d = l - star;
            -1.0 + 3.0 * d - 40.0 * d * d + 500.0 * d * d * d
        };
        let mut samples: Vec<(f64, f64)> = [star - 4e-3, star + 6e-3, star + 1e-4, star - 2e-6]
            .iter()
            .map(|&l| (l, m(l)))
            .collect();
        samples.push((star + 1e-11, m(star + 1e-11) + 1e-9));
        samples.push((star - 1e-11, m(star - 1e-11) - 1e-9));
        let slope = branch_slope(&samples, star, 1).unwrap();
        assert!((slope - 3.0).abs() < 1e-3, "{slope}");
        // The two closest samples alone would give a slope off by 30 %.
        let close = (samples[4].1 - samples[5].1) / 2e-11;
        assert!((close - 3.0).abs() > 0.3 * 3.0, "{close}");
        // Just the step's ends: their secant.
        let ends = branch_slope(&samples[..2], star, 1).unwrap();
        assert!((ends - (m(star + 6e-3) - m(star - 4e-3)) / 1e-2).abs() < 1e-12);
        assert_eq!(branch_slope(&samples[..1], star, 1), None);
        // A local slope against the step's secant gives way to the secant.
        let against = [
            (0.0, 0.0),
            (1.0, 1.0),
            (0.5, 10.0),
            (0.501, 9.9),
            (0.499, 10.1),
        ];
        assert_eq!(branch_slope(&against, 0.5, 1), Some(1.0));
    }
}
