//! The (x, y) plane (paper, Fig. 2): the curve C, the critical ellipse, the
//! block's path coloured by phase, the slip onsets, the block now, and the
//! pulling direction θν. Optionally (κx, y), in equal aspect, so that C is
//! the unit circle; else the true (x, y), with x stretched to fill the
//! plot. Every direction is drawn as it runs in the axes shown: the pull
//! arrow points where the stick segments go.

use eframe::egui;
use egui::{RichText, Ui};
use egui_plot::{LineStyle, MarkerShape, Plot, PlotPoints};

use super::axes::{self, AxisSpec};
use super::jobs::Jobs;
use super::markers::{self, Marker};
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
        legend_ui(ui, s.dark);
        let tf = self.plot_ui(ui, s, c_pts, crit);
        paint_path(ui, &tf, [&stick, &accel, &decel], &onsets, now, s.dark);
        paint_pull_arrow(ui, &tf, pull_direction(s.params.theta_nu, sx));
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
        // The quantity in full where it fits under the plot (a narrow
        // tile, the tour's at a projector's size: shorter).
        let w = ui.available_width();
        let x_axis = AxisSpec::linear(if s.scale_x_by_kappa {
            axes::fitting_width(
                ui,
                "κx, scaled block position (F₀/k_y)",
                "κx, position (F₀/k_y)",
                w,
            )
        } else {
            axes::fitting_width(ui, "x, block position (F₀/k_y)", "x, position (F₀/k_y)", w)
        });
        let dark = s.dark;
        let lw = style::width(ui.ctx(), 1.0);
        // Frame C (not the critical ellipse, which can be γ times taller).
        let (bx, by) = (1.2 / k * sx, 1.2);
        let fitted_for = self.fitted_for;
        let kbits = k.to_bits();
        let scaled = s.scale_x_by_kappa;
        let mut plot = Plot::new("plane")
            .show_background(false)
            .allow_double_click_reset(false);
        if scaled {
            plot = plot.data_aspect(1.0);
        }
        let resp =
            axes::apply(ui.ctx(), plot, &x_axis, &AxisSpec::linear("y (F₀/k_y)")).show(ui, |p| {
                let f = *p.transform().frame();
                let size = [f.width() as u32, f.height() as u32];
                let key = (kbits, scaled, size);
                let refit = fitted_for != Some(key) || p.response().double_clicked();
                if refit && f.height() > 0.0 {
                    let (hx, hy) = if scaled {
                        // Equal aspect: C round, the box widened to the plot.
                        let asp = (f.width() / f.height()) as f64;
                        if by * asp >= bx {
                            (by * asp, by)
                        } else {
                            (bx, bx / asp)
                        }
                    } else {
                        // The true x is κ times narrower: fill the plot.
                        (bx, by)
                    };
                    p.set_plot_bounds(egui_plot::PlotBounds::from_min_max([-hx, -hy], [hx, hy]));
                }
                p.line(
                    style::line("C: κ²x² + y² = 1", PlotPoints::from(c_pts))
                        .color(style::ink(dark))
                        .width(2.0 * lw),
                );
                // Dashed: cut to the plot's bounds first, so that a deep zoom
                // does not dash the whole ellipse at the zoom's scale.
                let b = p.plot_bounds();
                for part in super::clip::clip_polyline(&crit, b.min(), b.max()) {
                    p.line(
                        style::line("critical ellipse κ³x² + y² = γ²", PlotPoints::from(part))
                            .color(style::CRITICAL)
                            .style(LineStyle::Dashed { length: 8.0 })
                            .width(1.5 * lw),
                    );
                }
                key
            });
        self.fitted_for = Some(resp.inner);
        axes::remember_frame(ui.ctx(), "plane", *resp.transform.frame());
        resp.transform
    }
}

