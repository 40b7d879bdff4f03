//! The native window: `oneblock gui` opens it, a scripted run takes its
//! screenshot and exits. (The browser's entry is [`super::web`].)

use std::path::PathBuf;
use std::sync::{Arc, PoisonError};
use std::time::Duration;

use super::{
    Backend, Explorer, Layout, SCREENSHOT_GRACE, Script, Settings, ViewKind, is_software_gl,
    preset, preset_keys, saved_state, session,
};
use crate::worker::{LocalWorker, Worker, WorkerConfig};
use eframe::egui;

/// How to open the window.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Start on this preset (and ignore the saved parameters).
    pub preset: Option<String>,
    /// Take a screenshot here once the views are complete, then exit.
    pub screenshot: Option<PathBuf>,
    /// With `screenshot`: the layout (views, plots, the tour's box) as JSON
    /// here.
    pub layout: Option<PathBuf>,
    /// Open on this step of the tour (0-based).
    pub tour_step: Option<usize>,
    /// Inner window size in points.
    pub size: Option<[f32; 2]>,
    /// Measure and report frame times.
    pub frame_stats: bool,
    /// Show one view full size instead of the tiles.
    pub view: Option<ViewKind>,
    /// Text size multiplier.
    pub font_scale: Option<f32>,
    /// Start with the side panel hidden.
    pub hide_panel: bool,
    /// Start with θν playing; a scripted run plays it for a few seconds
    /// once the views are complete (its frames measured with
    /// `frame_stats`).
    pub play: bool,
    /// Give up a scripted run after this long.
    pub timeout: Option<Duration>,
    /// Open on this session file (`oneblock gui --session`).
    pub session: Option<PathBuf>,
    /// A scripted run that opens on the saved state as a plain launch does
    /// (checked, and set aside if unusable) but never writes it: how the
    /// tests check that no saved state bricks a launch.
    pub saved_state: bool,
    /// Run the jobs on the window's thread, a slice of each frame
    /// (`LocalWorker`), as the browser build does.
    pub single_thread: bool,
    /// Test-only: the first frame stalls for an hour, so that the tests can
    /// check that `timeout` bounds a stalled run.
    pub stall_first_frame: bool,
}

/// What `oneblock gui` says where there is no display to open a window on
/// (rather than the windowing library's own error).
const NO_DISPLAY: &str = "no display: the window needs X11 or Wayland (DISPLAY and WAYLAND_DISPLAY are unset); \
     for a --screenshot without a display, run it under xvfb-run";

/// Whether the environment (read by `var`) names an X11 or Wayland display.
fn has_display(var: impl Fn(&str) -> Option<std::ffi::OsString>) -> bool {
    ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|k| var(k).is_some_and(|v| !v.is_empty()))
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
    if scripted && !opts.saved_state {
        // A scripted run never reads or writes the user's saved state.
        native.persistence_path =
            Some(std::env::temp_dir().join(format!("oneblock-script-{}", std::process::id())));
    }
    native
}

/// What a launch has checked before the window opens: the preset, the
/// session, the saved state's verdict and the warnings to say at the end.
struct Launch {
    opts: RunOptions,
    preset: Option<crate::model::Preset>,
    session: Option<session::Loaded>,
    scripted: bool,
    /// Whether the saved state is read (a plain launch, or a scripted run
    /// asked to).
    reads_state: bool,
    /// Why the saved state was set aside, if it was.
    state_message: Option<String>,
    warnings: Vec<String>,
}

impl Launch {
    /// Checks the options: the preset, the session file, the screenshot's
    /// path, a display to open on, the saved state.
    fn check(opts: RunOptions) -> Result<Launch, String> {
        let preset = match &opts.preset {
            Some(k) => Some(*preset(k).ok_or_else(|| {
                format!("unknown preset '{k}': expected one of {}", preset_keys())
            })?),
            None => None,
        };
        let scripted = opts.screenshot.is_some();
        // Warnings are said once the run is over: on their own lines after
        // a success, folded into the one line of an error otherwise.
        let mut warnings: Vec<String> = Vec::new();
        let session = match &opts.session {
            Some(p) => {
                let loaded = session::Session::read(p).map_err(|e| format!("--session: {e}"))?;
                warnings.extend(loaded.message.clone());
                Some(loaded)
            }
            None => None,
        };
        for (flag, path) in [("screenshot", &opts.screenshot), ("layout", &opts.layout)] {
            if let Some(p) = path {
                crate::output::check_writable(p, false)
                    .map_err(|e| with_warnings(format!("--{flag}: {e}"), &warnings))?;
            }
        }
        // Without a display the window cannot open: one line saying so
        // (after any warning about the session), not the windowing
        // library's error.
        if !has_display(|k| std::env::var_os(k)) {
            return Err(with_warnings(NO_DISPLAY.into(), &warnings));
        }
        // The saved state is read by a plain launch (and by a scripted run
        // asked to): checked first, and set aside if it cannot be used.
        let reads_state = (!scripted || opts.saved_state) && session.is_none();
        let state_message = if reads_state {
            saved_state::default_path().and_then(|p| saved_state::check(&p))
        } else {
            None
        };
        warnings.extend(state_message.clone());
        Ok(Launch {
            opts,
            preset,
            session,
            scripted,
            reads_state,
            state_message,
            warnings,
        })
    }

