//! The Numerics view: the work-precision chart (log-log, max map error on
//! x, time or RHS evaluations per iterate on y, one curve per method) with
//! the settings the jobs now run with marked, and its table. It shows the
//! committed chart (`assets/work-precision.csv`) until the user re-measures
//! on the current parameters: that run is a worker job on the numerics
//! lane, its rows arriving one setting at a time.

use eframe::egui;
use egui::{Color32, RichText, Ui};
use egui_plot::{LineStyle, MarkerShape, Plot, PlotPoints};

use super::axes::{self, AxisSpec};
use super::data::WorkPrecisionData;
use super::jobs::{JobKind, JobState, Jobs, Slot};
use super::markers::{self, Marker};
use super::numerics_table::table_ui;
use super::settings::{AccuracyMode, Settings, ViewKind};
use super::style;
use super::view::{Action, View};
use crate::numerics::committed::{default_caption, default_rows};
use crate::numerics::quick::{QUICK_POINTS, QUICK_TIME_PER_SETTING, SLOW_ITERATE};
use crate::numerics::{Row, estimate};

/// The view's own state: the chart's switches (the run is the job
/// model's `numerics` slot).
#[derive(Clone, Debug, Default)]
pub struct NumericsView {
    /// RHS evaluations per iterate on y instead of µs.
    pub y_evals: bool,
    /// Hide the committed chart behind a run's curves.
    pub hide_committed: bool,
}

/// log10, with errors of exactly 0 put at 1e-17 (below any chart's floor).
fn lg(v: f64) -> f64 {
    v.max(1e-17).log10()
}

/// The cost a row is drawn at: µs or RHS evaluations per iterate.
fn cost(r: &Row, y_evals: bool) -> f64 {
    if y_evals {
        r.evals_per_iterate
    } else {
        r.median_us
    }
}

/// The chart's curves: per method (in order of first appearance), its rows
/// that succeeded on every point as (log10 max error, log10 cost). Rows
/// where a point failed are left out, as in the committed SVG.
pub fn curves(rows: &[Row], y_evals: bool) -> Vec<(&'static str, Vec<[f64; 2]>)> {
    let mut out: Vec<(&'static str, Vec<[f64; 2]>)> = Vec::new();
    for r in rows {
        let y = cost(r, y_evals);
        if r.failed > 0 || !r.max_error.is_finite() || !(y > 0.0) {
            continue;
        }
        let p = [lg(r.max_error), y.log10()];
        match out.iter_mut().find(|(m, _)| *m == r.method) {
            Some((_, pts)) => pts.push(p),
            None => out.push((r.method, vec![p])),
        }
    }
    out
}

/// Where each job's setting lies on a chart of `rows` (its row, or
/// interpolated between two), if the chart covers it.
pub fn in_use(rows: &[Row], s: &Settings, y_evals: bool) -> Vec<(JobKind, [f64; 2])> {
    JobKind::SOLVED
        .iter()
        .filter_map(|&job| {
            let e = estimate(rows, &job.solver(s)?)?;
            let y = if y_evals { e.evals } else { e.us };
            (e.max_error.is_finite() && y > 0.0).then(|| (job, [lg(e.max_error), y.log10()]))
        })
        .collect()
}

/// The job table's marker of `job`, as egui draws it.
fn job_marker(job: JobKind) -> MarkerShape {
    use crate::jobs::Marker;
    match job.marker() {
        Marker::Square => MarkerShape::Square,
        Marker::Diamond => MarkerShape::Diamond,
        Marker::Circle => MarkerShape::Circle,
        Marker::Up => MarkerShape::Up,
        Marker::Cross => MarkerShape::Cross,
        Marker::Down => MarkerShape::Down,
        Marker::Left => MarkerShape::Left,
        Marker::Right => MarkerShape::Right,
        Marker::Asterisk => MarkerShape::Asterisk,
    }
}

impl View for NumericsView {
    fn title(&self) -> &'static str {
        ViewKind::Numerics.title()
    }

    /// In the window: the controls, the notes, the chart and the table,
    /// scrolled where they run past the tile (text ×1.5 in a small tile).
    /// As a figure: the chart alone (its legend and plot), filling it.
    fn ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, out: &mut Vec<Action>) {
        let run = &jobs.numerics;
        let rows: &[Row] = if run.data.rows.is_empty() {
            default_rows()
        } else {
            &run.data.rows
        };
        let showing_run = !run.data.rows.is_empty();
        if style::figure_only(ui.ctx()) {
            self.chart_ui(ui, s, rows, showing_run, None);
            return;
        }
        let tile = ui.available_height();
        egui::ScrollArea::vertical()
            .auto_shrink(false)
            .show(ui, |ui| {
                self.controls_ui(ui, run, out);
                notes_ui(ui, s, run);
                self.chart_ui(ui, s, rows, showing_run, Some(tile));
                table_ui(ui, rows, s);
            });
    }
}

