//! What the window remembers between runs (eframe storage, serde with
//! `#[serde(default)]` so that older or partial saves still load), and the
//! named presets. Runtime handles (worker, textures, buffers) live elsewhere.

use serde::{Deserialize, Serialize};

use super::accuracy::{AccuracyMode, JobKind};
use super::phase_job::PhaseSettings;
use crate::integrate::{Method, SolverSettings};
use crate::model::Params;

/// The views the window can show.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum View {
    Plane,
    Block,
    Bifurcation,
    ReturnMap,
    Events,
    Numerics,
    Phase,
}

impl View {
    pub const ALL: [View; 7] = [
        View::Plane,
        View::Block,
        View::Bifurcation,
        View::ReturnMap,
        View::Events,
        View::Numerics,
        View::Phase,
    ];

    pub fn title(self) -> &'static str {
        match self {
            View::Plane => "Plane (x, y)",
            View::Block => "Block",
            View::Bifurcation => "Bifurcation",
            View::ReturnMap => "Return map",
            View::Events => "Events",
            View::Numerics => "Numerics",
            View::Phase => "Phase diagram",
        }
    }

    /// The name the command line uses (`--view`).
    pub fn key(self) -> &'static str {
        match self {
            View::Plane => "plane",
            View::Block => "block",
            View::Bifurcation => "bifurcation",
            View::ReturnMap => "return-map",
            View::Events => "events",
            View::Numerics => "numerics",
            View::Phase => "phase",
        }
    }

    pub fn from_key(s: &str) -> Option<View> {
        View::ALL.into_iter().find(|v| v.key() == s)
    }
}

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
    pub tab: View,
    /// Which views the tile layout shows.
    pub tiled: Vec<View>,
    /// Cycles kept on screen in the plane view.
    pub keep_cycles: usize,
    /// Cycles a trajectory job runs.
    pub trajectory_cycles: usize,
    /// Columns of the bifurcation diagram.
    pub columns: usize,
    /// Iterates dropped, then kept, per bifurcation column.
    pub sweep_transient: usize,
    pub sweep_keep: usize,
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
            tab: View::Plane,
            tiled: vec![
                View::Plane,
                View::Bifurcation,
                View::ReturnMap,
                View::Events,
            ],
            keep_cycles: 12,
            trajectory_cycles: 400,
            columns: 400,
            sweep_transient: 300,
            sweep_keep: 200,
            font_scale: 1.0,
            dark: false,
            smooth_lines: None,
            slip_measure: SlipMeasure::Distance,
            scale_x_by_kappa: true,
            save_dir: default_save_dir(),
            block_speed: 1.0,
            preset: Some("fig3b".into()),
            phase: PhaseSettings::default(),
        }
    }
}

fn default_save_dir() -> String {
    std::env::current_dir()
        .map(|p| p.display().to_string())
        .unwrap_or_else(|_| ".".into())
}

impl Settings {
    /// The Custom choice of method and tolerance/step (each job's setting
    /// is [`Settings::solver_for`]).
    pub fn custom_solver(&self) -> SolverSettings {
        if self.method.is_adaptive() {
            SolverSettings::adaptive(self.method, self.tol)
        } else {
            SolverSettings::fixed(self.method, self.step)
        }
    }

    /// The θν range of the full (unzoomed) bifurcation diagram.
    pub fn sweep_range(&self) -> (f64, f64) {
        if self.full_circle {
            (-std::f64::consts::PI, std::f64::consts::PI)
        } else {
            (0.0, std::f64::consts::FRAC_PI_2)
        }
    }

    /// The part of the settings a bifurcation sweep depends on (θν is its
    /// x-axis, so it is left out).
    pub fn sweep_key(&self) -> SweepKey {
        SweepKey {
            kappa: self.params.kappa,
            gamma: self.params.gamma,
            nu: self.params.nu,
            omega: self.params.omega,
            solver: self.solver_for(JobKind::Sweep),
            columns: self.columns,
            transient: self.sweep_transient,
            keep: self.sweep_keep,
            full_circle: self.full_circle,
        }
    }
}

/// What a bifurcation sweep depends on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepKey {
    pub kappa: f64,
    pub gamma: f64,
    pub nu: f64,
    pub omega: f64,
    pub solver: SolverSettings,
    pub columns: usize,
    pub transient: usize,
    pub keep: usize,
    pub full_circle: bool,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_lines_auto_is_off_only_on_software_gl() {
        let mut s = Settings::default();
        assert!(s.smooth_lines_on(false));
        assert!(!s.smooth_lines_on(true));
        s.smooth_lines = Some(true);
        assert!(s.smooth_lines_on(true));
        s.smooth_lines = Some(false);
        assert!(!s.smooth_lines_on(false));
    }
}
