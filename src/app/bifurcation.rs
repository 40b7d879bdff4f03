//! The live bifurcation diagram θ against θν (or κ, γ, ν, Ω: the
//! selector of [`super::diagram_axis`], on a log axis for those that span
//! decades), drawn as a density texture (one texel column per column)
//! rebuilt only when columns arrive: a plot marker per point would cost
//! ~80 ms a frame at 100k points (GUI-NOTES). Dragging a box zooms: the
//! window asks the worker for that range at full resolution and
//! rasterises the box's θ range. Back / reset walk the zoom stack; a click
//! sets the parameter. "Find bifurcations" asks the worker for the
//! branches over the shown range, drawn over the diagram
//! ([`super::overlay`]) with their special points in a table
//! ([`super::points_table`]).

use eframe::egui;
use egui::{RichText, TextureHandle, TextureOptions, Ui};
use egui_plot::{Plot, PlotBounds, PlotImage, PlotPoint};

use super::axes::{self, AxisSpec};
use super::basin_events;
use super::branches::{self, BranchData};
use super::data::SweepData;
use super::diagram_axis::{self, XAxis};
use super::diagram_lines::{Lines, lines_legend_ui};
use super::diagram_marks;
pub use super::diagram_raster::{OTHER_ATTRACTOR, auto_theta_range, rasterise};
use super::jobs::basins::BasinsData;
use super::jobs::{JobKind, JobState, Jobs, Slot};
use super::pinch::{Pinch, PinchEnd};
use super::settings::{Settings, ViewKind};
use super::style;
use super::view::{Action, View};
use super::{lyapunov_strip, overlay, points_table};

/// A zoomed part of the diagram.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Zoom {
    /// The range of the varied parameter (θν, the paper's, by default),
    /// in its values.
    pub theta_nu: (f64, f64),
    pub theta: (f64, f64),
}

/// The view's state: texture and zoom stack.
#[derive(Default)]
pub struct BifurcationView {
    texture: Option<TextureHandle>,
    built: Option<(u64, bool, usize)>,
    /// The θ range the texture covers.
    theta_range: (f64, f64),
    /// Zoom levels, innermost last; empty = the whole range.
    pub zoom: Vec<Zoom>,
    drag_from: Option<PlotPoint>,
    /// Two fingers on the diagram: a zoom box drawn until they lift.
    pinch: Pinch,
    /// The last frame's plot transform (tests find points on screen with it).
    pub transform: Option<egui_plot::PlotTransform>,
    /// The height the λ strip's legend took last frame, kept for it.
    strip_legend: f32,
    /// A figure's points as vector dots ([`diagram_marks`]).
    marks: Option<diagram_marks::Marks>,
}

impl BifurcationView {
    /// The range (of the varied parameter) the current zoom level asks
    /// for, if zoomed.
    pub fn theta_nu_range(&self) -> Option<(f64, f64)> {
        self.zoom.last().map(|z| z.theta_nu)
    }

    fn rebuild(&mut self, ui: &Ui, sweep: &SweepData, dark: bool) {
        // Thick lines (the projector's): points spread to about a line's
        // width, two texels a side at twice the width.
        let spread = ((style::width(ui.ctx(), 1.0) - 1.0) * 2.0).round().max(0.0) as usize;
        let key = (sweep.revision, dark, spread);
        if self.built == Some(key) && self.texture.is_some() {
            return;
        }
        self.theta_range = match self.zoom.last() {
            Some(z) => z.theta,
            None => auto_theta_range(sweep),
        };
        let (lo, hi) = self.theta_range;
        let img = rasterise(sweep, lo, hi, style::ink(dark), spread);
        let inks = (style::ink(dark), OTHER_ATTRACTOR);
        self.marks = diagram_marks::for_figure(ui.ctx(), sweep, (lo, hi), inks);
        match &mut self.texture {
            Some(t) => t.set(img, TextureOptions::NEAREST),
            None => {
                self.texture = Some(ui.ctx().load_texture(
                    "bifurcation",
                    img,
                    TextureOptions::NEAREST,
                ));
            }
        }
        self.built = Some(key);
    }

