//! What the front end asks of the worker: a job of [`crate::jobs`] to run
//! under a generation, and the worker's own commands (new parameters,
//! cancel, shut down).

use crate::integrate::SolverSettings;
use crate::jobs::{Generation, Lane, Spec};
use crate::model::Params;

/// What the front end asks of the worker.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Run a job (`Spec`) on its lane under `generation`, superseding the
    /// lane's job. Which updates it sends is the job's (see each spec).
    Run {
        /// The job's stamp.
        generation: Generation,
        /// What to run.
        spec: Spec,
    },
    /// A new parameter set (κ, γ, ν, θν, Ω, and optionally the solver):
    /// each lane's latest job whose result depends on what changed (the
    /// job table's `depends`, the window's rule too) does what its kind
    /// says of new parameters ([`Spec::on_params`]): a trajectory, iterates,
    /// a sweep and the Basins diagram run again under `generation`,
    /// superseding whatever runs (a sweep and the Basins diagram keep their
    /// range and ignore a change of the parameter they vary; a phase grid
    /// keeps both ranges and runs again only if γ, ν, Ω or the solver
    /// changed, and not after its lane was cancelled); a running
    /// continuation, curves, passage, scan or map-basins job is cancelled
    /// (answered by `Cancelled` for its lane); the numerics lane is left
    /// alone. `settings: None` keeps each
    /// job's own solver settings, which is what a front end that gives each
    /// kind of job its own accuracy wants; `Some` sets them all. A lane that
    /// has had no job stays idle; invalid values are reported by the re-run
    /// job, naming them.
    SetParams {
        generation: Generation,
        params: Params,
        settings: Option<SolverSettings>,
    },
    /// Stop the lane's job (every lane if `None`); answered by `Cancelled`.
    Cancel {
        generation: Generation,
        lane: Option<Lane>,
    },
    /// Stop everything and end the worker's threads.
    Shutdown,
}

impl Command {
    /// Run `spec` under `generation`.
    pub fn run(generation: Generation, spec: impl Into<Spec>) -> Command {
        Command::Run {
            generation,
            spec: spec.into(),
        }
    }

    /// Test-only fault injection: a job that panics after `after_cycles`
    /// cycles.
    #[doc(hidden)]
    pub fn inject_panic(generation: Generation, after_cycles: usize) -> Command {
        Command::Run {
            generation,
            spec: Spec::Panic { after_cycles },
        }
    }

    /// The job this command starts, with its generation (`None` for the
    /// worker's own commands).
    pub fn into_job(self) -> Option<(Generation, Spec)> {
        match self {
            Command::Run { generation, spec } => Some((generation, spec)),
            Command::SetParams { .. } | Command::Cancel { .. } | Command::Shutdown => None,
        }
    }
}
