//! The Basins view: every attractor's basin over the whole exit arc
//! against θν (`jobs::basins`, a cell graph per column, no orbit budget),
//! each basin coloured by the attractor it reaches, followed from column
//! to column (`jobs::basins::identity`), the basin boundary grey; below,
//! the basin fractions stacked against θν; each track's births, deaths
//! and period changes marked (`basin_events`), and explained on hover,
//! as is a basin. Dragging a box zooms (its θν range is recomputed with
//! all its columns); a click lists that column's attractors.

use eframe::egui::{self, Color32, RichText, Ui};
use egui_plot::{Plot, PlotBounds, PlotPoint, PlotPoints, Polygon, VLine};

use super::axes::{self, AxisSpec};
use super::basin_events;
use super::jobs::basins::BasinsData;
use super::jobs::{JobState, Jobs, Slot};
use super::settings::{MAX_COLUMNS, MIN_COLUMNS, Settings, ViewKind, is_usable_range};
use super::style;
use super::view::{Action, View};
use crate::sim::attractors::tracks::Identities;
use crate::sim::attractors::{Attractor, Basin, Verdict};

/// The basin boundary's grey.
pub const BOUNDARY: Color32 = Color32::from_gray(170);

/// Attractor colours, by track (an attractor followed along θν): the
/// colours of Tableau 20 that are not grey (the boundary's), the nine
/// strong ones first, then their light partners, and teal.
const PALETTE: [Color32; 18] = [
    Color32::from_rgb(31, 119, 180),
    Color32::from_rgb(255, 127, 14),
    Color32::from_rgb(44, 160, 44),
    Color32::from_rgb(214, 39, 40),
    Color32::from_rgb(148, 103, 189),
    Color32::from_rgb(140, 86, 75),
    Color32::from_rgb(227, 119, 194),
    Color32::from_rgb(188, 189, 34),
    Color32::from_rgb(23, 190, 207),
    Color32::from_rgb(174, 199, 232),
    Color32::from_rgb(255, 187, 120),
    Color32::from_rgb(152, 223, 138),
    Color32::from_rgb(255, 152, 150),
    Color32::from_rgb(197, 176, 213),
    Color32::from_rgb(196, 156, 148),
    Color32::from_rgb(247, 182, 210),
    Color32::from_rgb(219, 219, 141),
    // Teal in place of Tableau's light cyan, too near its light blue.
    Color32::from_rgb(0, 128, 128),
];

/// The colour of track `id`, never another track's: the palette, then
/// hues a golden angle apart at three lightnesses (each id its own colour;
/// past 18 tracks two may be close, and their names in the legend and a
/// click's list tell them apart).
pub fn track_color(id: usize) -> Color32 {
    if let Some(&c) = PALETTE.get(id) {
        return c;
    }
    let k = id - PALETTE.len();
    let hue = (k as f32 * 0.381_966).fract();
    let value = [0.55, 0.75, 0.95][k % 3];
    let saturation = [0.85, 0.6, 0.45][(k / 3) % 3];
    let c = egui::ecolor::Hsva::new(hue, saturation, value, 1.0);
    Color32::from(c)
}

/// `#rrggbb` of a colour, as the basins CSV writes it.
pub fn hex(c: Color32) -> String {
    format!("#{:02x}{:02x}{:02x}", c.r(), c.g(), c.b())
}

/// What a numbered name means, under the legend when one is drawn.
pub const SECOND_NAME: &str = "A name is an attractor followed along θν, its periods in \
    order (P2 → P1: a P2 that halves into a fixed point). A numbered one, as P2 (2), is \
    a second attractor of that kind, not the first one continued: neither lies in the \
    other's basin.";

/// The view's own state: the column clicked and a box being drawn.
#[derive(Default)]
pub struct BasinsView {
    selected: Option<usize>,
    drag_from: Option<PlotPoint>,
}

/// A column's θν and its half width.
fn column_x(d: &BasinsData, i: usize) -> (f64, f64) {
    let n = d.columns.len().max(1);
    let dx = if n > 1 {
        (d.to - d.from) / (n - 1) as f64
    } else {
        (d.to - d.from).abs().max(1e-3)
    };
    let x = d.columns[i]
        .as_ref()
        .map_or(d.from + dx * i as f64, |c| c.theta_nu);
    (x, dx.abs() / 2.0)
}

/// A filled rectangle, no stroke.
fn rect(name: &str, (x0, x1): (f64, f64), (y0, y1): (f64, f64), c: Color32) -> Polygon<'static> {
    let pts = vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]];
    Polygon::new(name, PlotPoints::from(pts))
        .fill_color(c)
        .stroke(egui::Stroke::NONE)
}

