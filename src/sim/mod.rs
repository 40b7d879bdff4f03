//! Simulation: one stick–slip cycle, the map θ → θ', orbits with their
//! period and Lyapunov exponent, and bifurcation sweeps over θν.

mod analysis;
mod cycle;
mod error;
pub mod field;
pub mod interpolant;
mod orbit;
pub mod phase;
mod sweep;
mod trajectory;
mod trig;

pub use analysis::{
    DERIVATIVE_STEP, PERIOD_MAX, cycle_with_derivative, detect_period, fixed_point, map_derivative,
    map_graph_grid, return_map_window,
};
pub use cycle::{
    LANES, Simulator, SlipEvent, Task, cycle_pair, cycles_in_lanes, default_settings, run_lanes,
};
pub use error::SimError;
pub use interpolant::{
    InterpolantError, InterpolantOptions, InterpolatedOrbit, MapChoice, MapInterpolant,
    orbit_interpolated,
};
pub use orbit::{Orbit, OrbitOptions, Period, mean_and_stderr};
pub use sweep::{
    Column, ColumnJob, SweepOptions, column_start, run_columns, segments, sweep_columns,
    sweep_segments, theta_nu_grid,
};
pub use trajectory::{Phase, Sample, Sampler};
