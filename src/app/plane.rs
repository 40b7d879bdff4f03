//! The (x, y) plane (paper, Fig. 2): the curve C, the critical ellipse, the
//! block's path coloured by phase, the slip onsets, the block now, and the
//! pulling direction θν. Equal aspect; optionally (κx, y) so that C is the
//! unit circle.

use eframe::egui;
use egui::{Color32, Ui};
use egui_plot::{Arrows, Legend, Line, LineStyle, Plot, PlotPoints, Points};

use super::data::Data;
use super::settings::Settings;
use super::style;
use crate::model::{critical_ellipse_point, ellipse_c_point};
use crate::sim::{Phase, Sample};

/// Most path vertices handed to the plot (the path is decimated beyond).
const MAX_VERTICES: usize = 24_000;

/// The indices of the samples in the last `keep` cycles.
pub fn recent_start(data: &Data, keep: usize) -> usize {
    let tr = &data.trajectory;
    if tr.events.len() <= keep {
        return 0;
    }
    let t0 = tr.events[tr.events.len() - keep].onset_time;
    tr.samples.partition_point(|s| s.t < t0 - 1e-12)
}

/// Splits the path into one polyline per phase (NaN-separated runs), each
/// run extended to the first point of the next so the path has no gaps.
pub fn phase_polylines(samples: &[Sample], sx: f64) -> [Vec<[f64; 2]>; 3] {
    let mut out: [Vec<[f64; 2]>; 3] = Default::default();
    let stride = samples.len().div_ceil(MAX_VERTICES).max(1);
    let idx = |p: Phase| match p {
        Phase::Stick => 0,
        Phase::Accel => 1,
        Phase::Decel => 2,
    };
    let mut prev: Option<&Sample> = None;
    for (i, s) in samples.iter().enumerate() {
        // Keep phase boundaries and the ends even when decimating.
        let boundary = prev.is_some_and(|p| p.phase != s.phase)
            || samples.get(i + 1).is_some_and(|n| n.phase != s.phase)
            || i + 1 == samples.len();
        if stride > 1 && i % stride != 0 && !boundary {
            continue;
        }
        let pt = [s.x * sx, s.y];
        match prev {
            Some(p) if p.phase != s.phase => {
                // Close the previous run at this point, open a new one.
                let k = idx(p.phase);
                out[k].push(pt);
                out[k].push([f64::NAN, f64::NAN]);
                let j = idx(s.phase);
                out[j].push([p.x * sx, p.y]);
                out[j].push(pt);
            }
            _ => out[idx(s.phase)].push(pt),
        }
        prev = Some(s);
    }
    out
}

/// The plane view (stateless: everything comes from settings and data).
#[derive(Default)]
pub struct PlaneView;

impl PlaneView {
    pub fn ui(&mut self, ui: &mut Ui, s: &Settings, data: &Data) {
        let k = s.params.kappa;
        let sx = if s.scale_x_by_kappa { k } else { 1.0 };
        let x_label = if s.scale_x_by_kappa { "κ x" } else { "x" };
        let ellipse = |f: &dyn Fn(f64) -> [f64; 2]| -> Vec<[f64; 2]> {
            (0..=256)
                .map(|i| {
                    let p = f(i as f64 / 256.0 * std::f64::consts::TAU);
                    [p[0] * sx, p[1]]
                })
                .collect()
        };
        let c_pts = ellipse(&|a| ellipse_c_point(k, a));
        let crit = ellipse(&|a| critical_ellipse_point(k, s.params.gamma, a));

        let start = recent_start(data, s.keep_cycles);
        let samples = &data.trajectory.samples[start..];
        let [stick, accel, decel] = phase_polylines(samples, sx);
        let n_ev = data.trajectory.events.len();
        let onsets: Vec<[f64; 2]> = data.trajectory.events[n_ev.saturating_sub(s.keep_cycles)..]
            .iter()
            .map(|e| [e.onset_x * sx, e.onset_y])
            .collect();
        let now = samples.last().map(|p| [p.x * sx, p.y]);
        let tn = s.params.theta_nu;
        let arrow_len = 0.45;
        let dir = [arrow_len * tn.cos(), arrow_len * tn.sin()];
        let dark = s.dark;

        ui.horizontal(|ui| {
            ui.label(format!(
                "{} cycles shown of {}",
                onsets.len(),
                data.trajectory.events.len()
            ));
            ui.separator();
            style::legend_swatch(ui, style::STICK, "stick");
            style::legend_swatch(ui, style::ACCEL, "slip: accelerating");
            style::legend_swatch(ui, style::DECEL, "slip: decelerating");
        });
        Plot::new("plane")
            .data_aspect(1.0)
            .x_axis_label(x_label)
            .y_axis_label("y")
            .legend(Legend::default().position(egui_plot::Corner::RightBottom))
            .include_y(-1.05)
            .include_y(1.05)
            .show(ui, |p| {
                p.line(
                    Line::new("C: κ²x² + y² = 1", PlotPoints::from(c_pts))
                        .color(style::ink(dark))
                        .width(2.0),
                );
                p.line(
                    Line::new("critical ellipse κ³x² + y² = γ²", PlotPoints::from(crit))
                        .color(style::CRITICAL)
                        .style(LineStyle::Dashed { length: 8.0 })
                        .width(1.5),
                );
                p.line(
                    Line::new("stick", PlotPoints::from(stick))
                        .color(style::STICK)
                        .width(1.5),
                );
                p.line(
                    Line::new("slip: accelerating", PlotPoints::from(accel))
                        .color(style::ACCEL)
                        .width(2.0),
                );
                p.line(
                    Line::new("slip: decelerating", PlotPoints::from(decel))
                        .color(style::DECEL)
                        .width(2.0),
                );
                p.add(
                    Points::new("slip onsets", PlotPoints::from(onsets))
                        .color(style::ONSET)
                        .radius(3.5)
                        .shape(egui_plot::MarkerShape::Diamond),
                );
                if let Some(b) = now {
                    p.add(
                        Points::new("block", PlotPoints::from(vec![b]))
                            .color(style::BLOCK)
                            .radius(6.0)
                            .shape(egui_plot::MarkerShape::Square)
                            .filled(true),
                    );
                }
                p.add(
                    Arrows::new(
                        "pull direction θν",
                        PlotPoints::from(vec![[0.0, 0.0]]),
                        PlotPoints::from(vec![dir]),
                    )
                    .color(style::PULL)
                    .tip_length(12.0),
                );
            });
    }
}

/// The colour of a path segment (for tests and the block view).
pub fn phase_color(p: Phase) -> Color32 {
    match p {
        Phase::Stick => style::STICK,
        Phase::Accel => style::ACCEL,
        Phase::Decel => style::DECEL,
    }
}