    /// Forces a rebuild on the next frame (zoom changed).
    pub fn invalidate(&mut self) {
        self.built = None;
    }

    /// Back, reset zoom, and where the sweep stands.
    fn buttons_ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, out: &mut Vec<Action>) {
        let slot: &Slot<SweepData> = &jobs.sweep;
        let sweep = &slot.data;
        let symbol = s.diagram.param.symbol();
        ui.horizontal_wrapped(|ui| diagram_axis::selector_ui(ui, s));
        ui.horizontal_wrapped(|ui| {
            find_button_ui(ui, jobs, symbol, out);
            if ui
                .add_enabled(!self.zoom.is_empty(), egui::Button::new("Back"))
                .on_hover_text("Previous zoom level (Backspace)")
                .clicked()
            {
                self.zoom.pop();
                self.invalidate();
            }
            if ui
                .add_enabled(!self.zoom.is_empty(), egui::Button::new("Reset zoom"))
                .on_hover_text("The whole range")
                .clicked()
            {
                self.zoom.clear();
                self.invalidate();
            }
            let state = match &slot.state {
                JobState::Running => "computing",
                JobState::Done => "done",
                JobState::Cancelled => "cancelled",
                JobState::Failed(_) => "failed",
                JobState::Idle => "idle",
            };
            ui.label(format!(
                "{}/{} columns · {} points · {state}",
                sweep.filled,
                sweep.columns.len(),
                sweep.points()
            ))
            .on_hover_text(format!(
                "Drag a box, or pinch two fingers apart, to zoom: that {symbol} range is \
                 recomputed with all its columns, not just magnified. A click sets {symbol}. \
                 Backspace or a pinch together: back."
            ));
            uncounted_ui(ui, sweep, symbol);
            ui.label(RichText::new(format!("drag or pinch: zoom · click: set {symbol}")).weak());
        });
    }

    /// The diagram, `height` points tall with a y axis `y_width` wide, with
    /// the branches over it; a box drawn zooms, a click sets θν.
    fn plot_ui(
        &mut self,
        ui: &mut Ui,
        s: &Settings,
        (sweep, events): (&SweepData, Option<&BasinsData>),
        found: &BranchData,
        (height, y_width): (f32, f32),
        out: &mut Vec<Action>,
    ) {
        let bounds = self.bounds(sweep);
        let axis = XAxis::of(sweep.param);
        let lines = Lines::of(ui.ctx(), s, bounds, sweep.param);
        let tex = self.texture.as_ref().map(|t| t.id());
        let (drag_from, pinch, marks) = (self.drag_from, self.pinch, self.marks.clone());
        let plot = Plot::new("bifurcation")
            .height(height)
            .show_background(false)
            .allow_drag(false)
            .allow_zoom(false)
            .allow_scroll(false)
            .allow_boxed_zoom(false)
            .allow_double_click_reset(false);
        let (ax, ay) = (
            axis.spec(s.angle_unit),
            AxisSpec::angle("θ, slip onset", s.angle_unit).fitted_along(ui, height),
        );
        let (hx, hy) = (ax.clone(), ay.clone());
        let resp = axes::apply(ui.ctx(), plot, &ax, &ay)
            .y_axis_min_width(y_width)
            // The overlay's items have hover labels of their own.
            .label_formatter(move |pos| match pos {
                egui_plot::HoverPosition::NearDataPoint { plot_name, .. }
                    if overlay::is_overlay_item(plot_name) =>
                {
                    None
                }
                _ => axes::hover_label(&hx, &hy, pos),
            })
            .show(ui, |p| {
                p.set_plot_bounds(PlotBounds::from_min_max(
                    [bounds.0, bounds.2],
                    [bounds.1, bounds.3],
                ));
                if let Some(id) = tex {
                    density_image(p, id, bounds);
                    if let Some(m) = marks {
                        diagram_marks::register(p.ctx(), id, m);
                    }
                }
                lines.draw(p);
                let (x0, x1, y0, y1) = bounds;
                let x = |v| axis.x(v);
                overlay::branch_items(p, found, lines.width, ([x0, y0], [x1, y1]), &x);
                if let Some(d) = events {
                    basin_events::event_items(p, d, Some(y1 - 0.025 * (y1 - y0)));
                }
                let pointer = p.pointer_coordinate();
                if let (Some(a), Some(b)) = (drag_from, pointer) {
                    p.add(style::zoom_box(a, b));
                }
                if let Some((a, b)) = pinch.preview(p.transform()) {
                    p.add(style::zoom_box(a, b));
                }
                pointer
            });
        axes::remember_frame(ui.ctx(), "bifurcation", *resp.transform.frame());
        self.transform = Some(resp.transform);
        self.hover_ui(&resp, found, events, axis);
        self.pointer_ui(ui, &resp.response, resp.inner, sweep, out);
    }

    /// The plot's bounds (x from, to, θ lo, hi; x the axis' coordinate
    /// of the varied parameter, [`XAxis`]): half a column's width beyond
    /// the end columns, so that each column's texel is centred on its
    /// value.
    pub fn bounds(&self, sweep: &SweepData) -> (f64, f64, f64, f64) {
        let axis = XAxis::of(sweep.param);
        let (from, to) = (axis.x(sweep.from), axis.x(sweep.to));
        let n = sweep.columns.len().max(2);
        let dx = (to - from) / (n - 1) as f64;
        let (lo, hi) = self.theta_range;
        (from - dx / 2.0, to + dx / 2.0, lo, hi)
    }

    /// The special point or branch under the pointer, named.
    fn hover_ui(
        &self,
        resp: &egui_plot::PlotResponse<Option<PlotPoint>>,
        found: &BranchData,
        events: Option<&BasinsData>,
        axis: XAxis,
    ) {
        let r = &resp.response;
        if self.drag_from.is_some() {
            return;
        }
        let Some(at) = r.hover_pos() else { return };
        let t = resp.transform;
        let to_screen = |xy: [f64; 2]| {
            let q = t.position_from_point(&PlotPoint::new(axis.x(xy[0]), xy[1]));
            [q.x, q.y]
        };
        if let Some(text) = branches::nearest(found, to_screen, [at.x, at.y], 8.0) {
            r.clone().on_hover_text_at_pointer(text);
        } else if let Some(d) = events {
            // An event's line within 4 points of the pointer (θν: the
            // axis is linear).
            let x = t.value_from_position(at).x;
            let reach = 4.0 * t.dvalue_dpos()[0].abs();
            if let Some(e) = basin_events::event_near(d, x, reach) {
                r.clone()
                    .on_hover_text_at_pointer(basin_events::event_sentence(e, d));
            }
        }
    }

    /// A box drawn zooms (recomputing its range of the varied parameter),
    /// a click sets that parameter, Backspace goes back a zoom level.
    fn pointer_ui(
        &mut self,
        ui: &Ui,
        r: &egui::Response,
        pointer: Option<PlotPoint>,
        sweep: &SweepData,
        out: &mut Vec<Action>,
    ) {
        let axis = XAxis::of(sweep.param);
        let (from, to) = (axis.x(sweep.from), axis.x(sweep.to));
        // In values: an end at the range's end is that end exactly (no
        // round trip through log10).
        let value = |x: f64| match x {
            _ if x == from => sweep.from,
            _ if x == to => sweep.to,
            _ => axis.value(x),
        };
        if let Some(t) = self.transform {
            match self.pinch.follow(ui, r.rect, &t) {
                Some(PinchEnd::In(x, th)) => {
                    self.zoom.push(Zoom {
                        theta_nu: (value(x.0.max(from)), value(x.1.min(to))),
                        theta: th,
                    });
                    self.invalidate();
                }
                Some(PinchEnd::Out) if !self.zoom.is_empty() => {
                    self.zoom.pop();
                    self.invalidate();
                }
                _ => {}
            }
        }
        if self.pinch.active() {
            // Two fingers zoom: no box, no click.
            self.drag_from = None;
            return;
        }
        if r.drag_started() {
            self.drag_from = pointer;
        }
        if r.drag_stopped() {
            if let (Some(a), Some(b)) = (self.drag_from.take(), pointer) {
                let ((x0, x1), th_range) = style::box_ranges(a, b);
                let tn_range = (x0.max(from), x1.min(to));
                if tn_range.1 - tn_range.0 > 1e-6 * (to - from).abs().max(1e-9)
                    && th_range.1 - th_range.0 > 1e-9
                {
                    self.zoom.push(Zoom {
                        theta_nu: (value(tn_range.0), value(tn_range.1)),
                        theta: th_range,
                    });
                    self.invalidate();
                }
            }
        } else if r.clicked()
            && let Some(p) = pointer
        {
            out.push(Action::SetParam(axis.param, axis.value(p.x)));
        }
        if r.hovered() && ui.input(|i| i.key_pressed(egui::Key::Backspace)) && !self.zoom.is_empty()
        {
            self.zoom.pop();
            self.invalidate();
        }
    }
}

