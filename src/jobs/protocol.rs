//! The typed messages between the front end and the simulation worker:
//! the specs a job is started from ([`super::specs`]) and the updates it
//! sends back.
//!
//! Which lane each kind of job runs on is the job table's
//! ([`super::kinds`]): a trajectory stays responsive while a diagram fills
//! in, and measuring never pauses the views.
//! Every job carries the generation it was started under; a receiver drops
//! any update whose generation is older than the latest it asked for.

use serde::{Deserialize, Serialize};

pub use super::kinds::Lane;
pub use super::specs::{
    Axis, BoundarySpec, CascadeFrom, ContinuationSpec, CurveFollow, GivenCycle, IterateOptions,
    IterateSpec, MAX_GRAPH_POWER, PhaseSpec, PhaseTuning, SweepSpec, Timing, TrajectorySpec,
    WorkPrecisionSpec,
};

use crate::numerics::{Row, Subject};
use crate::sim::attractors::Found;
use crate::sim::column_lyapunov::ColumnLyapunov;
use crate::sim::continuation::{Branch, Cascade, Curve, SpecialPoint};
use crate::sim::intermittency::{Passage, Scaling};
use crate::sim::interpolant::MapUsed;
use crate::sim::phase::PhaseCell;
use crate::sim::{Orbit, Period, Sample, SlipEvent};

/// A monotonically increasing job stamp. The front end issues them (one per
/// command that starts or cancels work), so it knows which updates are stale
/// without a round trip.
pub type Generation = u64;

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
        /// λ's standard error (`None` for a solved cycle's exact λ, or
        /// too few iterates to tell).
        lyapunov_stderr: Option<f64>,
    },
    /// The graph of the map f over the window the iterate job's orbit is
    /// drawn in (`sim::return_map_window`): f(θ) at each θ of `thetas`, NaN
    /// where that cycle failed. Sent after the kept iterates with f alone,
    /// and again with `powers` when the job asks for f², f³, ….
    MapGraph {
        generation: Generation,
        thetas: Vec<f64>,
        values: Vec<f64>,
        /// f^k at each of `thetas` for k = 2, 3, … (`graph_powers`), each
        /// from k cycles integrated in turn (never a composition of the
        /// sampled graph, which would carry its interpolation error k
        /// times); NaN where a cycle failed. Empty in the first send.
        powers: Vec<Vec<f64>>,
    },
    /// The whole orbit of an iterate job that asked for it
    /// ([`IterateOptions::report`]), after its last `MapIterates`.
    Orbit {
        generation: Generation,
        orbit: Box<Orbit>,
        /// How the map was evaluated.
        map: MapUsed,
    },
    /// One finished bifurcation column. A seeded sweep may send a column
    /// again, amended by its neighbour pass: the later replaces the earlier.
    Column {
        generation: Generation,
        /// Position of the column in the final grid (0 … columns−1).
        index: usize,
        /// The varied parameter's value there (the spec's `param`).
        value: f64,
        thetas: Vec<f64>,
        /// Whether this column belongs to the first, coarse pass.
        coarse: bool,
        /// Right-hand-side evaluations it cost.
        rhs_evals: u64,
        /// How its points after the transient were computed.
        map: MapUsed,
        /// Its Lyapunov exponent ([`crate::sim::column_lyapunov`]), `None`
        /// for an empty or failed column.
        lyapunov: Option<ColumnLyapunov>,
        /// The attractor of each of `thetas` (0: the followed one; see
        /// `sim::seeded::SeededColumn`); empty when the sweep has no seeds.
        attractor: Vec<u8>,
        /// Why a seeded column's other attractors were not counted (its
        /// exit arc's cell graph could not be built); `None` otherwise.
        uncounted: Option<String>,
    },
    /// The sample of a work-precision job: how many points, and how far
    /// its reference (DOP853 at 1e-14) is from DP5(4) at 1e-13 (the
    /// smallest error the measurement can resolve).
    WorkPrecisionSample {
        generation: Generation,
        points: usize,
        reference_spread: f64,
    },
    /// One measured setting of a work-precision job.
    WorkPrecisionRow {
        generation: Generation,
        /// Position of the subject in the command's list (0 … total−1).
        index: usize,
        total: usize,
        row: Row,
    },
    /// A setting the job did not measure, and why (a cheaper setting of the
    /// same method already took too long per iterate).
    WorkPrecisionSkipped {
        generation: Generation,
        index: usize,
        total: usize,
        subject: Subject,
        reason: String,
    },
    /// Finished phase-diagram cells, in batches. A batch holds only coarse
    /// or only refinement cells, and every coarse cell is sent before any
    /// refinement cell; each cell is sent exactly once.
    PhaseCells {
        generation: Generation,
        cells: Vec<GridCell>,
        /// Whether these cells belong to the first, coarse lattice.
        coarse: bool,
    },
    /// One continued branch of a `Branches` job (the first one
    /// over the whole range, then each level of the cascade).
    Branch {
        generation: Generation,
        branch: Branch,
    },
    /// A period doubling, fold, border or jump of the first branch of a
    /// `Branches` job, as it is located (before its branch ends).
    Special {
        generation: Generation,
        point: SpecialPoint,
    },
    /// The cascade of a `Branches` job that followed one, once it
    /// ends: its levels (also sent one by one as `Branch`), its doublings,
    /// and why it ended.
    Cascade {
        generation: Generation,
        cascade: Cascade,
    },
    /// One bifurcation curve of a `Boundaries` job, or of a
    /// `Branches` job with curves.
    Curve {
        generation: Generation,
        curve: Curve,
    },
    /// The channel passage of a `Passage` job, and the verdict of a `Scan`.
    Passage {
        generation: Generation,
        passage: Passage,
    },
    Scan {
        generation: Generation,
        scaling: Scaling,
    },
    /// One column of a Basins job (`lane`: the diagram's or the return
    /// map's), in the job's order (coarse first).
    Basins {
        generation: Generation,
        lane: Lane,
        column: Box<BasinColumn>,
    },
    /// A Basins job's tracks and their located births, deaths and period
    /// changes, once every column has arrived (the last update before
    /// `Finished`; none on a single-threaded host, see `jobs::basins`).
    BasinEvents {
        generation: Generation,
        lane: Lane,
        events: Box<crate::sim::attractors::events::Events>,
    },
    /// What a continuation or curves job has found so far and, once it
    /// ends, why it stopped (one line for the status bar).
    Summary {
        generation: Generation,
        lane: Lane,
        text: String,
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
            | Update::Orbit { generation, .. }
            | Update::Column { generation, .. }
            | Update::WorkPrecisionSample { generation, .. }
            | Update::WorkPrecisionRow { generation, .. }
            | Update::WorkPrecisionSkipped { generation, .. }
            | Update::PhaseCells { generation, .. }
            | Update::Branch { generation, .. }
            | Update::Special { generation, .. }
            | Update::Cascade { generation, .. }
            | Update::Curve { generation, .. }
            | Update::Passage { generation, .. }
            | Update::Scan { generation, .. }
            | Update::Basins { generation, .. }
            | Update::BasinEvents { generation, .. }
            | Update::Summary { generation, .. }
            | Update::Progress { generation, .. }
            | Update::Error { generation, .. }
            | Update::Finished { generation, .. }
            | Update::Cancelled { generation, .. } => *generation,
        }
    }
}

