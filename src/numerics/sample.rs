//! The fixed sample of attractor points the work-precision chart measures
//! on, with each point's reference iterate.

use serde::Serialize;

use super::fixed_sample;
use crate::integrate::{Method, SolverSettings};
use crate::model::Params;
use crate::sim::{OrbitOptions, SimError, Simulator, SlipEvent, cycles_in_lanes};

/// One map iterate as the measurement compares it: θ', the stop point, the
/// slip duration and what it cost.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Iterate {
    pub theta_next: f64,
    pub stop: [f64; 2],
    pub slip_duration: f64,
    pub rhs_evals: u64,
}

impl From<&SlipEvent> for Iterate {
    fn from(e: &SlipEvent) -> Self {
        Iterate {
            theta_next: e.theta_next,
            stop: [e.stop_x, e.stop_y],
            slip_duration: e.slip_duration,
            rhs_evals: e.rhs_evals,
        }
    }
}

/// An attractor the sample takes points from: an orbit of the reference
/// integrator from `theta0`, after `transient` iterates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Attractor {
    pub name: &'static str,
    pub params: Params,
    pub theta0: f64,
    pub transient: usize,
    /// A point measured in addition to the orbit's (a known hard case).
    pub extra: Option<f64>,
    /// The orbit's onsets, computed once and committed
    /// ([`super::fixed_sample`]): a sample of up to this many points takes
    /// its first ones instead of recomputing the orbit, so that it stays the
    /// same when the integrator's roundings change.
    pub fixed: Option<&'static [f64]>,
}

const fn p(kappa: f64, gamma: f64, nu: f64, theta_nu: f64) -> Params {
    Params {
        kappa,
        gamma,
        nu,
        theta_nu,
        omega: 50.0,
    }
}

/// The default sample: one attractor per regime, the two chaotic ones of the
/// issue, and a long-stick one near θν = π/2.
///
/// - `creep`: pure creep (γ = 0.5, κ = 3, ν = 1e-3, θν = 0.7), the orbit
///   approaching its fixed point (it takes thousands of iterates to settle);
/// - `stick-slip chaos`: Fig. 3b's chaotic band (κ = 18.95, ν = 1e-3, θν = 1.25);
/// - `mixed intermittent`: Fig. 3a's intermittent creep and large slips
///   (κ = 50, ν = 1e-4, θν = 1.4), plus θ = 0.234420692047657, where the
///   error at a given tolerance was seen to jump;
/// - `long stick`: κ = 50, ν = 1e-4, θν = 1.55, where an error in the stop's
///   x grows by about tan θν ≈ 48 on the way back to C.
pub fn default_attractors() -> Vec<Attractor> {
    vec![
        Attractor {
            name: "creep",
            params: p(3.0, 0.5, 1e-3, 0.7),
            theta0: 0.9,
            transient: 20,
            extra: None,
            fixed: Some(&fixed_sample::CREEP),
        },
        Attractor {
            name: "stick-slip chaos",
            params: p(18.95, 6.5, 1e-3, 1.25),
            theta0: 1.25,
            transient: 300,
            extra: None,
            fixed: Some(&fixed_sample::CHAOS),
        },
        Attractor {
            name: "mixed intermittent",
            params: p(50.0, 6.5, 1e-4, 1.4),
            theta0: 1.4,
            transient: 300,
            extra: Some(0.234420692047657),
            fixed: Some(&fixed_sample::INTERMITTENT),
        },
        Attractor {
            name: "long stick",
            params: p(50.0, 6.5, 1e-4, 1.55),
            theta0: 1.55,
            transient: 300,
            extra: None,
            fixed: Some(&fixed_sample::LONG_STICK),
        },
    ]
}

/// The reference: DOP853 at 1e-14.
pub fn reference_settings() -> SolverSettings {
    SolverSettings::adaptive(Method::Dop853, 1e-14)
}

/// Its cross-check: DP5(4) at 1e-13.
pub fn check_settings() -> SolverSettings {
    SolverSettings {
        max_steps: 2_000_000,
        ..SolverSettings::adaptive(Method::Dp54, 1e-13)
    }
}

/// One point of the sample with its reference iterate and the cross-check.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SamplePoint {
    /// Index into the attractor list.
    pub attractor: usize,
    pub params: Params,
    pub theta: f64,
    pub reference: Iterate,
    pub check: Iterate,
}

impl SamplePoint {
    /// |θ'_ref − θ'_check|: how far the reference can be trusted.
    pub fn reference_spread(&self) -> f64 {
        crate::model::wrap_angle(self.reference.theta_next - self.check.theta_next).abs()
    }
}

/// `per_attractor` consecutive orbit points of each attractor (plus its
/// extra point), with their references: the committed ones where the
/// attractor has enough, else a fresh orbit of the reference integrator.
pub fn build_sample(
    attractors: &[Attractor],
    per_attractor: usize,
) -> Result<Vec<SamplePoint>, SimError> {
    build_sample_until(attractors, per_attractor, &|| false)
}

/// [`build_sample`] that polls `cancel` once per reference cycle (the app's
/// worker builds a sample on the current attractor and must be able to stop
/// it); a cancelled build returns `SimError::Cancelled`.
pub fn build_sample_until(
    attractors: &[Attractor],
    per_attractor: usize,
    cancel: &dyn Fn() -> bool,
) -> Result<Vec<SamplePoint>, SimError> {
    let mut out = Vec::new();
    for (i, a) in attractors.iter().enumerate() {
        let reference = Simulator::new(a.params, reference_settings())?;
        let check = Simulator::new(a.params, check_settings())?;
        let mut thetas = match a.fixed {
            Some(fixed) if fixed.len() >= per_attractor => fixed[..per_attractor].to_vec(),
            _ => reference
                .orbit(
                    a.theta0,
                    &OrbitOptions {
                        transient: a.transient,
                        keep: per_attractor,
                        lyapunov: false,
                        period_tol: 1e-9,
                    },
                    cancel,
                )?
                .thetas(),
        };
        thetas.extend(a.extra);
        // Two points' reference cycles at a time, stepped together (bitwise
        // the values one at a time would give); DP5(4)'s checks one by one.
        for pair in thetas.chunks(2) {
            if cancel() {
                return Err(SimError::Cancelled);
            }
            let tasks: Vec<_> = pair.iter().map(|&th| (&reference, th, 0.0)).collect();
            for (&theta, r) in pair.iter().zip(cycles_in_lanes(&tasks)) {
                let r = r?;
                let c = check.cycle(theta, 0.0, None)?;
                out.push(SamplePoint {
                    attractor: i,
                    params: a.params,
                    theta,
                    reference: Iterate::from(&r),
                    check: Iterate::from(&c),
                });
            }
        }
    }
    Ok(out)
}
