//! The strip λ(θν) under the bifurcation diagram: the Lyapunov exponent
//! of every column ([`crate::sim::column_lyapunov`]), computed by the sweep
//! job with the column, on the diagram's θν axis and zoom.
//!
//! A column settled on a solved cycle has λ = ln|m|/p exactly (a filled
//! dot); an aperiodic one has the mean of ln|f′(θ)| with ±1 standard error
//! (a ring and a bar). λ = 0 is marked: it is touched at each period
//! doubling (m = −1) and at the cascade's accumulation, and crossed into
//! chaos. A strongly contracting cycle (m near 0: λ → −∞ at a
//! superstable one) below the strip's floor is a triangle pointing down at
//! the frame's foot, not a dot there.

use eframe::egui;
use egui::Ui;
use egui_plot::{HLine, LineStyle, MarkerShape, Plot, PlotBounds, PlotPoints, VLine};

use super::axes::{self, AxisSpec};
use super::data::SweepData;
use super::diagram_axis::XAxis;
use super::markers::{self, Marker};
use super::settings::Settings;
use super::style;

/// Names of the strip's items (legend and hover).
const EXACT: &str = "λ = ln|m|/p (solved cycle)";
const MEAN: &str = "λ = mean ln|f'| ± 1 s.e.";

/// The strip's markers, `r` the dot's radius: a solved cycle's filled
/// dot, a mean's ring, a λ below the strip's triangle pointing down.
fn strip_markers(ink: egui::Color32, r: f32) -> [Marker; 3] {
    [
        Marker::new(MarkerShape::Circle, ink, r, true),
        Marker::new(MarkerShape::Circle, style::ACCEL, r + 0.5, false),
        Marker::new(MarkerShape::Down, ink, r + 1.5, true),
    ]
}

/// The lowest λ the strip shows: a superstable cycle (m → 0) sends λ to
/// −∞, which would flatten everything else.
const FLOOR: f64 = -3.0;

/// The strip's lower edge when some of its points lie below it (λ under
/// the padded [`FLOOR`]).
pub fn below_strip(sweep: &SweepData) -> Option<f64> {
    let points = strip_points(sweep);
    let (lo, _) = lambda_range(&points);
    points.iter().any(|p| p.1 < lo).then_some(lo)
}

/// The name of the off-strip marker, below `lo`.
fn below_name(lo: f64) -> String {
    format!("λ < {lo:.2}, below the strip")
}

/// The strip's points: (x, λ, standard error) of every column with λ, x
/// the diagram's coordinate of its value ([`XAxis`]: θν, or log10 κ, …).
pub fn strip_points(sweep: &SweepData) -> Vec<(f64, f64, Option<f64>)> {
    let axis = XAxis::of(sweep.param);
    sweep
        .columns
        .iter()
        .flatten()
        .filter_map(|c| c.lyapunov.map(|l| (axis.x(c.value), l.lyapunov, l.stderr)))
        .filter(|p| p.1.is_finite())
        .collect()
}

/// The strip's λ range: every value (down to [`FLOOR`]) and 0, padded.
pub fn lambda_range(points: &[(f64, f64, Option<f64>)]) -> (f64, f64) {
    let (mut lo, mut hi) = (0.0f64, 0.0f64);
    for &(_, l, se) in points {
        let e = se.unwrap_or(0.0);
        lo = lo.min(l - e);
        hi = hi.max(l + e);
    }
    let lo = lo.max(FLOOR);
    let pad = ((hi - lo) * 0.08).max(0.05);
    (lo - pad, hi + pad)
}

/// Draws the strip, `height` points tall, over `x` (the diagram's bounds,
/// in its axis' coordinate), with a y axis `y_width` wide so that its
/// frame lines up with the diagram's. Returns the value of the varied
/// parameter clicked, if any.
pub fn strip_ui(
    ui: &mut Ui,
    s: &Settings,
    sweep: &SweepData,
    x: (f64, f64),
    (height, y_width): (f32, f32),
) -> Option<f64> {
    let points = strip_points(sweep);
    let (lo, hi) = lambda_range(&points);
    let ink = style::ink(s.dark);
    let axis = XAxis::of(sweep.param);
    let current_x = axis.x(axis.param.get(&s.params));
    let plot = Plot::new("lyapunov")
        .height(height)
        .show_background(false)
        .allow_drag(false)
        .allow_zoom(false)
        .allow_scroll(false)
        .allow_boxed_zoom(false)
        .allow_double_click_reset(false);
    let ax = axis.spec(s.angle_unit);
    // The quantity in full where it fits along the strip, else its name
    // short, else its symbol (the legend says what λ is).
    let short = axes::fitting_title(ui, "Lyapunov λ", "λ", height);
    let ay = AxisSpec::linear(axes::fitting_title(
        ui,
        "λ, Lyapunov exponent",
        short,
        height,
    ));
    let current = style::draws_current(ui.ctx());
    let resp = axes::apply(ui.ctx(), plot, &ax, &ay)
        .y_axis_min_width(y_width)
        .show(ui, |p| {
            p.set_plot_bounds(PlotBounds::from_min_max([x.0, lo], [x.1, hi]));
            p.add(
                HLine::new("λ = 0", 0.0)
                    .color(style::CRITICAL)
                    .style(LineStyle::Dashed { length: 8.0 })
                    .width(1.0),
            );
            if current {
                p.add(
                    VLine::new("current", current_x)
                        .color(style::CURRENT)
                        .width(2.0),
                );
            }
            marks(p, &points, (lo, hi), ink);
            p.pointer_coordinate()
        });
    axes::remember_frame(ui.ctx(), "lyapunov", *resp.transform.frame());
    let clicked = resp.response.clicked();
    resp.inner.filter(|_| clicked).map(|p| axis.value(p.x))
}

