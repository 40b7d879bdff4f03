//! What a two-parameter curve is asked for and what it gives: its kind
//! (a doubling or a fold), the walk's options, its points, the curve with
//! why each end stopped, and what a curve of a family shares ([`CurveOf`]).
//! The walk itself is `curve`.

use super::ContParam;
use crate::integrate::SolverSettings;
use crate::model::Params;

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

    /// λ per unit of μ: the box's widths.
    pub fn scale(&self) -> [f64; 2] {
        self.bounds.map(|b| (b[1] - b[0]).abs().max(1e-300))
    }
}

/// One point of a curve.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CurvePoint {
    /// (λ₁, λ₂).
    pub lambda: [f64; 2],
    /// A point θ₀ of the cycle there.
    pub theta: f64,
    /// The multiplier (−1 or +1 to the corrector's accuracy).
    pub multiplier: f64,
}

/// A continued curve: one polyline.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
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
    /// On a PD curve, where its flip's coefficient changes sign
    /// ([`super::generalised_flips`]); empty on a fold curve.
    pub generalised_flips: Vec<super::GeneralisedFlip>,
}

/// The curve asked for: where the p-cycle (`period`) meets the `kind`
/// condition in the parameter pair `params` (λ₁, λ₂), the other
/// parameters at `base`'s, computed with `settings`. What every function
/// on curves shares, as one value rather than five arguments each.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveOf {
    /// The parameters not on the curve (λ₂'s value here is where a start
    /// on a branch in λ₁ lies).
    pub base: Params,
    /// The solver and its accuracy.
    pub settings: SolverSettings,
    /// (λ₁, λ₂).
    pub params: [ContParam; 2],
    /// The cycle's period.
    pub period: usize,
    /// Which condition the curve is of.
    pub kind: CurveKind,
}

impl CurveOf {
    /// The curve `curve` is a run of, at this one's base and solver.
    pub fn of(&self, curve: &Curve) -> CurveOf {
        CurveOf {
            params: curve.params,
            period: curve.period,
            kind: curve.kind,
            ..*self
        }
    }
}