/// The name and colour of the attractor `a` of column `c`, or the
/// boundary's.
fn named(ids: &Identities, c: usize, a: Option<usize>) -> (String, Color32) {
    match a.and_then(|a| ids.track(c, a)) {
        Some(t) => (t.label.clone(), track_color(t.id)),
        None => ("basin boundary".into(), BOUNDARY),
    }
}

/// The basins of every column that arrived, over the exit arc.
fn basin_items(p: &mut egui_plot::PlotUi<'_>, d: &BasinsData) {
    for (i, col) in d.columns.iter().enumerate() {
        let Some(Ok(found)) = col.as_ref().map(|c| &c.found) else {
            continue;
        };
        let (x, h) = column_x(d, i);
        for &Basin {
            from,
            to,
            attractor,
        } in &found.basins
        {
            let (name, c) = named(&d.ids, i, attractor);
            p.add(rect(&name, (x - h, x + h), (from, to), c));
        }
    }
}

/// Each column's basin fractions stacked from 0, the boundary's on top.
fn fraction_items(p: &mut egui_plot::PlotUi<'_>, d: &BasinsData) {
    for (i, col) in d.columns.iter().enumerate() {
        let Some(Ok(found)) = col.as_ref().map(|c| &c.found) else {
            continue;
        };
        let (x, h) = column_x(d, i);
        let mut y = 0.0;
        for (a, at) in found.attractors.iter().enumerate() {
            let (name, c) = named(&d.ids, i, Some(a));
            p.add(rect(&name, (x - h, x + h), (y, y + at.basin_fraction), c));
            y += at.basin_fraction;
        }
        let (name, c) = named(&d.ids, i, None);
        p.add(rect(
            &name,
            (x - h, x + h),
            (y, y + found.boundary_fraction),
            c,
        ));
    }
}

/// The θ range the columns' arcs cover.
fn theta_range(d: &BasinsData) -> (f64, f64) {
    let arcs = d
        .columns
        .iter()
        .flatten()
        .filter_map(|c| c.found.as_ref().ok());
    let ends = arcs.filter_map(|f| Some((f.basins.first()?.from, f.basins.last()?.to)));
    let (lo, hi) = ends.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (l, h)| {
        (a.min(l), b.max(h))
    });
    if lo < hi { (lo, hi) } else { (-1.0, 2.0) }
}

/// One line per attractor of column `i`: what the window lists on a click
/// (and `figure --out x.csv` writes).
pub fn describe(a: &Attractor) -> String {
    let what = a.stability().replace("+-", "±");
    let verdict = match &a.verdict {
        Verdict::Proved => "proved".to_string(),
        Verdict::CycleInSet => "cycle in a larger set".to_string(),
        Verdict::Chaotic => "chaotic".to_string(),
        Verdict::Undecided(why) => format!("undecided: {why}"),
    };
    format!("basin {:.4}  {what}  ({verdict})", a.basin_fraction)
}

impl BasinsView {
    /// Columns, zoom buttons and where the job stands.
    fn settings_ui(&mut self, ui: &mut Ui, s: &mut Settings, slot: &Slot<BasinsData>) {
        ui.horizontal_wrapped(|ui| {
            ui.label("columns");
            ui.add(egui::DragValue::new(&mut s.basins.columns).range(MIN_COLUMNS..=MAX_COLUMNS))
                .on_hover_text(
                    "θν columns, each every attractor and basin from a cell graph of f \
                     over the exit arc (oneblock figure --view basins --columns)",
                );
            if ui
                .add_enabled(!s.basins.zoom.is_empty(), egui::Button::new("Back"))
                .clicked()
            {
                s.basins.zoom.pop();
            }
            if ui
                .add_enabled(!s.basins.zoom.is_empty(), egui::Button::new("Reset zoom"))
                .clicked()
            {
                s.basins.zoom.clear();
            }
            ui.label(RichText::new("drag: zoom · click: list a column").weak());
        });
        status_ui(ui, slot);
    }