/// The diagram's and the λ strip's heights (0: no strip), and the y-axis
/// width they share so that their frames line up, for `available` height.
/// The strip needs about 9 rows of text for five legible λ ticks; below 27
/// rows in all (a small tile) only the diagram is drawn. With the controls
/// folded (the tour's tiles, whose steps speak of λ) it is drawn down to
/// 17 rows in all, 7 of them its own (three ticks or more).
fn plot_sizes(ui: &Ui, available: f32) -> (f32, f32, f32) {
    let row = ui.text_style_height(&egui::TextStyle::Body);
    let (least, strip_least) = match style::controls_folded(ui.ctx()) {
        false => (27.0, 9.0),
        true => (17.0, 7.0),
    };
    if available < least * row {
        style::figure_note(ui.ctx(), lyapunov_strip::LEFT_OUT);
        return (available, 0.0, 5.5 * row);
    }
    let strip = (available * 0.3).clamp(strip_least * row, 18.0 * row);
    let diagram = available - strip - 0.5 * row;
    (diagram, strip, 5.5 * row)
}

/// The density image `id` over the plot's `bounds` (x from, to, θ lo,
/// hi). Its size narrows to single precision: one that does not fit is
/// not drawn (never an image at x="inf").
fn density_image(p: &mut egui_plot::PlotUi<'_>, id: egui::TextureId, bounds: (f64, f64, f64, f64)) {
    let (x0, x1, y0, y1) = bounds;
    let size = [(x1 - x0) as f32, (y1 - y0) as f32];
    if size.iter().all(|w| w.is_finite()) {
        p.add(PlotImage::new(
            "diagram",
            id,
            PlotPoint::new((x0 + x1) / 2.0, (y0 + y1) / 2.0),
            size,
        ));
    }
}