impl NumericsView {
    /// Run, Stop, the progress and the chart's switches.
    fn controls_ui(&mut self, ui: &mut Ui, run: &Slot<WorkPrecisionData>, out: &mut Vec<Action>) {
        let running = run.state == JobState::Running;
        ui.horizontal_wrapped(|ui| {
            let r = ui
                .add_enabled(!running, egui::Button::new("Run for current parameters"))
                .on_hover_text(format!(
                    "Measure every method on {QUICK_POINTS} orbit points of the current \
                     attractor, on the worker (the views keep running)."
                ));
            if r.clicked() {
                out.push(Action::Start(JobKind::Numerics));
            }
            if ui
                .add_enabled(running, egui::Button::new("Stop"))
                .on_hover_text("Stop the measurement; the rows so far stay.")
                .clicked()
            {
                out.push(Action::Stop(JobKind::Numerics));
            }
            if run.issued() {
                let (done, total) = (run.data.done(), run.data.total);
                ui.add(
                    egui::ProgressBar::new(done as f32 / total.max(1) as f32)
                        // Room for "57/57 settings" at any text size.
                        .desired_width(9.0 * ui.text_style_height(&egui::TextStyle::Body))
                        .text(format!("{done}/{total} settings")),
                );
                let state = match &run.state {
                    JobState::Running => "measuring…".to_string(),
                    JobState::Done => "done".to_string(),
                    JobState::Cancelled => "stopped".to_string(),
                    JobState::Failed(_) => "failed".to_string(),
                    JobState::Idle => String::new(),
                };
                ui.label(state);
            }
            ui.separator();
            ui.label("y:");
            ui.selectable_value(&mut self.y_evals, false, "µs per iterate");
            ui.selectable_value(&mut self.y_evals, true, "RHS evaluations per iterate")
                .on_hover_text("The machine-independent cost.");
            if run.issued() {
                ui.checkbox(&mut self.hide_committed, "hide committed chart");
            }
        });
    }
}

/// The run's error, what the chart shows, and how it was measured.
fn notes_ui(ui: &mut Ui, s: &Settings, run: &Slot<WorkPrecisionData>) {
    let run = &run.data;
    if let Some(e) = &run.error {
        ui.label(RichText::new(format!("error: {e}")).color(style::ERROR));
    }
    let showing_run = !run.rows.is_empty();
    let caption = match (showing_run, run.params) {
        (true, Some(p)) => {
            let stale = if p != s.params {
                " (not the current parameters)"
            } else {
                ""
            };
            format!(
                "Run on κ = {}, γ = {}, ν = {:e}, θν = {:.4}, Ω = {}{stale}: {} orbit points, \
                     reference spread {}; the committed chart faint behind it.",
                p.kappa,
                p.gamma,
                p.nu,
                p.theta_nu,
                p.omega,
                run.points,
                run.reference_spread
                    .map_or("?".into(), |x| format!("{x:.1e}")),
            )
        }
        _ => format!("Committed chart: {}", default_caption()),
    };
    ui.label(caption);
    if run.loaded()
        && let Some((l, cores)) = run.load
    {
        ui.label(
            RichText::new(format!(
                "Caution: the machine was busy when this run started (load average {l:.1} on \
                 {cores} cores): its wall times are inflated. Each is the fastest of \
                 {} timings, but only RHS evaluations per iterate are unaffected.",
                crate::worker::TIMING_REPEATS
            ))
            .color(style::ERROR),
        );
    }
    ui.label(
        RichText::new(format!(
            "Wall times measured while the other lanes run share the cores and are noisy; \
                 RHS evaluations per iterate are the machine-independent cost. A run times each \
                 setting for {} ms over {QUICK_POINTS} points and skips a method's finer \
                 settings once one takes over {} ms per iterate.",
            QUICK_TIME_PER_SETTING.as_millis(),
            SLOW_ITERATE.as_millis()
        ))
        .weak(),
    );
    for sk in &run.skipped {
        ui.label(format!("skipped {sk}"));
    }
}

