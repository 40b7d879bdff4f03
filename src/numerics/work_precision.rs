//! The work-precision measurement: for one method and setting, the map error
//! over the sample against the reference, and the cost per iterate.

use std::time::Duration;
use web_time::Instant;

use serde::Serialize;

use super::peer::{Peer, PeerMethod};
use super::sample::{Iterate, SamplePoint};
use crate::integrate::{Method, SolverSettings};
use crate::model::wrap_angle;
use crate::sim::Simulator;
use crate::sim::stats::median;

/// What is measured: one of our settings, or the peer at a tolerance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Subject {
    Own(SolverSettings),
    Peer(PeerMethod, f64),
}

impl Subject {
    /// The curve this setting belongs to.
    pub fn method_name(&self) -> &'static str {
        match self {
            Subject::Own(s) => match s.method {
                Method::Dp54 => "dp54",
                Method::Dop853 => "dop853",
                Method::Rk4 => "rk4",
                Method::Euler => "euler",
            },
            Subject::Peer(m, _) => m.name(),
        }
    }

    /// "tol" or "step", and its value.
    pub fn setting(&self) -> (&'static str, f64) {
        match self {
            Subject::Own(s) if s.method.is_adaptive() => ("tol", s.rtol),
            Subject::Own(s) => ("step", s.step),
            Subject::Peer(_, tol) => ("tol", *tol),
        }
    }

    fn iterate(&self, sp: &SamplePoint) -> Result<Iterate, String> {
        match self {
            Subject::Own(s) => {
                let sim = Simulator::new(sp.params, *s).map_err(|e| e.to_string())?;
                sim.cycle(sp.theta, 0.0, None)
                    .map(|e| Iterate::from(&e))
                    .map_err(|e| e.to_string())
            }
            Subject::Peer(m, tol) => Peer::new(*m, *tol)
                .cycle(&sp.params, sp.theta)
                .map_err(|e| e.to_string()),
        }
    }
}

/// The settings of the default chart: Euler and RK4 over fixed steps,
/// DP5(4), DOP853 and the peer's Dopri5 and Dop853 over tol 1e-3 … 1e-13.
pub fn default_subjects() -> Vec<Subject> {
    let mut v = Vec::new();
    for h in [1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5] {
        v.push(Subject::Own(SolverSettings {
            max_steps: 5_000_000,
            ..SolverSettings::fixed(Method::Euler, h)
        }));
    }
    for h in [0.1, 0.05, 0.02, 0.01, 5e-3, 2e-3, 1e-3] {
        v.push(Subject::Own(SolverSettings {
            max_steps: 5_000_000,
            ..SolverSettings::fixed(Method::Rk4, h)
        }));
    }
    let tols: Vec<f64> = (3..=13).map(|k| 10f64.powi(-k)).collect();
    for m in [Method::Dp54, Method::Dop853] {
        for &tol in &tols {
            v.push(Subject::Own(SolverSettings {
                max_steps: 2_000_000,
                ..SolverSettings::adaptive(m, tol)
            }));
        }
    }
    for m in [PeerMethod::Dopri5, PeerMethod::Dop853] {
        for &tol in &tols {
            v.push(Subject::Peer(m, tol));
        }
    }
    v
}

/// One row of the chart's table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    pub method: &'static str,
    /// "tol" or "step".
    pub kind: &'static str,
    pub setting: f64,
    pub points: usize,
    /// Points where the method returned an error instead of a number.
    pub failed: usize,
    /// The first failure's message.
    pub failure: Option<String>,
    /// max and median |θ' − θ'_ref| over the points that succeeded.
    pub max_error: f64,
    pub median_error: f64,
    /// max |stop − stop_ref| (Euclidean, in x and y).
    pub max_stop_error: f64,
    /// max |slip duration − its reference|.
    pub max_duration_error: f64,
    /// Median over the points of the wall time of one iterate, in µs.
    pub median_us: f64,
    /// Mean right-hand-side evaluations per iterate.
    pub evals_per_iterate: f64,
}

