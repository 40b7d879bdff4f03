//! The Basins view's events: where each track is born, dies or changes
//! its period (`sim::attractors::events`, located by the Basins job once
//! every column is in), drawn as a mark on the basins plot's top edge with
//! a dashed line down both plots, named in the legend, and explained in
//! one sentence when hovered, as is a basin.

use eframe::egui::{self, Color32, Pos2, Shape, Stroke, Ui};
use egui_plot::{LineStyle, MarkerShape, PlotPoints, PlotUi, Points, VLine};

use super::jobs::basins::BasinsData;
use super::jobs::{JobState, Jobs};
use super::settings::Settings;
use crate::sim::attractors::events::{Cause, Event};

/// The events' ink.
pub const EVENT_INK: Color32 = Color32::from_gray(30);

/// Every cause, in the legend's order.
const CAUSES: [Cause; 5] = [
    Cause::Fold,
    Cause::Flip,
    Cause::Border,
    Cause::Crisis,
    Cause::Unresolved,
];

/// A cause's mark.
fn shape(c: Cause) -> MarkerShape {
    match c {
        Cause::Fold => MarkerShape::Down,
        Cause::Flip => MarkerShape::Diamond,
        Cause::Border => MarkerShape::Square,
        Cause::Crisis => MarkerShape::Asterisk,
        Cause::Unresolved => MarkerShape::Circle,
    }
}

/// The events the view draws: those inside its θν range.
fn shown(d: &BasinsData) -> impl Iterator<Item = &Event> {
    let (lo, hi) = (d.from.min(d.to), d.from.max(d.to));
    d.events
        .iter()
        .flat_map(|e| e.events.iter())
        .filter(move |e| e.value.is_finite() && (lo..=hi).contains(&e.value))
}

/// A dashed line at each event, and on the top plot (`top`: its upper
/// edge) the cause's mark.
pub fn event_items(p: &mut PlotUi<'_>, d: &BasinsData, top: Option<f64>) {
    for e in shown(d) {
        let name = format!("event: {}", e.cause.name());
        p.add(
            VLine::new(name.clone(), e.value)
                .color(EVENT_INK.gamma_multiply(0.6))
                .width(0.8)
                .style(LineStyle::dashed_dense()),
        );
        if let Some(y) = top {
            let filled = e.cause != Cause::Unresolved;
            p.add(
                Points::new(name, PlotPoints::from(vec![[e.value, y]]))
                    .shape(shape(e.cause))
                    .radius(5.0)
                    .filled(filled)
                    .color(EVENT_INK),
            );
        }
    }
}

/// The event whose line lies within `reach` (θν) of `x`, the nearest.
pub fn event_near(d: &BasinsData, x: f64, reach: f64) -> Option<&Event> {
    shown(d)
        .filter(|e| (e.value - x).abs() <= reach)
        .min_by(|a, b| (a.value - x).abs().total_cmp(&(b.value - x).abs()))
}

/// An event in one sentence: "fold at θν = 1.420231535 (± 1e-10): the
/// P2 cycle vanishes with an unstable one (m = +1). Track: P2."
pub fn event_sentence(e: &Event, d: &BasinsData) -> String {
    let tracks: Vec<&str> = e
        .tracks
        .iter()
        .filter_map(|&t| d.ids.tracks.get(t).map(|t| t.label.as_str()))
        .collect();
    let at = match e.cause {
        Cause::Unresolved => format!("between θν = {} and {}", e.between.0, e.between.1),
        _ => format!("at θν = {} (± {:.0e})", e.value_text(), e.error),
    };
    format!(
        "{} {at}: {}. Track{}: {}.",
        e.cause.name(),
        e.detail,
        if tracks.len() > 1 { "s" } else { "" },
        tracks.join(", ")
    )
}

/// Column `c`'s attractor `a` and its track in one sentence: "P2, born
/// at θν = 1.363980195 in a fold, dies at 1.420231535 in a fold; basin
/// here 0.24; smallest kick 0.086 rad".
pub fn track_sentence(d: &BasinsData, c: usize, a: usize) -> Option<String> {
    let col = d.columns.get(c)?.as_ref()?;
    let found = col.found.as_ref().ok()?;
    let at = found.attractors.get(a)?;
    let t = d.ids.track(c, a)?;
    let life = match &d.events {
        Some(ev) => format!(
            ", {}, {}",
            ev.bound_words(t.id, true, "θν"),
            ev.bound_words(t.id, false, "θν")
        ),
        None if cfg!(target_arch = "wasm32") => {
            " (its births and deaths are located by the desktop app and `oneblock attractors`)"
                .into()
        }
        None => " (its births and deaths are being located)".into(),
    };
    let kick = found
        .kick_text(a)
        .map_or(String::new(), |k| format!("; smallest kick {k}"));
    Some(format!(
        "{}{life}; basin here {:.4} at θν = {:.6}{kick}",
        t.label, at.basin_fraction, col.theta_nu
    ))
}

