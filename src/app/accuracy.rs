//! "Model no more than a scene needs": which solver setting each kind of job
//! runs with. **Auto** gives each job the cheapest setting that the measured
//! work-precision chart says meets the accuracy its view can show
//! ([`numerics::budget_for`]); **Custom** runs every job with the method and
//! tolerance (or step) the user picked. Next to the choice, the panel shows
//! what the committed chart says each job's setting costs and how accurate
//! it is.

use eframe::egui;
use egui::{Color32, RichText, Ui};
use serde::{Deserialize, Serialize};

use super::settings::Settings;
use crate::integrate::SolverSettings;
use crate::numerics::committed::default_rows;
use crate::numerics::{Accuracy, Estimate, Subject, budget_for, estimate};

/// How the jobs' solver settings are chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum AccuracyMode {
    /// Each job gets the cheapest setting meeting its view's accuracy.
    #[default]
    Auto,
    /// Every job runs with the method and tolerance/step of the controls.
    Custom,
}

/// The kinds of job the window runs, by what their results are shown in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum JobKind {
    /// The trajectory: the plane, the block and the event catalogue.
    Trajectory,
    /// The bifurcation sweep.
    Sweep,
    /// Map iterates: the return map, the period and the Lyapunov exponent.
    Iterate,
    /// The phase diagram's cells.
    Phase,
}

impl JobKind {
    pub const ALL: [JobKind; 4] = [
        JobKind::Trajectory,
        JobKind::Sweep,
        JobKind::Iterate,
        JobKind::Phase,
    ];

    /// The accuracy its view can show (issue 5): a pixel of the (x, y)
    /// view; 1e-3 of the diagram's θ range per pixel; 1e-10 for the map.
    pub fn accuracy(self) -> Accuracy {
        match self {
            JobKind::Trajectory => Accuracy::TrajectoryView,
            JobKind::Sweep => Accuracy::BifurcationDiagram,
            JobKind::Iterate => Accuracy::ReturnMap,
            JobKind::Phase => Accuracy::PhaseDiagram,
        }
    }

    /// A short name for the panel.
    pub fn label(self) -> &'static str {
        match self {
            JobKind::Trajectory => "trajectory",
            JobKind::Sweep => "diagram",
            JobKind::Iterate => "map iterates",
            JobKind::Phase => "phase diagram",
        }
    }

    /// A one-word name for the side panel's table.
    pub fn short_label(self) -> &'static str {
        match self {
            JobKind::Trajectory => "path",
            JobKind::Sweep => "diagram",
            JobKind::Iterate => "map",
            JobKind::Phase => "phase",
        }
    }

    /// What it feeds and why it needs that accuracy.
    pub fn hover(self) -> &'static str {
        match self {
            JobKind::Trajectory => {
                "The trajectory feeds the plane, the block and the event catalogue: \
                 a map error of 1e-4 is about a pixel of the (x, y) view."
            }
            JobKind::Sweep => {
                "The bifurcation sweep: 1e-3 of its θ range is about a pixel. \
                 tests/work_precision.rs checks that this setting keeps every preset's \
                 period and Lyapunov sign as at tol 1e-12."
            }
            JobKind::Iterate => {
                "The map iterates feed the return map, the period and the Lyapunov \
                 exponent: 1e-10, as the command line."
            }
            JobKind::Phase => {
                "The phase diagram's cells: a class rests on the period test at \
                 1e4·tol and on the Lyapunov sign, so the map error must stay well \
                 below the period tolerance: 1e-8."
            }
        }
    }
}

impl Settings {
    /// The solver setting a `job` runs with: Auto's choice from the measured
    /// chart, or the user's Custom method and tolerance/step.
    pub fn solver_for(&self, job: JobKind) -> SolverSettings {
        match self.accuracy {
            AccuracyMode::Auto => budget_for(job.accuracy().target()).settings,
            AccuracyMode::Custom => self.custom_solver(),
        }
    }
}

/// What the committed chart says of one job's setting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JobEstimate {
    pub job: JobKind,
    pub settings: SolverSettings,
    /// `None`: the chart did not measure that method near that setting.
    pub estimate: Option<Estimate>,
}

impl JobEstimate {
    /// Whether the chart says the setting is coarser than the job's view.
    pub fn too_coarse(&self) -> bool {
        self.estimate
            .is_some_and(|e| !(e.max_error <= self.job.accuracy().target()) || e.failed > 0)
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
pub fn job_estimates(s: &Settings) -> [JobEstimate; 4] {
    JobKind::ALL.map(|job| {
        let settings = s.solver_for(job);
        JobEstimate {
            job,
            settings,
            estimate: estimate(default_rows(), &settings),
        }
    })
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
                    e.job.accuracy().target()
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
    fn auto_gives_each_job_what_the_budget_says() {
        let s = Settings::default();
        assert_eq!(s.accuracy, AccuracyMode::Auto);
        for (job, target) in [
            (JobKind::Trajectory, 1e-4),
            (JobKind::Sweep, 1e-3),
            (JobKind::Iterate, 1e-10),
            (JobKind::Phase, 1e-8),
        ] {
            assert_eq!(job.accuracy().target(), target);
            assert_eq!(s.solver_for(job), budget_for(target).settings);
        }
        // The numbers docs/numerics.md quotes.
        let got: Vec<(Method, f64)> = JobKind::ALL
            .iter()
            .map(|&j| {
                let x = s.solver_for(j);
                (x.method, x.rtol)
            })
            .collect();
        assert_eq!(
            got,
            [
                (Method::Dp54, 1e-5),
                (Method::Dp54, 1e-4),
                (Method::Dop853, 1e-10),
                (Method::Dop853, 1e-8)
            ]
        );
        for e in job_estimates(&s) {
            assert!(!e.too_coarse(), "{e:?}");
            assert!(e.estimate.is_some_and(|x| x.measured));
        }
    }

    #[test]
    fn custom_passes_the_method_and_tolerance_or_step_through() {
        let mut s = Settings {
            accuracy: AccuracyMode::Custom,
            method: Method::Dp54,
            tol: 3e-7,
            ..Settings::default()
        };
        for job in JobKind::ALL {
            assert_eq!(
                s.solver_for(job),
                SolverSettings::adaptive(Method::Dp54, 3e-7)
            );
        }
        s.method = Method::Rk4;
        s.step = 0.01;
        for job in JobKind::ALL {
            assert_eq!(s.solver_for(job), SolverSettings::fixed(Method::Rk4, 0.01));
        }
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
        assert_eq!(
            e.map(|x| x.too_coarse()),
            [false, false, true, true],
            "{e:?}"
        );
        s.step = 1e-4;
        assert_eq!(job_estimates(&s)[0].text(), "rk4 h 1e-4 · not measured");
    }
}
