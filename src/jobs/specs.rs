//! What the front end asks of a job: one typed spec per kind of job
//! (the job table, [`super::kinds`], names which is whose), with the grid
//! axes, options and timings they are made of.

use std::time::Duration;

use crate::integrate::SolverSettings;
use crate::model::Params;
use crate::numerics::Subject;
use crate::numerics::sample::Attractor;
use crate::sim::MapChoice;
use crate::sim::continuation::{ContParam, CurveKind};
use crate::sim::phase::PhaseOptions;

/// One axis of a job's grid: `steps` values from `from` to `to`, both ends
/// included (a single step is `from`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis {
    /// The first value.
    pub from: f64,
    /// The last value.
    pub to: f64,
    /// How many values (columns or rows).
    pub steps: usize,
}

impl Axis {
    /// `steps` values over [`from`, `to`].
    pub fn new(from: f64, to: f64, steps: usize) -> Axis {
        Axis { from, to, steps }
    }
}

/// A trajectory: follow the block from the onset θ0 (θν if `None`),
/// streaming its path sampled every `spacing` time units during slips, and
/// each slip event, for `cycles` cycles (until cancelled if `None`).
#[derive(Clone, Debug, PartialEq)]
pub struct TrajectorySpec {
    /// The model's parameters.
    pub params: Params,
    /// The solver and its accuracy.
    pub settings: SolverSettings,
    /// The first onset (θν if `None`).
    pub theta0: Option<f64>,
    /// Cycles run before the path starts (at t = 0), not recorded.
    pub transient: usize,
    /// Time between path samples during a slip.
    pub spacing: f64,
    /// Cycles to run (until cancelled if `None`).
    pub cycles: Option<usize>,
    /// The most samples the whole path may hold (`None`: no cap): the job
    /// fails with `SimError::TooManySamples` rather than hold more.
    pub max_samples: Option<usize>,
}

/// Map iterates: iterate the map from θ0 (θν if `None`), dropping
/// `transient` iterates and streaming `keep` more with the detected period
/// and the running Lyapunov exponent, then the graph of the map. The one
/// orbit loop of the window's return map and of `oneblock orbit`
/// (`sim::OrbitRun`).
#[derive(Clone, Debug, PartialEq)]
pub struct IterateSpec {
    /// The model's parameters.
    pub params: Params,
    /// The solver and its accuracy.
    pub settings: SolverSettings,
    /// The first onset (θν if `None`).
    pub theta0: Option<f64>,
    /// Iterates dropped before any is kept.
    pub transient: usize,
    /// Iterates kept and streamed.
    pub keep: usize,
    /// The highest power f^k whose graph follows f's (1: f alone; at most
    /// [`MAX_GRAPH_POWER`]; 0: no graph).
    pub graph_powers: usize,
    /// How the orbit is computed and reported beyond the window's way.
    pub options: IterateOptions,
}

/// How an iterate job computes its orbit and what it reports: the
/// window's way by default, `oneblock orbit`'s flags otherwise.
#[derive(Clone, Debug, PartialEq)]
pub struct IterateOptions {
    /// How the map is evaluated (default: every iterate integrated).
    pub map: MapChoice,
    /// The period test's tolerance (default:
    /// `OrbitOptions::period_tol_of` the settings).
    pub period_tol: Option<f64>,
    /// Whether kept iterates take f'(θ) for the Lyapunov exponent.
    pub lyapunov: bool,
    /// Whether the job ends with the orbit ([`super::Update::Orbit`]: its
    /// summary and how the map was evaluated).
    pub report: bool,
    /// Whether that orbit carries every kept slip event
    /// (`Orbit::events`: `oneblock orbit`'s CSV and `--stats`); without,
    /// neither it nor the job holds anything that grows with the orbit.
    pub events: bool,
}

impl Default for IterateOptions {
    fn default() -> Self {
        IterateOptions {
            map: MapChoice::Direct,
            period_tol: None,
            lyapunov: true,
            report: false,
            events: false,
        }
    }
}

/// The highest power of the map an iterate job draws the graph of.
pub const MAX_GRAPH_POWER: usize = 4;

