//! The phase diagram (the paper's Fig. 4): the attractor's class over a
//! (θν, κ) grid, drawn as a texture with one texel per cell, rebuilt only
//! when cells arrive. Cells not computed yet take the colour of the nearest
//! computed one, paler, so the coarse lattice already fills the picture as
//! blocks that the refinement splits. The current (θν, κ) is a cross-hair;
//! hovering a cell tells its class, λ and cost; a click sets the θν and κ
//! sliders there; a dragged box is recomputed at full resolution, with back
//! and reset. The grid and budget are set here; when the job runs is the
//! job model's phase policy. "Boundaries" follows the doubling curves on
//! the worker and draws them over the grid ([`super::overlay`]).

use eframe::egui;
use egui::{Color32, RichText, TextureHandle, TextureOptions, Ui};
use egui_plot::{
    HLine, Plot, PlotBounds, PlotImage, PlotPoint, PlotPoints, PlotTransform, Polygon, VLine,
};

use super::axes::{self, AxisSpec};
use super::jobs::{JobKind, JobState, Jobs};
use super::phase_attractors;
use super::phase_data::PhaseData;
pub use super::phase_raster::{PROVISIONAL_ALPHA, cell_at, class_colour, rasterise};
use super::settings::{MAX_BUDGET, MAX_STEPS, MIN_STEPS, PhaseRange, Settings, ViewKind};
use super::style;
use super::view::{Action, View};
use super::{overlay, points_table};
use crate::model::KAPPA_RANGE;
use crate::sim::phase::{CellClass, PhaseCell};

/// The legend's classes, in order (`oneblock phase --png` draws this view).
const LEGEND_CLASSES: [(CellClass, &str); 9] = [
    (CellClass::Periodic(1), "FP"),
    (CellClass::Periodic(2), "P2"),
    (CellClass::Periodic(3), "P3"),
    (CellClass::Periodic(4), "P4"),
    (CellClass::Periodic(5), "P5"),
    (CellClass::Periodic(6), "P6+"),
    (CellClass::Chaos, "chaos"),
    (CellClass::Undecided, "undecided"),
    (CellClass::Failed, "failed"),
];

/// The view's runtime state: texture, drag, last transform.
#[derive(Default)]
pub struct PhaseView {
    texture: Option<TextureHandle>,
    built: Option<u64>,
    drag_from: Option<PlotPoint>,
    /// The last frame's plot transform (tests find cells on screen with it).
    pub transform: Option<PlotTransform>,
    /// The (θν, κ) of the cell last clicked: a multistable one's
    /// attractors are listed under the controls.
    pub selected: Option<(f64, f64)>,
}

/// The hover text of a cell.
pub fn describe_cell(theta_nu: f64, kappa: f64, cell: Option<&PhaseCell>) -> String {
    let head = format!("θν = {theta_nu:.4}, κ = {kappa:.4}");
    let Some(c) = cell else {
        return format!("{head}\nnot computed yet");
    };
    let class = match c.class {
        CellClass::Periodic(1) => "FP (fixed point)".to_string(),
        CellClass::Periodic(p) => format!("P{p} (period {p})"),
        CellClass::Chaos => "chaos (λ − 3σ > 0)".into(),
        CellClass::Undecided => "undecided (no period, λ not clearly > 0)".into(),
        CellClass::Failed => "failed".into(),
    };
    let regime = c
        .regime
        .map_or(String::new(), |r| format!(", {} onsets", r.name()));
    let lyapunov = match (c.lyapunov, c.lyapunov_stderr) {
        (Some(l), Some(se)) => format!("\n{}", crate::text::lyapunov(l, Some(se), false)),
        (Some(l), None) => format!(
            "\n{} (the cycle's exponent)",
            crate::text::lyapunov(l, None, true)
        ),
        _ => String::new(),
    };
    let error = c.error.as_ref().map_or(String::new(), |e| format!("\n{e}"));
    let count = phase_attractors::count_line(c.attractors, c.uncounted.as_deref());
    format!(
        "{head}\n{class}{regime}{lyapunov}{count}\n{} iterates{error}",
        c.iterates
    )
}

