//! The solver setting each kind of job runs with (its accuracy, hover and
//! marker are the job table's, `jobs::kinds`): "model no more than a scene
//! needs". **Auto** gives each job the cheapest setting that the measured
//! work-precision chart says meets the accuracy its view can show
//! ([`budget_for`]); **Custom** runs every job with the method and
//! tolerance (or step) the user picked.

use crate::integrate::SolverSettings;
use crate::numerics::budget_for;

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