/// A bifurcation diagram over one parameter (`param`, θν in the paper's
/// Fig. 3; one column per step of `axis`): a coarse pass over the whole
/// range first, then refinement, each column continued from its nearest
/// computed neighbour (`sweep_plan`). `param`'s value in `params` is
/// ignored (it is the axis); the others are held fixed.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepSpec {
    /// The model's parameters (all but `param`'s).
    pub params: Params,
    /// The solver and its accuracy.
    pub settings: SolverSettings,
    /// The parameter varied along the axis.
    pub param: ContParam,
    /// Its columns: evenly spaced, in log10 of the value for a parameter
    /// that spans decades ([`crate::sim::param_grid`]).
    pub axis: Axis,
    /// Iterates each column drops before it keeps any.
    pub transient: usize,
    /// Iterates each column keeps.
    pub keep: usize,
    /// How an unsettled column evaluates the map after its transient
    /// ([`crate::sim::SweepOptions::map`]; the window's is `Auto`).
    pub map: MapChoice,
    /// Where each chain's first column starts (`None`: at its own θν).
    pub theta0: Option<f64>,
    /// θ₀ spread over each column's exit arc besides the followed orbit
    /// (0: none), each run to its attractor; every attractor found is
    /// drawn, labelled (`sim::seeded`).
    pub seeds: usize,
}

/// A phase diagram (the paper's Fig. 4) over θν (columns) and κ (rows) at
/// the γ, ν and Ω of `params` (its κ and θν are ignored: they are the
/// axes). A coarse lattice first, then refinement, each cell seeded by
/// its nearest computed neighbour in its block of 32 × 32 (`block_plan`).
#[derive(Clone, Debug, PartialEq)]
pub struct PhaseSpec {
    /// The model's parameters (γ, ν, Ω).
    pub params: Params,
    /// The solver and its accuracy.
    pub settings: SolverSettings,
    /// The θν columns.
    pub theta_nu: Axis,
    /// The κ rows (row 0 is `kappa.from`).
    pub kappa: Axis,
    /// Each cell's transient (`PhaseOptions::transient`).
    pub transient: usize,
    /// Each cell's kept iterates (`PhaseOptions::keep`).
    pub keep: usize,
    /// What the command line may set beyond the budget.
    pub tuning: PhaseTuning,
}

/// The phase options the command line exposes beyond the budget (the
/// window keeps the defaults).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseTuning {
    /// [`PhaseOptions::early_exit`] (`false`: brute force).
    pub early_exit: bool,
    /// [`PhaseOptions::map`].
    pub map: MapChoice,
    /// [`PhaseOptions::period_tol`], if not the solver's own.
    pub period_tol: Option<f64>,
    /// [`PhaseOptions::seeds`] (0: attractors not counted).
    pub seeds: usize,
    /// With seeds, list each multistable cell's attractors as
    /// `oneblock attractors` finds them from the same seeds
    /// ([`GridCell::listed`]; the window's click list). Off on the command
    /// line, whose CSV has only the count.
    pub list_attractors: bool,
    /// Only part K of N of the grid (`oneblock phase --shard K/N`): a run
    /// of whole blocks of the plan (`plan::shard_blocks`), each cell as
    /// the whole grid computes it.
    pub shard: Option<(usize, usize)>,
}

impl Default for PhaseTuning {
    fn default() -> Self {
        PhaseTuning {
            early_exit: true,
            map: MapChoice::Auto,
            period_tol: None,
            seeds: 0,
            list_attractors: false,
            shard: None,
        }
    }
}

impl PhaseSpec {
    /// A cell's budget: this spec's transient, keep and tuning, the rest as
    /// the core chooses for its solver settings.
    pub fn options(&self) -> PhaseOptions {
        let base = PhaseOptions::for_settings(&self.settings);
        PhaseOptions {
            transient: self.transient,
            keep: self.keep,
            early_exit: self.tuning.early_exit,
            map: self.tuning.map,
            period_tol: self.tuning.period_tol.unwrap_or(base.period_tol),
            seeds: self.tuning.seeds,
            ..base
        }
    }
}