/// The pull direction V = (cos θν, sin θν) in the plotted coordinates:
/// (κ cos θν, sin θν) when x is plotted as κx (`sx` = κ), so that it runs
/// along the stick segments, which move with V; normalised.
pub fn pull_direction(theta_nu: f64, sx: f64) -> [f64; 2] {
    let (dx, dy) = (sx * theta_nu.cos(), theta_nu.sin());
    let n = dx.hypot(dy);
    [dx / n, dy / n]
}

/// The pull arrow from the origin along `dir` (plot coordinates), drawn in
/// screen space through the plot's transform, so that it keeps its angle
/// in any aspect; its length is a fixed share of the plot, not to scale.
fn paint_pull_arrow(ui: &Ui, tf: &egui_plot::PlotTransform, dir: [f64; 2]) {
    let frame = *tf.frame();
    let o = tf.position_from_point(&egui_plot::PlotPoint::new(0.0, 0.0));
    let tip = tf.position_from_point(&egui_plot::PlotPoint::new(dir[0], dir[1]));
    let d = (tip - o).normalized();
    if !d.x.is_finite() {
        return;
    }
    let len = 0.3 * frame.width().min(frame.height());
    let end = o + d * len;
    let w = style::width(ui.ctx(), 2.5);
    let painter = ui.painter().with_clip_rect(frame);
    painter.line_segment([o, end], egui::Stroke::new(w, style::PULL));
    let head = 12.0;
    let n = egui::vec2(-d.y, d.x);
    painter.add(egui::Shape::convex_polygon(
        vec![
            end + d * 2.0,
            end - d * head + n * head * 0.45,
            end - d * head - n * head * 0.45,
        ],
        style::PULL,
        egui::Stroke::NONE,
    ));
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

/// The marker of a slip onset.
const ONSET_MARKER: Marker = Marker::new(MarkerShape::Diamond, style::ONSET, 4.5, true);

/// The legend above the plot.
fn legend_ui(ui: &mut Ui, dark: bool) {
    style::legend_row(ui, |ui| {
        style::legend_swatch(ui, style::STICK, "stick");
        style::legend_swatch(ui, style::ACCEL, "slip, accelerating");
        style::legend_swatch(ui, style::DECEL, "slip, decelerating");
        markers::legend(ui, &[ONSET_MARKER], "slip onset");
        style::legend_line(ui, style::ink(dark), false, "C");
        style::legend_line(ui, style::CRITICAL, true, "critical ellipse");
        style::legend_line(ui, style::PULL, false, "pull θν");
        // Short, so that at text size 1.5 the legend keeps to two rows of
        // a tile; the full sentence on hover.
        ui.label(RichText::new("(arrow: direction only)").weak())
            .on_hover_text(
                "The arrow's direction is the pull's in these axes; its length is not to scale.",
            );
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
        ONSET_MARKER.paint(&painter, to_screen(o));
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

    fn controls_ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, _out: &mut Vec<Action>) {
        let total = jobs.trajectory.data.events.len();
        controls_ui(ui, s, total.min(s.keep_cycles), total);
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
    fn the_pull_arrow_runs_along_a_stick_segment_in_the_axes_shown() {
        // A stick moves the block with V: from (x, y) to (x, y) + V t.
        let (kappa, theta_nu) = (50.0f64, 1.4f64);
        for sx in [kappa, 1.0] {
            let a = [0.01, 0.2];
            let b = [a[0] + 0.3 * theta_nu.cos(), a[1] + 0.3 * theta_nu.sin()];
            let seg = [sx * (b[0] - a[0]), b[1] - a[1]];
            let d = pull_direction(theta_nu, sx);
            let cross = d[0] * seg[1] - d[1] * seg[0];
            assert!(cross.abs() < 1e-12 && d[0] * seg[0] + d[1] * seg[1] > 0.0);
        }
        // In κx at κ = 50, θν = 1.4 the stick runs at about 6.6°, not 80°.
        let d = pull_direction(theta_nu, kappa);
        assert!((d[1].atan2(d[0]).to_degrees() - 6.6).abs() < 0.1);
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
