//! The window: `eframe::App` and its state; what the user asked for
//! ([`Action`](super::view::Action)) is applied in `actions.rs`, the layout is `layout.rs`'s.
//! The jobs are the job model's ([`Jobs`]); a scripted run is
//! [`Script`]'s. It can be built with any [`Backend`] and stepped without
//! a window (`logic_step` then `show`), which is how the kittest tests
//! drive it.

use eframe::egui;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use egui::{Context, Rect, Ui};

use super::backend::Backend;
use super::controls::Controls;
use super::frame_stats::FrameStats;
use super::jobs::{Jobs, Shown};
use super::play::{Play, Tick};
use super::screenshot::Shots;
use super::script::{Script, Window};
use super::session::Session;
use super::settings::{Layout, Settings, ViewKind};
use super::style;
use super::svg_render;
use super::title_buttons::RECORD_PLAY_FRAMES;
use super::tour::Tour;
use super::views::Views;
use crate::sim::continuation::ContParam;

/// The slice of each frame a backend without threads may compute in: the
/// rest of a 30 fps frame is left for drawing.
pub const PUMP_BUDGET: Duration = crate::bench::diagram::PAGE_SLICE;

/// The side panel's normal width, points.
pub(super) const PANEL_WIDTH: f32 = 330.0;

/// The explorer app.
pub struct Explorer {
    pub settings: Settings,
    pub jobs: Jobs,
    pub controls: Controls,
    pub views: Views,
    pub shots: Shots,
    pub script: Option<Script>,
    pub stats: FrameStats,
    /// Test-only: the next frame stalls for an hour (`gui
    /// --stall-first-frame`).
    pub stall_first_frame: bool,
    /// Whether `save` writes the settings (not in scripted runs).
    pub persist: bool,
    /// Where the frame-time report goes when the window closes.
    pub stats_sink: Option<Arc<Mutex<Option<String>>>>,
    pub(super) view_rects: HashMap<ViewKind, Rect>,
    /// Each view's controls' height when last drawn above it, points: a
    /// tile that would give them over a quarter of its height folds them
    /// into its title row's menu (`Explorer::view_ui`).
    pub(super) controls_heights: HashMap<ViewKind, f32>,
    /// The views drawn in the last frame, with their plots (`--layout`).
    pub(super) drawn: super::layout_report::Drawn,
    /// The guided tour, when it runs.
    pub tour: Tour,
    /// The play clock of θν (and of the stepped cobweb).
    pub play: Play,
    /// On a phone: the panel's drawer is open over the view.
    pub drawer_open: bool,
    /// While a view fills the window: the layout and panel it replaced.
    pub(super) fill_restore: Option<(Layout, bool)>,
    /// The status bar's and the side panel's rectangles in the last frame
    /// (the panel's zero when hidden), for the tests.
    pub status_rect: Rect,
    pub panel_rect: Rect,
    /// The band under the views kept for the tour's box.
    pub(super) tour_band: Rect,
    /// The diagram's zoom from before the tour, which End tour gives back
    /// with the settings (a step's parameters clear it).
    tour_zoom: Option<Vec<super::bifurcation::Zoom>>,
    /// Frames left in which the side panel is held at its normal width.
    pub(super) panel_reset: u8,
    applied_style: Option<(f32, bool, bool)>,
    pub(super) now: f64,
    /// The desktop's "Open session…" modal, while it is open.
    #[cfg(not(target_arch = "wasm32"))]
    pub open_dialog: Option<super::open_session::OpenDialog>,
    /// The browser build's uploads and page context.
    #[cfg(target_arch = "wasm32")]
    pub web: super::web::WebState,
}

impl Explorer {
    /// A window over `backend`, showing `settings` (any field a saved file
    /// spoiled is back to its default, with a message saying which).
    pub fn new(backend: Box<dyn Backend>, settings: Settings) -> Self {
        let (settings, bad) = settings.sanitised();
        let mut shots = Shots::default();
        if !bad.is_empty() {
            shots.toast(
                format!(
                    "The saved settings held invalid values ({}): those are back to their defaults.",
                    bad.join(", ")
                ),
                true,
                0.0,
            );
        }
        Explorer {
            settings,
            jobs: Jobs::new(backend),
            controls: Controls::new(),
            views: Views::default(),
            shots,
            script: None,
            stats: FrameStats::default(),
            stall_first_frame: false,
            persist: true,
            stats_sink: None,
            view_rects: HashMap::new(),
            controls_heights: HashMap::new(),
            drawn: Default::default(),
            tour: Tour::default(),
            play: Play::default(),
            drawer_open: false,
            fill_restore: None,
            status_rect: Rect::NOTHING,
            panel_rect: Rect::NOTHING,
            tour_band: Rect::NOTHING,
            tour_zoom: None,
            panel_reset: 0,
            applied_style: None,
            now: 0.0,
            #[cfg(not(target_arch = "wasm32"))]
            open_dialog: None,
            #[cfg(target_arch = "wasm32")]
            web: Default::default(),
        }
    }

