//! The fixed sample of attractor points the work-precision chart measures
//! on, with each point's reference iterate.

use serde::Serialize;

use super::fixed_sample;
use crate::integrate::{Method, SolverSettings};
use crate::model::Params;
use crate::sim::{OrbitOptions, OrbitRun, SimError, Simulator, SlipEvent, cycles_in_lanes};

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
    let mut build = SampleBuild::new(attractors, per_attractor);
    loop {
        if let Some(done) = build.advance(cancel) {
            return done;
        }
    }
}

/// [`build_sample_until`] one piece at a time, so that a host on a slice
/// of time (the browser's) can stop between two and go on later with the
/// same sample bit for bit. A piece is one reference cycle of an
/// attractor's orbit, two points' reference cycles (stepped together,
/// bitwise what one at a time gives), or one point's DP5(4) check.
pub struct SampleBuild {
    attractors: Vec<Attractor>,
    per_attractor: usize,
    /// The attractor being sampled.
    at: usize,
    stage: Stage,
    out: Vec<SamplePoint>,
}

enum Stage {
    /// The attractor's simulators are yet to be made.
    Start,
    /// Its orbit under the reference integrator, a cycle a piece (only
    /// its onsets are wanted: it is not settled).
    Orbit(Box<(Simulator, Simulator, OrbitRun)>),
    /// Its points: the references of the next pair, then each point's
    /// check.
    Points {
        sims: Box<(Simulator, Simulator)>,
        thetas: Vec<f64>,
        /// Points with their reference, awaiting their check.
        referenced: Vec<(f64, Iterate)>,
        next: usize,
    },
}

impl SampleBuild {
    /// `per_attractor` points of each of `attractors`, nothing computed.
    pub fn new(attractors: &[Attractor], per_attractor: usize) -> Self {
        SampleBuild {
            attractors: attractors.to_vec(),
            per_attractor,
            at: 0,
            stage: Stage::Start,
            out: Vec::new(),
        }
    }

    /// One piece (`cancel` polled before a reference cycle) and `None`,
    /// or the sample once built.
    pub fn advance(
        &mut self,
        cancel: &dyn Fn() -> bool,
    ) -> Option<Result<Vec<SamplePoint>, SimError>> {
        match self.piece(cancel) {
            Ok(true) => Some(Ok(std::mem::take(&mut self.out))),
            Ok(false) => None,
            Err(e) => Some(Err(e)),
        }
    }

    /// One piece: `true` once the sample is built.
    fn piece(&mut self, cancel: &dyn Fn() -> bool) -> Result<bool, SimError> {
        let Some(a) = self.attractors.get(self.at).copied() else {
            return Ok(true);
        };
        match &mut self.stage {
            Stage::Start => {
                let reference = Simulator::new(a.params, reference_settings())?;
                let check = Simulator::new(a.params, check_settings())?;
                self.stage = match a.fixed {
                    Some(fixed) if fixed.len() >= self.per_attractor => {
                        let mut thetas = fixed[..self.per_attractor].to_vec();
                        thetas.extend(a.extra);
                        Stage::points((reference, check), thetas)
                    }
                    _ => {
                        let opts = OrbitOptions {
                            transient: a.transient,
                            keep: self.per_attractor,
                            lyapunov: false,
                            period_tol: 1e-9,
                        };
                        let run = OrbitRun::new(&reference, a.theta0, &opts)?;
                        Stage::Orbit(Box::new((reference, check, run)))
                    }
                };
            }
            Stage::Orbit(o) => {
                let (reference, _, run) = &mut **o;
                if !run.settling() {
                    if let Some(Err(e)) = run.advance(reference, cancel) {
                        return Err(e);
                    }
                    return Ok(false);
                }
                let mut thetas: Vec<f64> = run.events().iter().map(|e| e.theta).collect();
                thetas.extend(a.extra);
                let Stage::Orbit(o) = std::mem::replace(&mut self.stage, Stage::Start) else {
                    unreachable!("matched above");
                };
                let (reference, check, _) = *o;
                self.stage = Stage::points((reference, check), thetas);
            }
            Stage::Points {
                sims,
                thetas,
                referenced,
                next,
            } => {
                let (reference, check) = &**sims;
                if let Some((theta, r)) = referenced.first().copied() {
                    let c = check.cycle(theta, 0.0, None)?;
                    referenced.remove(0);
                    self.out.push(SamplePoint {
                        attractor: self.at,
                        params: a.params,
                        theta,
                        reference: r,
                        check: Iterate::from(&c),
                    });
                } else if *next < thetas.len() {
                    if cancel() {
                        return Err(SimError::Cancelled);
                    }
                    let pair = &thetas[*next..(*next + 2).min(thetas.len())];
                    let tasks: Vec<_> = pair.iter().map(|&th| (reference, th, 0.0)).collect();
                    for (&theta, r) in pair.iter().zip(cycles_in_lanes(&tasks)) {
                        referenced.push((theta, Iterate::from(&r?)));
                    }
                    *next += pair.len();
                } else {
                    self.at += 1;
                    self.stage = Stage::Start;
                }
            }
        }
        Ok(self.at >= self.attractors.len())
    }
}

impl Stage {
    fn points(sims: (Simulator, Simulator), thetas: Vec<f64>) -> Stage {
        Stage::Points {
            sims: Box::new(sims),
            thetas,
            referenced: Vec::new(),
            next: 0,
        }
    }
}
