//! Simulation: one stick–slip cycle, the map θ → θ', orbits with their
//! period and Lyapunov exponent, and bifurcation sweeps over θν.

mod analysis;
pub mod attractors;
pub mod column_lyapunov;
pub mod continuation;
mod cycle;
pub mod cycles;
mod error;
pub mod field;
pub mod intermittency;
pub mod interpolant;
mod orbit;
pub mod period;
pub mod phase;
pub mod seeded;
pub mod stats;
mod sweep;
mod trajectory;
mod trig;
pub mod variational;

pub use analysis::{
    DERIVATIVE_STEP, cycle_with_derivative, fixed_point, map_derivative, map_graph_grid,
    return_map_window, slope_counts,
};
pub use cycle::{
    LANES, Simulator, SlipEvent, Task, cycle_pair, cycles_in_lanes, default_settings, run_lanes,
};
pub use cycles::{Cycle, CycleFailure, CycleOptions, solve_cycle};
pub use error::SimError;
pub use interpolant::{InterpolantError, InterpolantOptions, Layout, MapChoice, MapInterpolant};
pub use orbit::{
    InterpolatedOrbit, OnInterpolant, Orbit, OrbitOptions, OrbitRun, Period, Settled,
    orbit_interpolated,
};
pub use period::{PERIOD_MAX, settled_period};
pub use stats::mean_and_stderr;
pub use sweep::{
    Column, ColumnJob, Handover, LaneEnd, NeverYield, PausedColumn, SweepOptions, Yield,
    column_start, param_grid, run_columns, sweep_columns, theta_nu_grid,
};
pub use trajectory::{Phase, Sample, Sampler};
