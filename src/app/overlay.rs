//! The continuation's results drawn over the diagrams: the branches of
//! "Find bifurcations" over the bifurcation diagram (stable parts solid,
//! unstable parts dashed, PD, subcritical PD, fold, border and jump points
//! each with a marker of its own), and the boundary curves of "Boundaries"
//! (or `phase --boundaries`) over the phase diagram, each kind and level in
//! a style of its own, with their generalised flips (where the flip's coefficient
//! changes sign: the doubling turns from supercritical to subcritical).
//! Only drawing: the numbers come from [`super::branches`].

use eframe::egui;
use egui::{Color32, Ui};
use egui_plot::{HoverPosition, Line, LineStyle, MarkerShape, PlotPoints, PlotUi};

use super::branches::{BranchData, CurveData, runs, special_rows};
use super::markers::{self, Marker};
use super::style;
use crate::sim::continuation::{Criticality, CurveKind, SpecialKind, SpecialPoint};

/// The branches' colour.
pub const BRANCH: Color32 = Color32::from_rgb(0, 114, 178);

/// The names of the overlay's plot items (the legend's words).
pub const STABLE: &str = "stable branch";
pub const UNSTABLE: &str = "unstable branch";

/// The radius of a special point's marker.
const SPECIAL_RADIUS: f32 = 5.0;

/// A special point's filled marker of `shape` and `colour`.
const fn special(shape: MarkerShape, colour: Color32) -> Marker {
    Marker::new(shape, colour, SPECIAL_RADIUS, true)
}

