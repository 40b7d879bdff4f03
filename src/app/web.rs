//! The browser's entry (wasm32; built by `web/build.sh`): the same
//! explorer on the page's canvas, its jobs run by [`LocalWorker`] a slice
//! of each frame (a page has no threads). What differs from the native
//! window is only how things leave and enter the page:
//!
//! - files (PNG, SVG, CSV, a session's JSON) are downloads ([`download`]);
//! - a session is opened from an uploaded file ([`Upload`]);
//! - the URL's query opens a state, and "Copy link" writes one
//!   ([`super::url_state`]);
//! - settings persist in the page's local storage (eframe's persistence).
//!
//! `web/index.html` shows a loading note and, if the app cannot start (no
//! WebGL2, no wasm, a panic), the reason: [`show_failure`] writes it there.

use std::cell::RefCell;
use std::path::Path;
use std::rc::Rc;

use wasm_bindgen::JsCast as _;
use wasm_bindgen::prelude::*;

use eframe::egui::{Context, Ui};

use super::settings::ViewKind;
use super::title_buttons::RECORD_FRAMES;
use super::view::Action;
use super::{Explorer, Settings, preset, url_state};
use crate::worker::LocalWorker;

/// The id of the page's canvas (`web/index.html`).
const CANVAS_ID: &str = "oneblock_canvas";
/// The id of the page's status line (loading note, or why it failed).
const STATUS_ID: &str = "oneblock_status";
/// The share of a page's frame a recording takes (a frame of the GIF at
/// least): beside the jobs' 12 ms slice.
const RECORD_BUDGET: std::time::Duration = std::time::Duration::from_millis(8);

/// Starts the explorer on the page (`main` of the wasm binary).
pub fn start() {
    // A page without the canvas (web/bench.html) only calls the exports.
    let Some(canvas) = canvas() else {
        return;
    };
    let runner = eframe::WebRunner::new();
    wasm_bindgen_futures::spawn_local(async move {
        let options = eframe::WebOptions {
            // No gradients to band; dithering costs fill rate, and many a
            // lecture-hall PC renders WebGL in software.
            dithering: false,
            // eframe listens for touchmove on the document, which the
            // browser makes passive: preventing a move's default there
            // logged an error per move of a drag (12 a drag on a phone).
            // The page's CSS (touch-action: none) already keeps the
            // browser from scrolling or zooming under a finger.
            should_prevent_default: Box::new(|e| {
                !matches!(e, eframe::egui::Event::PointerMoved(_))
            }),
            ..Default::default()
        };
        let started = runner
            .start(canvas, options, Box::new(|cc| Ok(Box::new(explorer(cc)))))
            .await;
        match started {
            Ok(()) => set_status(None),
            Err(e) => show_failure(&format!(
                "the explorer could not start: {} (it needs WebGL2; try another browser or \
                 enable hardware acceleration)",
                js_text(&e)
            )),
        }
    });
    // A panic after the start: the page says so instead of freezing.
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        previous(info);
        show_failure(&format!("the explorer stopped: {info}"));
    }));
}

/// Times the Fig. 3b diagram on the single-threaded host, as
/// `oneblock bench-worker --single-thread` does natively: seconds of wall
/// time (web/test compares the two in one run).
#[wasm_bindgen]
pub fn bench_diagram(
    columns: usize,
    transient: usize,
    keep: usize,
    tol: f64,
) -> Result<f64, JsValue> {
    let spec = crate::bench::diagram::fig3b_diagram(columns, transient, keep, tol);
    crate::bench::diagram::time_diagram(spec, None)
        .map(|t| t.seconds)
        .map_err(|e| JsValue::from_str(&e))
}