    /// Tells the window it runs on a software OpenGL rasteriser (see
    /// `Settings::smooth_lines`).
    pub fn set_software_gl(&mut self, software: bool) {
        self.controls.software_gl = software;
    }

    /// What the window shows that decides which jobs run.
    pub(super) fn shown(&self) -> Shown {
        Shown {
            now: self.now,
            sweep_zoom: self.views.bifurcation.theta_nu_range(),
            phase: self.settings.shows(ViewKind::Phase),
        }
    }

    /// Hands the settings to the job model: whatever they now call for
    /// starts, or waits for its debounce.
    pub fn sync_jobs(&mut self, ctx: &Context) {
        self.jobs.playing = self.play.on;
        let out = self.jobs.sync(&self.settings, self.shown());
        if out.zoom_stale {
            self.views.bifurcation.zoom.clear();
            self.views.bifurcation.invalidate();
        }
        if let Some(wait) = out.repaint_after {
            ctx.request_repaint_after(Duration::from_secs_f64(wait));
        }
    }

    /// Opens a session (a file of Open session…, or an upload in the
    /// browser): its settings and zoom replace the current ones, its kept
    /// results are shown ([`Explorer::restore_results`]), and what had to
    /// be set to a default or dropped is said in a toast. The save folder
    /// stays the window's own.
    pub fn open_session(&mut self, loaded: super::session::Loaded) {
        self.restore_results(&loaded.session);
        let dir = std::mem::take(&mut self.settings.save_dir);
        self.settings = loaded.session.settings;
        self.settings.save_dir = dir;
        self.views.bifurcation.zoom = loaded.session.bifurcation_zoom;
        self.views.bifurcation.invalidate();
        self.controls.resync();
        match loaded.message {
            Some(m) => self.shots.toast(m, true, self.now),
            None => self.shots.toast("session opened".into(), false, self.now),
        }
    }

    /// Shows the results `session` kept, without a job, bound to the
    /// session's own settings: options that changed the window's since
    /// (a preset at launch) make the first sync clear them, as any later
    /// change does.
    pub fn restore_results(&mut self, session: &Session) {
        let zoom = session.bifurcation_zoom.last().map(|z| z.theta_nu);
        let diagram = super::jobs::continuation_range(&session.settings, zoom);
        self.jobs
            .restore(&session.settings, diagram, session.results.clone());
    }

    /// Sends everything pending now (tests; the end of a scripted wait).
    pub fn flush(&mut self, ctx: &Context) {
        self.now +=
            super::jobs::JobKind::Sweep.debounce() + super::jobs::JobKind::Trajectory.debounce();
        self.sync_jobs(ctx);
    }

