//! Continuation of cycles in one parameter, and of their period doublings
//! and folds in two (docs/continuation.md).
//!
//! A period-p cycle is a zero of G(θ, λ) = wrap(f^p(θ; λ) − θ). Its
//! partial derivatives come from the exact map derivatives
//! ([`Simulator::cycle_derivatives`]) by the chain rule along the cycle:
//! G_θ = Π f'(θᵢ) − 1 (the multiplier less one), and G_λ = d_p with
//! d₀ = 0, d_{i+1} = f'(θᵢ)·dᵢ + ∂f/∂λ(θᵢ). The zero set is a curve in the
//! (θ, λ) plane, followed by pseudo-arclength ([`continue_branch`]) through
//! folds and through both its stable and unstable parts.

mod branch;
mod cascade;
mod curve;
mod curve_types;
mod curves;
mod flip;
mod pace;
mod refine;
mod stencil;
mod switch;
mod tip;
mod walk;

use crate::integrate::SolverSettings;
use crate::model::{Params, wrap_angle};
use crate::sim::variational::{
    D_GAMMA, D_KAPPA, D_NU, D_OMEGA, D_THETA, D_THETA_NU, MapDerivatives, NotDifferentiable,
};
use crate::sim::{SimError, Simulator};

pub use branch::{Branch, BranchPoint, ContOptions, M_ACCURACY, SpecialKind, SpecialPoint, Stop};
pub use cascade::{
    Cascade, FirstLevel, cascade, cascade_paced, cascade_reporting, feigenbaum_ratios,
};
pub use curve::{Curve, CurveKind, CurveOf, CurveOptions, CurvePoint};
pub use curves::{
    continue_curve, continue_curve_paced, continue_curves, continue_curves_paced, curve_crossings,
};
pub use flip::{Criticality, Flip, GeneralisedFlip, branch_slope, flip_at, generalised_flips};
pub use pace::{Ask, Pace, drive, one_piece};
pub use stencil::Stencil;
pub use walk::{Reach, continue_branch, continue_branch_paced, continue_branch_reporting};

/// A parameter a branch can be continued in (and a bifurcation diagram
/// drawn over; θν, the paper's, by default).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum ContParam {
    /// θν, the pulling direction.
    #[default]
    ThetaNu,
    /// κ, the spring anisotropy.
    Kappa,
    /// γ, the friction weakening.
    Gamma,
    /// ν, the pulling speed.
    Nu,
    /// Ω, the memory of the friction direction.
    Omega,
}

/// `lambda` moved onto the end of the model's range of `param` when it
/// lies past it by a rounding (1e-9 relative): a branch that ends at the
/// range's end reaches it through the scaled coordinate λ/scale·scale,
/// which may land a few ulps outside.
fn snap(param: ContParam, lambda: f64) -> f64 {
    let range = match param {
        ContParam::Kappa => crate::model::KAPPA_RANGE,
        ContParam::Gamma => crate::model::GAMMA_RANGE,
        ContParam::Nu => crate::model::NU_RANGE,
        ContParam::ThetaNu | ContParam::Omega => return lambda,
    };
    let (lo, hi) = (*range.start(), *range.end());
    let near = |end: f64| (lambda - end).abs() <= 1e-9 * end.abs();
    if lambda > hi && near(hi) {
        hi
    } else if lambda < lo && near(lo) {
        lo
    } else {
        lambda
    }
}

impl ContParam {
    /// All five, in the command line's order.
    pub const ALL: [ContParam; 5] = [
        ContParam::ThetaNu,
        ContParam::Kappa,
        ContParam::Gamma,
        ContParam::Nu,
        ContParam::Omega,
    ];