/// Find bifurcations: follow a cycle in `param` over [`from`, `to`] (the
/// attractor's at `from`, its period found by the orbit's period detector,
/// or the one `cycle` gives), locating its period doublings, folds and
/// borders; if it doubles, follow the cascade up to period `max_period`
/// (as `cascade` says); with `curves`, follow the branch's bifurcations of
/// one kind as curves in two parameters. Each branch, special point and
/// curve is sent as it is found.
#[derive(Clone, Debug, PartialEq)]
pub struct ContinuationSpec {
    /// The model's parameters (`param`'s value is the range's).
    pub params: Params,
    /// The solver and its accuracy.
    pub settings: SolverSettings,
    /// The parameter varied.
    pub param: ContParam,
    /// Where the branch starts.
    pub from: f64,
    /// Where it ends (may be below `from`).
    pub to: f64,
    /// The cascade's longest period (at most `sim::PERIOD_MAX`; the
    /// cycle's own period: no cascade).
    pub max_period: usize,
    /// The cycle followed: `None`, the attractor's at `from` (the
    /// window's); or a given one (`oneblock continue`, which has checked
    /// it).
    pub cycle: Option<GivenCycle>,
    /// How the cascade's levels are followed.
    pub cascade: CascadeFrom,
    /// The curves through the branch's bifurcations, if asked
    /// (`continue --curve`; no cascade then).
    pub curves: Option<CurveFollow>,
}

/// A cycle to follow, where the window follows the attractor's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GivenCycle {
    /// Its period p.
    pub period: usize,
    /// A point θ of it at the branch's start (a Newton seed).
    pub theta: f64,
}

/// How a cascade is followed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CascadeFrom {
    /// The branch over the whole range first (every bifurcation in the
    /// range is on it), then the levels after its first doubling (the
    /// window's "Find bifurcations").
    Branch,
    /// Each level, the first included, from its birth to its doubling
    /// (`continue --cascade`).
    Levels,
}

/// Curves through the branch's bifurcations of one kind, followed in the
/// branch's parameter and `param` within the box [from, to] × `range`
/// (the model's `param` inside `range`). A start on a curve already
/// followed is skipped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveFollow {
    /// Period doublings or folds.
    pub kind: CurveKind,
    /// The second parameter.
    pub param: ContParam,
    /// Its range (either order).
    pub range: [f64; 2],
}

/// Boundaries of the phase diagram as curves: the doublings of the
/// attractor's cycle at θν = `theta_nu.0` (and of the cycle it doubles
/// into) located along θν at the κ of `params`, each followed in (θν, κ)
/// within the box `theta_nu` × `kappa` (FP→P2 and P2→P4 when the attractor
/// there is the fixed point). Each curve is sent as it ends.
#[derive(Clone, Debug, PartialEq)]
pub struct BoundarySpec {
    /// The model's parameters: γ, ν, Ω, and the κ the doublings are
    /// located at (inside `kappa`).
    pub params: Params,
    /// The solver and its accuracy.
    pub settings: SolverSettings,
    /// The θν range (the box's first side).
    pub theta_nu: (f64, f64),
    /// The κ range (the box's second side).
    pub kappa: (f64, f64),
}

/// A work-precision measurement: `subjects` (solver settings) against a
/// reference on `points` orbit points of each of `attractors`, timed as
/// `timing` says.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkPrecisionSpec {
    /// The attractors the sample takes its points from: the current one
    /// (`numerics::quick::current_attractor`) in the window; the committed
    /// four, or one given, on the command line.
    pub attractors: Vec<Attractor>,
    /// Orbit points per attractor.
    pub points: usize,
    /// How each setting is timed.
    pub timing: Timing,
    /// The settings measured, in order.
    pub subjects: Vec<Subject>,
}

/// How a work-precision job times a setting. Either way a setting is
/// measured point by point and the points' rows combined
/// (`numerics::quick::combine`: the numbers `measure` gives for the whole
/// sample), polling between points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Timing {
    /// The window's: this long per setting in all, each point the fastest
    /// of `TIMING_REPEATS` timings; a method whose setting is slower than
    /// `numerics::quick::SLOW_ITERATE` per iterate has its later settings
    /// skipped.
    PerSetting(Duration),
    /// `oneblock work-precision`'s: each point timed over repeated runs
    /// lasting at least this long; every setting measured.
    PerPoint(Duration),
}
