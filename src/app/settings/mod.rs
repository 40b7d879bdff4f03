//! What the window remembers between runs (eframe storage, serde with
//! `#[serde(default)]` so that older or partial saves still load), and the
//! named presets. Runtime handles (worker, textures, buffers) live elsewhere.

use serde::{Deserialize, Serialize};

use std::f64::consts::{FRAC_PI_2, PI};

use crate::integrate::{Method, SolverSettings};
use crate::model::Params;

mod diagram;
mod grids;
pub use diagram::*;
pub use grids::*;

/// The views the window can show.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ViewKind {
    Plane,
    Block,
    Bifurcation,
    ReturnMap,
    Events,
    Numerics,
    Phase,
    TimeSeries,
    Basins,
}

impl ViewKind {
    pub const ALL: [ViewKind; 9] = [
        ViewKind::Plane,
        ViewKind::Block,
        ViewKind::Bifurcation,
        ViewKind::ReturnMap,
        ViewKind::Events,
        ViewKind::Numerics,
        ViewKind::Phase,
        ViewKind::TimeSeries,
        ViewKind::Basins,
    ];

    pub fn title(self) -> &'static str {
        match self {
            ViewKind::Plane => "Plane (x, y)",
            ViewKind::Block => "Block",
            ViewKind::Bifurcation => "Bifurcation",
            ViewKind::ReturnMap => "Return map",
            ViewKind::Events => "Events",
            ViewKind::Numerics => "Numerics",
            ViewKind::Phase => "Phase diagram",
            ViewKind::TimeSeries => "Time series",
            ViewKind::Basins => "Basins",
        }
    }

    /// The tab bar's shorter name: nine full titles wrapped the bar onto a
    /// second line at text ×1.5, taking height from the view.
    pub fn tab_title(self) -> &'static str {
        match self {
            ViewKind::Plane => "Plane",
            ViewKind::Phase => "Phase",
            v => v.title(),
        }
    }

    /// The name the command line uses (`--view`).
    pub fn key(self) -> &'static str {
        match self {
            ViewKind::Plane => "plane",
            ViewKind::Block => "block",
            ViewKind::Bifurcation => "bifurcation",
            ViewKind::ReturnMap => "return-map",
            ViewKind::Events => "events",
            ViewKind::Numerics => "numerics",
            ViewKind::Phase => "phase",
            ViewKind::TimeSeries => "time-series",
            ViewKind::Basins => "basins",
        }
    }

    pub fn from_key(s: &str) -> Option<ViewKind> {
        ViewKind::ALL.into_iter().find(|v| v.key() == s)
    }
}

/// How the jobs' solver settings are chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum AccuracyMode {
    /// Each job gets the cheapest setting meeting its view's accuracy.
    #[default]
    Auto,
    /// Every job runs with the method and tolerance/step of the controls.
    Custom,
}

/// The longest save folder a saved file may name, in bytes (a path this
/// long is already far past any file system's limit; a 10 MB string once
/// made the window abort laying out its text field).
pub const MAX_SAVE_DIR_LEN: usize = 4096;
/// The most zoom levels a saved file may stack (phase or bifurcation).
pub const MAX_ZOOM_LEVELS: usize = 64;

/// Whether (a, b) is a range a view can show: finite, increasing, and
/// wider than 1e-12 of its ends' size (and than 1e-12 absolutely). A
/// narrower range has no distinct round values to label, and a saved
/// zoom of width 5e-324 once froze the window.
pub fn is_usable_range((a, b): (f64, f64)) -> bool {
    // The width and the centre finite too: -1e308 to 1e308 is not a range
    // a plot can draw (inf and NaN coordinates).
    a.is_finite()
        && b.is_finite()
        && (b - a).is_finite()
        && (a + b).is_finite()
        && b - a > 1e-12 * a.abs().max(b.abs()).max(1.0)
}

/// The most cycles a saved trajectory length may ask for.
pub const MAX_TRAJECTORY_CYCLES: usize = 100_000;
/// The most iterates a saved diagram column may drop or keep.
pub const MAX_SWEEP_ITERATES: usize = 100_000;
/// The most seeds a diagram column may have in the window.
pub const MAX_SWEEP_SEEDS: usize = 64;

/// One view at a time, or several side by side.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Layout {
    Tabs,
    Tiles,
}

/// How a slip's size is measured in the event catalogue.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum SlipMeasure {
    /// |stop − onset|.
    Distance,
    /// Elastic energy released.
    Energy,
}