/// The same diagram run in the page's compute slices (12 ms a frame), as
/// the explorer runs it: `[seconds, p99 step ms, longest step ms]`.
#[wasm_bindgen]
pub fn bench_diagram_sliced(
    columns: usize,
    transient: usize,
    keep: usize,
    tol: f64,
) -> Result<Vec<f64>, JsValue> {
    let spec = crate::bench::diagram::fig3b_diagram(columns, transient, keep, tol);
    let slice = Some(crate::bench::diagram::PAGE_SLICE);
    crate::bench::diagram::time_diagram(spec, slice)
        .map(|t| vec![t.seconds, t.step_ms(0.99), t.step_ms(1.0)])
        .map_err(|e| JsValue::from_str(&e))
}

/// The explorer as the page opens it: the saved settings (local storage),
/// then the link's state over them, on a worker without threads.
fn explorer(cc: &eframe::CreationContext<'_>) -> Explorer {
    let mut settings: Settings = cc
        .storage
        .and_then(|s| eframe::get_value(s, eframe::APP_KEY))
        .unwrap_or_default();
    let query = page_query();
    let message = url_state::apply_query(&query, &mut settings);
    if let Some(p) = settings.preset.as_deref().and_then(preset)
        && p.params == settings.params
    {
        settings.apply_preset(&p.params, p.key);
    }
    let mut app = Explorer::new(Box::new(LocalWorker::default()), settings);
    if let Some(m) = message {
        app.shots.toast(m, true, 0.0);
    }
    // WebGL hides the renderer's name behind "WebKit WebGL"; the debug
    // extension tells it. On a software rasteriser (SwiftShader, llvmpipe)
    // lines are drawn without feathering, as natively.
    let software = cc.gl.as_deref().is_some_and(super::is_software_gl) || software_webgl();
    app.set_software_gl(software);
    app.web.ctx = Some(cc.egui_ctx.clone());
    app
}

/// Whether the browser renders WebGL in software (Chrome's SwiftShader,
/// Mesa's llvmpipe), as its unmasked renderer name says where the browser
/// tells it (`WEBGL_debug_renderer_info`). Called through JS reflection:
/// no WebGL bindings are needed for one string.
fn software_webgl() -> bool {
    use js_sys::{Function, Reflect};
    let call = |obj: &JsValue, name: &str, args: &js_sys::Array| -> Option<JsValue> {
        let f: Function = Reflect::get(obj, &name.into()).ok()?.dyn_into().ok()?;
        f.apply(obj, args).ok()
    };
    let renderer = (|| {
        let doc = web_sys::window()?.document()?;
        let canvas: JsValue = doc.create_element("canvas").ok()?.into();
        let gl = call(&canvas, "getContext", &js_sys::Array::of1(&"webgl2".into()))?;
        if gl.is_null() {
            return None;
        }
        let ext = call(
            &gl,
            "getExtension",
            &js_sys::Array::of1(&"WEBGL_debug_renderer_info".into()),
        )?;
        if ext.is_null() {
            return None;
        }
        let which = Reflect::get(&ext, &"UNMASKED_RENDERER_WEBGL".into()).ok()?;
        call(&gl, "getParameter", &js_sys::Array::of1(&which))?.as_string()
    })();
    renderer.is_some_and(|r| {
        let r = r.to_lowercase();
        ["swiftshader", "llvmpipe", "softpipe", "software"]
            .iter()
            .any(|k| r.contains(k))
    })
}

/// The page's canvas, if it has one.
fn canvas() -> Option<web_sys::HtmlCanvasElement> {
    web_sys::window()?
        .document()?
        .get_element_by_id(CANVAS_ID)?
        .dyn_into()
        .ok()
}

/// The page's status line: hidden (`None`) or showing `text`.
fn set_status(text: Option<&str>) {
    let Some(el) = web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.get_element_by_id(STATUS_ID))
    else {
        return;
    };
    match text {
        None => el.remove(),
        Some(t) => el.set_text_content(Some(t)),
    }
}

/// Says on the page (and in the console) why the explorer is not running.
fn show_failure(why: &str) {
    web_sys::console::error_1(&JsValue::from_str(why));
    if let Some(doc) = web_sys::window().and_then(|w| w.document()) {
        let el = doc.get_element_by_id(STATUS_ID).or_else(|| {
            let el = doc.create_element("div").ok()?;
            el.set_id(STATUS_ID);
            doc.body()?.append_child(&el).ok()?;
            Some(el)
        });
        if let Some(el) = el {
            el.set_class_name("failed");
            el.set_text_content(Some(why));
        }
    }
}