/// The marker of a special point, and its name.
pub fn marker(kind: SpecialKind) -> (Marker, &'static str) {
    match kind {
        SpecialKind::PeriodDoubling => (
            special(MarkerShape::Diamond, Color32::from_rgb(204, 0, 102)),
            "PD",
        ),
        SpecialKind::Fold => (
            special(MarkerShape::Square, Color32::from_rgb(230, 159, 0)),
            "fold",
        ),
        SpecialKind::Border => (
            special(MarkerShape::Cross, Color32::from_rgb(213, 94, 0)),
            "border",
        ),
        SpecialKind::Jump => (
            special(MarkerShape::Asterisk, Color32::from_rgb(120, 120, 120)),
            "jump of m",
        ),
        SpecialKind::End => (special(MarkerShape::Circle, style::CRITICAL), "end"),
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
pub const SUBCRITICAL: (Marker, &str) = (
    special(MarkerShape::Up, Color32::from_rgb(204, 0, 102)),
    "subcritical PD",
);

/// Whether `name` is one of the overlay's items (their hover is the
/// overlay's own, to 9 digits; the plot's 3-decimal label is left out).
pub fn is_overlay_item(name: &str) -> bool {
    name == STABLE
        || name == UNSTABLE
        || is_curve_name(name)
        || name == SUBCRITICAL.1
        || name == GENERALISED_NAME
        || MARKED.iter().any(|&k| marker(k).1 == name)
}

/// Whether `name` is a boundary curve's ([`curve_style`]): "FP to P2",
/// "P2 to P4", …, "fold of FP", ….
fn is_curve_name(name: &str) -> bool {
    name.starts_with("fold of ")
        || name
            .split_once(" to P")
            .is_some_and(|(from, _)| from == "FP" || from.starts_with('P'))
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
/// `x` maps a parameter value to the plot's coordinate (log10 on a log
/// axis).
pub fn branch_items(
    p: &mut PlotUi<'_>,
    data: &BranchData,
    line_width: f32,
    (min, max): ([f64; 2], [f64; 2]),
    x: &dyn Fn(f64) -> f64,
) {
    let on_axis =
        |pts: Vec<[f64; 2]>| -> Vec<[f64; 2]> { pts.into_iter().map(|[l, t]| [x(l), t]).collect() };
    let line = |name, pts: Vec<[f64; 2]>| {
        Line::new(name, PlotPoints::from(pts))
            .color(BRANCH)
            .width(line_width)
            .allow_hover(false)
    };
    // Every run cut to the bounds in double precision: a kept point far
    // outside (a session's at 1e308) once overflowed the single-precision
    // screen coordinates into `MNaN,NaN` paths.
    for b in &data.branches {
        for r in runs(b) {
            let points = on_axis(r.points);
            for part in super::clip::clip_polyline(&points, min, max) {
                if r.stable {
                    p.line(line(STABLE, part));
                } else {
                    p.line(line(UNSTABLE, part).style(LineStyle::Dashed { length: 8.0 }));
                }
            }
        }
    }
    for (m, name, pts) in marked_groups(data, (min, max), x) {
        p.points(m.points(name, PlotPoints::from(pts)));
    }
}

/// The special points drawn over a plot of bounds `(min, max)`, by
/// marker: each kind's points within the box, the kinds with none left out.
fn marked_groups(
    data: &BranchData,
    (min, max): ([f64; 2], [f64; 2]),
    x: &dyn Fn(f64) -> f64,
) -> Vec<(Marker, &'static str, Vec<[f64; 2]>)> {
    let rows = special_rows(data);
    let subcritical = |s: &&&SpecialPoint| {
        s.flip
            .is_some_and(|f| f.criticality() == Criticality::Subcritical)
    };
    let groups = MARKED
        .map(|kind| (marker(kind), kind, false))
        .into_iter()
        .chain([(SUBCRITICAL, SpecialKind::PeriodDoubling, true)]);
    groups
        .filter_map(|((m, name), kind, sub)| {
            let pts: Vec<[f64; 2]> = rows
                .iter()
                .filter(|s| s.kind == kind && subcritical(s) == sub)
                .map(|s| [x(s.lambda), s.theta])
                .filter(|&q| within(q, min, max))
                .collect();
            (!pts.is_empty()).then_some((m, name, pts))
        })
        .collect()
}

/// Whether a stable and an unstable run cross the box `(min, max)`.
fn runs_drawn(
    data: &BranchData,
    (min, max): ([f64; 2], [f64; 2]),
    x: &dyn Fn(f64) -> f64,
) -> (bool, bool) {
    let mut drawn = (false, false);
    for r in data.branches.iter().flat_map(runs) {
        let points: Vec<[f64; 2]> = r.points.into_iter().map(|[l, t]| [x(l), t]).collect();
        if !super::clip::clip_polyline(&points, min, max).is_empty() {
            if r.stable {
                drawn.0 = true;
            } else {
                drawn.1 = true;
            }
        }
    }
    drawn
}

/// Whether `q` is finite and inside the box `min`–`max`: a kept result is
/// drawn only where it fits the plot.
fn within(q: [f64; 2], min: [f64; 2], max: [f64; 2]) -> bool {
    (0..2).all(|i| q[i].is_finite() && min[i] <= q[i] && q[i] <= max[i])
}

/// The legend of the branches over a plot of bounds `(min, max)` (`x`
/// as [`branch_items`]): the line styles and the markers drawn there,
/// nothing for a kind with no point in the plot.
pub fn branch_legend_ui(
    ui: &mut Ui,
    data: &BranchData,
    bounds: ([f64; 2], [f64; 2]),
    x: &dyn Fn(f64) -> f64,
) {
    let (stable, unstable) = runs_drawn(data, bounds, x);
    let groups = marked_groups(data, bounds, x);
    if !stable && !unstable && groups.is_empty() {
        return;
    }
    style::legend_row(ui, |ui| {
        if stable {
            style::legend_line(ui, BRANCH, false, STABLE);
        }
        if unstable {
            style::legend_line(ui, BRANCH, true, UNSTABLE);
        }
        for (m, name, _) in groups {
            markers::legend(ui, &[m], name);
        }
    });
}

/// How one boundary curve is drawn: its legend's words, its colour and
/// whether it is dashed. Each doubling level has a colour of its own
/// (FP to P2 white, P2 to P4 cyan, P4 to P8 yellow, beyond pink); a fold
/// curve is dashed, in its cycle's colour. All are drawn on a dark halo,
/// so that they show over every class's colour.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveStyle {
    pub name: String,
    pub colour: Color32,
    pub dashed: bool,
}

/// The colours of the doubling levels: period 1, 2, 4, 8 and beyond.
pub const LEVEL_COLOURS: [Color32; 4] = [
    Color32::from_rgb(255, 255, 255),
    Color32::from_rgb(0, 229, 255),
    Color32::from_rgb(255, 221, 0),
    Color32::from_rgb(255, 128, 208),
];

/// The name of a cycle of period `p` in the phase diagram's words.
fn cycle_name(p: usize) -> String {
    if p == 1 { "FP".into() } else { format!("P{p}") }
}

/// The style of a curve of `kind` for the cycle of `period`: a doubling
/// "FP to P2", "P2 to P4", …, solid; a fold "fold of FP", dashed.
pub fn curve_style(kind: CurveKind, period: usize) -> CurveStyle {
    let level = period.max(1).ilog2() as usize;
    let colour = LEVEL_COLOURS[level.min(LEVEL_COLOURS.len() - 1)];
    match kind {
        CurveKind::PeriodDoubling => CurveStyle {
            name: format!("{} to {}", cycle_name(period), cycle_name(2 * period)),
            colour,
            dashed: false,
        },
        CurveKind::Fold => CurveStyle {
            name: format!("fold of {}", cycle_name(period)),
            colour,
            dashed: true,
        },
    }
}

/// The marker of a generalised flip on a doubling curve: the PD's colour,
/// a triangle pointing down (the subcritical PD's points up), on a black
/// one a little larger so that it shows over every class's colour.
pub const GENERALISED: [Marker; 2] = [
    Marker::new(MarkerShape::Down, Color32::BLACK, 8.0, true),
    Marker::new(MarkerShape::Down, Color32::from_rgb(204, 0, 102), 6.0, true),
];

/// The generalised flip's name (legend and hover).
pub const GENERALISED_NAME: &str = "generalised flip";

/// The halo under every boundary curve.
const HALO: Color32 = Color32::from_black_alpha(200);

/// The styles of the curves of `data` drawn in a plot of bounds `(min,
/// max)` (some point inside), each once: doublings by period, then folds.
pub fn drawn_styles(data: &CurveData, (min, max): ([f64; 2], [f64; 2])) -> Vec<CurveStyle> {
    let mut keys: Vec<(u8, usize)> = data
        .curves
        .iter()
        .filter(|c| {
            let pts: Vec<[f64; 2]> = c.points.iter().map(|q| q.lambda).collect();
            !super::clip::clip_polyline(&pts, min, max).is_empty()
        })
        .map(|c| (u8::from(c.kind == CurveKind::Fold), c.period))
        .collect();
    keys.sort_unstable();
    keys.dedup();
    keys.into_iter()
        .map(|(fold, p)| {
            let kind = if fold == 1 {
                CurveKind::Fold
            } else {
                CurveKind::PeriodDoubling
            };
            curve_style(kind, p)
        })
        .collect()
}

/// The curves' legend over a plot of bounds `(min, max)`: an entry for
/// each style drawn there, its key the line as drawn (on its halo), and,
/// when a flip is drawn, the generalised flip's marker.
pub fn curve_legend_ui(ui: &mut Ui, data: &CurveData, bounds: ([f64; 2], [f64; 2])) {
    let styles = drawn_styles(data, bounds);
    let flips = data
        .curves
        .iter()
        .flat_map(|c| &c.generalised_flips)
        .any(|g| within(g.lambda, bounds.0, bounds.1));
    if styles.is_empty() && !flips {
        return;
    }
    style::legend_row(ui, |ui| {
        for st in &styles {
            style::legend_entry(ui, egui::vec2(22.0, 14.0), &st.name, |rect, k| {
                let (y, x0, x1) = (rect.center().y, rect.left(), rect.right());
                let pieces: Vec<[egui::Pos2; 2]> = if st.dashed {
                    vec![
                        [egui::pos2(x0, y), egui::pos2(x0 + 8.0 * k, y)],
                        [egui::pos2(x1 - 8.0 * k, y), egui::pos2(x1, y)],
                    ]
                } else {
                    vec![[egui::pos2(x0, y), egui::pos2(x1, y)]]
                };
                let mut shapes = Vec::new();
                for (colour, w) in [(HALO, 4.0), (st.colour, 2.0)] {
                    for ends in &pieces {
                        shapes.push(egui::Shape::line_segment(
                            *ends,
                            egui::Stroke::new(w * k, colour),
                        ));
                    }
                }
                shapes
            });
        }
        if flips {
            markers::legend(ui, &GENERALISED, GENERALISED_NAME);
        }
    });
}

/// The boundary curves over the phase diagram, each in its own style
/// ([`curve_style`]: a colour per doubling level, folds dashed), each a
/// polyline in (θν, κ), and the doublings' generalised flips' markers,
/// over a plot of bounds `(min, max)`: each cut to them in double
/// precision, a flip drawn only inside them.
pub fn curve_items(
    p: &mut PlotUi<'_>,
    data: &CurveData,
    line_width: f32,
    (min, max): ([f64; 2], [f64; 2]),
) {
    for c in &data.curves {
        let pts: Vec<[f64; 2]> = c.points.iter().map(|q| q.lambda).collect();
        let st = curve_style(c.kind, c.period);
        let line = if st.dashed {
            LineStyle::Dashed { length: 10.0 }
        } else {
            LineStyle::Solid
        };
        for part in super::clip::clip_polyline(&pts, min, max) {
            // A dark halo keeps the line visible over pale classes.
            p.line(
                Line::new(st.name.as_str(), PlotPoints::from(part.clone()))
                    .color(HALO)
                    .width(line_width + 2.0)
                    .style(line)
                    .allow_hover(false),
            );
            p.line(
                Line::new(st.name.as_str(), PlotPoints::from(part))
                    .color(st.colour)
                    .width(line_width)
                    .style(line)
                    .allow_hover(false),
            );
        }
    }
    let flips: Vec<[f64; 2]> = data
        .curves
        .iter()
        .flat_map(|c| c.generalised_flips.iter().map(|g| g.lambda))
        .filter(|&q| within(q, min, max))
        .collect();
    if flips.is_empty() {
        return;
    }
    for m in GENERALISED {
        p.points(m.points(GENERALISED_NAME, PlotPoints::from(flips.clone())));
    }
}