impl NumericsView {
    /// The legend, the jobs' markers and the log-log plot of `rows`
    /// (a run's, over the faint committed chart unless hidden); the plot
    /// 62 % of the `tile`'s height, or all the height left (a figure).
    fn chart_ui(
        &self,
        ui: &mut Ui,
        s: &Settings,
        rows: &[Row],
        showing_run: bool,
        tile: Option<f32>,
    ) {
        let y_evals = self.y_evals;
        let committed =
            (showing_run && !self.hide_committed).then(|| curves(default_rows(), y_evals));
        let marks = in_use(rows, s, y_evals);
        let mode = match s.accuracy {
            AccuracyMode::Auto => "Auto",
            AccuracyMode::Custom => "Custom",
        };
        let ink = style::ink(s.dark);
        chart_legend_ui(ui, rows, y_evals, &marks, mode, ink);
        // In the window, tall enough for five labelled decades at any text
        // size (the tile scrolls); a figure takes the height it is given.
        let line = ui.text_style_height(&egui::TextStyle::Body);
        let plot_h = match tile {
            Some(h) => (h * 0.62).max(14.0 * line),
            None => ui.available_height(),
        };
        let lw = style::width(ui.ctx(), 1.0);
        let plot = Plot::new("work_precision")
            .show_background(false)
            .height(plot_h);
        // The y title in short where it would run past a short plot.
        let (long, short) = if y_evals {
            ("RHS evaluations per iterate", "RHS evals / iterate")
        } else {
            ("wall time per iterate (µs)", "µs / iterate")
        };
        let y_title = axes::fitting_title(ui, long, short, plot_h);
        let plot = axes::apply(
            ui.ctx(),
            plot,
            &AxisSpec::log10("max map error |θ' − θ'_ref| (rad)"),
            &AxisSpec::log10(y_title),
        );
        let resp = plot
            .label_formatter(|pos| {
                let p = match pos {
                    egui_plot::HoverPosition::NearDataPoint { position, .. } => position,
                    egui_plot::HoverPosition::Elsewhere { position } => position,
                };
                Some(format!(
                    "error {:.2e}\n{} {:.3}",
                    10f64.powf(p.x),
                    if y_evals { "evals" } else { "µs" },
                    10f64.powf(p.y)
                ))
            })
            .show(ui, |p| {
                if let Some(c) = committed {
                    for (m, pts) in c {
                        // Unnamed: the committed curves stay out of the legend.
                        p.line(
                            style::line("", PlotPoints::from(pts))
                                .color(style::method_color(m).gamma_multiply(0.3))
                                .width(1.0),
                        );
                    }
                }
                method_items(p, rows, y_evals, lw);
                for (job, pt) in marks {
                    p.add(job_mark(job, ink).points(format!("{mode}: {}", job.label()), vec![pt]));
                }
            });
        axes::remember_shown(ui, "work_precision", *resp.transform.frame());
    }
}

