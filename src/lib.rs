//! oneblock: the two-dimensional one-block earthquake model of Montagne &
//! Vasconcelos, simulated exactly as `docs/model.md` states it.
//!
//! - [`model`]: parameters, regimes, the curve C, the closed-form stick phase.
//! - [`integrate`]: Runge–Kutta tableaus, one stepping loop, dense output.
//! - [`sim`]: one stick–slip cycle, the map θ → θ', orbits, sweeps.
//! - [`jobs`]: every long computation, defined once, run by any host.
//! - [`worker`]: the background threads the GUI talks to (the jobs' threaded host).
//! - [`bench`]: what times the jobs (`oneblock bench-worker`), apart from them.
//! - [`cli`]: the headless subcommands (not in the browser build).
//! - [`formats`]: the CSV formats and class colours every front end writes;
//!   [`provenance`]: the `#` lines every CSV begins with.
//! - `app` (feature `gui`): the eframe/egui explorer.

#[cfg(feature = "gui")]
pub mod app;
pub mod bench;
// The browser build (wasm32) has no command line, no terminal and no file
// system to write into: the commands and the atomic file writer are native.
#[cfg(not(target_arch = "wasm32"))]
pub mod cli;
pub mod figure;
pub mod formats;
pub mod integrate;
pub mod jobs;
pub mod model;
pub mod numerics;
#[cfg(not(target_arch = "wasm32"))]
pub mod output;
pub mod provenance;
pub mod sim;
pub mod text;
pub mod worker;

pub use integrate::{Method, SolverSettings};
pub use model::{Params, Regime};
pub use sim::{SimError, Simulator, SlipEvent};