impl View for BifurcationView {
    fn title(&self) -> &'static str {
        ViewKind::Bifurcation.title()
    }

    fn controls_ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, out: &mut Vec<Action>) {
        self.buttons_ui(ui, s, jobs, out);
        seeds_ui(ui, s);
        points_table::points_ui(ui, &jobs.branches.data);
        points_table::cascade_ui(ui, &jobs.branches.data);
    }

    fn ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, out: &mut Vec<Action>) {
        self.rebuild(ui, &jobs.sweep.data, s.dark);
        let sweep = &jobs.sweep.data;
        lines_legend_ui(ui, &Lines::of(ui.ctx(), s, self.bounds(sweep), sweep.param));
        if s.sweep_seeds > 0 {
            style::legend_row(ui, |ui| seeds_legend_ui(ui, s));
        }
        if s.diagram_events() {
            style::legend_row(ui, |ui| basin_events::diagram_legend_ui(ui, jobs));
        }
        let (x0, x1, y0, y1) = self.bounds(sweep);
        let x = |v| XAxis::of(sweep.param).x(v);
        overlay::branch_legend_ui(ui, &jobs.branches.data, ([x0, y0], [x1, y1]), &x);
        // The λ strip's legend is drawn in its own panel, between the two
        // plots, in the room it took last frame.
        let with_strip = plot_sizes(ui, ui.available_height()).1 > 0.0;
        let legend = if with_strip { self.strip_legend } else { 0.0 };
        let (diagram, strip, y_width) = plot_sizes(ui, ui.available_height() - legend);
        let events = s.diagram_events().then_some(&jobs.basins.data);
        self.plot_ui(
            ui,
            s,
            (sweep, events),
            &jobs.branches.data,
            (diagram, y_width),
            out,
        );
        if with_strip && strip > 0.0 {
            let top = ui.cursor().top();
            lyapunov_strip::legend_ui(ui, s.dark, lyapunov_strip::below_strip(sweep));
            self.strip_legend = ui.cursor().top() - top;
            if let Some(tn) = lyapunov_strip::strip_ui(ui, s, sweep, (x0, x1), (strip, y_width)) {
                out.push(Action::SetParam(sweep.param, tn));
            }
        }
    }
}

