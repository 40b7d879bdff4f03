//! The quick work-precision run the app's Numerics panel makes on the
//! current parameters: a handful of points of the current attractor instead
//! of the committed chart's 65, a short timing per setting, settings that
//! would take too long skipped, and a measurement made point by point so
//! that the worker can stop between any two iterates.

use std::time::Duration;

use super::sample::Attractor;
use super::work_precision::{Row, Subject, default_subjects};
use crate::model::Params;
use crate::sim::stats::median;

/// Orbit points of the current attractor a quick run measures on.
pub const QUICK_POINTS: usize = 12;
/// Most points a quick run accepts (its reference costs ~0.3 ms a point).
pub const MAX_QUICK_POINTS: usize = 64;
/// Transient of the reference orbit when it starts at θν (a start already
/// on the attractor, such as the app's last orbit point, needs less).
pub const QUICK_TRANSIENT: usize = 300;
/// Wall time each setting is timed for, over the whole sample.
pub const QUICK_TIME_PER_SETTING: Duration = Duration::from_millis(40);
/// A setting whose median iterate takes longer than this ends its method's
/// curve: the method's later settings (finer steps, tighter tolerances) are
/// more expensive still. Forward Euler below h = 1e-4 is the usual case
/// (2.5 ms an iterate at h = 1e-4 and 8.6 ms at 3e-5 in the committed chart).
pub const SLOW_ITERATE: Duration = Duration::from_millis(2);

/// The settings a quick run measures: the committed chart's, each method's
/// ordered from cheap to expensive (which [`SLOW_ITERATE`] relies on).
pub fn quick_subjects() -> Vec<Subject> {
    default_subjects()
}

/// The attractor of the current parameters, as a sample source.
pub fn current_attractor(params: Params, theta0: Option<f64>, transient: usize) -> Attractor {
    Attractor {
        name: "current",
        params,
        theta0: theta0.unwrap_or(params.theta_nu),
        transient,
        extra: None,
        fixed: None,
    }
}

/// The row of a whole sample from the rows of its points measured one at
/// a time (`measure(&[point], …)`): the same numbers `measure` gives for the
/// sample (the timings are of different runs, so they differ as any two
/// timings do). `None` for no rows.
pub fn combine(per_point: &[Row]) -> Option<Row> {
    let first = per_point.first()?;
    let ok: Vec<&Row> = per_point.iter().filter(|r| r.failed == 0).collect();
    let errs: Vec<f64> = ok.iter().map(|r| r.max_error).collect();
    let times: Vec<f64> = ok.iter().map(|r| r.median_us).collect();
    let max_of = |f: fn(&Row) -> f64| {
        if ok.is_empty() {
            f64::NAN
        } else {
            ok.iter().map(|r| f(r)).fold(0.0, f64::max)
        }
    };
    Some(Row {
        method: first.method,
        kind: first.kind,
        setting: first.setting,
        points: per_point.iter().map(|r| r.points).sum(),
        failed: per_point.iter().map(|r| r.failed).sum(),
        failure: per_point.iter().find_map(|r| r.failure.clone()),
        max_error: errs.iter().copied().fold(f64::NAN, f64::max),
        median_error: median(&errs),
        max_stop_error: max_of(|r| r.max_stop_error),
        max_duration_error: max_of(|r| r.max_duration_error),
        median_us: median(&times),
        evals_per_iterate: ok.iter().map(|r| r.evals_per_iterate).sum::<f64>()
            / ok.len().max(1) as f64,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::{Method, SolverSettings};
    use crate::numerics::sample::build_sample;
    use crate::numerics::work_precision::measure;

    #[test]
    fn point_by_point_rows_combine_to_the_whole_samples_row() {
        let p = Params {
            kappa: 18.95,
            gamma: 6.5,
            nu: 1e-3,
            theta_nu: 1.25,
            omega: 50.0,
        };
        let sample = build_sample(&[current_attractor(p, None, 100)], 5).expect("sample");
        for subject in [
            Subject::Own(SolverSettings::adaptive(Method::Dop853, 1e-6)),
            // Every point fails: h > 1/√κ.
            Subject::Own(SolverSettings::fixed(Method::Rk4, 0.9)),
        ] {
            let whole = measure(&sample, &subject, Duration::ZERO);
            let parts: Vec<Row> = sample
                .iter()
                .map(|sp| measure(std::slice::from_ref(sp), &subject, Duration::ZERO))
                .collect();
            let mut c = combine(&parts).expect("rows");
            assert!(c.median_us.is_nan() == whole.median_us.is_nan());
            c.median_us = whole.median_us;
            let same = |a: f64, b: f64| a == b || (a.is_nan() && b.is_nan());
            assert!(
                same(c.max_error, whole.max_error)
                    && same(c.median_error, whole.median_error)
                    && same(c.max_stop_error, whole.max_stop_error)
                    && same(c.max_duration_error, whole.max_duration_error)
                    && c.evals_per_iterate == whole.evals_per_iterate
                    && (c.points, c.failed, &c.failure)
                        == (whole.points, whole.failed, &whole.failure),
                "{c:?} vs {whole:?}"
            );
        }
        assert!(combine(&[]).is_none());
    }

    #[test]
    fn each_methods_settings_go_from_cheap_to_expensive() {
        let subjects = quick_subjects();
        for w in subjects.windows(2) {
            if w[0].method_name() == w[1].method_name() {
                // Smaller steps and tighter tolerances cost more.
                assert!(w[1].setting().1 < w[0].setting().1, "{w:?}");
            }
        }
    }
}