/// Which of the Events view's plots it shows when it is too narrow for
/// all of them (a tile, or large text).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum EventsPlot {
    /// The slip sizes over the event number.
    #[default]
    Series,
    /// The slip-size distribution.
    Sizes,
    /// The laminar lengths' distribution.
    Laminar,
    /// The mean laminar length against the distance to a located tangency.
    Scaling,
}

impl EventsPlot {
    /// Every plot, in the menu's order.
    pub const ALL: [EventsPlot; 4] = [
        EventsPlot::Series,
        EventsPlot::Sizes,
        EventsPlot::Laminar,
        EventsPlot::Scaling,
    ];
}

/// How angle axes (θν, θ) are labelled.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum AngleUnit {
    /// Radians at 1-2-5 steps.
    #[default]
    Radians,
    /// Degrees at 1-2-5 steps.
    Degrees,
    /// Fractions of π (π/8, π/4, …).
    PiFractions,
}

/// Everything persisted. Parameters are kept valid: typed values reach
/// them only after validation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Settings {
    pub params: Params,
    /// Auto: each job gets the cheapest setting for its view; Custom: the
    /// method and tolerance/step below for every job.
    pub accuracy: AccuracyMode,
    /// Custom's method.
    pub method: Method,
    /// Custom's tolerance of the adaptive methods (rtol = atol).
    pub tol: f64,
    /// Custom's step of the fixed-step methods.
    pub step: f64,
    /// θν slider over the full circle instead of 0 … π/2.
    pub full_circle: bool,
    pub layout: Layout,
    /// The view shown in tab layout.
    pub tab: ViewKind,
    /// Which views the tile layout shows.
    pub tiled: Vec<ViewKind>,
    /// Cycles kept on screen in the plane view.
    pub keep_cycles: usize,
    /// Cycles a trajectory job runs.
    pub trajectory_cycles: usize,
    /// Columns of the bifurcation diagram.
    pub columns: usize,
    /// Iterates dropped, then kept, per bifurcation column.
    pub sweep_transient: usize,
    pub sweep_keep: usize,
    /// θ₀ spread over each column's exit arc besides the followed orbit
    /// (`oneblock bifurcation --seeds`; 0: none): every attractor is drawn.
    pub sweep_seeds: usize,
    /// Births and deaths of attractors (the Basins job's events, located
    /// along θν) marked on a θν bifurcation diagram.
    pub sweep_events: bool,
    /// Text size multiplier (projectors).
    pub font_scale: f32,
    pub dark: bool,
    /// Anti-aliased lines and shapes (egui's feathering); `None` = auto: on,
    /// except under a software OpenGL rasteriser, which is fill-bound and
    /// draws the feathered edges' extra triangles at a third of its frame
    /// time (docs/gui.md, "Frame time").
    pub smooth_lines: Option<bool>,
    pub slip_measure: SlipMeasure,
    /// Plot (κx, y) instead of (x, y): C becomes the unit circle.
    pub scale_x_by_kappa: bool,
    /// Folder where screenshots and exports go.
    pub save_dir: String,
    /// Playback speed of the block view (slip time units per second).
    pub block_speed: f32,
    /// Name of the preset last applied (for the window title).
    pub preset: Option<String>,
    /// The phase diagram's grid, range and zoom.
    pub phase: PhaseSettings,
    /// How θν and θ axes are labelled.
    pub angle_unit: AngleUnit,
    /// Which of f², f³, f⁴ the return map draws beside f.
    pub map_powers: [bool; 3],
    /// The return map drawn as f(θ) − θ against θ: where f hugs the
    /// diagonal (creep, the inset of the paper's Fig. 3a) its distance
    /// from it is too small to see otherwise.
    pub map_difference: bool,
    /// The projector preset: thick lines and high contrast (and, when
    /// switched on, large text).
    pub projector: bool,
    /// The Events view's plot when it shows one at a time.
    pub events_plot: EventsPlot,
    /// The Basins view's columns and θν zoom.
    pub basins: BasinsSettings,
    /// Presentation: the side panel hidden (H, the top bar's Panel,
    /// `gui --hide-panel`), the views taking its width.
    pub hide_panel: bool,
    /// How fast Play moves θν, in radians per second of the window.
    pub play_speed: f64,
    /// The bifurcation diagram's axis: the parameter it varies (θν, or
    /// κ, γ, ν, Ω) and their ranges.
    pub diagram: DiagramAxis,
}