    /// The non-drawing half of a frame: drain the worker, restart jobs,
    /// collect saved files, drive a scripted run.
    pub fn logic_step(&mut self, ctx: &Context) {
        if std::mem::take(&mut self.stall_first_frame) {
            std::thread::sleep(Duration::from_secs(3600));
        }
        let smooth = self.settings.smooth_lines_on(self.controls.software_gl);
        if ctx.tessellation_options(|o| o.feathering) != smooth {
            ctx.tessellation_options_mut(|o| o.feathering = smooth);
        }
        self.now = ctx.input(|i| i.time);
        // A backend without threads computes here, within a slice of the
        // frame; the threaded worker wakes the window itself.
        let pumping = self.jobs.pump(PUMP_BUDGET);
        if self.jobs.receive() || pumping {
            ctx.request_repaint();
        }
        #[cfg(target_arch = "wasm32")]
        {
            self.take_upload();
            self.record_step(ctx);
            self.web.set_title(super::status::title(&self.jobs));
            let views = svg_render::shown_views(&self.settings);
            self.web.count_filled(&self.jobs, &views, self.play.on);
            let step = self
                .tour
                .step
                .map(|i| format!("{}/{}", i + 1, super::tour::STEPS.len()));
            self.web.publish("data-tour", step.unwrap_or_default());
            let theta_nu = format!("{:.6}", self.settings.params.theta_nu);
            self.web.publish("data-theta-nu", theta_nu);
        }
        self.play_step(ctx);
        self.sync_jobs(ctx);
        self.shots.poll(self.now);
        if self.shots.in_flight > 0 || !self.shots.toasts.is_empty() {
            ctx.request_repaint_after(Duration::from_millis(100));
        }
        let shown = svg_render::shown_views(&self.settings);
        let area = self.views_area(&shown);
        if let Some(script) = &mut self.script {
            let w = Window {
                area,
                layout: self.drawn.report(self.tour.box_rect),
                zoom: &self.views.bifurcation.zoom,
                settings: &mut self.settings,
                jobs: &mut self.jobs,
                shots: &mut self.shots,
                stats: &mut self.stats,
                play: &mut self.play,
                now: self.now,
            };
            script.step(ctx, w);
        }
        if self.stats.enabled {
            ctx.request_repaint();
        }
    }

    /// Where view `v` was drawn in the last frame, if it was shown.
    pub fn view_rect(&self, v: ViewKind) -> Option<Rect> {
        self.view_rects.get(&v).copied()
    }

    /// The last frame's views, their plots and the tour's box, as
    /// `gui --layout` writes them.
    pub fn layout_report(&self) -> super::layout_report::LayoutReport {
        self.drawn.report(self.tour.box_rect)
    }

    /// The view under the pointer, if any.
    pub(super) fn view_under_pointer(&self, ctx: &Context) -> Option<ViewKind> {
        let at = ctx.pointer_hover_pos()?;
        self.view_rects
            .iter()
            .find(|(_, r)| r.contains(at))
            .map(|(v, _)| *v)
    }

    /// The size of the area `views` take on screen now (the window's
    /// default view area before the first frame).
    pub fn views_area(&self, views: &[ViewKind]) -> egui::Vec2 {
        views
            .iter()
            .filter_map(|v| self.view_rects.get(v))
            .copied()
            .reduce(|a, b| a.union(b))
            .map_or(egui::vec2(940.0, 700.0), |r| r.size())
    }

    fn apply_style(&mut self, ctx: &Context) {
        let projector = self.settings.projector;
        style::set_line_scale(ctx, if projector { 2.0 } else { 1.0 });
        let want = (self.settings.font_scale, self.settings.dark, projector);
        if self.applied_style == Some(want) {
            return;
        }
        if self.applied_style.is_none() {
            style::install_fonts(ctx);
        }
        if self.applied_style.is_some_and(|a| a.2) && !projector {
            self.panel_reset = 3;
        }
        ctx.set_theme(if want.1 {
            egui::Theme::Dark
        } else {
            egui::Theme::Light
        });
        let base = egui::Style::default().text_styles;
        let scale = want.0.clamp(0.5, 3.0);
        ctx.all_styles_mut(|s| {
            for (ts, font) in s.text_styles.iter_mut() {
                if let Some(b) = base.get(ts) {
                    font.size = b.size * scale;
                }
            }
            // High contrast: text in full ink, not egui's greys.
            s.visuals.override_text_color = projector.then_some(if s.visuals.dark_mode {
                egui::Color32::WHITE
            } else {
                egui::Color32::BLACK
            });
        });
        self.applied_style = Some(want);
    }

    /// What the Record menu's "θν played" records of view `v`: the
    /// window's settings and diagram zoom, θν across the diagram's range
    /// (the range Play turns at) in [`RECORD_PLAY_FRAMES`] frames.
    pub(super) fn played(
        &self,
        v: ViewKind,
    ) -> (super::figure::Figure, super::animation::PlaySpan) {
        let mut fig = super::figure::Figure::record(v, self.settings.clone());
        fig.zoom = self.views.bifurcation.zoom.clone();
        let span = super::animation::PlaySpan::of_diagram(&fig, RECORD_PLAY_FRAMES);
        (fig, span)
    }