impl PhaseView {
    fn rebuild(&mut self, ui: &Ui, data: &PhaseData) {
        if self.built == Some(data.revision) && self.texture.is_some() {
            return;
        }
        let img = rasterise(data);
        match &mut self.texture {
            Some(t) => t.set(img, TextureOptions::NEAREST),
            None => {
                self.texture = Some(ui.ctx().load_texture("phase", img, TextureOptions::NEAREST));
            }
        }
        self.built = Some(data.revision);
    }

    /// Compute / Stop, the zoom buttons, where the grid stands, its
    /// resolution and budget, and the legend.
    /// The grid's legend, the attractors of the cell selected, the errors
    /// and the boundaries found (the controls are the window's to place:
    /// `View::controls_ui`).
    fn results_ui(&mut self, ui: &mut Ui, s: &Settings, jobs: &Jobs) {
        let data = &jobs.phase.data;
        legend_row_ui(ui, data, s.phase.seeds > 0);
        if let Some(sel) = self.selected
            && phase_attractors::list_ui(ui, data, sel)
        {
            self.selected = None;
        }
        if let Some(e) = &data.error {
            ui.label(RichText::new(e).color(style::ERROR));
        }
        if let Some(text) = &jobs.curves.summary {
            ui.label(RichText::new(format!("boundaries: {text}")).weak());
        }
        overlay::curve_legend_ui(ui, &jobs.curves.data, plot_box(s, data));
        points_table::generalised_flips_ui(ui, &jobs.curves.data);
    }

