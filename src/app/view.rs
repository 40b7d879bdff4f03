//! The shape every view has, and what a view (or the side panel, or a
//! keyboard shortcut) can ask of the window. A view draws from the
//! settings and the jobs' results, may change the settings it owns, and
//! pushes [`Action`]s for anything else; the explorer applies them all in
//! one place after the frame is drawn.

use eframe::egui;

use super::jobs::{JobKind, Jobs};
use super::settings::{Settings, ViewKind};

/// What to export as CSV.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Export {
    Events,
    Trajectory,
    Bifurcation,
    Phase,
}

/// Something the user asked of the window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Action {
    /// A PNG of the whole window.
    Screenshot,
    /// A PNG of one view only.
    ViewScreenshot(ViewKind),
    /// An SVG of one view, or (`None`) of the views shown.
    SvgScreenshot(Option<ViewKind>),
    /// An animated GIF of the block or plane view, made off the UI thread,
    /// played at this speed (1 real time, below slowed).
    Record(ViewKind, f64),
    /// An animated GIF of a view following θν played across the diagram's
    /// range, made off the UI thread (a view of
    /// [`super::animation::PLAY_VIEWS`]).
    RecordPlay(ViewKind),
    /// The session (settings, zoom) as a JSON file.
    SaveSession,
    /// A CSV into the save folder.
    Export(Export),
    /// Open a session file (the desktop: a path in a modal; the browser:
    /// an upload).
    OpenSession,
    /// Write the current state into the page's URL and copy it (the
    /// browser build).
    #[cfg(target_arch = "wasm32")]
    CopyLink,
    /// Every parameter and view choice back to the first-launch demo.
    ResetDefaults,
    /// The trajectory again from θ = θν.
    RestartOrbit,
    /// Move θν (a click on the bifurcation diagram), within the slider's range.
    SetThetaNu(f64),
    /// Move one parameter (a click on a diagram in it), within the
    /// diagram's range and the model's.
    SetParam(crate::sim::continuation::ContParam, f64),
    /// Move θν and κ (a click on the phase diagram).
    SetPoint { theta_nu: f64, kappa: f64 },
    /// Start a job of this kind now, for the settings on screen (the
    /// buttons: Measure, Compute, Find bifurcations, Boundaries, Scan; how
    /// each starts is its line of the window's slot table).
    Start(JobKind),
    /// Stop the job of this kind; what it found so far stays.
    Stop(JobKind),
    /// The creep channel's passage time through the channel holding this
    /// creep onset, for the parameters on screen (the Events view).
    Passage(f64),
}

/// One view of the window.
pub trait View {
    /// The title over the view.
    fn title(&self) -> &'static str;

    /// The view's own controls (its switches, buttons and counts): drawn
    /// by the window above the view, or in its title row's menu where a
    /// tile is too small to give them the room, and never in a figure nor
    /// in the tour's tiles (see `Explorer::view_ui`).
    fn controls_ui(
        &mut self,
        _ui: &mut egui::Ui,
        _s: &mut Settings,
        _jobs: &Jobs,
        _out: &mut Vec<Action>,
    ) {
    }

    /// Draws the view into `ui` from the settings `s` and the results in
    /// `jobs`, below its controls; what it asks of the window goes to `out`.
    fn ui(&mut self, ui: &mut egui::Ui, s: &mut Settings, jobs: &Jobs, out: &mut Vec<Action>);
}
