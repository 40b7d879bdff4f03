//! The committed work-precision chart (`assets/work-precision.csv`, read at
//! build time) as [`Row`]s, and what it says of a setting that is not one of
//! its rows.
//!
//! The app shows this chart until the user re-measures on the current
//! parameters, and reads its estimates (map error, RHS evaluations and µs per
//! iterate) for the setting each job runs with; [`super::budget::measured`]
//! takes its adaptive rows from here.

use std::sync::LazyLock;

use super::work_precision::{Row, Subject};
use crate::integrate::SolverSettings;

/// The committed chart's CSV text.
pub const DEFAULT_CSV: &str = include_str!("../../assets/work-precision.csv");

/// The methods a chart may name (a [`Row`] keeps its method as a static name).
const METHODS: [&str; 6] = [
    "euler",
    "rk4",
    "dp54",
    "dop853",
    "ode_solvers-dopri5",
    "ode_solvers-dop853",
];

/// Parses the CSV `oneblock work-precision --out` writes (comment lines
/// start with `#`; the failure messages are not in it).
pub fn parse_csv(text: &str) -> Result<Vec<Row>, String> {
    let mut rows = Vec::new();
    // Flexible: a header and the rows differ in length, and a row of the
    // wrong length is reported below with its line.
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .flexible(true)
        .from_reader(text.as_bytes());
    for record in reader.records() {
        let f = record.map_err(|e| format!("not CSV: {e}"))?;
        let n = f.position().map_or(0, |p| p.line());
        if f.get(0) == Some("method") || f.iter().all(str::is_empty) {
            continue;
        }
        let line = f.iter().collect::<Vec<_>>().join(",");
        let bad = |what: &str| format!("line {n}: {what}: {line}");
        if f.len() != 11 {
            return Err(bad("expected 11 fields"));
        }
        let f: Vec<&str> = f.iter().collect();
        let method = METHODS
            .iter()
            .copied()
            .find(|m| *m == f[0])
            .ok_or_else(|| bad("unknown method"))?;
        let kind = match f[1] {
            "tol" => "tol",
            "step" => "step",
            _ => return Err(bad("kind must be tol or step")),
        };
        let num = |i: usize| f[i].parse::<f64>().map_err(|_| bad("not a number"));
        let int = |i: usize| f[i].parse::<usize>().map_err(|_| bad("not a count"));
        let (points, failed) = (int(3)?, int(4)?);
        rows.push(Row {
            method,
            kind,
            setting: num(2)?,
            points,
            failed,
            failure: (failed > 0).then(|| format!("{failed} of {points} points failed")),
            max_error: num(5)?,
            median_error: num(6)?,
            max_stop_error: num(7)?,
            max_duration_error: num(8)?,
            median_us: num(9)?,
            evals_per_iterate: num(10)?,
        });
    }
    Ok(rows)
}

static DEFAULT_ROWS: LazyLock<Vec<Row>> =
    LazyLock::new(|| parse_csv(DEFAULT_CSV).unwrap_or_default());

/// The committed chart's rows (a unit test checks the file parses).
pub fn default_rows() -> &'static [Row] {
    &DEFAULT_ROWS
}

/// The committed chart's first comment line (sample, reference, load),
/// without the command's name.
pub fn default_caption() -> &'static str {
    DEFAULT_CSV
        .lines()
        .next()
        .and_then(|l| l.strip_prefix("# oneblock work-precision: "))
        .unwrap_or("")
}

/// What a chart says of one setting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// max |θ' − θ'_ref| over the chart's sample.
    pub max_error: f64,
    pub median_error: f64,
    /// RHS evaluations per iterate (the machine-independent cost).
    pub evals: f64,
    /// Median µs per iterate, as timed on the machine that made the chart.
    pub us: f64,
    /// Points of the sample where the setting (or a neighbour it is
    /// interpolated from) failed.
    pub failed: usize,
    /// A row of the chart (true), or interpolated between two (false).
    pub measured: bool,
}

impl Estimate {
    fn of(r: &Row) -> Self {
        Estimate {
            max_error: r.max_error,
            median_error: r.median_error,
            evals: r.evals_per_iterate,
            us: r.median_us,
            failed: r.failed,
            measured: true,
        }
    }
}