/// A JS value (an error) as text.
fn js_text(v: &JsValue) -> String {
    v.as_string()
        .or_else(|| {
            v.dyn_ref::<js_sys::Error>()
                .map(|e| String::from(e.message()))
        })
        .unwrap_or_else(|| format!("{v:?}"))
}

/// The URL's query (`?…`), or "" if there is none.
fn page_query() -> String {
    web_sys::window()
        .and_then(|w| w.location().search().ok())
        .unwrap_or_default()
}

/// The page's address with `query` as its query, also put in the address
/// bar (without a reload or a history entry): what "Copy link" copies.
pub fn link_to(query: &str) -> Option<String> {
    let window = web_sys::window()?;
    let loc = window.location();
    let base = format!("{}{}", loc.origin().ok()?, loc.pathname().ok()?);
    let url = format!("{base}?{query}");
    if let Ok(history) = window.history() {
        // Failing only on a cross-origin URL, which this is not.
        let _ = history.replace_state_with_url(&JsValue::NULL, "", Some(&url));
    }
    Some(url)
}

/// Hands `bytes` to the browser as a download named after `path`'s file
/// name (the folder is the browser's to choose).
pub fn download(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "oneblock-download".into());
    let mime = match path.extension().and_then(|e| e.to_str()) {
        Some("png") => "image/png",
        Some("svg") => "image/svg+xml",
        Some("csv") => "text/csv",
        Some("json") => "application/json",
        _ => "application/octet-stream",
    };
    let fail = |e: JsValue| format!("cannot download {name}: {}", js_text(&e));
    let parts = js_sys::Array::of1(&js_sys::Uint8Array::from(bytes));
    let props = web_sys::BlobPropertyBag::new();
    props.set_type(mime);
    let blob =
        web_sys::Blob::new_with_u8_array_sequence_and_options(&parts, &props).map_err(fail)?;
    let url = web_sys::Url::create_object_url_with_blob(&blob).map_err(fail)?;
    let doc = web_sys::window()
        .and_then(|w| w.document())
        .ok_or_else(|| format!("cannot download {name}: no document"))?;
    let a: web_sys::HtmlAnchorElement = doc
        .create_element("a")
        .map_err(fail)?
        .dyn_into()
        .map_err(|_| format!("cannot download {name}: no anchor element"))?;
    a.set_href(&url);
    a.set_download(&name);
    a.click();
    // The click has started the download; the URL may go.
    let _ = web_sys::Url::revoke_object_url(&url);
    Ok(())
}

/// What the browser build keeps beside the explorer: the egui context (to
/// wake the page when an upload arrives), the upload and the recording
/// under way.
#[derive(Default)]
pub struct WebState {
    /// Set when the page starts (none in tests).
    pub ctx: Option<Context>,
    /// A session file being read: (file name, its text) or why not.
    pub upload: Upload,
    /// The page's title as last set.
    pub title: String,
    /// A GIF being recorded, a frame or so per frame of the page, and the
    /// file it downloads as.
    pub recording: Option<(super::animation::Recording, std::path::PathBuf)>,
    /// While θν plays: per view shown, (frames it showed a result in,
    /// frames), published for the page's check as the document's
    /// `data-filled` ("plane:1.00 return-map:0.98").
    pub filled: std::collections::BTreeMap<&'static str, (usize, usize)>,
    /// Whether θν played at the last frame.
    pub playing: bool,
    /// The document's attributes as last published ([`WebState::publish`]).
    published: std::collections::BTreeMap<&'static str, String>,
}

impl WebState {
    /// Sets the document's attribute `name` to `value` if it changed: what
    /// the page's check reads of the window's state (the tour's step as
    /// `data-tour` "2/6", θν as `data-theta-nu`).
    pub fn publish(&mut self, name: &'static str, value: String) {
        if self.published.get(name) == Some(&value) {
            return;
        }
        if let Some(root) = web_sys::window()
            .and_then(|w| w.document())
            .and_then(|d| d.document_element())
        {
            let _ = root.set_attribute(name, &value);
        }
        self.published.insert(name, value);
    }