/// Measures one setting on the sample. Each point is timed over repeated
/// runs lasting at least `min_time` (at least one run).
pub fn measure(sample: &[SamplePoint], subject: &Subject, min_time: Duration) -> Row {
    let (kind, setting) = subject.setting();
    let mut errs = Vec::new();
    let mut times = Vec::new();
    let (mut stop_err, mut dur_err) = (0.0f64, 0.0f64);
    let mut evals = 0u64;
    let mut failed = 0;
    let mut failure = None;
    for sp in sample {
        let start = Instant::now();
        let first = subject.iterate(sp);
        let mut elapsed = start.elapsed();
        let it = match first {
            Ok(it) => it,
            Err(e) => {
                failed += 1;
                failure.get_or_insert(e);
                continue;
            }
        };
        let mut runs = 1u32;
        if elapsed < min_time {
            let more = ((min_time.as_secs_f64() / elapsed.as_secs_f64().max(1e-9)).ceil() as u32)
                .clamp(1, 10_000);
            let start = Instant::now();
            for _ in 0..more {
                std::hint::black_box(subject.iterate(std::hint::black_box(sp))).ok();
            }
            elapsed = start.elapsed();
            runs = more;
        }
        times.push(elapsed.as_secs_f64() * 1e6 / runs as f64);
        let r = &sp.reference;
        errs.push(wrap_angle(it.theta_next - r.theta_next).abs());
        stop_err = stop_err.max((it.stop[0] - r.stop[0]).hypot(it.stop[1] - r.stop[1]));
        dur_err = dur_err.max((it.slip_duration - r.slip_duration).abs());
        evals += it.rhs_evals;
    }
    let ok = errs.len();
    let max_error = errs.iter().copied().fold(f64::NAN, f64::max);
    Row {
        method: subject.method_name(),
        kind,
        setting,
        points: sample.len(),
        failed,
        failure,
        max_error,
        median_error: median(&errs),
        max_stop_error: if ok > 0 { stop_err } else { f64::NAN },
        max_duration_error: if ok > 0 { dur_err } else { f64::NAN },
        median_us: median(&times),
        evals_per_iterate: evals as f64 / ok.max(1) as f64,
    }
}

/// The CSV header of [`Row`]s.
pub const CSV_HEADER: &str = "method,kind,setting,points,failed,max_error,median_error,max_stop_error,max_duration_error,median_us_per_iterate,rhs_evals_per_iterate";

/// A measured number as the CSV writes it: empty when there is none (every
/// point of the setting failed), never "NaN".
fn field(v: f64, exp: bool, decimals: usize) -> String {
    if !v.is_finite() {
        String::new()
    } else if exp {
        format!("{v:.decimals$e}")
    } else {
        format!("{v:.decimals$}")
    }
}

impl Row {
    /// Whether every point failed: the row then has no measurement.
    pub fn all_failed(&self) -> bool {
        self.failed >= self.points
    }

    /// One CSV line (no newline); the failure message is left to the
    /// summary. A setting whose every point failed has its `failed` column
    /// equal to `points` and its measured columns empty, never NaN.
    pub fn csv(&self) -> String {
        let none = self.all_failed();
        let m = |v: f64, exp: bool, d: usize| {
            if none {
                String::new()
            } else {
                field(v, exp, d)
            }
        };
        format!(
            "{},{},{:e},{},{},{},{},{},{},{},{}",
            self.method,
            self.kind,
            self.setting,
            self.points,
            self.failed,
            m(self.max_error, true, 3),
            m(self.median_error, true, 3),
            m(self.max_stop_error, true, 3),
            m(self.max_duration_error, true, 3),
            m(self.median_us, false, 4),
            m(self.evals_per_iterate, false, 1)
        )
    }
}
