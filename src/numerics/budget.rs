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
    m(Method::Dp54, 1e-3, 5.202e-1, 1.270e-3, 94.6, 25.9),
    m(Method::Dp54, 1e-4, 1.774e-3, 2.994e-5, 246.5, 54.9),
    m(Method::Dp54, 1e-5, 9.520e-5, 6.392e-6, 305.0, 56.2),
    m(Method::Dp54, 1e-6, 1.864e-6, 2.177e-7, 454.2, 70.3),
    m(Method::Dp54, 1e-7, 6.098e-7, 2.272e-8, 641.6, 88.0),
    m(Method::Dp54, 1e-8, 1.510e-7, 3.525e-9, 897.5, 154.3),
    m(Method::Dp54, 1e-9, 2.853e-8, 5.396e-10, 1267.3, 208.2),
    m(Method::Dp54, 1e-10, 4.407e-9, 7.663e-11, 1836.7, 204.5),
    m(Method::Dp54, 1e-11, 6.168e-10, 1.184e-11, 2750.0, 696.2),
    m(Method::Dp54, 1e-12, 7.944e-11, 1.374e-12, 4218.6, 919.5),
    m(Method::Dp54, 1e-13, 9.832e-12, 1.367e-13, 6559.5, 1588.1),
    m(Method::Dop853, 1e-3, 3.767e-3, 5.599e-4, 174.3, 49.3),
    m(Method::Dop853, 1e-4, 1.551e-4, 2.937e-5, 306.5, 58.3),
    m(Method::Dop853, 1e-5, 3.665e-5, 1.907e-6, 331.7, 70.0),
    m(Method::Dop853, 1e-6, 1.792e-6, 9.256e-8, 437.5, 75.3),
    m(Method::Dop853, 1e-7, 3.797e-7, 1.203e-8, 547.8, 85.9),
    m(Method::Dop853, 1e-8, 2.042e-8, 6.036e-10, 700.8, 98.9),
    m(Method::Dop853, 1e-9, 1.472e-8, 1.178e-10, 895.4, 134.9),
    m(Method::Dop853, 1e-10, 2.239e-10, 7.730e-12, 1119.4, 190.2),
    m(Method::Dop853, 1e-11, 3.140e-11, 5.165e-13, 1480.0, 196.4),
    m(Method::Dop853, 1e-12, 4.186e-12, 9.848e-14, 2008.0, 289.9),
    m(Method::Dop853, 1e-13, 3.981e-13, 8.271e-15, 2657.8, 373.7),
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