    /// The grid of cells; a box drawn zooms, a click sets θν and κ.
    fn plot_ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, out: &mut Vec<Action>) {
        let data = &jobs.phase.data;
        let grid = drawn_grid(s, data);
        let (range, dt, dk) = grid;
        let (t0, t1) = range.theta_nu;
        let (k0, k1) = range.kappa;
        let (tn, kappa) = (s.params.theta_nu, s.params.kappa);
        let tex = (data.rows * data.columns > 0)
            .then(|| self.texture.as_ref().map(|t| t.id()))
            .flatten();
        let drag_from = self.drag_from;
        let line_width = style::width(ui.ctx(), 2.0);
        // A cell's width on screen, from the last frame's transform.
        let cell_px = self.transform.map_or(0.0, |t| {
            (t.position_from_point_x(t0 + dt) - t.position_from_point_x(t0)).abs()
        });
        let resp = Plot::new("phase")
            .show_background(false)
            .allow_drag(false)
            .allow_zoom(false)
            .allow_scroll(false)
            .allow_boxed_zoom(false)
            .allow_double_click_reset(false)
            .show_x(false)
            .show_y(false)
            // Grid lines over a map of discrete cells read as cell borders.
            .show_grid(false);
        let current = style::draws_current(ui.ctx());
        let (x, y) = (
            AxisSpec::angle("θν, pull direction", s.angle_unit),
            AxisSpec::linear("κ = k_x/k_y, anisotropy"),
        );
        let resp = axes::apply(ui.ctx(), resp, &x, &y).show(ui, |p| {
            p.set_plot_bounds(PlotBounds::from_min_max(
                [t0 - dt / 2.0, k0 - dk / 2.0],
                [t1 + dt / 2.0, k1 + dk / 2.0],
            ));
            if let Some(id) = tex {
                p.add(PlotImage::new(
                    "phase diagram",
                    id,
                    PlotPoint::new((t0 + t1) / 2.0, (k0 + k1) / 2.0),
                    [(t1 - t0 + dt) as f32, (k1 - k0 + dk) as f32],
                ));
            }
            phase_attractors::marks(p, data, cell_px);
            // The grid's outline: chaos is black, and so is a dark panel.
            let (x0, x1) = (t0 - dt / 2.0, t1 + dt / 2.0);
            let (y0, y1) = (k0 - dk / 2.0, k1 + dk / 2.0);
            p.add(
                Polygon::new(
                    "grid outline",
                    PlotPoints::from(vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]),
                )
                .fill_color(Color32::TRANSPARENT)
                .stroke(egui::Stroke::new(1.0, style::CRITICAL)),
            );
            if current {
                p.add(
                    VLine::new("current θν", tn)
                        .color(style::CURRENT)
                        .width(1.5),
                );
                p.add(
                    HLine::new("current κ", kappa)
                        .color(style::CURRENT)
                        .width(1.5),
                );
            }
            overlay::curve_items(p, &jobs.curves.data, line_width, ([x0, y0], [x1, y1]));
            let pointer = p.pointer_coordinate();
            if let (Some(a), Some(b)) = (drag_from, pointer) {
                p.add(style::zoom_box(a, b));
            }
            pointer
        });
        axes::remember_frame(ui.ctx(), "phase", *resp.transform.frame());
        self.transform = Some(resp.transform);
        self.pointer_ui(ui, &resp.response, resp.inner, s, data, grid, out);
    }

    /// The hovered cell described; a box drawn zooms, a click sets θν and
    /// κ, Backspace goes back a zoom level.
    #[allow(clippy::too_many_arguments)]
    fn pointer_ui(
        &mut self,
        ui: &Ui,
        r: &egui::Response,
        pointer: Option<PlotPoint>,
        s: &mut Settings,
        data: &PhaseData,
        (range, dt, dk): (PhaseRange, f64, f64),
        out: &mut Vec<Action>,
    ) {
        let ((t0, t1), (k0, k1)) = (range.theta_nu, range.kappa);
        let hovered = pointer.and_then(|p| cell_at(data, p));
        if let Some((row, col)) = hovered
            && self.drag_from.is_none()
        {
            let (tns, ks) = (data.theta_nus(), data.kappas());
            let text = describe_cell(tns[col], ks[row], data.cell(row, col));
            r.clone().on_hover_text_at_pointer(text);
        }
        if r.drag_started() {
            self.drag_from = pointer;
        }
        if r.drag_stopped() {
            if let (Some(a), Some(b)) = (self.drag_from.take(), pointer) {
                let ((x0, x1), (y0, y1)) = style::box_ranges(a, b);
                let z = PhaseRange {
                    theta_nu: (x0.max(t0), x1.min(t1)),
                    kappa: (y0.max(k0), y1.min(k1)),
                };
                // A box narrower than a cell is a slip of the hand, not a zoom.
                let wide = z.theta_nu.1 - z.theta_nu.0 >= dt.abs().min(t1 - t0) * 0.5
                    && z.kappa.1 - z.kappa.0 >= dk.abs().min(k1 - k0) * 0.5;
                if wide && z.is_valid() {
                    s.phase.zoom.push(z);
                }
            }
        } else if r.clicked()
            && let Some((row, col)) = hovered
        {
            let (tns, ks) = (data.theta_nus(), data.kappas());
            self.selected = Some((tns[col], ks[row]));
            out.push(Action::SetPoint {
                theta_nu: tns[col],
                kappa: ks[row],
            });
        }
        if r.hovered() && ui.input(|i| i.key_pressed(egui::Key::Backspace)) {
            s.phase.zoom.pop();
        }
    }
}

impl View for PhaseView {
    fn title(&self) -> &'static str {
        ViewKind::Phase.title()
    }

    fn controls_ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, out: &mut Vec<Action>) {
        ui.horizontal_wrapped(|ui| {
            compute_button_ui(ui, jobs.phase.state == JobState::Running, out);
            boundaries_button_ui(ui, jobs, out);
            zoom_buttons_ui(ui, s);
            state_label_ui(ui, jobs);
        });
        grid_row_ui(ui, s);
    }

    fn ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, out: &mut Vec<Action>) {
        self.rebuild(ui, &jobs.phase.data);
        if style::figure_only(ui.ctx()) {
            legend_row_ui(ui, &jobs.phase.data, s.phase.seeds > 0);
            let bounds = plot_box(s, &jobs.phase.data);
            overlay::curve_legend_ui(ui, &jobs.curves.data, bounds);
        } else {
            self.results_ui(ui, s, jobs);
        }
        self.plot_ui(ui, s, jobs, out);
    }
}

