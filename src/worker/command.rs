//! What the front end asks of the worker: the jobs of [`crate::jobs`] under
//! a generation, and the worker's own commands (new parameters, cancel,
//! shut down).

use crate::integrate::SolverSettings;
use crate::jobs::{
    BoundarySpec, ContinuationSpec, Generation, IterateSpec, Lane, PhaseSpec, Spec, SweepSpec,
    TrajectorySpec, WorkPrecisionSpec,
};
use crate::model::Params;

/// What the front end asks of the worker. A job command carries the
/// generation it starts under and its typed spec.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Run any job (`Spec`) on its lane: what a new kind of job is sent
    /// with (the typed variants below are the same, spelled per kind).
    Run {
        /// The job's stamp.
        generation: Generation,
        /// What to run.
        spec: Spec,
    },
    /// Run a trajectory (`TrajectorySpec`) on the orbit lane: `TrajectoryChunk`s
    /// and `Slip`s.
    Trajectory {
        /// The job's stamp.
        generation: Generation,
        /// What to run.
        spec: TrajectorySpec,
    },
    /// Iterate the map (`IterateSpec`) on the orbit lane: `MapIterates`,
    /// then one `MapGraph`.
    Iterate {
        /// The job's stamp.
        generation: Generation,
        /// What to run.
        spec: IterateSpec,
    },
    /// A bifurcation diagram (`SweepSpec`) on the sweep lane: one `Column`
    /// per θν, coarse pass first.
    Sweep {
        /// The job's stamp.
        generation: Generation,
        /// What to run.
        spec: SweepSpec,
    },
    /// A phase diagram (`PhaseSpec`) on the phase lane: `PhaseCells`,
    /// coarse lattice first.
    Phase {
        /// The job's stamp.
        generation: Generation,
        /// What to run.
        spec: PhaseSpec,
    },
    /// A new parameter set (κ, γ, ν, θν, Ω, and optionally the solver):
    /// each lane's latest trajectory/iterate, sweep or phase job runs again
    /// with it under `generation`, superseding whatever runs (a sweep keeps
    /// its θν range; a phase grid keeps both ranges and runs again only if
    /// γ, ν, Ω or the solver changed, and not after its lane was cancelled).
    /// `settings: None` keeps each job's own solver settings, which is what a
    /// front end that gives each kind of job its own accuracy wants; `Some`
    /// sets them all. A lane that has had no job stays idle; invalid values
    /// are reported by the re-run job, naming them. The numerics lane is not
    /// re-run; a running continuation or curves job is cancelled (answered
    /// by `Cancelled` for its lane), not re-run.
    SetParams {
        generation: Generation,
        params: Params,
        settings: Option<SolverSettings>,
    },
    /// Measure work against precision (`WorkPrecisionSpec`) on the
    /// numerics lane: `WorkPrecisionSample` once the sample is built, then
    /// one `WorkPrecisionRow` (or `WorkPrecisionSkipped`) per subject in
    /// order.
    WorkPrecision {
        /// The job's stamp.
        generation: Generation,
        /// What to measure.
        spec: WorkPrecisionSpec,
    },
    /// Find bifurcations (`ContinuationSpec`) on the continuation lane: one
    /// `Branch` per followed branch, `Progress` and `Summary` as they come.
    FindBifurcations {
        /// The job's stamp.
        generation: Generation,
        /// What to follow.
        spec: ContinuationSpec,
    },
    /// Bifurcation curves in (θν, κ) (`BoundarySpec`) on the curves lane:
    /// one `Curve` per followed curve, `Progress` and `Summary`.
    Boundaries {
        /// The job's stamp.
        generation: Generation,
        /// What to follow.
        spec: BoundarySpec,
    },
    /// Stop the lane's job (every lane if `None`); answered by `Cancelled`.
    Cancel {
        generation: Generation,
        lane: Option<Lane>,
    },
    /// Stop everything and end the worker's threads.
    Shutdown,
    /// Test-only fault injection: the job panics after `after_cycles` cycles.
    #[doc(hidden)]
    InjectPanic {
        generation: Generation,
        after_cycles: usize,
    },
}

impl Command {
    /// The job this command starts, with its generation (`None` for the
    /// worker's own commands).
    pub fn into_job(self) -> Option<(Generation, Spec)> {
        Some(match self {
            Command::Run { generation, spec } => (generation, spec),
            Command::Trajectory { generation, spec } => (generation, Spec::Trajectory(spec)),
            Command::Iterate { generation, spec } => (generation, Spec::Iterate(spec)),
            Command::Sweep { generation, spec } => (generation, Spec::Sweep(spec)),
            Command::Phase { generation, spec } => (generation, Spec::Phase(spec)),
            Command::WorkPrecision { generation, spec } => (generation, Spec::Numerics(spec)),
            Command::FindBifurcations { generation, spec } => (generation, Spec::Branches(spec)),
            Command::Boundaries { generation, spec } => (generation, Spec::Curves(spec)),
            Command::InjectPanic {
                generation,
                after_cycles,
            } => (generation, Spec::Panic { after_cycles }),
            Command::SetParams { .. } | Command::Cancel { .. } | Command::Shutdown => return None,
        })
    }
}