    /// The parameter the command line calls `name` (`theta-nu`, `kappa`, …).
    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }

    /// The command line's name, as the model flags spell it.
    pub fn name(self) -> &'static str {
        match self {
            ContParam::ThetaNu => "theta-nu",
            ContParam::Kappa => "kappa",
            ContParam::Gamma => "gamma",
            ContParam::Nu => "nu",
            ContParam::Omega => "omega",
        }
    }

    /// Whether its values span decades (κ, ν, Ω): a diagram in it is laid
    /// out on a log axis, its columns evenly spaced in log10 of the value
    /// ([`crate::sim::param_grid`]), as the window's sliders move it.
    pub fn spans_decades(self) -> bool {
        matches!(self, ContParam::Kappa | ContParam::Nu | ContParam::Omega)
    }

    /// The paper's symbol (θν, κ, γ, ν, Ω).
    pub fn symbol(self) -> &'static str {
        match self {
            ContParam::ThetaNu => "θν",
            ContParam::Kappa => "κ",
            ContParam::Gamma => "γ",
            ContParam::Nu => "ν",
            ContParam::Omega => "Ω",
        }
    }

    /// The CSV column's name.
    pub fn column(self) -> &'static str {
        match self {
            ContParam::ThetaNu => "theta_nu",
            other => other.name(),
        }
    }

    /// Its value in `p`.
    pub fn get(self, p: &Params) -> f64 {
        match self {
            ContParam::ThetaNu => p.theta_nu,
            ContParam::Kappa => p.kappa,
            ContParam::Gamma => p.gamma,
            ContParam::Nu => p.nu,
            ContParam::Omega => p.omega,
        }
    }

    /// `p` with this parameter set to `v`.
    pub fn set(self, p: &Params, v: f64) -> Params {
        let mut q = *p;
        match self {
            ContParam::ThetaNu => q.theta_nu = v,
            ContParam::Kappa => q.kappa = v,
            ContParam::Gamma => q.gamma = v,
            ContParam::Nu => q.nu = v,
            ContParam::Omega => q.omega = v,
        }
        q
    }

    /// This parameter's direction among the map's derivatives
    /// (`Simulator::cycle_partials`).
    pub fn direction(self) -> usize {
        match self {
            ContParam::ThetaNu => D_THETA_NU,
            ContParam::Kappa => D_KAPPA,
            ContParam::Gamma => D_GAMMA,
            ContParam::Nu => D_NU,
            ContParam::Omega => D_OMEGA,
        }
    }

    /// ∂f/∂λ for this parameter.
    pub fn partial(self, d: &MapDerivatives) -> f64 {
        match self {
            ContParam::ThetaNu => d.d_theta_nu,
            ContParam::Kappa => d.d_kappa,
            ContParam::Gamma => d.d_gamma,
            ContParam::Nu => d.d_nu,
            ContParam::Omega => d.d_omega,
        }
    }
}

/// Why G could not be evaluated with its derivatives at a point.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EvalError {
    /// A cycle point is where f has no derivative: a border of the branch.
    #[error("at theta = {theta}: {reason}")]
    NotDifferentiable {
        /// The cycle point.
        theta: f64,
        /// Why.
        reason: NotDifferentiable,
    },
    /// A cycle point left the exit arc (the map is not defined there).
    #[error("theta = {theta} is off the exit arc")]
    OffArc {
        /// The point.
        theta: f64,
    },
    /// The parameters are invalid or the integration failed.
    #[error(transparent)]
    Sim(SimError),
    /// G or a derivative overflowed (a multiplier beyond f64's range).
    #[error("the cycle's derivatives are not finite")]
    NonFinite,
}

impl EvalError {
    /// Whether this marks the edge of the map's smooth part (a border),
    /// rather than a failure of the computation.
    pub fn is_border(&self) -> bool {
        matches!(
            self,
            EvalError::NotDifferentiable { .. } | EvalError::OffArc { .. }
        )
    }
}

/// G and its derivatives at one (θ, λ).
#[derive(Clone, Debug, PartialEq)]
pub struct Eval {
    /// G = wrap(f^p(θ) − θ).
    pub g: f64,
    /// Π f'(θᵢ): G_θ = multiplier − 1.
    pub multiplier: f64,
    /// G_λ = ∂f^p/∂λ.
    pub g_lambda: f64,
    /// θ₀ … θ_{p−1}.
    pub points: Vec<f64>,
    /// f'(θ₀) … f'(θ_{p−1}), whose product is the multiplier.
    pub slopes: Vec<f64>,
}

/// What every evaluation of G shares: the fixed parameters, the solver,
/// the parameter varied and the period.
#[derive(Clone, Copy, Debug)]
pub struct Problem {
    /// The parameters; the varied one is overridden at each evaluation.
    pub base: Params,
    /// The integrator.
    pub settings: SolverSettings,
    /// The parameter varied.
    pub param: ContParam,
    /// The period p.
    pub period: usize,
}

impl Problem {
    /// The simulator at λ.
    pub fn sim(&self, lambda: f64) -> Result<Simulator, SimError> {
        Simulator::new(
            self.param.set(&self.base, snap(self.param, lambda)),
            self.settings,
        )
    }

    /// The same problem at another period.
    pub fn with_period(&self, period: usize) -> Self {
        Problem { period, ..*self }
    }

    /// G, G_θ + 1 and G_λ at (θ, λ), counting map evaluations in `evals`.
    pub fn eval(&self, theta: f64, lambda: f64, evals: &mut u64) -> Result<Eval, EvalError> {
        let pace = Pace::new();
        drive(&pace, self.eval_paced(&pace, theta, lambda, evals), &|| {
            false
        })
    }

    /// [`Problem::eval`], a piece after each map evaluation.
    pub(super) async fn eval_paced(
        &self,
        pace: &Pace,
        theta: f64,
        lambda: f64,
        evals: &mut u64,
    ) -> Result<Eval, EvalError> {
        let sim = self.sim(lambda).map_err(EvalError::Sim)?;
        eval_paced(pace, &sim, self.param, self.period, theta, evals).await
    }
}