    /// One tick of the play clock: θν moves (or the stepped cobweb grows),
    /// and the next frame is asked for.
    fn play_step(&mut self, ctx: &Context) {
        if !self.play.on {
            return;
        }
        // The diagram's zoom, when it is one in θν.
        let range = match self.settings.diagram.param {
            ContParam::ThetaNu => self
                .views
                .bifurcation
                .theta_nu_range()
                .unwrap_or_else(|| self.settings.sweep_range()),
            _ => self.settings.theta_nu_range(),
        };
        let steps = &mut self.views.return_map.steps;
        match self.play.tick(&self.settings, range, steps.on, self.now) {
            Tick::ThetaNu(x) => self.settings.params.theta_nu = x,
            Tick::Iterates(n) => {
                let available = self.jobs.trajectory.data.events.len();
                steps.step(n as isize, available);
            }
            Tick::Nothing => {}
        }
        ctx.request_repaint();
    }

    /// The whole window.
    pub fn show(&mut self, ui: &mut Ui) {
        let ctx = ui.ctx().clone();
        self.now = ctx.input(|i| i.time);
        self.apply_style(&ctx);
        super::axes::clear_frames(&ctx);
        let mut actions = Vec::new();
        self.shortcuts(&ctx, &mut actions);

        self.panels_ui(ui, &mut actions);
        for a in actions {
            self.apply(a, &ctx);
        }
        let narrow = super::style::is_narrow(&ctx);
        self.tour
            .ui(&ctx, &mut self.settings, self.tour_band, narrow);
        self.keep_zoom_over_the_tour();
        #[cfg(not(target_arch = "wasm32"))]
        self.open_dialog_ui(&ctx);
        self.sync_jobs(&ctx);
        if self.stats.enabled {
            self.stats.overlay(&ctx);
        }
    }

    /// The diagram's zoom kept when the tour starts (before this frame's
    /// new parameters clear it) and given back when it ends.
    fn keep_zoom_over_the_tour(&mut self) {
        let zoom = &mut self.views.bifurcation.zoom;
        match (self.tour.step, self.tour_zoom.is_some()) {
            (Some(_), false) => self.tour_zoom = Some(zoom.clone()),
            (None, true) => {
                *zoom = self.tour_zoom.take().unwrap_or_default();
                self.views.bifurcation.invalidate();
            }
            _ => {}
        }
    }

    /// The "Open session…" modal while it is open: a session read opens
    /// (the modal closes); a file refused keeps it open with the reason.
    #[cfg(not(target_arch = "wasm32"))]
    fn open_dialog_ui(&mut self, ctx: &Context) {
        use super::open_session::Outcome;
        let Some(dialog) = &mut self.open_dialog else {
            return;
        };
        match dialog.ui(ctx) {
            None => {}
            Some(Outcome::Close) => self.open_dialog = None,
            Some(Outcome::Open(loaded)) => {
                self.open_dialog = None;
                self.open_session(*loaded);
            }
        }
    }
}

impl eframe::App for Explorer {
    fn logic(&mut self, ctx: &Context, frame: &mut eframe::Frame) {
        self.stats.record(frame.info().cpu_usage);
        let views = super::svg_render::shown_views(&self.settings);
        self.stats.count_filled(&self.jobs, &views);
        self.logic_step(ctx);
    }

    fn ui(&mut self, ui: &mut Ui, _frame: &mut eframe::Frame) {
        self.show(ui);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        if self.persist {
            eframe::set_value(storage, eframe::APP_KEY, &self.settings);
        }
    }

    fn persist_egui_memory(&self) -> bool {
        self.persist
    }

    fn raw_input_hook(&mut self, _ctx: &Context, raw_input: &mut egui::RawInput) {
        // A scripted run draws for a picture: wherever the X server left the
        // pointer, it must not hover a plot (crosshairs, tooltips).
        if self.script.is_some() {
            raw_input.events.retain(|e| {
                !matches!(
                    e,
                    egui::Event::PointerMoved(_)
                        | egui::Event::MouseMoved(_)
                        | egui::Event::PointerButton { .. }
                )
            });
            raw_input.events.push(egui::Event::PointerGone);
        }
    }

    fn clear_color(&self, visuals: &egui::Visuals) -> [f32; 4] {
        visuals.panel_fill.to_normalized_gamma_f32()
    }
}

impl Drop for Explorer {
    fn drop(&mut self) {
        if self.stats.enabled
            && let Some(sink) = &self.stats_sink
        {
            *sink.lock().unwrap_or_else(PoisonError::into_inner) = Some(self.stats.report());
        }
    }
}