    /// The basins plot; a box drawn zooms, a click selects a column.
    fn basins_plot_ui(&mut self, ui: &mut Ui, s: &mut Settings, d: &BasinsData, height: f32) {
        let (lo, hi) = theta_range(d);
        let (x0, x1) = x_bounds(d);
        let drag_from = self.drag_from;
        let selected = self.selected.filter(|_| !style::figure_only(ui.ctx()));
        let sel_x = selected
            .filter(|&i| i < d.columns.len())
            .map(|i| column_x(d, i).0);
        let plot = plain_plot(ui, "basins", height);
        let (ax, ay) = (
            AxisSpec::angle("θν, pull direction", s.angle_unit),
            AxisSpec::angle("θ₀, slip onset", s.angle_unit).fitted_along(ui, height),
        );
        let resp = axes::apply(ui.ctx(), plot, &ax, &ay).show(ui, |p| {
            p.set_plot_bounds(PlotBounds::from_min_max([x0, lo], [x1, hi]));
            basin_items(p, d);
            basin_events::event_items(p, d, Some(hi - 0.025 * (hi - lo)));
            if let Some(x) = sel_x {
                p.add(VLine::new("selected column", x).color(style::CURRENT));
            }
            let pointer = p.pointer_coordinate();
            if let (Some(a), Some(b)) = (drag_from, pointer) {
                p.add(style::zoom_box(a, b));
            }
            pointer
        });
        axes::remember_frame(ui.ctx(), "basins", *resp.transform.frame());
        if self.drag_from.is_none()
            && let Some(at) = resp.inner.filter(|_| resp.response.hovered())
        {
            let per_point = 1.0 / resp.transform.dpos_dvalue_x().abs().max(1e-300);
            if let Some(text) = basin_events::hover_sentence(d, at, per_point) {
                resp.response.clone().on_hover_text_at_pointer(text);
            }
        }
        self.pointer_ui(&resp.response, resp.inner, s, d);
    }

    /// A box drawn zooms to its θν range; a click selects the nearest
    /// column.
    fn pointer_ui(
        &mut self,
        r: &egui::Response,
        at: Option<PlotPoint>,
        s: &mut Settings,
        d: &BasinsData,
    ) {
        if r.drag_started() {
            self.drag_from = at;
        }
        if r.drag_stopped() {
            if let (Some(a), Some(b)) = (self.drag_from.take(), at) {
                let ((x0, x1), _) = style::box_ranges(a, b);
                let (x0, x1) = (x0.max(d.from.min(d.to)), x1.min(d.to.max(d.from)));
                if is_usable_range((x0, x1)) && x1 - x0 > 1e-6 {
                    s.basins.zoom.push((x0, x1));
                    self.selected = None;
                }
            }
        } else if r.clicked()
            && let Some(p) = at
        {
            self.selected = (0..d.columns.len())
                .filter(|&i| d.columns[i].is_some())
                .min_by(|&i, &j| {
                    (column_x(d, i).0 - p.x)
                        .abs()
                        .total_cmp(&(column_x(d, j).0 - p.x).abs())
                });
        }
    }

    /// The clicked column's attractors.
    fn list_ui(&self, ui: &mut Ui, d: &BasinsData, out: &mut Vec<Action>) {
        let Some(i) = self.selected else { return };
        let Some(Some(col)) = d.columns.get(i) else {
            return;
        };
        ui.horizontal(|ui| {
            ui.label(RichText::new(format!("θν = {:.6}", col.theta_nu)).strong());
            if ui.button("Set θν here").clicked() {
                out.push(Action::SetThetaNu(col.theta_nu));
            }
        });
        match &col.found {
            Err(e) => {
                ui.colored_label(style::ERROR, format!("this column failed: {e}"));
            }
            Ok(f) => {
                for (a, at) in f.attractors.iter().enumerate() {
                    let (name, c) = named(&d.ids, i, Some(a));
                    ui.horizontal(|ui| {
                        style::legend_swatch(ui, c, &name);
                        ui.label(describe(at));
                    });
                }
                ui.label(format!(
                    "basin boundary {:.4} of the arc ({} cells, ε = {:.1e})",
                    f.boundary_fraction, f.resolution.cells, f.resolution.eps
                ));
            }
        }
    }
}

/// A plot without egui's own zoom and drag (the view does its own).
fn plain_plot(ui: &Ui, id: &str, height: f32) -> Plot<'static> {
    let row = ui.text_style_height(&egui::TextStyle::Body);
    Plot::new(id.to_string())
        .height(height)
        .show_background(false)
        .allow_drag(false)
        .allow_zoom(false)
        .allow_scroll(false)
        .allow_boxed_zoom(false)
        .allow_double_click_reset(false)
        .y_axis_min_width(5.5 * row)
}

/// The plots' θν bounds: half a column beyond the end columns.
fn x_bounds(d: &BasinsData) -> (f64, f64) {
    if d.columns.is_empty() {
        return (d.from, d.to.max(d.from + 1e-9));
    }
    let h = column_x(d, 0).1;
    (d.from.min(d.to) - h, d.to.max(d.from) + h)
}

