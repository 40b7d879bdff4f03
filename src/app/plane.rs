//! The (x, y) plane (paper, Fig. 2): the curve C, the critical ellipse, the
//! block's path coloured by phase, the slip onsets, the block now, and the
//! pulling direction θν. Equal aspect; optionally (κx, y) so that C is the
//! unit circle.

use eframe::egui;
use egui::Ui;
use egui_plot::{Arrows, LineStyle, Plot, PlotPoints};

use super::jobs::Jobs;
use super::settings::{Settings, ViewKind};
use super::style;
use super::view::{Action, View};
use crate::model::{critical_ellipse_point, ellipse_c_point};
use crate::sim::{Phase, Sample};

/// Most path vertices handed to the plot (the path is decimated beyond).
const MAX_VERTICES: usize = 24_000;

/// Splits the path into runs of one phase each, every run extended to the
/// first point of the next so the path has no gaps: `[stick, accel, decel]`.
/// (Separate runs rather than NaN breaks: egui_plot would carry a NaN into
/// the tessellated path and lose the run.)
pub fn phase_polylines(samples: &[Sample], sx: f64) -> [Vec<Vec<[f64; 2]>>; 3] {
    let mut out: [Vec<Vec<[f64; 2]>>; 3] = Default::default();
    let stride = samples.len().div_ceil(MAX_VERTICES).max(1);
    let idx = |p: Phase| match p {
        Phase::Stick => 0,
        Phase::Accel => 1,
        Phase::Decel => 2,
    };
    // Repeated points (a slip's stop is also its stick's start) make the
    // tessellator drop a segment: never push one twice.
    let push = |v: &mut Vec<[f64; 2]>, q: [f64; 2]| {
        if v.last() != Some(&q) {
            v.push(q);
        }
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
        let j = idx(s.phase);
        match prev {
            Some(p) if p.phase == s.phase => {
                if let Some(run) = out[j].last_mut() {
                    push(run, pt);
                }
            }
            Some(p) => {
                // Close the previous run at this point, open a new one.
                if let Some(run) = out[idx(p.phase)].last_mut() {
                    push(run, pt);
                }
                let mut run = vec![[p.x * sx, p.y]];
                push(&mut run, pt);
                out[j].push(run);
            }
            None => out[j].push(vec![pt]),
        }
        prev = Some(s);
    }
    out
}

/// The plane view. It frames C when κ, the axis scaling or the plot's size
/// change, and otherwise leaves the user's pan and zoom alone.
#[derive(Default)]
pub struct PlaneView {
    fitted_for: Option<(u64, bool, [u32; 2])>,
}

impl PlaneView {
    fn show(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs) {
        let k = s.params.kappa;
        let sx = if s.scale_x_by_kappa { k } else { 1.0 };
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

        let start = jobs.trajectory.data.recent_start(s.keep_cycles);
        let samples = &jobs.trajectory.data.samples[start..];
        let [stick, accel, decel] = phase_polylines(samples, sx);
        let n_ev = jobs.trajectory.data.events.len();
        let onsets: Vec<[f64; 2]> = jobs.trajectory.data.events
            [n_ev.saturating_sub(s.keep_cycles)..]
            .iter()
            .map(|e| [e.onset_x * sx, e.onset_y])
            .collect();
        let now = samples.last().map(|p| [p.x * sx, p.y]);
        controls_ui(ui, s, onsets.len(), jobs.trajectory.data.events.len());
        legend_ui(ui, s.dark);
        let tf = self.plot_ui(ui, s, c_pts, crit);
        paint_path(ui, &tf, [&stick, &accel, &decel], &onsets, now, s.dark);
    }

    /// The plot with C, the critical ellipse and the pull arrow, framed on
    /// C when κ, the axis scaling or the plot's size change; returns its
    /// transform.
    fn plot_ui(
        &mut self,
        ui: &mut Ui,
        s: &Settings,
        c_pts: Vec<[f64; 2]>,
        crit: Vec<[f64; 2]>,
    ) -> egui_plot::PlotTransform {
        let k = s.params.kappa;
        let sx = if s.scale_x_by_kappa { k } else { 1.0 };
        let x_label = if s.scale_x_by_kappa { "κ x" } else { "x" };
        let tn = s.params.theta_nu;
        let arrow_len = 0.45;
        let dir = [arrow_len * tn.cos(), arrow_len * tn.sin()];
        let dark = s.dark;
        // Frame C (not the critical ellipse, which can be γ times taller).
        let (bx, by) = (1.2 / k * sx, 1.2);
        let fitted_for = self.fitted_for;
        let kbits = k.to_bits();
        let scaled = s.scale_x_by_kappa;
        let resp = Plot::new("plane")
            .show_background(false)
            .data_aspect(1.0)
            .allow_double_click_reset(false)
            .x_axis_label(x_label)
            .y_axis_label("y")
            .show(ui, |p| {
                let f = *p.transform().frame();
                let size = [f.width() as u32, f.height() as u32];
                let key = (kbits, scaled, size);
                let refit = fitted_for != Some(key) || p.response().double_clicked();
                if refit && f.height() > 0.0 {
                    let asp = (f.width() / f.height()) as f64;
                    let (hx, hy) = if by * asp >= bx {
                        (by * asp, by)
                    } else {
                        (bx, bx / asp)
                    };
                    p.set_plot_bounds(egui_plot::PlotBounds::from_min_max([-hx, -hy], [hx, hy]));
                }
                p.line(
                    style::line("C: κ²x² + y² = 1", PlotPoints::from(c_pts))
                        .color(style::ink(dark))
                        .width(2.0),
                );
                p.line(
                    style::line("critical ellipse κ³x² + y² = γ²", PlotPoints::from(crit))
                        .color(style::CRITICAL)
                        .style(LineStyle::Dashed { length: 8.0 })
                        .width(1.5),
                );
                p.add(
                    Arrows::new(
                        "pull direction θν",
                        PlotPoints::from(vec![[0.0, 0.0]]),
                        PlotPoints::from(vec![dir]),
                    )
                    .color(style::PULL)
                    .tip_length(12.0),
                );
                key
            });
        self.fitted_for = Some(resp.inner);
        resp.transform
    }
}