    /// Counts one frame of play for each view shown (a play that starts
    /// starts the count afresh), and publishes the shares.
    pub fn count_filled(&mut self, jobs: &super::jobs::Jobs, views: &[ViewKind], playing: bool) {
        if playing && !self.playing {
            self.filled.clear();
        }
        self.playing = playing;
        if !playing {
            return;
        }
        for &v in views {
            let e = self.filled.entry(v.key()).or_default();
            e.0 += usize::from(super::frame_stats::shows_result(jobs, v));
            e.1 += 1;
        }
        let text: Vec<String> = self
            .filled
            .iter()
            .map(|(k, (f, n))| format!("{k}:{:.2}", *f as f64 / (*n).max(1) as f64))
            .collect();
        self.publish("data-filled", text.join(" "));
    }

    /// Sets the page's title to `title` if it changed.
    pub fn set_title(&mut self, title: String) {
        if title != self.title
            && let Some(doc) = web_sys::window().and_then(|w| w.document())
        {
            doc.set_title(&title);
            self.title = title;
        }
    }
}

/// A file the user picked, read asynchronously by the browser.
pub type Upload = Rc<RefCell<Option<Result<(String, String), String>>>>;

/// Opens the browser's file picker for a session (`.json`); the file's text
/// arrives in `slot` when read, and the page is woken to take it.
pub fn pick_session(slot: &Upload, ctx: Option<Context>) -> Result<(), String> {
    let doc = web_sys::window()
        .and_then(|w| w.document())
        .ok_or("no document")?;
    let input: web_sys::HtmlInputElement = doc
        .create_element("input")
        .map_err(|e| js_text(&e))?
        .dyn_into()
        .map_err(|_| "no input element".to_string())?;
    input.set_type("file");
    input.set_accept(".json,application/json");
    let (slot, picked) = (slot.clone(), input.clone());
    let on_change = Closure::once_into_js(move || {
        let Some(file) = picked.files().and_then(|f| f.get(0)) else {
            return;
        };
        let name = file.name();
        if file.size() > super::session::MAX_FILE_BYTES as f64 {
            *slot.borrow_mut() = Some(Err(format!(
                "session {name}: over {} bytes, not read",
                super::session::MAX_FILE_BYTES
            )));
            if let Some(c) = &ctx {
                c.request_repaint();
            }
            return;
        }
        let reader = match web_sys::FileReader::new() {
            Ok(r) => r,
            Err(e) => {
                *slot.borrow_mut() = Some(Err(format!("session {name}: {}", js_text(&e))));
                return;
            }
        };
        let (slot2, reader2, ctx2) = (slot.clone(), reader.clone(), ctx.clone());
        let on_load = Closure::once_into_js(move || {
            let text = reader2.result().ok().and_then(|v| v.as_string());
            *slot2.borrow_mut() = Some(match text {
                Some(t) => Ok((name, t)),
                None => Err(format!("session {name}: could not be read as text")),
            });
            if let Some(c) = &ctx2 {
                c.request_repaint();
            }
        });
        reader.set_onloadend(Some(on_load.unchecked_ref()));
        if let Err(e) = reader.read_as_text(&file) {
            *slot.borrow_mut() = Some(Err(format!("session {}: {}", file.name(), js_text(&e))));
        }
    });
    input.set_onchange(Some(on_change.unchecked_ref()));
    input.click();
    Ok(())
}