/// The legend's marks for the causes drawn, and a word where the events
/// are still being located.
pub fn legend_ui(ui: &mut Ui, d: &BasinsData) {
    let present: Vec<Cause> = CAUSES
        .into_iter()
        .filter(|&c| shown(d).any(|e| e.cause == c))
        .collect();
    if present.is_empty() {
        return;
    }
    ui.label("events:");
    for c in present {
        let size = ui.text_style_height(&egui::TextStyle::Body);
        let (rect, resp) = ui.allocate_exact_size(egui::vec2(size, size), egui::Sense::hover());
        mark(ui, rect.center(), 0.32 * size, c);
        resp.on_hover_text(format!(
            "{}: hover its mark on the plot to read it",
            c.name()
        ));
        ui.label(c.name());
    }
}

/// The mark of cause `c` at `at`, radius `r`, as the plot draws it.
fn mark(ui: &Ui, at: Pos2, r: f32, c: Cause) {
    let p = ui.painter();
    let pts = |v: &[(f32, f32)]| {
        v.iter()
            .map(|&(x, y)| at + egui::vec2(x * r, y * r))
            .collect()
    };
    let ink = EVENT_INK;
    match c {
        Cause::Fold => {
            p.add(Shape::convex_polygon(
                pts(&[(-1.0, -0.8), (1.0, -0.8), (0.0, 0.9)]),
                ink,
                Stroke::NONE,
            ));
        }
        Cause::Flip => {
            p.add(Shape::convex_polygon(
                pts(&[(0.0, -1.0), (1.0, 0.0), (0.0, 1.0), (-1.0, 0.0)]),
                ink,
                Stroke::NONE,
            ));
        }
        Cause::Border => {
            p.add(Shape::rect_filled(
                egui::Rect::from_center_size(at, egui::vec2(1.6 * r, 1.6 * r)),
                0.0,
                ink,
            ));
        }
        Cause::Crisis => {
            for k in 0..3 {
                let a = std::f32::consts::PI * k as f32 / 3.0;
                let d = egui::vec2(a.cos(), a.sin()) * r;
                p.line_segment([at - d, at + d], Stroke::new(1.5, ink));
            }
        }
        Cause::Unresolved => {
            p.add(Shape::circle_stroke(at, 0.8 * r, Stroke::new(1.2, ink)));
        }
    }
}

/// What the pointer is over on the basins plot, in one sentence: an
/// event's mark or line (within 6 points), else the basin under it.
pub fn hover_sentence(d: &BasinsData, at: egui_plot::PlotPoint, per_point: f64) -> Option<String> {
    if let Some(e) = event_near(d, at.x, 6.0 * per_point) {
        return Some(event_sentence(e, d));
    }
    let c = (0..d.columns.len())
        .filter(|&i| d.columns[i].is_some())
        .min_by(|&i, &j| {
            let x = |k: usize| d.columns[k].as_ref().map_or(f64::INFINITY, |c| c.theta_nu);
            (x(i) - at.x).abs().total_cmp(&(x(j) - at.x).abs())
        })?;
    let found = d.columns[c].as_ref()?.found.as_ref().ok()?;
    let a = found.basin_of(at.y)?;
    track_sentence(d, c, a)
}

/// The bifurcation diagram's "births & deaths" toggle (a θν diagram only).
pub fn diagram_toggle_ui(ui: &mut Ui, s: &mut Settings) {
    let along_theta_nu = s.diagram.param == crate::sim::continuation::ContParam::ThetaNu;
    ui.add_enabled(
        along_theta_nu,
        egui::Checkbox::new(&mut s.sweep_events, "births & deaths"),
    )
    .on_hover_text(
        "Where each attractor is born or dies, and why (fold, flip, border collision, \
             crisis), located to 1e-8 along θν by the Basins job over this diagram's range: \
             dashed lines, marks at the top, a sentence on hover (oneblock attractors \
             --param theta-nu)",
    )
    .on_disabled_hover_text("Births and deaths are located along θν: vary θν to show them");
}

/// The births and deaths marked: their legend, or where the Basins job
/// that locates them stands.
pub fn diagram_legend_ui(ui: &mut Ui, jobs: &Jobs) {
    let d = &jobs.basins.data;
    match &d.events {
        Some(e) if e.events.is_empty() => {
            ui.weak("births & deaths: none in this range");
        }
        Some(_) => legend_ui(ui, d),
        None if jobs.basins.state == JobState::Running => {
            let done = d.columns.iter().flatten().count();
            ui.weak(format!(
                "births & deaths: finding every attractor ({done} of {} columns), then locating \
                 the events",
                d.columns.len()
            ));
        }
        None => {
            ui.weak("births & deaths: not located (see the Basins view)");
        }
    }
}