/// The strip's marks: each column's λ (a dot, or a ring with its error
/// bar), and a triangle at the foot for a λ below the frame [lo, hi].
fn marks(
    p: &mut egui_plot::PlotUi,
    points: &[(f64, f64, Option<f64>)],
    (lo, hi): (f64, f64),
    ink: egui::Color32,
) {
    for &(t, l, se) in points {
        if let Some(e) = se {
            p.line(
                style::line(MEAN, PlotPoints::from(vec![[t, l - e], [t, l + e]]))
                    .color(style::ACCEL.gamma_multiply(0.7)),
            );
        }
    }
    let dots = |exact: bool| -> Vec<[f64; 2]> {
        points
            .iter()
            .filter(|p| p.2.is_none() == exact && p.1 >= lo)
            .map(|p| [p.0, p.1])
            .collect()
    };
    let below: Vec<[f64; 2]> = points
        .iter()
        .filter(|p| p.1 < lo)
        .map(|p| [p.0, lo + 0.06 * (hi - lo)])
        .collect();
    let [exact, mean, under] = strip_markers(ink, style::width(p.ctx(), 2.0));
    p.points(exact.points(EXACT, dots(true)));
    p.points(mean.points(MEAN, dots(false)));
    if !below.is_empty() {
        p.points(under.points(below_name(lo), below));
    }
}

/// What a figure too short for the strip says on stderr.
pub const LEFT_OUT: &str = "the λ strip is left out: the figure is too short for it (larger --size or smaller --font-size)";

/// The strip's legend: what its marks mean, with the off-strip marker
/// when some points lie `below` the strip's lower edge.
pub fn legend_ui(ui: &mut Ui, dark: bool, below: Option<f64>) {
    style::legend_row(ui, |ui| {
        let [exact, mean, under] = strip_markers(style::ink(dark), style::width(ui.ctx(), 2.0));
        markers::legend(ui, &[exact], EXACT);
        markers::legend(ui, &[mean], MEAN);
        style::legend_line(ui, style::CRITICAL, true, "λ = 0");
        if let Some(lo) = below {
            let name = below_name(lo);
            markers::legend(ui, &[under], &name);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::data::Column;
    use crate::sim::column_lyapunov::ColumnLyapunov;

    fn sweep(values: &[(f64, Option<f64>)]) -> SweepData {
        let mut s = SweepData::new(1.0, 1.5, values.len());
        for (i, &(l, se)) in values.iter().enumerate() {
            s.insert(
                i,
                Column {
                    value: 1.0 + 0.1 * i as f64,
                    thetas: vec![0.1],
                    coarse: false,
                    lyapunov: Some(ColumnLyapunov {
                        lyapunov: l,
                        stderr: se,
                        period: se.is_none().then_some(1),
                    }),
                    attractor: Vec::new(),
                    uncounted: None,
                },
            );
        }
        s
    }

    #[test]
    fn the_range_holds_zero_every_error_bar_and_stops_at_the_floor() {
        let s = sweep(&[(-0.5, None), (0.2, Some(0.1)), (-40.0, None)]);
        let pts = strip_points(&s);
        assert_eq!(pts.len(), 3);
        let (lo, hi) = lambda_range(&pts);
        assert!((0.3..0.6).contains(&hi), "{hi}");
        assert!(lo < FLOOR && lo > FLOOR - 0.5, "{lo}");
        let s = sweep(&[(-0.5, None)]);
        let (lo, hi) = lambda_range(&strip_points(&s));
        assert!(lo < -0.5 && hi > 0.0, "{lo} {hi}");
    }

    #[test]
    fn only_a_lambda_under_the_frame_is_off_the_strip() {
        // −40 (near superstable) is under the frame; −3.02 is under the
        // floor but inside the padding, so it is drawn where it is.
        let s = sweep(&[(-0.5, None), (-40.0, None), (-3.02, None)]);
        let lo = below_strip(&s).unwrap();
        assert!(lo < -3.02 && lo > -40.0, "{lo}");
        let pts = strip_points(&s);
        assert_eq!(pts.iter().filter(|p| p.1 < lo).count(), 1);
        assert_eq!(
            below_strip(&sweep(&[(-0.5, None), (0.1, Some(0.05))])),
            None
        );
    }
}