/// The seeds of each column (a change recomputes the diagram); the
/// legend of the attractors they find is the view's.
fn seeds_ui(ui: &mut Ui, s: &mut Settings) {
    ui.horizontal_wrapped(|ui| {
        let mut on = s.sweep_seeds > 0;
        let r = ui.checkbox(&mut on, "every attractor").on_hover_text(
            "Every attractor at each column, from the exit arc's cell graph with no orbit \
             budget, beside the followed one: coexisting branches (hysteresis) show \
             (oneblock bifurcation --seeds 1).",
        );
        if r.changed() {
            s.sweep_seeds = usize::from(on);
        }
        basin_events::diagram_toggle_ui(ui, s);
    });
}

/// With seeds, the colours of the followed attractor and the others.
fn seeds_legend_ui(ui: &mut Ui, s: &Settings) {
    if s.sweep_seeds > 0 {
        style::legend_swatch(ui, style::ink(s.dark), "followed attractor");
        style::legend_swatch(ui, OTHER_ATTRACTOR, "other attractors");
    }
}

/// "Find bifurcations" (or "Stop" while it runs), and where it stands.
fn find_button_ui(ui: &mut Ui, jobs: &Jobs, symbol: &str, out: &mut Vec<Action>) {
    let slot = &jobs.branches;
    if slot.state == JobState::Running {
        if ui
            .button("Stop")
            .on_hover_text("Stop following the branches (those found so far stay)")
            .clicked()
        {
            out.push(Action::Stop(JobKind::Branches));
        }
    } else if ui
        .button("Find bifurcations")
        .on_hover_text(format!(
            "Follow the attractor's cycle at the left end of the shown {symbol} range to the \
             right end, locating its period doublings (PD), folds and borders to 1e-10, \
             then the doubled cycles in turn up to period 32. Runs on the worker; a \
             parameter or range change stops it."
        ))
        .clicked()
    {
        out.push(Action::Start(JobKind::Branches));
    }
}

/// The seeded columns whose attractors could not be counted (the exit
/// arc's cell graph could not be built), named: each shows its followed
/// orbit alone, which is no count of one (as `bifurcation --seeds` warns).
fn uncounted_ui(ui: &mut Ui, sweep: &SweepData, symbol: &str) {
    let uncounted: Vec<(f64, &str)> = sweep
        .columns
        .iter()
        .flatten()
        .filter_map(|c| Some((c.value, c.uncounted.as_deref()?)))
        .collect();
    if uncounted.is_empty() {
        return;
    }
    const LISTED: usize = 5;
    let mut list: Vec<String> = uncounted
        .iter()
        .take(LISTED)
        .map(|(v, why)| format!("{symbol} = {v:.4}: {why}"))
        .collect();
    if uncounted.len() > LISTED {
        list.push(format!("and {} more", uncounted.len() - LISTED));
    }
    ui.label(
        RichText::new(format!("{} not counted", uncounted.len())).color(ui.visuals().warn_fg_color),
    )
    .on_hover_text(format!(
        "Columns whose attractors could not be counted: the exit arc's cell graph could \
         not be built there, so each shows its followed orbit alone, which is no count of \
         one.\n{}",
        list.join("\n")
    ));
}
