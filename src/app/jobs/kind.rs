//! The kinds of job the window runs, where each one's results are shown,
//! and the solver setting each runs with: "model no more than a scene
//! needs". **Auto** gives each job the cheapest setting that the measured
//! work-precision chart says meets the accuracy its view can show
//! ([`budget_for`]); **Custom** runs every job with the method and
//! tolerance (or step) the user picked.

use crate::integrate::SolverSettings;
use crate::numerics::{Accuracy, budget_for};

use super::super::settings::{AccuracyMode, Settings};

/// The kinds of job, from the job model: here, what the window shows of
/// each and the accuracy it runs with.
pub use crate::jobs::Kind as JobKind;

impl JobKind {
    /// The jobs that integrate with one solver setting (the side panel's
    /// accuracy table), in its order.
    pub const SOLVED: [JobKind; 4] = [
        JobKind::Trajectory,
        JobKind::Sweep,
        JobKind::Iterate,
        JobKind::Phase,
    ];

    /// The accuracy its view can show: a pixel of the (x, y) view; 1e-3 of
    /// the diagram's θ range per pixel; 1e-10 for the map; 1e-8 for the
    /// phase diagram's classes; the command line's 1e-10 for continuation
    /// (its points are located to 1e-10). `None` for the work-precision job
    /// and the Events view's (at dop853 1e-8 always: `events_settings`).
    pub fn accuracy(self) -> Option<Accuracy> {
        match self {
            JobKind::Trajectory => Some(Accuracy::TrajectoryView),
            JobKind::Sweep => Some(Accuracy::BifurcationDiagram),
            JobKind::Iterate | JobKind::Basins | JobKind::MapBasins => Some(Accuracy::ReturnMap),
            JobKind::Phase => Some(Accuracy::PhaseDiagram),
            JobKind::Branches | JobKind::Curves => Some(Accuracy::CommandLine),
            JobKind::Numerics | JobKind::Passage | JobKind::Scan => None,
        }
    }

    /// The solver setting it runs with: Auto's choice from the measured
    /// chart, or the user's Custom method and tolerance/step. `None` for
    /// the work-precision job.
    pub fn solver(self, s: &Settings) -> Option<SolverSettings> {
        let accuracy = self.accuracy()?;
        Some(match s.accuracy {
            AccuracyMode::Auto => budget_for(accuracy.target()).settings,
            AccuracyMode::Custom => s.custom_solver(),
        })
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
            JobKind::Numerics => {
                "The Numerics view's measurement runs every method against a \
                 reference at tol 1e-14."
            }
            JobKind::Branches | JobKind::Curves => {
                "Continuation locates doublings and folds to 1e-10 in the \
                 parameter: the command line's accuracy, 1e-10."
            }
            JobKind::Basins | JobKind::MapBasins => {
                "Attractors and basins from f's verified interpolant over the exit \
                 arc (a cell graph): the map at 1e-10, as `oneblock attractors`."
            }
            JobKind::Passage | JobKind::Scan => {
                "The Events view's channel passage and tangency scan evaluate \
                 the map at dop853, tol 1e-8: slip onsets to about 1e-8."
            }
        }
    }
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
            assert_eq!(job.accuracy().map(|a| a.target()), Some(target));
            assert_eq!(job.solver(&s), Some(budget_for(target).settings));
        }
        assert_eq!(JobKind::Numerics.solver(&s), None);
        // The numbers docs/gui.md quotes.
        let got: Vec<(Method, f64)> = JobKind::SOLVED
            .iter()
            .filter_map(|&j| j.solver(&s))
            .map(|x| (x.method, x.rtol))
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
    }

    #[test]
    fn custom_passes_the_method_and_tolerance_or_step_through() {
        let mut s = Settings {
            accuracy: AccuracyMode::Custom,
            method: Method::Dp54,
            tol: 3e-7,
            ..Settings::default()
        };
        for job in JobKind::SOLVED {
            assert_eq!(
                job.solver(&s),
                Some(SolverSettings::adaptive(Method::Dp54, 3e-7))
            );
        }
        s.method = Method::Rk4;
        s.step = 0.01;
        for job in JobKind::SOLVED {
            assert_eq!(
                job.solver(&s),
                Some(SolverSettings::fixed(Method::Rk4, 0.01))
            );
        }
    }
}