/// How many cycles are shown, and the κx switch.
fn controls_ui(ui: &mut Ui, s: &mut Settings, shown: usize, total: usize) {
    ui.horizontal_wrapped(|ui| {
        ui.label(format!("{shown} cycles shown of {total}"));
        ui.checkbox(&mut s.scale_x_by_kappa, "x axis as κx")
            .on_hover_text(
                "Plot (κx, y): C becomes the unit circle and θ the polar angle. \
                     Off: the true (x, y), where C is κ times narrower than tall.",
            );
    });
}

/// The legend above the plot.
fn legend_ui(ui: &mut Ui, dark: bool) {
    ui.horizontal_wrapped(|ui| {
        style::legend_swatch(ui, style::STICK, "stick");
        style::legend_swatch(ui, style::ACCEL, "slip, accelerating");
        style::legend_swatch(ui, style::DECEL, "slip, decelerating");
        style::legend_marker(ui, style::ONSET, "slip onset");
        style::legend_line(ui, style::ink(dark), false, "C");
        style::legend_line(ui, style::CRITICAL, true, "critical ellipse");
        style::legend_line(ui, style::PULL, false, "pull θν");
    });
}

/// The path, onsets and block, painted over the plot in screen space.
fn paint_path(
    ui: &Ui,
    tf: &egui_plot::PlotTransform,
    [stick, accel, decel]: [&[Vec<[f64; 2]>]; 3],
    onsets: &[[f64; 2]],
    now: Option<[f64; 2]>,
    dark: bool,
) {
    let painter = ui.painter().with_clip_rect(*tf.frame());
    let to_screen = |p: &[f64; 2]| tf.position_from_point(&egui_plot::PlotPoint::new(p[0], p[1]));
    for (runs, color, width) in [
        (accel, style::ACCEL, 2.0),
        (decel, style::DECEL, 2.0),
        // On top: in κx a stick often retraces the slip before it.
        (stick, style::STICK, 1.6),
    ] {
        for run in runs.iter().filter(|r| r.len() > 1) {
            let pts: Vec<egui::Pos2> = run.iter().map(to_screen).collect();
            painter.add(egui::Shape::line(pts, egui::Stroke::new(width, color)));
        }
    }
    for o in onsets {
        let c = to_screen(o);
        let r = 4.5;
        painter.add(egui::Shape::convex_polygon(
            vec![
                c + egui::vec2(0.0, -r),
                c + egui::vec2(r, 0.0),
                c + egui::vec2(0.0, r),
                c + egui::vec2(-r, 0.0),
            ],
            style::ONSET,
            egui::Stroke::NONE,
        ));
    }
    if let Some(b) = now {
        let c = to_screen(&b);
        painter.rect_filled(
            egui::Rect::from_center_size(c, egui::vec2(11.0, 11.0)),
            1.0,
            style::ink(dark),
        );
    }
}

impl View for PlaneView {
    fn title(&self) -> &'static str {
        ViewKind::Plane.title()
    }

    fn ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, _out: &mut Vec<Action>) {
        self.show(ui, s, jobs);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(t: f64, x: f64, phase: Phase) -> Sample {
        Sample {
            t,
            x,
            y: 0.0,
            u: 0.0,
            w: 0.0,
            phase,
        }
    }

    #[test]
    fn each_phase_gets_its_own_connected_runs() {
        let path = [
            s(0.0, 0.0, Phase::Accel),
            s(1.0, 1.0, Phase::Accel),
            s(2.0, 2.0, Phase::Decel),
            s(3.0, 3.0, Phase::Decel),
            s(3.5, 3.5, Phase::Stick),
            s(9.0, 9.0, Phase::Stick),
            s(9.0, 9.0, Phase::Accel),
            s(10.0, 10.0, Phase::Accel),
        ];
        let [stick, accel, decel] = phase_polylines(&path, 1.0);
        let xs = |v: &Vec<[f64; 2]>| v.iter().map(|p| p[0]).collect::<Vec<_>>();
        assert_eq!(stick.len(), 1);
        assert_eq!(xs(&stick[0]), [3.0, 3.5, 9.0]);
        assert_eq!(accel.len(), 2);
        assert_eq!(xs(&accel[0]), [0.0, 1.0, 2.0]);
        assert_eq!(xs(&accel[1]), [9.0, 10.0]);
        assert_eq!(xs(&decel[0]), [1.0, 2.0, 3.0, 3.5]);
        for run in stick.iter().chain(&accel).chain(&decel) {
            assert!(run.windows(2).all(|w| w[0] != w[1]), "no repeated points");
        }
    }
}