impl Settings {
    /// Sets every parameter from a preset (and its name, for the title);
    /// a preset's θν outside [0, π/2] turns the full circle on.
    pub fn apply_preset(&mut self, p: &Params, key: &str) {
        self.params = *p;
        if !(0.0..=FRAC_PI_2).contains(&p.theta_nu) {
            self.full_circle = true;
        }
        self.preset = Some(key.to_string());
    }
}

impl Settings {
    /// Whether lines are anti-aliased, given whether the renderer is a
    /// software rasteriser.
    pub fn smooth_lines_on(&self, software_gl: bool) -> bool {
        self.smooth_lines.unwrap_or(!software_gl)
    }
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            params: Params::default(),
            accuracy: AccuracyMode::Auto,
            method: Method::Dop853,
            tol: 1e-9,
            step: 1e-3,
            full_circle: false,
            layout: Layout::Tiles,
            tab: ViewKind::Plane,
            tiled: vec![
                ViewKind::Plane,
                ViewKind::Bifurcation,
                ViewKind::ReturnMap,
                ViewKind::Events,
            ],
            keep_cycles: 12,
            trajectory_cycles: 400,
            columns: 400,
            sweep_transient: 300,
            sweep_keep: 200,
            sweep_seeds: 0,
            sweep_events: false,
            font_scale: 1.0,
            dark: false,
            smooth_lines: None,
            slip_measure: SlipMeasure::Distance,
            scale_x_by_kappa: true,
            save_dir: default_save_dir(),
            block_speed: 1.0,
            preset: Some("fig3b".into()),
            phase: PhaseSettings::default(),
            angle_unit: AngleUnit::Radians,
            map_powers: [false; 3],
            map_difference: false,
            projector: false,
            events_plot: EventsPlot::Series,
            basins: Default::default(),
            hide_panel: false,
            play_speed: PLAY_SPEEDS[1],
            diagram: DiagramAxis::default(),
        }
    }
}

/// Play's speeds of θν (radians per second): the cascade of Fig. 3b
/// (θν 1.05 … 1.57) in about 50, 20 and 8 seconds.
pub const PLAY_SPEEDS: [f64; 3] = [0.01, 0.025, 0.06];

fn default_save_dir() -> String {
    std::env::current_dir()
        .map(|p| p.display().to_string())
        .unwrap_or_else(|_| ".".into())
}

/// Resets `v` to `default` if it is outside `range`, naming it in `bad`.
fn within<T: PartialOrd + Copy>(
    v: &mut T,
    range: std::ops::RangeInclusive<T>,
    default: T,
    name: &'static str,
    bad: &mut Vec<&'static str>,
) {
    if !range.contains(v) {
        *v = default;
        bad.push(name);
    }
}

impl Settings {
    /// The Custom choice of method and tolerance/step (each job's setting
    /// is `JobKind::solver`).
    pub fn custom_solver(&self) -> SolverSettings {
        if self.method.is_adaptive() {
            SolverSettings::adaptive(self.method, self.tol)
        } else {
            SolverSettings::fixed(self.method, self.step)
        }
    }

    /// The same settings with every field a saved file may have spoiled
    /// (NaN, infinite, negative, huge) back to its default, and the names
    /// of the fields that were. A loaded file may hold anything: the window
    /// must open on values it can run.
    pub fn sanitised(mut self) -> (Settings, Vec<&'static str>) {
        let d = Settings::default();
        let mut bad = Vec::new();
        self.sanitise_model(&d, &mut bad);
        self.sanitise_counts(&d, &mut bad);
        self.sanitise_layout(&d, &mut bad);
        (self, bad)
    }

    /// The parameters and the solver's tolerance and step.
    fn sanitise_model(&mut self, d: &Settings, bad: &mut Vec<&'static str>) {
        let params_ok =
            self.params.validate().is_ok() && (-PI..=PI).contains(&self.params.theta_nu);
        if !params_ok {
            self.params = d.params;
            self.full_circle = d.full_circle;
            bad.push("parameters");
        } else if !(0.0..=FRAC_PI_2).contains(&self.params.theta_nu) {
            self.full_circle = true;
        }
        if SolverSettings::adaptive(Method::Dop853, self.tol)
            .validate()
            .is_err()
        {
            self.tol = d.tol;
            bad.push("tolerance");
        }
        if SolverSettings::fixed(Method::Rk4, self.step)
            .validate()
            .is_err()
        {
            self.step = d.step;
            bad.push("step");
        }
    }

