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
//! from θ (not a cycle off θ*); g'' = M' and g''' = M'' come from the
//! five-point central differences of M at three steps h = 0.01, h/2, h/4
//! (eight evaluations of M besides the one at θ*, as ±2·(h/2) = ±h). M carries
//! the integrator's error (about 1e-9 relative), which the quotients
//! divide by h²; their truncation error grows like h⁴. The pair of
//! neighbouring steps whose estimates of c agree best is kept: the
//! smaller step's value, and the difference as its error. Where the
//! error exceeds |c|, the criticality is not decided (near a generalised
//! flip, where c changes sign). The multiplier's rate along the branch,
//! dm/dλ = M'·dθ*/dλ + ∂M/∂λ (dθ*/dλ = G_λ/2 at m = −1), takes one more
//! central difference, in λ.

use super::{EvalError, Problem};

/// The step h of the differences in θ for a fixed point (M at θ* ± h and
/// ± 2h); a p-cycle's is h/p.
const STEP: f64 = 5e-3;
/// The relative step of the difference in λ (of the range's scale).
const LAMBDA_STEP: f64 = 1e-5;

/// A flip's normal form, at a located period doubling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flip {
    /// c = g''²/4 + g'''/6: positive for a supercritical flip.
    pub coefficient: f64,
    /// The coefficient's error, estimated from two difference steps.
    pub error: f64,
    /// dm/dλ along the p-cycle's branch at the flip.
    pub dm_dlambda: f64,
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
/// located period doubling of `prob` whose multiplier there is `m0`
/// (computed when `None`); `g_lambda` is G_λ there and `scale` the range's
/// length (for the λ step). Counts map evaluations in `evals`.
pub fn flip_at(
    prob: &Problem,
    lambda: f64,
    theta: f64,
    m0: Option<f64>,
    g_lambda: f64,
    scale: f64,
    evals: &mut u64,
) -> Result<Flip, EvalError> {
    let (coefficient, error, d2, m0) = coefficient(prob, lambda, theta, m0, evals)?;
    // ∂M/∂λ by a forward difference at θ* held: its truncation error is
    // ~1e-5 relative, its noise (M's 1e-9 over the step) ~1e-4 absolute.
    let hl = LAMBDA_STEP * scale;
    let s = prob.sim(lambda + hl).map_err(EvalError::Sim)?;
    let m_up = super::eval_at(&s, prob.param, prob.period, theta, evals)?.multiplier;
    let dm_partial = (m_up - m0) / hl;
    // On the branch, dθ*/dλ = −G_λ/G_θ = G_λ/2 at m = −1.
    let dm_dlambda = d2 * (0.5 * g_lambda) + dm_partial;
    if !dm_dlambda.is_finite() {
        return Err(EvalError::NonFinite);
    }
    Ok(Flip {
        coefficient,
        error,
        dm_dlambda,
    })
}

/// The coefficient c at θ*, its error, g'' = M'(θ*) and M(θ*): from M at θ* ± h
/// and θ* ± 2h, c by the five-point differences, its error as the
/// difference from c by the three-point ones at ± h (second order against
/// fourth: a pessimistic bound on the five-point value's error, large
/// wherever M is not smooth over ± 2h).
fn coefficient(
    prob: &Problem,
    lambda: f64,
    theta: f64,
    m0: Option<f64>,
    evals: &mut u64,
) -> Result<(f64, f64, f64, f64), EvalError> {
    let sim = prob.sim(lambda).map_err(EvalError::Sim)?;
    let mut m_at = |dx: f64| -> Result<f64, EvalError> {
        Ok(super::eval_at(&sim, prob.param, prob.period, theta + dx, evals)?.multiplier)
    };
    let m0 = match m0 {
        Some(m) => m,
        None => m_at(0.0)?,
    };
    // g = f^p bends on a scale that shrinks with p (its derivatives grow
    // like products of p slopes): the step shrinks with it.
    let h = STEP / prob.period as f64;
    let (p1, n1, p2, n2) = (m_at(h)?, m_at(-h)?, m_at(2.0 * h)?, m_at(-2.0 * h)?);
    let c_of = |d2: f64, d3: f64| 0.25 * d2 * d2 + d3 / 6.0;
    let d2 = (n2 - 8.0 * n1 + 8.0 * p1 - p2) / (12.0 * h);
    let d3 = (-n2 + 16.0 * n1 - 30.0 * m0 + 16.0 * p1 - p2) / (12.0 * h * h);
    let c = c_of(d2, d3);
    let c3 = c_of((p1 - n1) / (2.0 * h), (p1 - 2.0 * m0 + n1) / (h * h));
    let error = (c - c3).abs();
    if !(c.is_finite() && error.is_finite()) {
        return Err(EvalError::NonFinite);
    }
    Ok((c, error, d2, m0))
}

/// A generalised flip on a PD curve: where the flip's coefficient c
/// changes sign between two neighbouring points of the curve at which the
/// criticality is decided (|c| beyond its error); (λ₁, λ₂) there by linear
/// interpolation of c between them.
#[derive(Clone, Copy, Debug, PartialEq)]
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
    let decided: Vec<([f64; 2], f64)> = points
        .iter()
        .filter_map(|pt| {
            let prob = Problem {
                base: params[1].set(base, pt.lambda[1]),
                settings: *settings,
                param: params[0],
                period,
            };
            let (c, error, ..) = coefficient(&prob, pt.lambda[0], pt.theta, None, evals).ok()?;
            (c.abs() > error).then_some((pt.lambda, c))
        })
        .collect();
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
