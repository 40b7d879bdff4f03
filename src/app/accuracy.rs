//! The side panel's accuracy section: the Auto / Custom switch (each job's
//! setting is [`JobKind::solver`]), and what the committed work-precision
//! chart says each job's setting costs and how accurate it is.

use eframe::egui;
use egui::{Color32, RichText, Ui};

use super::jobs::JobKind;
use super::settings::{AccuracyMode, Settings};
use crate::integrate::SolverSettings;
use crate::numerics::committed::default_rows;
use crate::numerics::{Estimate, Subject, estimate};

/// What the committed chart says of one job's setting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JobEstimate {
    pub job: JobKind,
    pub settings: SolverSettings,
    /// The largest map error its view can show.
    pub target: f64,
    /// `None`: the chart did not measure that method near that setting.
    pub estimate: Option<Estimate>,
}

impl JobEstimate {
    /// Whether the chart says the setting is coarser than the job's view.
    pub fn too_coarse(&self) -> bool {
        self.estimate
            .is_some_and(|e| !(e.max_error <= self.target) || e.failed > 0)
    }

    /// The panel's three short cells: "dop853 1e-5", "err 3e-5", "332 ev".
    pub fn cells(&self) -> [String; 3] {
        let subject = Subject::Own(self.settings);
        let (kind, value) = subject.setting();
        let kind = if kind == "step" { "h" } else { "" };
        let setting = format!("{} {kind}{value:e}", subject.method_name());
        match self.estimate {
            None => [setting, "not measured".into(), String::new()],
            Some(est) => {
                let approx = if est.measured { "" } else { "≈" };
                let failed = if est.failed > 0 { " fails" } else { "" };
                [
                    setting,
                    format!("err {approx}{:.0e}{failed}", est.max_error),
                    format!("{approx}{:.0} ev", est.evals),
                ]
            }
        }
    }

    /// One line: "dop853 tol 1e-5 · err ≤ 3.3e-5 · 332 evals · 24 µs".
    pub fn text(&self) -> String {
        let subject = Subject::Own(self.settings);
        let (kind, value) = subject.setting();
        let kind = if kind == "step" { "h" } else { kind };
        let setting = format!("{} {kind} {value:e}", subject.method_name());
        match self.estimate {
            None => format!("{setting} · not measured"),
            Some(e) => {
                let approx = if e.measured { "" } else { "≈ " };
                let failed = if e.failed > 0 {
                    format!(" · fails on {} chart points", e.failed)
                } else {
                    String::new()
                };
                format!(
                    "{setting} · err ≤ {approx}{:.1e} · {approx}{:.0} evals · {approx}{:.0} µs{failed}",
                    e.max_error, e.evals, e.us
                )
            }
        }
    }
}

/// Each job's setting under the current choice, with the chart's estimate.
pub fn job_estimates(s: &Settings) -> Vec<JobEstimate> {
    JobKind::SOLVED
        .into_iter()
        .filter_map(|job| {
            let settings = job.solver(s)?;
            Some(JobEstimate {
                job,
                settings,
                target: job.accuracy()?.target(),
                estimate: estimate(default_rows(), &settings),
            })
        })
        .collect()
}

/// The Auto / Custom switch.
pub fn mode_ui(ui: &mut Ui, s: &mut Settings) {
    ui.horizontal(|ui| {
        ui.label("accuracy");
        ui.selectable_value(&mut s.accuracy, AccuracyMode::Auto, "Auto")
            .on_hover_text(
                "Each job gets the cheapest setting that the measured work-precision chart \
                 says meets what its view can show (see the Numerics view).",
            );
        ui.selectable_value(&mut s.accuracy, AccuracyMode::Custom, "Custom")
            .on_hover_text("Every job runs with the method and tolerance (or step) you pick.");
    });
}

/// The estimates table: per job, its setting, the chart's max map error
/// and cost, one short row each so the side panel keeps its width (the full
/// line, with the µs, is the row's hover text). Red when Custom is coarser
/// than the job's view can show.
pub fn estimates_ui(ui: &mut Ui, s: &Settings) {
    // Scrolled sideways where the panel is narrower than the table (text
    // ×1.5 on a projector's 1024 points), rather than widening the panel.
    egui::ScrollArea::horizontal()
        .id_salt("accuracy_estimates")
        .show(ui, |ui| estimates_grid_ui(ui, s));
}

fn estimates_grid_ui(ui: &mut Ui, s: &Settings) {
    egui::Grid::new("accuracy_estimates")
        .num_columns(4)
        .spacing([8.0, 2.0])
        .show(ui, |ui| {
            for e in job_estimates(s) {
                let hover = format!(
                    "{}\n\n{}\n\nNeeds a map error ≤ {:e}. Estimates from the committed \
                     chart (65 points on 4 attractors: max error over the sample, RHS \
                     evaluations and µs per iterate; ≈ interpolated between two measured \
                     settings).",
                    e.job.hover(),
                    e.text(),
                    e.target
                );
                let red = e.too_coarse();
                let cell = |ui: &mut Ui, t: String| {
                    let mut text = RichText::new(t).small().monospace();
                    if red {
                        text = text.color(Color32::from_rgb(220, 30, 30));
                    }
                    ui.label(text).on_hover_text(&hover);
                };
                ui.label(e.job.short_label()).on_hover_text(&hover);
                for text in e.cells() {
                    cell(ui, text);
                }
                ui.end_row();
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::Method;

    #[test]
    fn autos_settings_are_measured_and_fine_enough() {
        let e = job_estimates(&Settings::default());
        assert_eq!(e.len(), 4);
        for e in e {
            assert!(!e.too_coarse(), "{e:?}");
            assert!(e.estimate.is_some_and(|x| x.measured));
        }
    }

    #[test]
    fn a_coarse_custom_setting_is_flagged_for_the_jobs_it_is_too_coarse_for() {
        let mut s = Settings {
            accuracy: AccuracyMode::Custom,
            method: Method::Rk4,
            step: 0.01,
            ..Settings::default()
        };
        // RK4 h = 0.01 is a chart row: 2.6e-6, 1505 evaluations; too coarse
        // for the map iterates (1e-10) and the phase diagram (1e-8) only.
        // (The µs are the committed chart's, which move with the host.)
        let e = job_estimates(&s);
        let us = crate::numerics::committed::default_rows()
            .iter()
            .find(|r| r.method == "rk4" && r.setting == 0.01)
            .expect("the chart's row")
            .median_us;
        assert_eq!(
            e[0].text(),
            format!("rk4 h 1e-2 · err ≤ 2.6e-6 · 1505 evals · {us:.0} µs")
        );
        let coarse: Vec<bool> = e.iter().map(JobEstimate::too_coarse).collect();
        assert_eq!(coarse, [false, false, true, true], "{e:?}");
        s.step = 1e-4;
        assert_eq!(job_estimates(&s)[0].text(), "rk4 h 1e-4 · not measured");
    }
}
