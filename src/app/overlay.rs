//! The continuation's results drawn over the diagrams: the branches of
//! "Find bifurcations" over the bifurcation diagram (stable parts solid,
//! unstable parts dashed, PD, fold and border points each with a marker of
//! its own), and the doubling curves of "Boundaries" over the phase
//! diagram. Only drawing: the numbers come from [`super::branches`].

use eframe::egui;
use egui::{Color32, Ui};
use egui_plot::{HoverPosition, Line, LineStyle, MarkerShape, PlotPoints, PlotUi, Points};

use super::branches::{BranchData, CurveData, runs, special_rows};
use super::style;
use crate::sim::continuation::SpecialKind;

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

/// Whether `name` is one of the overlay's items (their hover is the
/// overlay's own, to 9 digits; the plot's 3-decimal label is left out).
pub fn is_overlay_item(name: &str) -> bool {
    name == STABLE
        || name == UNSTABLE
        || name == CURVE
        || MARKED.iter().any(|&k| marker(k).2 == name)
}

/// The plot's hover label: egui_plot's own, except over the overlay.
pub fn label(pos: &HoverPosition<'_>) -> Option<String> {
    match pos {
        HoverPosition::NearDataPoint { plot_name, .. } if is_overlay_item(plot_name) => None,
        _ => egui_plot::default_label_formatter(pos),
    }
}

/// The branches' lines and the special points' markers.
pub fn branch_items(p: &mut PlotUi<'_>, data: &BranchData, line_width: f32) {
    for b in &data.branches {
        for r in runs(b) {
            let line = Line::new(
                if r.stable { STABLE } else { UNSTABLE },
                PlotPoints::from(r.points),
            )
            .color(BRANCH)
            .width(line_width)
            .allow_hover(false);
            p.line(if r.stable {
                line
            } else {
                line.style(LineStyle::Dashed { length: 8.0 })
            });
        }
    }
    let rows = special_rows(data);
    for kind in MARKED {
        let pts: Vec<[f64; 2]> = rows
            .iter()
            .filter(|s| s.kind == kind)
            .map(|s| [s.lambda, s.theta])
            .collect();
        if pts.is_empty() {
            continue;
        }
        let (shape, colour, name) = marker(kind);
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
    });
}

/// A marker of `shape` and its label.
fn legend_shape(ui: &mut Ui, shape: MarkerShape, colour: Color32, label: &str) {
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
        _ => {
            painter.circle_filled(c, r, colour);
        }
    }
    ui.label(label);
}

/// The name of the boundary curves' item.
pub const CURVE: &str = "doubling curve";

/// The doubling curves over the phase diagram, each a polyline in (θν, κ).
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
}