    /// The settings the window opens on: the session's, the saved ones or
    /// the defaults, then the preset and the options over them.
    fn settings(&self, storage: Option<&dyn eframe::Storage>) -> Settings {
        let opts = &self.opts;
        let mut settings: Settings = if let Some(l) = &self.session {
            l.session.settings.clone()
        } else if !self.reads_state {
            Settings::default()
        } else {
            storage
                .and_then(|s| eframe::get_value(s, eframe::APP_KEY))
                .unwrap_or_default()
        };
        if let Some(p) = &self.preset {
            settings.apply_preset(&p.params, p.key);
        }
        if let Some(v) = opts.view {
            settings.layout = Layout::Tabs;
            settings.tab = v;
        } else if self.scripted && self.session.is_none() {
            settings.layout = Layout::Tiles;
        }
        if let Some(f) = opts.font_scale {
            settings.font_scale = f;
        }
        if opts.hide_panel {
            settings.hide_panel = true;
        }
        if self.scripted && !opts.frame_stats {
            // A screenshot is a picture for a document: anti-aliased even
            // under software OpenGL, where it only costs time.
            settings.smooth_lines = Some(true);
        }
        settings
    }

    /// The app, on its worker, with the session's zoom and the messages
    /// about the session and the saved state shown as toasts.
    fn explorer(&self, cc: &eframe::CreationContext<'_>) -> Explorer {
        let ctx = cc.egui_ctx.clone();
        let worker: Box<dyn Backend> = if self.opts.single_thread {
            Box::new(LocalWorker::default())
        } else {
            Box::new(Worker::spawn(
                WorkerConfig::default(),
                Arc::new(move || ctx.request_repaint()),
            ))
        };
        let mut app = Explorer::new(worker, self.settings(cc.storage));
        app.stall_first_frame = self.opts.stall_first_frame;
        if let Some(l) = &self.session {
            app.views.bifurcation.zoom = l.session.bifurcation_zoom.clone();
            app.restore_results(&l.session);
            if let Some(m) = &l.message {
                app.shots.toast(m.clone(), true, 0.0);
            }
        }
        if let Some(m) = &self.state_message {
            app.shots.toast(m.clone(), true, 0.0);
        }
        app.set_software_gl(cc.gl.as_deref().is_some_and(is_software_gl));
        app.persist = !self.scripted;
        app.stats.enabled = self.opts.frame_stats;
        if self.opts.play && !self.scripted {
            app.play.toggle();
        }
        if let Some(i) = self.opts.tour_step {
            app.tour.go(i, &mut app.settings);
        }
        app
    }
}

