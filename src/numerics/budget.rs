//! "Model no more than a scene needs": each consumer states the accuracy it
//! can show, and gets the cheapest setting that the measured work-precision
//! chart says meets it.
//!
//! The table is the adaptive rows of `assets/work-precision.csv` (65 points
//! in three regimes, max error over the sample, RHS evaluations per iterate
//! as the machine-independent cost); `oneblock work-precision` re-measures
//! it, and `docs/numerics.md` explains the choices.

use std::sync::LazyLock;

use super::committed::default_rows;
use crate::integrate::{Method, SolverSettings};

/// One measured setting of the chart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measured {
    pub method: Method,
    pub tol: f64,
    /// max |θ' − θ'_ref| over the sample.
    pub max_error: f64,
    /// median |θ' − θ'_ref| over the sample.
    pub median_error: f64,
    /// Mean right-hand-side evaluations per iterate.
    pub evals: f64,
    /// Median wall time per iterate, µs (on a loaded 2-core machine; see
    /// the chart's CSV header for the load).
    pub us: f64,
}

/// The adaptive rows (DP5(4) and DOP853, by tolerance) of the committed
/// chart, `assets/work-precision.csv`, read from the same parsed rows the
/// app's Numerics view shows: one source for the numbers.
pub fn measured() -> &'static [Measured] {
    static TABLE: LazyLock<Vec<Measured>> = LazyLock::new(|| {
        default_rows()
            .iter()
            .filter(|r| r.kind == "tol" && r.failed == 0)
            .filter_map(|r| {
                let method = match r.method {
                    "dp54" => Method::Dp54,
                    "dop853" => Method::Dop853,
                    _ => return None,
                };
                Some(Measured {
                    method,
                    tol: r.setting,
                    max_error: r.max_error,
                    median_error: r.median_error,
                    evals: r.evals_per_iterate,
                    us: r.median_us,
                })
            })
            .collect()
    });
    &TABLE
}

/// What a consumer can show.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Accuracy {
    /// The (x, y) view: about a pixel, 1e-4 of the ellipse.
    TrajectoryView,
    /// The bifurcation diagram: about 1e-3 of its θ range per pixel. The
    /// cheaper setting must not change the attractor: `tests/work_precision.rs`
    /// checks period and Lyapunov sign against tol 1e-12.
    BifurcationDiagram,
    /// The return map: 1e-10.
    ReturnMap,
    /// The phase diagram: its classes rest on the period test at 1e4·tol
    /// and on the Lyapunov exponent's sign, so the map error must sit well
    /// below the period tolerance (1e-5 at tol 1e-9): 1e-8.
    PhaseDiagram,
    /// The command line's default: 1e-10.
    CommandLine,
    /// A map error the user asks for.
    Custom(f64),
}

impl Accuracy {
    /// The largest map error |θ' − θ'_exact| the consumer accepts.
    pub fn target(self) -> f64 {
        match self {
            Accuracy::TrajectoryView => 1e-4,
            Accuracy::BifurcationDiagram => 1e-3,
            Accuracy::PhaseDiagram => 1e-8,
            Accuracy::ReturnMap | Accuracy::CommandLine => 1e-10,
            Accuracy::Custom(e) => e,
        }
    }
}

/// The setting chosen for an accuracy, with what the chart says of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget {
    pub settings: SolverSettings,
    /// The measured max map error of that setting over the sample.
    pub est_error: f64,
    /// RHS evaluations per iterate (machine-independent).
    pub est_evals: f64,
    /// Median µs per iterate, as measured with the chart.
    pub est_us: f64,
}

/// The cheapest measured setting (fewest RHS evaluations per iterate) whose
/// max map error over the sample is at most `accuracy`; the most accurate
/// one when none is (or when `accuracy` is not a positive number).
pub fn budget_for(accuracy: f64) -> Budget {
    let fits = measured()
        .iter()
        .filter(|e| e.max_error <= accuracy)
        .min_by(|a, b| a.evals.total_cmp(&b.evals));
    let best = measured()
        .iter()
        .min_by(|a, b| a.max_error.total_cmp(&b.max_error));
    let e = fits
        .or(best)
        .copied()
        // Only if the committed chart had no adaptive row: the command
        // line's default.
        .unwrap_or(Measured {
            method: Method::Dop853,
            tol: 1e-10,
            max_error: f64::NAN,
            median_error: f64::NAN,
            evals: f64::NAN,
            us: f64::NAN,
        });
    Budget {
        settings: SolverSettings::adaptive(e.method, e.tol),
        est_error: e.max_error,
        est_evals: e.evals,
        est_us: e.us,
    }
}

/// [`budget_for`] as a tuple: (settings, estimated max map error, estimated
/// cost in RHS evaluations per iterate).
pub fn settings_for(accuracy: f64) -> (SolverSettings, f64, f64) {
    let b = budget_for(accuracy);
    (b.settings, b.est_error, b.est_evals)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tighter_accuracy_never_costs_less() {
        let mut last = 0.0;
        for k in 2..=13 {
            let b = budget_for(10f64.powi(-k));
            assert!(b.est_evals >= last, "1e-{k}: {b:?}");
            last = b.est_evals;
            if k <= 12 {
                assert!(b.est_error <= 10f64.powi(-k), "1e-{k}: {b:?}");
            }
        }
    }

    #[test]
    fn impossible_accuracy_gets_the_most_accurate_setting() {
        let b = budget_for(1e-20);
        let best = measured()
            .iter()
            .map(|e| e.max_error)
            .fold(f64::MAX, f64::min);
        assert_eq!(b.est_error, best);
        assert_eq!(budget_for(f64::NAN).est_error, best);
    }
}
