//! "Model no more than a scene needs": each consumer states the accuracy it
//! can show, and gets the cheapest setting that the measured work-precision
//! chart says meets it.
//!
//! The table is the adaptive rows of `assets/work-precision.csv` (65 points
//! in three regimes, max error over the sample, RHS evaluations per iterate
//! as the machine-independent cost); `oneblock work-precision` re-measures
//! it, and `docs/numerics.md` explains the choices.

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

const fn m(
    method: Method,
    tol: f64,
    max_error: f64,
    median_error: f64,
    evals: f64,
    us: f64,
) -> Measured {
    Measured {
        method,
        tol,
        max_error,
        median_error,
        evals,
        us,
    }
}

/// The adaptive rows of the default chart (`assets/work-precision.csv`).
#[rustfmt::skip]
pub const MEASURED: &[Measured] = &[
    // method, tol, max error, median error, RHS evaluations, µs per iterate
    m(Method::Dp54, 1e-3, 5.081e-1, 1.236e-3, 96.6, 11.2),
    m(Method::Dp54, 1e-4, 2.166e-3, 2.203e-4, 132.3, 15.4),
    m(Method::Dp54, 1e-5, 1.082e-4, 1.585e-5, 298.2, 23.7),
    m(Method::Dp54, 1e-6, 1.574e-6, 2.083e-7, 443.4, 33.9),
    m(Method::Dp54, 1e-7, 4.927e-7, 2.022e-8, 620.9, 47.3),
    m(Method::Dp54, 1e-8, 1.313e-7, 3.053e-9, 865.2, 67.6),
    m(Method::Dp54, 1e-9, 2.469e-8, 5.093e-10, 1214.6, 100.1),
    m(Method::Dp54, 1e-10, 3.845e-9, 6.669e-11, 1747.2, 149.9),
    m(Method::Dp54, 1e-11, 5.281e-10, 1.203e-11, 2611.1, 223.6),
    m(Method::Dp54, 1e-12, 6.654e-11, 1.322e-12, 3995.0, 331.0),
    m(Method::Dp54, 1e-13, 7.872e-12, 1.304e-13, 6198.9, 490.5),
    m(Method::Dop853, 1e-3, 9.479e-3, 5.338e-4, 167.6, 19.4),
    m(Method::Dop853, 1e-4, 1.260e-3, 4.444e-5, 307.7, 22.9),
    m(Method::Dop853, 1e-5, 3.254e-5, 2.106e-6, 331.5, 23.9),
    m(Method::Dop853, 1e-6, 2.469e-6, 1.252e-7, 433.1, 27.3),
    m(Method::Dop853, 1e-7, 3.875e-7, 1.239e-8, 543.1, 31.9),
    m(Method::Dop853, 1e-8, 1.608e-8, 4.311e-10, 691.4, 38.4),
    m(Method::Dop853, 1e-9, 3.895e-9, 1.124e-10, 879.6, 48.3),
    m(Method::Dop853, 1e-10, 2.426e-10, 1.235e-11, 1095.9, 58.3),
    m(Method::Dop853, 1e-11, 2.813e-11, 1.065e-12, 1442.3, 73.2),
    m(Method::Dop853, 1e-12, 3.735e-12, 8.243e-14, 1954.4, 94.4),
    m(Method::Dop853, 1e-13, 6.661e-13, 5.329e-15, 2574.9, 132.5),
];

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
    let fits = MEASURED
        .iter()
        .filter(|e| e.max_error <= accuracy)
        .min_by(|a, b| a.evals.total_cmp(&b.evals));
    let best = MEASURED
        .iter()
        .min_by(|a, b| a.max_error.total_cmp(&b.max_error));
    let e = fits
        .or(best)
        .copied()
        .unwrap_or(m(Method::Dop853, 1e-10, 1e-9, 1e-11, 1100.0, 60.0));
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
        let best = MEASURED
            .iter()
            .map(|e| e.max_error)
            .fold(f64::MAX, f64::min);
        assert_eq!(b.est_error, best);
        assert_eq!(budget_for(f64::NAN).est_error, best);
    }
}