/// One computed cell of a phase diagram, with its place in the grid.
#[derive(Clone, Debug, PartialEq)]
pub struct GridCell {
    /// κ row, 0 … kappa_steps−1 (row 0 is `kappa_from`).
    pub row: usize,
    /// θν column, 0 … theta_nu_steps−1 (column 0 is `theta_nu_from`).
    pub column: usize,
    /// The core's result, as `phase_cell` returned it (its `theta_nu` and
    /// `kappa` are the cell's).
    pub cell: PhaseCell,
    /// A multistable cell's attractors (with
    /// [`PhaseTuning::list_attractors`]; empty otherwise), at most
    /// [`MAX_LISTED`], with only what the window shows of each.
    pub listed: Vec<ListedAttractor>,
}

/// The most attractors a cell's list keeps (the rest are counted in
/// [`PhaseCell::attractors`] only).
pub const MAX_LISTED: usize = 8;

/// One attractor of a multistable cell, as the window lists it: what
/// `sim::attractors::Attractor` says of it without its points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ListedAttractor {
    /// The period, `None` for an aperiodic (chaotic) attractor.
    pub period: Option<usize>,
    /// A cycle's multiplier.
    pub multiplier: Option<f64>,
    /// An aperiodic attractor's Lyapunov exponent and its standard error.
    pub lyapunov: Option<(f64, Option<f64>)>,
    /// Its basin's share of the exit arc.
    pub basin_fraction: f64,
}

impl ListedAttractor {
    /// What the list keeps of `a`.
    pub fn of(a: &crate::sim::attractors::Attractor) -> Self {
        ListedAttractor {
            period: a.period,
            multiplier: a.multiplier,
            lyapunov: match a.period {
                None => a.lyapunov.map(|l| (l, a.lyapunov_stderr)),
                Some(_) => None,
            },
            basin_fraction: a.basin_fraction,
        }
    }
}

/// One column of a Basins job: its attractors and basins.
#[derive(Clone, Debug, PartialEq)]
pub struct BasinColumn {
    /// Its place in the grid (0 … steps − 1).
    pub index: usize,
    /// The varied parameter's value there (the spec's `param`).
    pub value: f64,
    /// Its θν (the value itself when θν is varied).
    pub theta_nu: f64,
    /// Every attractor and basin there, or why they could not be found.
    pub found: Result<Found, String>,
}