/// Where the job stands, in words: computing (k of n columns), failed
/// (why), or done (with any columns that failed).
fn status_ui(ui: &mut Ui, slot: &Slot<BasinsData>) {
    let d = &slot.data;
    let failed = d
        .columns
        .iter()
        .flatten()
        .filter(|c| c.found.is_err())
        .count();
    let n = d.columns.len();
    match &slot.state {
        JobState::Running => {
            ui.label(format!(
                "computing attractors and basins: {} of {n} columns",
                d.arrived()
            ));
        }
        JobState::Failed(m) => {
            ui.colored_label(
                style::ERROR,
                format!("the basins could not be computed: {m}"),
            );
        }
        JobState::Cancelled => {
            ui.label(format!("stopped after {} of {n} columns", d.arrived()));
        }
        JobState::Done if cfg!(target_arch = "wasm32") => {
            ui.label(
                RichText::new(
                    "where each attractor is born or dies is located by the desktop app and \
                     oneblock attractors --param theta-nu, not in the page",
                )
                .weak(),
            );
        }
        _ => {}
    }
    if failed > 0 {
        let first = d
            .columns
            .iter()
            .flatten()
            .find_map(|c| c.found.as_ref().err());
        let why = first.map_or(String::new(), |e| format!(": {e}"));
        ui.colored_label(style::ERROR, format!("{failed} column(s) failed{why}"));
    }
}

/// The legend: every track drawn, then the boundary; under it, what a
/// numbered name ("P2 (2)") means, when there is one.
fn legend_ui(ui: &mut Ui, d: &BasinsData) {
    let ids = &d.ids;
    style::legend_row(ui, |ui| {
        for t in &ids.tracks {
            style::legend_swatch(ui, track_color(t.id), &t.label);
        }
        style::legend_swatch(ui, BOUNDARY, "basin boundary");
        basin_events::legend_ui(ui, d);
    });
    // In the window only: a figure's caption is its author's to write.
    if !style::figure_only(ui.ctx())
        && ids
            .tracks
            .iter()
            .any(|t| t.label.ends_with(')') || t.periods.len() > 1)
    {
        ui.label(RichText::new(SECOND_NAME).weak().small());
    }
}

impl View for BasinsView {
    fn title(&self) -> &'static str {
        ViewKind::Basins.title()
    }

    fn controls_ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, _out: &mut Vec<Action>) {
        self.settings_ui(ui, s, &jobs.basins);
    }

    fn ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, out: &mut Vec<Action>) {
        let figure = style::figure_only(ui.ctx());
        let d = &jobs.basins.data;
        legend_ui(ui, d);
        let row = ui.text_style_height(&egui::TextStyle::Body);
        // Room for the top tick label, centred on the plot's top edge.
        ui.add_space(0.5 * row);
        let listed = !figure && self.selected.is_some();
        let list = if listed { 7.0 * row } else { 0.0 };
        let avail = (ui.available_height() - list).max(0.0);
        // The fractions need about 12 rows of text for legible ticks;
        // below 30 rows in all (a small tile) only the basins are drawn.
        let top = if avail < 30.0 * row {
            avail
        } else {
            avail * 0.6
        };
        self.basins_plot_ui(ui, s, d, top);
        if top < avail {
            fractions_ui(ui, s, d, avail - top - 0.5 * row);
        }
        if listed {
            egui::ScrollArea::vertical()
                .id_salt("basins list")
                .show(ui, |ui| self.list_ui(ui, d, out));
        }
    }
}

/// The basin fractions stacked against θν, `height` points tall.
fn fractions_ui(ui: &mut Ui, s: &Settings, d: &BasinsData, height: f32) {
    let (x0, x1) = x_bounds(d);
    let plot = plain_plot(ui, "basin fractions", height);
    let (ax, ay) = (
        AxisSpec::angle("θν, pull direction", s.angle_unit),
        AxisSpec::linear("basin fraction"),
    );
    axes::apply(ui.ctx(), plot, &ax, &ay).show(ui, |p| {
        p.set_plot_bounds(PlotBounds::from_min_max([x0, 0.0], [x1, 1.0]));
        fraction_items(p, d);
        basin_events::event_items(p, d, None);
    });
}

#[cfg(test)]
mod colour_tests {
    use super::*;

    #[test]
    fn no_two_tracks_share_a_colour_and_none_is_the_boundarys() {
        let cs: Vec<Color32> = (0..300).map(track_color).collect();
        let distinct: std::collections::HashSet<_> = cs.iter().collect();
        assert_eq!(distinct.len(), cs.len());
        assert!(!cs.contains(&BOUNDARY));
        // The palette's colours are far apart (RGB distance).
        let d = |a: Color32, b: Color32| {
            let s: i32 = [(a.r(), b.r()), (a.g(), b.g()), (a.b(), b.b())]
                .iter()
                .map(|&(x, y)| (i32::from(x) - i32::from(y)).pow(2))
                .sum();
            f64::from(s).sqrt()
        };
        for i in 0..18 {
            for j in 0..i {
                assert!(d(cs[i], cs[j]) > 35.0, "{i} and {j}");
            }
        }
        assert_eq!(hex(Color32::from_rgb(31, 119, 180)), "#1f77b4");
    }
}
