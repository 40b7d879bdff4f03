//! The typed messages between the front end and the simulation worker.
//!
//! The worker runs two lanes: the *orbit lane* (trajectory or map iterates,
//! one job at a time) and the *sweep lane* (bifurcation columns, on its own
//! threads), so that a trajectory stays responsive while a sweep fills in.
//! Every job carries the generation it was started under; a receiver drops
//! any update whose generation is older than the latest it asked for.

use serde::{Deserialize, Serialize};

use crate::integrate::SolverSettings;
use crate::model::Params;
use crate::sim::{Period, Sample, SlipEvent};

/// A monotonically increasing job stamp. The front end issues them (one per
/// command that starts or cancels work), so it knows which updates are stale
/// without a round trip.
pub type Generation = u64;

/// Which lane a job runs on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Lane {
    /// Trajectories and map iterates.
    Orbit,
    /// Bifurcation sweeps.
    Sweep,
}

/// What the front end asks of the worker.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Follow the block from the onset θ0 (θν if `None`), streaming its path
    /// sampled every `spacing` time units during slips, and each slip event.
    /// Runs `cycles` cycles, or until cancelled if `None`.
    Trajectory {
        generation: Generation,
        params: Params,
        settings: SolverSettings,
        theta0: Option<f64>,
        spacing: f64,
        cycles: Option<usize>,
    },
    /// Iterate the map from θ0 (θν if `None`), streaming iterates with the
    /// detected period and the running Lyapunov exponent.
    Iterate {
        generation: Generation,
        params: Params,
        settings: SolverSettings,
        theta0: Option<f64>,
        transient: usize,
        keep: usize,
    },
    /// A bifurcation diagram over θν ∈ [from, to] with `columns` columns:
    /// a coarse pass over the whole range first, then refinement, each
    /// column continued from its nearest computed neighbour.
    Sweep {
        generation: Generation,
        params: Params,
        settings: SolverSettings,
        theta_nu_from: f64,
        theta_nu_to: f64,
        columns: usize,
        transient: usize,
        keep: usize,
    },
    /// A new parameter set (κ, γ, ν, θν, Ω, method, tolerance): each lane's
    /// latest trajectory/iterate or sweep job runs again with it under
    /// `generation`, superseding whatever runs (a sweep keeps its θν range
    /// and uses the other parameters). A lane that has had no job stays
    /// idle; invalid values are reported by the re-run job, naming them.
    SetParams {
        generation: Generation,
        params: Params,
        settings: SolverSettings,
    },
    /// Stop the lane's job (both lanes if `None`); answered by `Cancelled`.
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

/// How a job ended.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Outcome {
    /// It ran to the end.
    Completed,
    /// A `Cancel` or a newer job on its lane stopped it.
    Cancelled,
    /// It could not run or failed (an `Error` update said why).
    Failed(String),
}

/// What the worker sends back. Every variant names its generation.
#[derive(Clone, Debug, PartialEq)]
pub enum Update {
    /// Path samples at display density.
    TrajectoryChunk {
        generation: Generation,
        samples: Vec<Sample>,
    },
    /// One completed cycle of a trajectory job.
    Slip {
        generation: Generation,
        event: SlipEvent,
    },
    /// New map iterates (in order), with the analysis of all so far.
    MapIterates {
        generation: Generation,
        /// Index of the first of `thetas` in the kept sequence.
        first_index: usize,
        thetas: Vec<f64>,
        period: Period,
        lyapunov: Option<f64>,
    },
    /// The graph of the map f over the window the iterate job's orbit is
    /// drawn in (`sim::return_map_window`): f(θ) at each θ of `thetas`, NaN
    /// where that cycle failed. Sent once, after the kept iterates.
    MapGraph {
        generation: Generation,
        thetas: Vec<f64>,
        values: Vec<f64>,
    },
    /// One finished bifurcation column.
    Column {
        generation: Generation,
        /// Position of the column in the final grid (0 … columns−1).
        index: usize,
        theta_nu: f64,
        thetas: Vec<f64>,
        /// Whether this column belongs to the first, coarse pass.
        coarse: bool,
    },
    /// How far the lane's job is, and how fast it goes.
    Progress {
        generation: Generation,
        lane: Lane,
        fraction: f64,
        iterates_per_second: f64,
    },
    /// A job could not run or failed; `parameter` names the culprit if any.
    Error {
        generation: Generation,
        lane: Lane,
        message: String,
        parameter: Option<&'static str>,
    },
    /// A job ended.
    Finished {
        generation: Generation,
        lane: Lane,
        outcome: Outcome,
    },
    /// Acknowledges a `Cancel`: nothing of an older generation on that lane
    /// follows it.
    Cancelled {
        generation: Generation,
        lane: Option<Lane>,
    },
}

impl Update {
    /// The generation of the job (or cancellation) the update belongs to.
    pub fn generation(&self) -> Generation {
        match self {
            Update::TrajectoryChunk { generation, .. }
            | Update::Slip { generation, .. }
            | Update::MapIterates { generation, .. }
            | Update::MapGraph { generation, .. }
            | Update::Column { generation, .. }
            | Update::Progress { generation, .. }
            | Update::Error { generation, .. }
            | Update::Finished { generation, .. }
            | Update::Cancelled { generation, .. } => *generation,
        }
    }
}