/// The classes' colours, one swatch each (in a figure only the classes
/// its cells show: no "undecided" or "failed" where there is none), with
/// seeds the mark of a multistable cell, and while coarse cells are shown
/// what their pale colour means.
fn legend_row_ui(ui: &mut Ui, data: &PhaseData, seeds: bool) {
    let pale = !data.complete();
    let all = !style::figure_only(ui.ctx());
    style::legend_row(ui, |ui| {
        for (c, name) in LEGEND_CLASSES {
            let shown = |cell: &PhaseCell| class_colour(cell.class, 255) == class_colour(c, 255);
            if all || data.cells.iter().flatten().any(shown) {
                style::legend_swatch(ui, class_colour(c, 255), name);
            }
        }
        if seeds {
            phase_attractors::multistable_legend_ui(ui);
        }
        if pale {
            ui.label(RichText::new("pale: not refined yet").weak());
        }
    });
}

/// "Boundaries" (or "Stop" while the curves are followed).
fn boundaries_button_ui(ui: &mut Ui, jobs: &Jobs, out: &mut Vec<Action>) {
    if jobs.curves.state == JobState::Running {
        if ui
            .button("Stop curves")
            .on_hover_text("Stop following the doubling curves (those found stay)")
            .clicked()
        {
            out.push(Action::Stop(JobKind::Curves));
        }
    } else if ui
        .button("Boundaries")
        .on_hover_text(
            "Follow the period-doubling curves (FP to P2, P2 to P4) through the box in (θν, κ), \
             from the doublings found along θν at the κ slider's value. Runs on the \
             worker; a change of γ, ν, Ω or of the box stops it.",
        )
        .clicked()
    {
        out.push(Action::Start(JobKind::Curves));
    }
}

/// The whole range's ends (a change drops the zoom levels, which were
/// inside the old one).
fn range_ui(ui: &mut Ui, range: &mut PhaseRange, zoom: &mut Vec<PhaseRange>) {
    let before = *range;
    let PhaseRange { theta_nu, kappa } = range;
    egui::Grid::new("phase range").show(ui, |ui| {
        ui.label("θν from");
        ui.add(
            egui::DragValue::new(&mut theta_nu.0)
                .range(-std::f64::consts::PI..=theta_nu.1 - 1e-3)
                .speed(0.01),
        );
        ui.label("to");
        ui.add(
            egui::DragValue::new(&mut theta_nu.1)
                .range(theta_nu.0 + 1e-3..=std::f64::consts::PI)
                .speed(0.01),
        );
        ui.end_row();
        ui.label("κ from");
        ui.add(
            egui::DragValue::new(&mut kappa.0)
                .range(1e-3..=kappa.1 * 0.999)
                .speed(0.1),
        );
        ui.label("to");
        ui.add(
            egui::DragValue::new(&mut kappa.1)
                .range(kappa.0 * 1.001..=*KAPPA_RANGE.end())
                .speed(0.1),
        );
        ui.end_row();
    });
    if ui.button("The paper's (Fig. 4)").clicked() {
        *range = PhaseRange::PAPER;
    }
    if *range != before {
        if !range.is_valid() {
            *range = before;
        }
        zoom.clear();
    }
}

/// The grid drawn and its cells' sizes in θν and κ: the one computed (or
/// being computed); before any, the one that will be.
fn drawn_grid(s: &Settings, data: &PhaseData) -> (PhaseRange, f64, f64) {
    let (range, columns, rows) = if data.rows * data.columns > 0 {
        let range = PhaseRange {
            theta_nu: data.theta_nu,
            kappa: data.kappa,
        };
        (range, data.columns, data.rows)
    } else {
        let p = &s.phase;
        (p.current(), p.theta_nu_steps, p.kappa_steps)
    };
    let step = |(a, b): (f64, f64), n: usize| {
        if n > 1 {
            (b - a) / (n - 1) as f64
        } else {
            (b - a).abs().max(1e-3)
        }
    };
    let (dt, dk) = (step(range.theta_nu, columns), step(range.kappa, rows));
    (range, dt, dk)
}

