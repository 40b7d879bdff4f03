//! What a tour step must show, checked on the window's layout (`gui
//! --layout`'s JSON, or the same report read from a headless window):
//! every view the step names, each at least 200 × 150 points and inside
//! the window; its plots whole (the time series' four, the diagram's λ
//! strip where the step speaks of λ); the box over no plot.

use oneblock::app::layout_report::{LayoutReport, Xywh};
use oneblock::app::tour::TourStep;

/// The least size of a view a step names, points.
pub const LEAST_VIEW: (f32, f32) = (200.0, 150.0);

/// The least size of each of its plots' frames (the data area inside the
/// axes), points: a cobweb or a spike that can be seen from the back.
pub const LEAST_PLOT: (f32, f32) = (150.0, 100.0);

fn overlap(a: Xywh, b: Xywh) -> bool {
    a[0] < b[0] + b[2] && b[0] < a[0] + a[2] && a[1] < b[1] + b[3] && b[1] < a[1] + a[3]
}

fn inside(a: Xywh, window: (f32, f32)) -> bool {
    a[0] >= -0.5 && a[1] >= -0.5 && a[0] + a[2] <= window.0 + 0.5 && a[1] + a[3] <= window.1 + 0.5
}

/// The problems of `report` as step `step` of a `window`-sized window,
/// one line each (none: the step is shown as it must be).
pub fn step_problems(report: &LayoutReport, step: &TourStep, window: (f32, f32)) -> Vec<String> {
    let mut bad = Vec::new();
    let shown: Vec<&str> = report.views.iter().map(|v| v.view.as_str()).collect();
    let named: Vec<&str> = step.views.iter().map(|v| v.key()).collect();
    if shown != named {
        bad.push(format!("views {shown:?}, the step names {named:?}"));
    }
    let Some(tour) = report.tour else {
        bad.push("no tour box".into());
        return bad;
    };
    if !inside(tour, window) {
        bad.push(format!("the box {tour:?} leaves the window"));
    }
    for v in &report.views {
        let [_, _, w, h] = v.rect;
        if w < LEAST_VIEW.0 || h < LEAST_VIEW.1 || !inside(v.rect, window) {
            bad.push(format!("{} is {w} x {h} at {:?}", v.view, v.rect));
        }
        if v.plots.is_empty() {
            bad.push(format!("{}: no plot drawn whole", v.view));
        }
        for p in &v.plots {
            if overlap(p.rect, tour) {
                bad.push(format!("the box {tour:?} covers {} {:?}", p.name, p.rect));
            }
            if p.rect[2] < LEAST_PLOT.0 || p.rect[3] < LEAST_PLOT.1 {
                bad.push(format!("{} is only {:?}", p.name, p.rect));
            }
            if !inside(p.rect, window) {
                bad.push(format!("{} {:?} leaves the window", p.name, p.rect));
            }
        }
        let names: Vec<&str> = v.plots.iter().map(|p| p.name.as_str()).collect();
        let wants: &[&str] = match v.view.as_str() {
            "time-series" => &[
                "time-series-x",
                "time-series-y",
                "time-series-vr",
                "time-series-energy",
            ],
            "bifurcation" if step.strip => &["bifurcation", "lyapunov"],
            "return-map" => &["return_map"],
            "plane" => &["plane"],
            _ => &[],
        };
        for want in wants {
            if !names.contains(want) {
                bad.push(format!(
                    "{}: {want} not drawn whole (plots {names:?})",
                    v.view
                ));
            }
        }
    }
    bad
}
