//! The eframe/egui explorer (feature `gui`). One file per view, the controls
//! apart from the plots; the physics lives in the core and runs on the
//! worker: the UI thread only draws what the worker streams.
//!
//! Modules, each importing only those listed before it:
//!
//! - [`style`], [`describe`], [`backend`]: colours and legends, the words
//!   for a regime or an attractor, the worker behind a trait.
//! - [`settings`]: everything that persists, and its sanitising on load.
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
//! - [`export`], [`screenshot`], [`save`]: CSV, PNG, writing them.
//! - [`frame_stats`], [`script`]: `--frame-stats` and scripted runs.
//! - [`status`]: the status bar.
//! - [`explorer`]: the app: layout, `eframe::App`, applying actions.

pub mod accuracy;
pub mod axes;
pub mod backend;
pub mod bifurcation;
pub mod block;
pub mod branches;
pub mod controls;
pub mod data;
pub mod describe;
pub mod events;
pub mod explorer;
pub mod export;
pub mod frame_stats;
pub mod jobs;
pub mod numerics_table;
pub mod numerics_view;
pub mod overlay;
pub mod phase_data;
pub mod phase_view;
pub mod plane;
pub mod points_table;
pub mod return_map;
pub mod save;
pub mod screenshot;
pub mod script;
pub mod session;
pub mod settings;
pub mod status;
pub mod style;
pub mod svg;
pub mod svg_render;
pub mod view;
pub mod views;

use std::path::PathBuf;
use std::sync::{Arc, PoisonError};
use std::time::Duration;

pub use crate::model::{PRESETS, preset, preset_keys};
pub use backend::{Backend, Recorder};
pub use explorer::Explorer;
pub use script::Script;
pub use settings::{Layout, Settings, ViewKind};

use crate::worker::{Worker, WorkerConfig};
use eframe::egui;

/// How to open the window.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Start on this preset (and ignore the saved parameters).
    pub preset: Option<String>,
    /// Take a screenshot here once the views are complete, then exit.
    pub screenshot: Option<PathBuf>,
    /// Inner window size in points.
    pub size: Option<[f32; 2]>,
    /// Measure and report frame times.
    pub frame_stats: bool,
    /// Show one view full size instead of the tiles.
    pub view: Option<ViewKind>,
    /// Text size multiplier.
    pub font_scale: Option<f32>,
    /// Give up a scripted run after this long.
    pub timeout: Option<Duration>,
    /// Open on this session file (`oneblock gui --session`).
    pub session: Option<PathBuf>,
}

/// Whether OpenGL is a CPU rasteriser (Mesa's llvmpipe, softpipe, swrast):
/// fill-bound, so the window saves on anti-aliasing there (`smooth_lines`).
fn is_software_gl(gl: &eframe::glow::Context) -> bool {
    use eframe::glow::HasContext as _;
    // SAFETY: called on the thread that owns the current context (eframe's
    // app-creation callback), with a valid enum; glGetString has no other
    // precondition.
    let renderer = unsafe { gl.get_parameter_string(eframe::glow::RENDERER) }.to_lowercase();
    ["llvmpipe", "softpipe", "swrast", "software"]
        .iter()
        .any(|k| renderer.contains(k))
}

/// The window's options: title and size, the glow renderer, and for a
/// scripted run (a screenshot) no saved state read or written.
fn native_options(opts: &RunOptions, size: [f32; 2], scripted: bool) -> eframe::NativeOptions {
    let mut native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("oneblock: one-block earthquake model")
            .with_app_id("oneblock")
            .with_inner_size(size)
            .with_min_inner_size([800.0, 560.0]),
        renderer: eframe::Renderer::Glow,
        // Dithering costs a noticeable share of each frame under software
        // rendering (llvmpipe is fill-bound here) and the plots have no
        // gradients to band.
        dithering: false,
        persist_window: !scripted,
        ..Default::default()
    };
    if opts.frame_stats {
        // Measure drawing, not waiting for the display.
        native.glow_options.vsync = false;
    }
    if scripted {
        // A scripted run never reads or writes the user's saved state.
        native.persistence_path =
            Some(std::env::temp_dir().join(format!("oneblock-script-{}", std::process::id())));
    }
    native
}