/// The plot's bounds, (θν, κ) of its lower left and upper right corners:
/// the drawn grid's outer cell edges.
fn plot_box(s: &Settings, data: &PhaseData) -> ([f64; 2], [f64; 2]) {
    let (range, dt, dk) = drawn_grid(s, data);
    let ((t0, t1), (k0, k1)) = (range.theta_nu, range.kappa);
    (
        [t0 - dt / 2.0, k0 - dk / 2.0],
        [t1 + dt / 2.0, k1 + dk / 2.0],
    )
}

/// Compute (or Stop while the grid runs).
fn compute_button_ui(ui: &mut Ui, running: bool, out: &mut Vec<Action>) {
    if running {
        if ui
            .button("Stop")
            .on_hover_text("Stop computing this grid")
            .clicked()
        {
            out.push(Action::Stop(JobKind::Phase));
        }
    } else if ui
        .button("Compute")
        .on_hover_text(
            "Compute the grid now; it goes on even if the view is then hidden \
             (otherwise a grid runs only while its view is shown)",
        )
        .clicked()
    {
        out.push(Action::Start(JobKind::Phase));
    }
}

/// Back and Reset zoom.
fn zoom_buttons_ui(ui: &mut Ui, s: &mut Settings) {
    let zoomed = !s.phase.zoom.is_empty();
    if ui
        .add_enabled(zoomed, egui::Button::new("Back"))
        .on_hover_text("Previous zoom level (Backspace)")
        .clicked()
    {
        s.phase.zoom.pop();
    }
    if ui
        .add_enabled(zoomed, egui::Button::new("Reset zoom"))
        .on_hover_text("The whole range")
        .clicked()
    {
        s.phase.zoom.clear();
    }
}

/// How many cells are computed, and where the grid's job stands.
fn state_label_ui(ui: &mut Ui, jobs: &Jobs) {
    let (slot, data) = (&jobs.phase, &jobs.phase.data);
    let state = match &slot.state {
        JobState::Running => {
            format!(
                "computing, {:.0} iterates/s",
                slot.progress.iterates_per_second
            )
        }
        JobState::Done => "done".into(),
        JobState::Cancelled if jobs.phase_policy.stopped => "stopped".into(),
        JobState::Cancelled => "paused (view hidden)".into(),
        JobState::Failed(_) => "failed".into(),
        JobState::Idle => "computed when shown".into(),
    };
    ui.label(format!(
        "{}/{} cells · {state}",
        data.filled,
        data.rows * data.columns
    ))
    .on_hover_text(
        "Drag a box to zoom: that range is recomputed at full resolution. \
         A click sets the θν and κ sliders to the cell. Backspace: back.",
    );
}

/// The grid's size, the cells' iterate budgets and its range.
fn grid_row_ui(ui: &mut Ui, s: &mut Settings) {
    ui.horizontal_wrapped(|ui| {
        let p = &mut s.phase;
        ui.label("grid");
        ui.add(egui::DragValue::new(&mut p.theta_nu_steps).range(MIN_STEPS..=MAX_STEPS))
            .on_hover_text("θν columns (recomputes the grid)");
        ui.label("×");
        ui.add(egui::DragValue::new(&mut p.kappa_steps).range(MIN_STEPS..=MAX_STEPS))
            .on_hover_text("κ rows (recomputes the grid)");
        ui.label("transient");
        ui.add(egui::DragValue::new(&mut p.transient).range(0..=MAX_BUDGET))
            .on_hover_text(
                "The most iterates a cell spends looking for a period (oneblock phase --transient)",
            );
        ui.label("keep");
        ui.add(egui::DragValue::new(&mut p.keep).range(16..=MAX_BUDGET))
            .on_hover_text(
                "The most iterates with f'(θ) for the Lyapunov exponent when no period \
                 was found (oneblock phase --keep)",
            );
        ui.menu_button("range", |ui| range_ui(ui, &mut p.range, &mut p.zoom));
        phase_attractors::seeds_ui(ui, s);
    });
}
