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

/// The steps of the differences in θ: h₀ and its halves.
const STEP0: f64 = 2e-2;
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
/// located period doubling of `prob`; `g_lambda` is G_λ there and `scale`
/// the range's length (for the λ step). Counts map evaluations in `evals`.
pub fn flip_at(
    prob: &Problem,
    lambda: f64,
    theta: f64,
    g_lambda: f64,
    scale: f64,
    evals: &mut u64,
) -> Result<Flip, EvalError> {
    let sim = prob.sim(lambda).map_err(EvalError::Sim)?;
    let mut m_at = |dx: f64| -> Option<f64> {
        super::eval_at(&sim, prob.param, prob.period, theta + dx, evals)
            .ok()
            .map(|e| e.multiplier)
    };
    let m0 = m_at(0.0).ok_or(EvalError::NonFinite)?;
    // M at ±h₀/2^k for k = 0 … 3 (the stencils at h₀, h₀/2, h₀/4 use
    // ±h and ±2h).
    let mut plus = [None; 4];
    let mut minus = [None; 4];
    for k in 0..4 {
        let h = STEP0 / f64::from(1u32 << k);
        plus[k] = m_at(h);
        minus[k] = m_at(-h);
    }
    // (c, g'') at the step h₀/2^(k+1), k = 0 … 2.
    let stencil = |k: usize| -> Option<(f64, f64)> {
        let h = STEP0 / f64::from(2u32 << k);
        let (p1, p2, n1, n2) = (plus[k + 1]?, plus[k]?, minus[k + 1]?, minus[k]?);
        let d2 = (n2 - 8.0 * n1 + 8.0 * p1 - p2) / (12.0 * h);
        let d3 = (-n2 + 16.0 * n1 - 30.0 * m0 + 16.0 * p1 - p2) / (12.0 * h * h);
        let c = 0.25 * d2 * d2 + d3 / 6.0;
        c.is_finite().then_some((c, d2))
    };
    let est: Vec<(f64, f64)> = (0..3).filter_map(stencil).collect();
    let (coefficient, error, d2) = match est.len() {
        0 => return Err(EvalError::NonFinite),
        1 => (est[0].0, est[0].0.abs(), est[0].1),
        _ => est
            .windows(2)
            .map(|w| (w[1].0, (w[1].0 - w[0].0).abs(), w[1].1))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .ok_or(EvalError::NonFinite)?,
    };
    // ∂M/∂λ by a central difference at θ* held.
    let hl = LAMBDA_STEP * scale;
    let mut m_lambda = |l: f64| -> Result<f64, EvalError> {
        let s = prob.sim(l).map_err(EvalError::Sim)?;
        Ok(super::eval_at(&s, prob.param, prob.period, theta, evals)?.multiplier)
    };
    let dm_partial = (m_lambda(lambda + hl)? - m_lambda(lambda - hl)?) / (2.0 * hl);
    // On the branch, dθ*/dλ = −G_λ/G_θ = G_λ/2 at m = −1.
    let dm_dlambda = d2 * (0.5 * g_lambda) + dm_partial;
    if !(dm_dlambda.is_finite() && coefficient.is_finite()) {
        return Err(EvalError::NonFinite);
    }
    Ok(Flip {
        coefficient,
        error,
        dm_dlambda,
    })
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
/// order; λ₁ is the parameter the flips are computed along, with range
/// scale `scale`): c at every point by [`flip_at`], and each sign change
/// between consecutive decided points. Counts map evaluations in `evals`.
pub fn generalised_flips(
    base: &crate::model::Params,
    settings: &crate::integrate::SolverSettings,
    params: [super::ContParam; 2],
    period: usize,
    points: &[super::CurvePoint],
    scale: f64,
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
            let f = flip_at(&prob, pt.lambda[0], pt.theta, 0.0, scale, evals).ok()?;
            (f.coefficient.abs() > f.error).then_some((pt.lambda, f.coefficient))
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