/// A scripted run never hangs: if the event loop itself stalls past
/// `limit`, the process gives up loudly.
fn start_watchdog(limit: Duration) -> Result<(), String> {
    std::thread::Builder::new()
        .name("oneblock-watchdog".into())
        .spawn(move || {
            std::thread::sleep(limit);
            eprintln!(
                "error: the window did not finish within {:.0} s",
                limit.as_secs_f64()
            );
            std::process::exit(1);
        })
        .map(drop)
        .map_err(|e| format!("cannot start the watchdog thread: {e}"))
}

/// Opens the window; returns when it is closed. A scripted run (with
/// `screenshot`) returns an error if the picture could not be made.
pub fn run(opts: RunOptions) -> Result<(), String> {
    let preset =
        match &opts.preset {
            Some(k) => Some(*preset(k).ok_or_else(|| {
                format!("unknown preset '{k}': expected one of {}", preset_keys())
            })?),
            None => None,
        };
    let scripted = opts.screenshot.is_some();
    let session = match &opts.session {
        Some(p) => {
            let text = std::fs::read_to_string(p)
                .map_err(|e| format!("--session: cannot read {}: {e}", p.display()))?;
            let loaded = session::Session::from_json(&text, &p.display().to_string());
            if let Some(m) = &loaded.message {
                eprintln!("warning: {m}");
            }
            Some(loaded)
        }
        None => None,
    };
    if let Some(p) = &opts.screenshot {
        crate::output::check_writable(p, false).map_err(|e| e.to_string())?;
    }
    let size = opts.size.unwrap_or([1280.0, 800.0]);
    let timeout = opts.timeout.unwrap_or(Duration::from_secs(180));
    let measure = opts.frame_stats.then(|| Duration::from_secs(5));

    let native = native_options(&opts, size, scripted);
    let outcome = Arc::new(std::sync::Mutex::new(None));
    let stats_report = Arc::new(std::sync::Mutex::new(None::<String>));
    if scripted {
        start_watchdog(timeout + Duration::from_secs(60))?;
    }

    let out2 = outcome.clone();
    let stats2 = stats_report.clone();
    let shot = opts.screenshot.clone();
    let r = eframe::run_native(
        "oneblock",
        native,
        Box::new(move |cc| {
            let ctx = cc.egui_ctx.clone();
            let worker = Worker::spawn(
                WorkerConfig::default(),
                Arc::new(move || ctx.request_repaint()),
            );
            let mut settings: Settings = if let Some(l) = &session {
                l.session.settings.clone()
            } else if scripted {
                Settings::default()
            } else {
                cc.storage
                    .and_then(|s| eframe::get_value(s, eframe::APP_KEY))
                    .unwrap_or_default()
            };
            if let Some(p) = &preset {
                controls::apply_preset(&mut settings, &p.params, p.key);
            }
            if let Some(v) = opts.view {
                settings.layout = Layout::Tabs;
                settings.tab = v;
            } else if scripted && session.is_none() {
                settings.layout = Layout::Tiles;
            }
            if let Some(f) = opts.font_scale {
                settings.font_scale = f;
            }
            if scripted && !opts.frame_stats {
                // A screenshot is a picture for a document: anti-aliased
                // even under software OpenGL, where it only costs time.
                settings.smooth_lines = Some(true);
            }
            let mut app = Explorer::new(Box::new(worker), settings);
            if let Some(l) = &session {
                app.views.bifurcation.zoom = l.session.bifurcation_zoom.clone();
                if let Some(m) = &l.message {
                    app.shots.toast(m.clone(), true, 0.0);
                }
            }
            app.set_software_gl(cc.gl.as_deref().is_some_and(is_software_gl));
            app.persist = !scripted;
            app.stats.enabled = opts.frame_stats;
            if let Some(path) = shot {
                let mut sc = Script::new(path, timeout, measure);
                sc.outcome = out2;
                app.script = Some(sc);
            }
            app.stats_sink = Some(stats2);
            Ok(Box::new(app))
        }),
    );
    if let Some(rep) = stats_report
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .take()
    {
        eprintln!("{rep}");
    }
    r.map_err(|e| format!("the window failed: {e}"))?;
    if scripted {
        match outcome
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .take()
        {
            Some(Ok(path)) => {
                eprintln!("saved {path}");
                Ok(())
            }
            Some(Err(e)) => Err(e),
            None => Err("the window closed before the screenshot was taken".into()),
        }
    } else {
        Ok(())
    }
}