/// Opens the window; returns when it is closed. A scripted run (with
/// `screenshot`) returns an error if the picture could not be made.
pub fn run(opts: RunOptions) -> Result<(), String> {
    let launch = Launch::check(opts)?;
    let opts = &launch.opts;
    let size = opts.size.unwrap_or([1280.0, 800.0]);
    let timeout = opts.timeout.unwrap_or(Duration::from_secs(180));
    let measure = opts.frame_stats.then(|| Duration::from_secs(5));
    let native = native_options(opts, size, launch.scripted);
    let outcome = Arc::new(std::sync::Mutex::new(None));
    let stats_report = Arc::new(std::sync::Mutex::new(None::<String>));
    if launch.scripted {
        // The test's stalled frame (`--stall-first-frame`) comes before any
        // picture is due: nothing needs the grace's time to be saved.
        let grace = if opts.stall_first_frame {
            STALL_TEST_GRACE
        } else {
            SCREENSHOT_GRACE
        };
        spawn_watchdog(timeout, grace)?;
    }
    on_interrupt(launch.scripted);
    on_display_lost();
    let (out2, stats2) = (outcome.clone(), stats_report.clone());
    let shot = opts.screenshot.clone();
    let layout = opts.layout.clone();
    let warnings = launch.warnings.clone();
    let scripted = launch.scripted;
    let play = opts.play;
    let r = eframe::run_native(
        "oneblock",
        native,
        Box::new(move |cc| {
            let mut app = launch.explorer(cc);
            if let Some(path) = shot {
                let mut sc = Script::new(path, timeout, measure);
                sc.outcome = out2;
                sc.layout = layout;
                sc.play = play;
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
    r.map_err(|e| with_warnings(format!("the window failed: {e}"), &warnings))?;
    let shot = outcome
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .take();
    finish(scripted, shot, &warnings)
}

/// The watchdog's grace in the test of a stalled first frame.
const STALL_TEST_GRACE: Duration = Duration::from_secs(2);

/// Never hang: if a frame stalls (so the script's own check of the time
/// never runs), a scripted run gives up loudly soon after `timeout`. The
/// grace covers taking and encoding the picture once the views are done.
fn spawn_watchdog(timeout: Duration, grace: Duration) -> Result<(), String> {
    let limit = timeout + grace;
    std::thread::Builder::new()
        .name("oneblock-watchdog".into())
        .spawn(move || {
            std::thread::sleep(limit);
            eprintln!(
                "error: the window did not finish within --timeout {:.0} s \
                 (and {:.0} s to save the picture)",
                timeout.as_secs_f64(),
                grace.as_secs_f64()
            );
            std::process::exit(1);
        })
        .map(drop)
        .map_err(|e| e.to_string())
}

/// Ctrl+C (SIGINT) ends the window at once, with one line and exit code 1,
/// between file writes (a screenshot being saved is finished first). The
/// handler is installed whatever the signal's inherited disposition: a
/// `--screenshot` run started in the background of a script ignored SIGINT
/// and ran on to its end.
fn on_interrupt(scripted: bool) {
    ctrlc::set_handler(move || {
        let written = crate::output::writes_lock();
        let what = if scripted && *written == 0 {
            ": no screenshot was written"
        } else {
            ""
        };
        eprintln!("error: gui: interrupted (Ctrl+C){what}");
        quit_now();
    })
    .ok();
}

/// Ends the process at once with exit code 1, running no exit handlers:
/// `std::process::exit` from another thread ran the GL driver's teardown
/// while the window's thread still drew, and against a display already
/// gone (Ctrl+C under `xvfb-run` reaches the server too) that crashed with
/// a segmentation fault (exit 139).
fn quit_now() -> ! {
    #[cfg(target_os = "linux")]
    // SAFETY: `_exit` only ends the process; no Rust state is touched.
    unsafe {
        libc::_exit(1)
    }
    #[cfg(not(target_os = "linux"))]
    std::process::exit(1)
}

/// The one line a window whose display went away ends with.
fn display_gone(why: &str) -> ! {
    eprintln!("error: gui: the display went away ({why}); the window closed");
    quit_now()
}

/// A display that goes away (its server killed, the connection broken)
/// ends the window with one line and exit 1, never a crash: Xlib's fatal
/// I/O handler (its default prints its own line and calls `exit`, whose
/// teardown crashed), and a panic of the windowing code over the broken
/// connection (winit unwraps X replies), both end in [`display_gone`].
fn on_display_lost() {
    #[cfg(target_os = "linux")]
    set_x_io_handler();
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let msg = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if is_connection_loss(msg) {
            display_gone("the connection to the display server broke");
        }
        previous(info);
    }));
}

/// Whether a panic's message is the windowing code's on a lost X or
/// Wayland connection.
fn is_connection_loss(msg: &str) -> bool {
    [
        "Connection(IoError",
        "ConnectionError",
        "X connection",
        "Broken pipe",
    ]
    .iter()
    .any(|k| msg.contains(k))
}

/// Installs Xlib's fatal I/O error handler, if the process can load
/// libX11 (a Wayland-only system cannot, and needs none). eframe opens the
/// same library later; the handler is process-wide, and nothing else sets
/// it.
#[cfg(target_os = "linux")]
fn set_x_io_handler() {
    type Handler = unsafe extern "C" fn(*mut libc::c_void) -> libc::c_int;
    type SetHandler = unsafe extern "C" fn(Option<Handler>) -> Option<Handler>;
    unsafe extern "C" fn on_io_error(_display: *mut libc::c_void) -> libc::c_int {
        display_gone("the X connection broke")
    }
    // SAFETY: dlopen/dlsym with NUL-terminated names; the symbol, when
    // found, is Xlib's `XSetIOErrorHandler`, whose C signature `SetHandler`
    // is, and it is called with a handler of Xlib's `XIOErrorHandler` type.
    unsafe {
        let lib = libc::dlopen(c"libX11.so.6".as_ptr(), libc::RTLD_LAZY);
        if lib.is_null() {
            return;
        }
        let sym = libc::dlsym(lib, c"XSetIOErrorHandler".as_ptr());
        if sym.is_null() {
            return;
        }
        let set: SetHandler = std::mem::transmute::<*mut libc::c_void, SetHandler>(sym);
        set(Some(on_io_error));
    }
}

/// The end of a run: a scripted run's outcome (`shot`), the warnings on
/// their own lines after a success or folded into the error's one line.
fn finish(
    scripted: bool,
    shot: Option<Result<String, String>>,
    warnings: &[String],
) -> Result<(), String> {
    let done = match (scripted, shot) {
        (false, _) => Ok(String::new()),
        (true, Some(Ok(path))) => Ok(format!("saved {path}")),
        (true, Some(Err(e))) => Err(e),
        (true, None) => Err("the window closed before the screenshot was taken".into()),
    };
    match done {
        Ok(said) => {
            for w in warnings {
                eprintln!("warning: {w}");
            }
            if !said.is_empty() {
                eprintln!("{said}");
            }
            Ok(())
        }
        Err(e) => Err(with_warnings(e, warnings)),
    }
}

/// An error with the warnings before it folded in: one line in all.
fn with_warnings(error: String, warnings: &[String]) -> String {
    if warnings.is_empty() {
        error
    } else {
        format!("{error} (after warning: {})", warnings.join("; "))
    }
}