    /// The counts and sizes, each within its slider's range.
    fn sanitise_counts(&mut self, d: &Settings, bad: &mut Vec<&'static str>) {
        within(
            &mut self.keep_cycles,
            1..=1000,
            d.keep_cycles,
            "cycles shown",
            bad,
        );
        within(
            &mut self.trajectory_cycles,
            1..=MAX_TRAJECTORY_CYCLES,
            d.trajectory_cycles,
            "trajectory cycles",
            bad,
        );
        within(
            &mut self.columns,
            20..=2000,
            d.columns,
            "diagram columns",
            bad,
        );
        within(
            &mut self.sweep_transient,
            0..=MAX_SWEEP_ITERATES,
            d.sweep_transient,
            "diagram transient",
            bad,
        );
        within(
            &mut self.sweep_keep,
            1..=MAX_SWEEP_ITERATES,
            d.sweep_keep,
            "diagram iterates kept",
            bad,
        );
        within(
            &mut self.sweep_seeds,
            0..=MAX_SWEEP_SEEDS,
            d.sweep_seeds,
            "diagram seeds",
            bad,
        );
        within(
            &mut self.font_scale,
            0.5..=3.0,
            d.font_scale,
            "text size",
            bad,
        );
        within(
            &mut self.play_speed,
            PLAY_SPEEDS[0]..=PLAY_SPEEDS[2],
            d.play_speed,
            "play speed",
            bad,
        );
        within(
            &mut self.block_speed,
            0.1..=10.0,
            d.block_speed,
            "block speed",
            bad,
        );
    }

    /// The tiles, the save folder, the preset's name and the phase grid.
    fn sanitise_layout(&mut self, d: &Settings, bad: &mut Vec<&'static str>) {
        // Tiles are the views that exist, each once (a file once held
        // 10,000, and laying them out aborted the window).
        let mut tiles = Vec::new();
        for v in &self.tiled {
            if !tiles.contains(v) {
                tiles.push(*v);
            }
        }
        if tiles.is_empty() || tiles.len() != self.tiled.len() {
            self.tiled = if tiles.is_empty() {
                d.tiled.clone()
            } else {
                tiles
            };
            bad.push("tiles");
        }
        if self.save_dir.len() > MAX_SAVE_DIR_LEN || self.save_dir.contains('\0') {
            self.save_dir = d.save_dir.clone();
            bad.push("save folder");
        }
        // The preset only names the window's title: a known key or none.
        if self
            .preset
            .as_deref()
            .is_some_and(|k| crate::model::preset(k).is_none())
        {
            self.preset = None;
            bad.push("preset");
        }
        let phase = self.phase.clone().sanitised();
        if phase != self.phase {
            self.phase = phase;
            bad.push("phase grid");
        }
        let (diagram, spoiled) = self.diagram.sanitised();
        if spoiled {
            self.diagram = diagram;
            bad.push("diagram range");
        }
        let basins = self.basins.clone().sanitised();
        if basins != self.basins {
            self.basins = basins;
            bad.push("basins view");
        }
    }

    /// The highest power f^k of the map the return map draws (1: f alone).
    pub fn graph_power(&self) -> usize {
        self.map_powers
            .iter()
            .rposition(|&on| on)
            .map_or(1, |i| i + 2)
    }

    /// Whether `v` is on screen (as the tab, or one of the tiles).
    pub fn shows(&self, v: ViewKind) -> bool {
        match self.layout {
            Layout::Tabs => self.tab == v,
            Layout::Tiles => self.tiled.contains(&v),
        }
    }

    /// The range of the full (unzoomed) bifurcation diagram, in the
    /// parameter it varies ([`DiagramAxis`]).
    pub fn sweep_range(&self) -> (f64, f64) {
        self.diagram
            .range(self.diagram.param)
            .unwrap_or_else(|| self.theta_nu_range())
    }

    /// Whether a θν bifurcation diagram marks births and deaths
    /// ([`Self::sweep_events`]: the Basins job then runs over its range).
    pub fn diagram_events(&self) -> bool {
        self.sweep_events
            && self.diagram.param == crate::sim::continuation::ContParam::ThetaNu
            && self.shows(ViewKind::Bifurcation)
    }

    /// The θν slider's range: [0, π/2], or the full circle.
    pub fn theta_nu_range(&self) -> (f64, f64) {
        if self.full_circle {
            (-std::f64::consts::PI, std::f64::consts::PI)
        } else {
            (0.0, std::f64::consts::FRAC_PI_2)
        }
    }
}

#[cfg(test)]
mod tests;
