//! The continuation's results drawn over the diagrams: the branches of
//! "Find bifurcations" over the bifurcation diagram (stable parts solid,
//! unstable parts dashed, PD, subcritical PD, fold, border and jump points
//! each with a marker of its own), and the doubling curves of "Boundaries" over the phase
//! diagram with their generalised flips (where the flip's coefficient
//! changes sign: the doubling turns from supercritical to subcritical).
//! Only drawing: the numbers come from [`super::branches`].

use eframe::egui;
use egui::{Color32, Ui};
use egui_plot::{HoverPosition, Line, LineStyle, MarkerShape, PlotPoints, PlotUi, Points};

use super::branches::{BranchData, CurveData, runs, special_rows};
use super::style;
use crate::sim::continuation::{Criticality, SpecialKind, SpecialPoint};

/// The branches' colour.
pub const BRANCH: Color32 = Color32::from_rgb(0, 114, 178);
/// The boundary curves' colour (over the phase diagram's class colours).
pub const BOUNDARY: Color32 = Color32::from_rgb(255, 255, 255);

/// The names of the overlay's plot items (the legend's words).
pub const STABLE: &str = "stable branch";
pub const UNSTABLE: &str = "unstable branch";

/// The marker of a special point: shape, colour, name.
pub fn marker(kind: SpecialKind) -> (MarkerShape, Color32, &'static str) {
    match kind {
        SpecialKind::PeriodDoubling => (MarkerShape::Diamond, Color32::from_rgb(204, 0, 102), "PD"),
        SpecialKind::Fold => (MarkerShape::Square, Color32::from_rgb(230, 159, 0), "fold"),
        SpecialKind::Border => (MarkerShape::Cross, Color32::from_rgb(213, 94, 0), "border"),
        SpecialKind::Jump => (
            MarkerShape::Asterisk,
            Color32::from_rgb(120, 120, 120),
            "jump of m",
        ),
        SpecialKind::End => (MarkerShape::Circle, style::CRITICAL, "end"),
    }
}

/// The kinds marked, in the legend's order.
pub const MARKED: [SpecialKind; 4] = [
    SpecialKind::PeriodDoubling,
    SpecialKind::Fold,
    SpecialKind::Border,
    SpecialKind::Jump,
];

/// The marker of a subcritical period doubling (where the attractor jumps
/// away, rather than doubling): the PD's colour, another shape.
pub const SUBCRITICAL: (MarkerShape, Color32, &str) = (
    MarkerShape::Up,
    Color32::from_rgb(204, 0, 102),
    "subcritical PD",
);

/// Whether `name` is one of the overlay's items (their hover is the
/// overlay's own, to 9 digits; the plot's 3-decimal label is left out).
pub fn is_overlay_item(name: &str) -> bool {
    name == STABLE
        || name == UNSTABLE
        || name == CURVE
        || name == SUBCRITICAL.2
        || name == GENERALISED.2
        || MARKED.iter().any(|&k| marker(k).2 == name)
}

/// The plot's hover label: egui_plot's own, except over the overlay.
pub fn label(pos: &HoverPosition<'_>) -> Option<String> {
    match pos {
        HoverPosition::NearDataPoint { plot_name, .. } if is_overlay_item(plot_name) => None,
        _ => egui_plot::default_label_formatter(pos),
    }
}

/// The branches' lines and the special points' markers, over a plot of
/// bounds `(min, max)`: the unstable (dashed) runs are cut to them, as a
/// dash is laid along the line's whole length on screen ([`super::clip`]).
pub fn branch_items(
    p: &mut PlotUi<'_>,
    data: &BranchData,
    line_width: f32,
    (min, max): ([f64; 2], [f64; 2]),
) {
    let line = |name, pts: Vec<[f64; 2]>| {
        Line::new(name, PlotPoints::from(pts))
            .color(BRANCH)
            .width(line_width)
            .allow_hover(false)
    };
    for b in &data.branches {
        for r in runs(b) {
            if r.stable {
                p.line(line(STABLE, r.points));
                continue;
            }
            for part in super::clip::clip_polyline(&r.points, min, max) {
                p.line(line(UNSTABLE, part).style(LineStyle::Dashed { length: 8.0 }));
            }
        }
    }
    let rows = special_rows(data);
    let subcritical = |s: &&&SpecialPoint| {
        s.flip
            .is_some_and(|f| f.criticality() == Criticality::Subcritical)
    };
    let groups = MARKED
        .map(|kind| (marker(kind), kind, false))
        .into_iter()
        .chain([(SUBCRITICAL, SpecialKind::PeriodDoubling, true)]);
    for ((shape, colour, name), kind, sub) in groups {
        let pts: Vec<[f64; 2]> = rows
            .iter()
            .filter(|s| s.kind == kind && subcritical(s) == sub)
            .map(|s| [s.lambda, s.theta])
            .collect();
        if pts.is_empty() {
            continue;
        }
        p.points(
            Points::new(name, PlotPoints::from(pts))
                .shape(shape)
                .color(colour)
                .filled(true)
                .radius(5.0),
        );
    }
}