/// The legend above the chart (inside, it would hide some corner of the
/// curves): the methods, then the jobs' markers on a line of their own, so
/// that wrapping never parts a marker from its label at usual widths.
fn chart_legend_ui(
    ui: &mut Ui,
    rows: &[Row],
    y_evals: bool,
    marks: &[(JobKind, [f64; 2])],
    mode: &str,
    ink: egui::Color32,
) {
    style::legend_row(ui, |ui| {
        for (m, _) in curves(rows, y_evals) {
            legend_method(ui, m);
        }
    });
    style::legend_row(ui, |ui| {
        ui.label(format!("settings in use ({mode}):"));
        for job in JobKind::SOLVED {
            if marks.iter().any(|(j, _)| *j == job) {
                markers::legend(ui, &[job_mark(job, ink)], job.label());
            }
        }
    });
}

/// Each method's measured curve: a line through its markers.
fn method_items(p: &mut egui_plot::PlotUi<'_>, rows: &[Row], y_evals: bool, lw: f32) {
    for (m, pts) in curves(rows, y_evals) {
        let c = style::method_color(m);
        let mut line = style::line(m, PlotPoints::from(pts.clone()))
            .color(c)
            .width(1.8 * lw);
        if m.starts_with("ode_solvers") {
            line = line.style(LineStyle::Dashed { length: 6.0 });
        }
        p.line(line);
        p.add(method_mark(m, lw).points(m, PlotPoints::from(pts)));
    }
}

/// A method's line and marker, and its name.
fn legend_method(ui: &mut Ui, method: &str) {
    let color = style::method_color(method);
    let k = style::key_scale(ui.ctx());
    style::keep_key_with_label(ui, 26.0 * k, method);
    let (rect, _) = ui.allocate_exact_size(egui::vec2(26.0, 14.0) * k, egui::Sense::hover());
    let y = rect.center().y;
    let stroke = egui::Stroke::new(2.0 * k, color);
    let p = ui.painter();
    if method.starts_with("ode_solvers") {
        for i in 0..3 {
            let x = rect.left() + i as f32 * 9.0 * k;
            p.line_segment([egui::pos2(x, y), egui::pos2(x + 5.0 * k, y)], stroke);
        }
    } else {
        p.line_segment([rect.left_center(), rect.right_center()], stroke);
    }
    markers::paint_key(ui, rect, &[method_mark(method, 1.0)]);
    ui.label(method);
}

/// A method's marker on its curve, at line scale `lw`.
fn method_mark(method: &str, lw: f32) -> Marker {
    Marker::new(
        style::method_marker(method),
        style::method_color(method),
        4.0 * lw,
        true,
    )
}

/// The ring marking a job's settings on the chart.
fn job_mark(job: JobKind, ink: Color32) -> Marker {
    Marker::new(job_marker(job), ink, 9.0, false)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_committed_chart_has_a_curve_per_method_and_marks_autos_settings() {
        let c = curves(default_rows(), false);
        let names: Vec<&str> = c.iter().map(|(m, _)| *m).collect();
        assert_eq!(
            names,
            [
                "euler",
                "rk4",
                "dp54",
                "dop853",
                "ode_solvers-dopri5",
                "ode_solvers-dop853"
            ]
        );
        // RK4 at h = 0.1 failed on 29 points: not on the curve.
        assert_eq!(c[1].1.len(), 6);
        let s = Settings::default();
        let marks = in_use(default_rows(), &s, true);
        // One mark per kind of job: trajectory, sweep, map iterates, phase.
        assert_eq!(marks.len(), 4);
        // The trajectory's DP5(4) tol 1e-5: 3.628e-5, 259.3 evaluations.
        let (job, [x, y]) = marks[0];
        assert_eq!(job, JobKind::Trajectory);
        assert!((x - 3.628e-5f64.log10()).abs() < 1e-12 && (y - 259.3f64.log10()).abs() < 1e-12);
    }

    #[test]
    fn every_method_has_its_own_colour_and_marker() {
        // Every method has its own colour and its own marker.
        let ms = [
            "euler",
            "rk4",
            "dp54",
            "dop853",
            "ode_solvers-dopri5",
            "ode_solvers-dop853",
        ];
        for (i, a) in ms.iter().enumerate() {
            for b in &ms[i + 1..] {
                assert_ne!(style::method_color(a), style::method_color(b), "{a} {b}");
                assert_ne!(style::method_marker(a), style::method_marker(b), "{a} {b}");
            }
        }
    }
}