/// The browser's own actions and uploads, applied by the explorer.
impl Explorer {
    /// The browser's own actions: a session uploaded, the state as a link.
    pub(super) fn apply_web(&mut self, a: Action, ctx: &Context) {
        let now = self.now;
        match a {
            Action::OpenSession => {
                let ctx = self.web.ctx.clone();
                if let Err(e) = pick_session(&self.web.upload, ctx) {
                    self.shots
                        .toast(format!("cannot open a session: {e}"), true, now);
                }
            }
            Action::CopyLink => {
                let query = url_state::query_of(&self.settings);
                match link_to(&query) {
                    Some(url) => {
                        ctx.copy_text(url);
                        self.shots
                            .toast("link copied (and in the address bar)".into(), false, now);
                    }
                    None => self
                        .shots
                        .toast("cannot make a link here".into(), true, now),
                }
            }
            _ => {}
        }
    }

    /// Starts recording `v` as a GIF made between the page's frames
    /// ([`Explorer::record_step`]): of [`RECORD_FRAMES`] frames at
    /// `speed` (the block or plane's playback), or, without one, of θν
    /// played across the diagram's range.
    pub(super) fn record_web(&mut self, v: ViewKind, speed: Option<f64>) {
        use super::animation::{GifRun, PlayRun, Recording};
        let now = self.now;
        if self.web.recording.is_some() {
            self.shots
                .toast("a recording is under way already".into(), true, now);
            return;
        }
        let (run, frames, name) = match speed {
            Some(speed) => {
                let fig = super::figure::Figure::record(v, self.settings.clone());
                let run = GifRun::new(fig, RECORD_FRAMES, speed)
                    .map(|r| Recording::Playback(Box::new(r)));
                (run, RECORD_FRAMES, v.key().to_string())
            }
            None => {
                let (fig, span) = self.played(v);
                let run = PlayRun::new(fig, span).map(|r| Recording::Played(Box::new(r)));
                (run, span.frames, format!("{}-played", v.key()))
            }
        };
        match run {
            Ok(run) => {
                let path = super::files::fresh_path("", &name, "gif");
                self.shots.toast(
                    format!("Recording {frames} frames to {}…", path.display()),
                    false,
                    now,
                );
                self.web.recording = Some((run, path));
            }
            Err(e) => self.shots.toast(format!("cannot record: {e}"), true, now),
        }
    }

    /// Moves the recording on for about [`RECORD_BUDGET`] (a piece at
    /// least: the data for that long, or a frame); downloads the GIF once
    /// it is made.
    pub(super) fn record_step(&mut self, ctx: &Context) {
        let Some((run, _)) = &mut self.web.recording else {
            return;
        };
        let start = web_time::Instant::now();
        let done = loop {
            if let Some(r) = run.advance(RECORD_BUDGET) {
                break Some(r);
            }
            if start.elapsed() >= RECORD_BUDGET {
                break None;
            }
        };
        ctx.request_repaint();
        let Some(r) = done else { return };
        let Some((_, path)) = self.web.recording.take() else {
            return;
        };
        match r {
            Ok(bytes) => self.shots.write(path, bytes),
            Err(e) => self
                .shots
                .toast(format!("Not recorded: {e}"), true, self.now),
        }
    }

    /// Opens a session whose upload has arrived, or says why it could not.
    pub(super) fn take_upload(&mut self) {
        let arrived = self.web.upload.borrow_mut().take();
        match arrived {
            None => {}
            Some(Ok((name, text))) => {
                match super::session::Session::from_text(&text, &crate::text::echo(&name)) {
                    Ok(loaded) => self.open_session(loaded),
                    Err(e) => self.shots.toast(e, true, self.now),
                }
            }
            Some(Err(e)) => self.shots.toast(e, true, self.now),
        }
    }
}

/// The browser build's own file controls: a session opened by upload, and
/// the state as a link.
pub(super) fn files_ui(ui: &mut Ui, out: &mut Vec<Action>) {
    if ui
        .button("Open session…")
        .on_hover_text("A session saved before (a JSON file): its parameters, views and zoom.")
        .clicked()
    {
        out.push(Action::OpenSession);
    }
    if ui
        .button("Copy link")
        .on_hover_text(
            "The address of this state (preset, view and parameters): \
             it opens the explorer here, for students or a slide.",
        )
        .clicked()
    {
        out.push(Action::CopyLink);
    }
}