/// G and its derivatives for `sim` (see the module notes).
pub fn eval_at(
    sim: &Simulator,
    param: ContParam,
    period: usize,
    theta: f64,
    evals: &mut u64,
) -> Result<Eval, EvalError> {
    let pace = Pace::new();
    drive(
        &pace,
        eval_paced(&pace, sim, param, period, theta, evals),
        &|| false,
    )
}

/// [`eval_at`], a piece after each map evaluation.
pub(super) async fn eval_paced(
    pace: &Pace,
    sim: &Simulator,
    param: ContParam,
    period: usize,
    theta: f64,
    evals: &mut u64,
) -> Result<Eval, EvalError> {
    let mut th = theta;
    let mut multiplier = 1.0;
    let mut d_lambda = 0.0;
    let mut points = Vec::with_capacity(period);
    let mut slopes = Vec::with_capacity(period);
    for _ in 0..period {
        if sim.check_onset(th).is_err() {
            return Err(EvalError::OffArc { theta: th });
        }
        points.push(th);
        let dirs = [D_THETA, param.direction()];
        let (ev, d, _) = sim.cycle_partials(th, 0.0, dirs).map_err(EvalError::Sim)?;
        *evals += 1;
        pace.piece().await;
        let [d_theta, d_param] =
            d.map_err(|reason| EvalError::NotDifferentiable { theta: th, reason })?;
        if ev.restarted {
            return Err(EvalError::NotDifferentiable {
                theta: th,
                reason: NotDifferentiable::Restart,
            });
        }
        d_lambda = d_theta * d_lambda + d_param;
        multiplier *= d_theta;
        slopes.push(d_theta);
        th = ev.theta_next;
    }
    let g = wrap_angle(th - theta);
    if !(g.is_finite() && multiplier.is_finite() && d_lambda.is_finite()) {
        return Err(EvalError::NonFinite);
    }
    Ok(Eval {
        g,
        multiplier,
        g_lambda: d_lambda,
        points,
        slopes,
    })
}

/// The attractor a branch starts from, when no seed is given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Attractor {
    /// A solved p-cycle through `theta`.
    Cycle { period: usize, theta: f64 },
    /// Periodic with this period, but its cycle was not solved.
    Unsolved(usize),
    /// No period up to the detector's limit.
    Aperiodic,
}

impl Attractor {
    /// What it is, for a message: "has period 2", "is aperiodic".
    pub fn describe(self) -> String {
        match self {
            Attractor::Cycle { period, .. } => format!("has period {period}"),
            Attractor::Unsolved(q) => format!("has period {q} but no cycle was solved"),
            Attractor::Aperiodic => "is aperiodic".into(),
        }
    }
}

/// The attractor at `params` from the exit arc's start: 2000 iterates
/// dropped, the period detector on 256 more, the cycle solved where it is
/// periodic. The seed of a branch when none is given (the command line's
/// `continue` without `--theta`, the window's Find bifurcations).
pub fn attractor_cycle(
    params: Params,
    settings: SolverSettings,
    cancel: &dyn Fn() -> bool,
) -> Result<Attractor, SimError> {
    let pace = Pace::new();
    drive(
        &pace,
        attractor_cycle_paced(&pace, params, settings),
        cancel,
    )
}

/// [`attractor_cycle`], a piece after each slip cycle (the settling one
/// piece), a cancel before each.
pub async fn attractor_cycle_paced(
    pace: &Pace,
    params: Params,
    settings: SolverSettings,
) -> Result<Attractor, SimError> {
    let sim = Simulator::new(params, settings)?;
    let (psi, _) = crate::model::exit_arc(params.kappa, params.theta_nu);
    let opts = crate::sim::OrbitOptions {
        transient: 2000,
        keep: 256,
        lyapunov: false,
        period_tol: crate::sim::OrbitOptions::period_tol_for(settings.rtol),
    };
    let mut run = crate::sim::OrbitRun::new(&sim, psi, &opts)?;
    let orbit = loop {
        // The cancel `Simulator::orbit` polls before each cycle, not before
        // the settling.
        let stop = !run.settling() && pace.cancelled().await;
        let step = run.advance(&sim, &|| stop);
        pace.piece().await;
        if let Some(orbit) = step {
            break orbit?;
        }
    };
    Ok(match (orbit.period, &orbit.cycle) {
        (crate::sim::Period::Periodic(period), Some(c)) => Attractor::Cycle {
            period,
            theta: c.points[0],
        },
        (crate::sim::Period::Periodic(q), None) => Attractor::Unsolved(q),
        (crate::sim::Period::Aperiodic, _) => Attractor::Aperiodic,
    })
}