/// What `rows` say of `settings`: its row if the chart measured it, else a
/// log-log interpolation (in the tolerance or step) between the two
/// measured settings of the same method around it. `None` outside the
/// measured range or for a method the chart lacks: the chart cannot vouch
/// for a setting it never ran, and accuracy does not extrapolate safely
/// (RK4's max error levels off, DP5(4)'s grows faster than its tolerance).
pub fn estimate(rows: &[Row], settings: &SolverSettings) -> Option<Estimate> {
    let subject = Subject::Own(*settings);
    let (kind, x) = subject.setting();
    let name = subject.method_name();
    if !(x > 0.0 && x.is_finite()) {
        return None;
    }
    let mut curve: Vec<&Row> = rows
        .iter()
        .filter(|r| r.method == name && r.kind == kind && r.setting > 0.0)
        .collect();
    curve.sort_by(|a, b| a.setting.total_cmp(&b.setting));
    if let Some(r) = curve.iter().find(|r| ((r.setting - x) / x).abs() < 1e-9) {
        return Some(Estimate::of(r));
    }
    let (lo, hi) = curve
        .windows(2)
        .map(|w| (w[0], w[1]))
        .find(|(a, b)| a.setting < x && x < b.setting)?;
    let t = (x.ln() - lo.setting.ln()) / (hi.setting.ln() - lo.setting.ln());
    let lerp = |a: f64, b: f64| {
        if a > 0.0 && b > 0.0 {
            (a.ln() + t * (b.ln() - a.ln())).exp()
        } else {
            f64::NAN
        }
    };
    Some(Estimate {
        max_error: lerp(lo.max_error, hi.max_error),
        median_error: lerp(lo.median_error, hi.median_error),
        evals: lerp(lo.evals_per_iterate, hi.evals_per_iterate),
        us: lerp(lo.median_us, hi.median_us),
        failed: lo.failed.max(hi.failed),
        measured: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::Method;
    use crate::numerics::budget::measured;

    #[test]
    fn the_committed_chart_parses_with_every_method() {
        let rows = default_rows();
        assert_eq!(rows.len(), 57);
        for m in METHODS {
            assert!(rows.iter().any(|r| r.method == m), "{m}");
        }
        assert!(default_caption().starts_with("65 points on 4 attractor(s)"));
        // RK4 at h = 0.1 is the one setting where points failed.
        let failed: Vec<_> = rows.iter().filter(|r| r.failed > 0).collect();
        assert_eq!(failed.len(), 1);
        assert_eq!((failed[0].method, failed[0].setting), ("rk4", 0.1));
    }

    #[test]
    fn the_budget_table_is_the_charts_adaptive_rows() {
        // Both adaptive methods at every decade 1e-3 … 1e-13, and each
        // entry reads back through `estimate` as a measured row.
        let m = measured();
        assert_eq!(m.len(), 22);
        for method in [Method::Dp54, Method::Dop853] {
            let mut tols: Vec<f64> = m
                .iter()
                .filter(|e| e.method == method)
                .map(|e| e.tol)
                .collect();
            tols.sort_by(f64::total_cmp);
            let want: Vec<f64> = (3..=13).rev().map(|k| 10f64.powi(-k)).collect();
            assert_eq!(tols.len(), want.len(), "{method}");
            for (t, w) in tols.iter().zip(&want) {
                assert!((t / w - 1.0).abs() < 1e-12, "{method}: {t} vs {w}");
            }
        }
        for e in m {
            let est = estimate(default_rows(), &SolverSettings::adaptive(e.method, e.tol))
                .expect("measured");
            assert!(est.measured);
            assert_eq!((est.max_error, est.evals), (e.max_error, e.evals), "{e:?}");
        }
        // The figures docs/numerics.md quotes for DOP853 at 1e-10.
        let d = m
            .iter()
            .find(|e| e.method == Method::Dop853 && e.tol == 1e-10)
            .expect("row");
        assert_eq!((d.max_error, d.evals), (8.877e-11, 605.0));
    }

    #[test]
    fn a_setting_between_two_rows_is_interpolated_log_log() {
        let rows = default_rows();
        // DOP853 at tol 1e-9 and 1e-10: 6.505e-10 / 481.9 and 8.877e-11 / 605.0.
        let e = estimate(
            rows,
            &SolverSettings::adaptive(Method::Dop853, 10f64.powf(-9.5)),
        )
        .expect("inside the chart");
        assert!(!e.measured);
        assert!((e.max_error - (6.505e-10f64 * 8.877e-11).sqrt()).abs() < 1e-12);
        assert!((e.evals - (481.9f64 * 605.0).sqrt()).abs() < 1e-6);
        // Fixed steps by their step.
        let e = estimate(rows, &SolverSettings::fixed(Method::Euler, 1e-3)).expect("a row");
        assert!(e.measured && (e.evals - 2548.6).abs() < 1e-9);
        // RK4 between 0.1 (29 points failed) and 0.05 carries the failures.
        let e = estimate(rows, &SolverSettings::fixed(Method::Rk4, 0.07)).expect("inside");
        assert_eq!(e.failed, 29);
        // Outside the measured range: no estimate.
        assert!(estimate(rows, &SolverSettings::adaptive(Method::Dop853, 1e-14)).is_none());
        assert!(estimate(rows, &SolverSettings::fixed(Method::Euler, 1e-5)).is_none());
        assert!(estimate(rows, &SolverSettings::fixed(Method::Rk4, 0.5)).is_none());
    }

    #[test]
    fn bad_csv_is_an_error_naming_the_line() {
        let e = parse_csv("method,kind\nfoo,tol,1e-3,1,0,1,1,1,1,1,1\n").unwrap_err();
        assert!(e.starts_with("line 2: unknown method"), "{e}");
        assert!(parse_csv("dp54,tol,x,1,0,1,1,1,1,1,1").is_err());
        assert!(parse_csv("dp54,tol,1e-3").is_err());
    }
}
