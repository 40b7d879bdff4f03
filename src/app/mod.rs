//! The eframe/egui explorer (feature `gui`). One file per view, the controls
//! apart from the plots; the physics lives in the core and runs on the
//! worker: the UI thread only draws what the worker streams.
//!
//! Modules, each importing only those listed before it:
//!
//! - [`style`], [`markers`], [`describe`], [`backend`]: colours and
//!   legends, point markers (a plot's and its legend's from one
//!   description), the words for a regime or an attractor, the worker
//!   behind a trait.
//! - [`settings`]: everything that persists, and its sanitising on load;
//!   [`saved_state`]: the saved file checked, and set aside if unusable.
//! - [`axes`]: ticks and axis titles for every plot (and for exports).
//! - [`data`], [`phase_data`], [`branches`]: what the worker sent for
//!   each kind of job.
//! - [`jobs`]: the job model: one slot per job, `apply(Update)`, the
//!   debounces, the phase grid's policy, each job's solver setting.
//! - [`view`]: the `View` trait and the `Action` enum.
//! - [`accuracy`], [`controls`]: the side panel.
//! - [`overlay`], [`points_table`]: the continuation's branches and curves
//!   drawn over the diagrams, and its special points as a table.
//! - [`plane`], [`block`], [`bifurcation`], [`return_map`], [`events`],
//!   [`numerics_view`] (with [`numerics_table`]), [`phase_view`]: the views.
//! - [`export`], [`screenshot`], [`save`]: CSV, PNG, writing them;
//!   [`figure`]: one view drawn headless (`oneblock figure`).
//! - [`frame_stats`], [`script`]: `--frame-stats` and scripted runs.
//! - [`status`]: the status bar.
//! - [`explorer`]: the app: layout, `eframe::App`, applying actions.

pub mod accuracy;
mod actions;
pub mod animation;
pub mod axes;
pub mod backend;
pub mod basin_events;
pub mod basins;
pub mod bifurcation;
pub mod block;
pub mod branches;
pub mod clip;
pub mod controls;
pub mod data;
pub mod describe;
pub mod diagram_axis;
mod diagram_lines;
pub mod diagram_marks;
mod diagram_raster;
pub mod events;
mod events_plots;
pub mod explorer;
pub mod export;
pub mod figure;
pub mod files;
pub mod frame_stats;
pub mod help;
pub mod hold;
pub mod jobs;
mod layout;
pub mod layout_report;
pub mod legend;
pub mod lyapunov_strip;
mod map_basins;
pub mod markers;
#[cfg(not(target_arch = "wasm32"))]
mod native;
pub mod numerics_table;
pub mod numerics_view;
#[cfg(not(target_arch = "wasm32"))]
pub mod open_session;
pub mod overlay;
pub mod phase_attractors;
pub mod phase_data;
pub mod phase_raster;
pub mod phase_view;
mod pinch;
pub mod plane;
pub mod play;
pub mod points_table;
pub mod raster;
pub mod return_map;
pub mod save;
pub mod saved_state;
pub mod screenshot;
pub mod script;
pub mod session;
pub mod session_results;
pub mod settings;
mod shortcuts;
pub mod status;
pub mod style;
pub mod svg;
pub mod svg_render;
mod svg_text;
pub mod time_series;
pub mod title_buttons;
mod top_bar;
pub mod tour;
pub mod url_state;
pub mod view;
pub mod views;
#[cfg(target_arch = "wasm32")]
pub mod web;

pub use crate::model::{PRESETS, preset, preset_keys};
pub use backend::{Backend, Recorder};
pub use explorer::Explorer;
pub use script::Script;
pub use settings::{Layout, Settings, ViewKind};

#[cfg(not(target_arch = "wasm32"))]
pub use native::{RunOptions, run};

/// How long past `--timeout` a scripted run may take to save its picture
/// before the watchdog ends it.
pub const SCREENSHOT_GRACE: std::time::Duration = std::time::Duration::from_secs(20);

/// Whether OpenGL is a CPU rasteriser (Mesa's llvmpipe, softpipe, swrast):
/// fill-bound, so the window saves on anti-aliasing there (`smooth_lines`).
pub(crate) fn is_software_gl(gl: &eframe::glow::Context) -> bool {
    use eframe::glow::HasContext as _;
    // SAFETY: called on the thread that owns the current context (eframe's
    // app-creation callback), with a valid enum; glGetString has no other
    // precondition.
    let renderer = unsafe { gl.get_parameter_string(eframe::glow::RENDERER) }.to_lowercase();
    ["llvmpipe", "softpipe", "swrast", "software"]
        .iter()
        .any(|k| renderer.contains(k))
}