/// The legend of the branches: the two line styles and the markers in use.
pub fn branch_legend_ui(ui: &mut Ui, data: &BranchData) {
    if data.branches.is_empty() {
        return;
    }
    ui.horizontal_wrapped(|ui| {
        style::legend_line(ui, BRANCH, false, STABLE);
        style::legend_line(ui, BRANCH, true, UNSTABLE);
        for kind in MARKED {
            let (shape, colour, name) = marker(kind);
            legend_shape(ui, shape, colour, name);
        }
        let (shape, colour, name) = SUBCRITICAL;
        legend_shape(ui, shape, colour, name);
    });
}

/// A marker of `shape` and its label.
pub fn legend_shape(ui: &mut Ui, shape: MarkerShape, colour: Color32, label: &str) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(14.0, 14.0), egui::Sense::hover());
    let (c, r) = (rect.center(), 5.0);
    let painter = ui.painter();
    match shape {
        MarkerShape::Square => {
            painter.rect_filled(
                egui::Rect::from_center_size(c, egui::vec2(2.0 * r, 2.0 * r)),
                0.0,
                colour,
            );
        }
        MarkerShape::Cross => {
            let s = egui::Stroke::new(2.0, colour);
            painter.line_segment([c + egui::vec2(-r, -r), c + egui::vec2(r, r)], s);
            painter.line_segment([c + egui::vec2(-r, r), c + egui::vec2(r, -r)], s);
        }
        MarkerShape::Diamond => {
            painter.add(egui::Shape::convex_polygon(
                vec![
                    c + egui::vec2(0.0, -r),
                    c + egui::vec2(r, 0.0),
                    c + egui::vec2(0.0, r),
                    c + egui::vec2(-r, 0.0),
                ],
                colour,
                egui::Stroke::NONE,
            ));
        }
        MarkerShape::Up | MarkerShape::Down => {
            let up = shape == MarkerShape::Up;
            let s = if up { 1.0 } else { -1.0 };
            // The generalised flip's (down) is outlined, as on the plot.
            let outline = if up {
                egui::Stroke::NONE
            } else {
                egui::Stroke::new(1.0, Color32::BLACK)
            };
            painter.add(egui::Shape::convex_polygon(
                vec![
                    c + egui::vec2(0.0, -r * s),
                    c + egui::vec2(r, r * s),
                    c + egui::vec2(-r, r * s),
                ],
                colour,
                outline,
            ));
        }
        MarkerShape::Asterisk => {
            let s = egui::Stroke::new(1.5, colour);
            for (dx, dy) in [(0.0, r), (0.87 * r, 0.5 * r), (0.87 * r, -0.5 * r)] {
                let d = egui::vec2(dx, dy);
                painter.line_segment([c - d, c + d], s);
            }
        }
        _ => {
            painter.circle_filled(c, r, colour);
        }
    }
    ui.label(label);
}

/// The name of the boundary curves' item.
pub const CURVE: &str = "doubling curve";

/// The marker of a generalised flip on a doubling curve: the PD's colour,
/// a triangle pointing down (the subcritical PD's points up), on a black
/// one a little larger so that it shows over every class's colour.
pub const GENERALISED: (MarkerShape, Color32, &str) = (
    MarkerShape::Down,
    Color32::from_rgb(204, 0, 102),
    "generalised flip",
);

/// The curves' legend: the line and, when a curve has one, the
/// generalised flip's marker.
pub fn curve_legend_ui(ui: &mut Ui, data: &CurveData) {
    if data.curves.is_empty() {
        return;
    }
    ui.horizontal_wrapped(|ui| {
        // The white line on its dark halo, as drawn.
        let (rect, _) = ui.allocate_exact_size(egui::vec2(22.0, 14.0), egui::Sense::hover());
        let ends = [rect.left_center(), rect.right_center()];
        let painter = ui.painter();
        painter.line_segment(ends, egui::Stroke::new(4.0, Color32::from_black_alpha(200)));
        painter.line_segment(ends, egui::Stroke::new(2.0, BOUNDARY));
        ui.label(CURVE);
        if data.curves.iter().any(|c| !c.generalised_flips.is_empty()) {
            let (shape, colour, name) = GENERALISED;
            legend_shape(ui, shape, colour, name);
        }
    });
}

/// The doubling curves over the phase diagram, each a polyline in (θν, κ),
/// and their generalised flips' markers.
pub fn curve_items(p: &mut PlotUi<'_>, data: &CurveData, line_width: f32) {
    for c in &data.curves {
        let pts: Vec<[f64; 2]> = c.points.iter().map(|q| q.lambda).collect();
        // A dark halo keeps the white line visible over pale classes.
        p.line(
            Line::new(CURVE, PlotPoints::from(pts.clone()))
                .color(Color32::from_black_alpha(200))
                .width(line_width + 2.0)
                .allow_hover(false),
        );
        p.line(
            Line::new(CURVE, PlotPoints::from(pts))
                .color(BOUNDARY)
                .width(line_width)
                .allow_hover(false),
        );
    }
    let flips: Vec<[f64; 2]> = data
        .curves
        .iter()
        .flat_map(|c| c.generalised_flips.iter().map(|g| g.lambda))
        .collect();
    if flips.is_empty() {
        return;
    }
    let (shape, colour, name) = GENERALISED;
    for (c, r) in [(Color32::BLACK, 8.0), (colour, 6.0)] {
        p.points(
            Points::new(name, PlotPoints::from(flips.clone()))
                .shape(shape)
                .color(c)
                .filled(true)
                .radius(r),
        );
    }
}
