//! The commands run the window's jobs: `orbit` and `trajectory` print the
//! numbers the window's iterate and trajectory jobs send, bit for bit, and
//! `attractors` the return map's basin band.

use crate::cli_support::{assert_ok, oneblock, stdout};
use crate::common::fixture::preset;
use oneblock::jobs::{IterateOptions, IterateSpec, Spec, TrajectorySpec, Update, run_collect};
use oneblock::sim::{Period, default_settings};

/// Fig. 3b at θν = 1.25 (chaotic), as flags.
const FIG3B_CHAOS: [&str; 4] = ["--preset", "fig3b", "--theta-nu", "1.25"];

fn updates(spec: Spec) -> Vec<Update> {
    run_collect(spec, 1, |_| {}, || false).expect("the job runs")
}

#[test]
fn orbit_prints_the_window_iterate_jobs_orbit_bit_for_bit() {
    let mut args = vec!["orbit"];
    args.extend(FIG3B_CHAOS);
    args.extend([
        "--transient",
        "50",
        "--keep",
        "120",
        "--tol",
        "1e-9",
        "--json",
        "--out",
        "-",
    ]);
    // --json and --out - both on stdout are refused: the rows go to a file.
    let dir = tempfile::tempdir().expect("temp dir");
    let csv = dir.path().join("orbit.csv");
    let n = args.len();
    args[n - 1] = csv.to_str().expect("utf-8 path");
    let o = oneblock(&args);
    assert_ok(&o);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON summary");

    let params = preset("fig3b").with_theta_nu(1.25);
    let spec = IterateSpec {
        params,
        settings: default_settings(1e-9),
        theta0: None,
        transient: 50,
        keep: 120,
        graph_powers: 1,
        options: IterateOptions::default(),
    };
    let mut thetas = Vec::new();
    let mut last = None;
    for u in updates(spec.into()) {
        if let Update::MapIterates {
            thetas: t,
            period,
            lyapunov,
            ..
        } = u
        {
            thetas.extend(t);
            last = Some((period, lyapunov));
        }
    }
    let (period, lyapunov) = last.expect("iterates");
    assert_eq!(period, Period::Aperiodic);
    assert_eq!(v["period"], "aperiodic");
    assert_eq!(
        v["lyapunov"].as_f64().map(f64::to_bits),
        lyapunov.map(f64::to_bits),
        "the exponent, bit for bit"
    );
    let text = std::fs::read_to_string(&csv).expect("the CSV");
    let rows: Vec<f64> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| {
            l.split(',')
                .next()
                .and_then(|x| x.parse().ok())
                .expect("theta")
        })
        .collect();
    assert_eq!(rows.len(), 120);
    for (row, job) in rows.iter().zip(&thetas) {
        assert_eq!(row.to_bits(), job.to_bits(), "{row} vs {job}");
    }
}

#[test]
fn trajectory_prints_the_window_trajectory_jobs_path_bit_for_bit() {
    let mut args = vec!["trajectory"];
    args.extend(FIG3B_CHAOS);
    args.extend([
        "--tol",
        "1e-9",
        "--transient",
        "3",
        "--events",
        "2",
        "--spacing",
        "0.05",
    ]);
    let o = oneblock(&args);
    assert_ok(&o);
    let text = stdout(&o);
    let rows: Vec<Vec<f64>> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| {
            l.split(',')
                .take(5)
                .map(|x| x.parse().expect("number"))
                .collect()
        })
        .collect();

    let params = preset("fig3b").with_theta_nu(1.25);
    let spec = TrajectorySpec {
        params,
        settings: default_settings(1e-9),
        theta0: None,
        transient: 3,
        spacing: 0.05,
        cycles: Some(2),
        max_samples: None,
    };
    let samples: Vec<_> = updates(spec.into())
        .into_iter()
        .flat_map(|u| match u {
            Update::TrajectoryChunk { samples, .. } => samples,
            _ => Vec::new(),
        })
        .collect();
    assert!(samples.len() > 10, "{} samples", samples.len());
    assert_eq!(rows.len(), samples.len());
    for (row, s) in rows.iter().zip(&samples) {
        let job = [s.t, s.x, s.y, s.u, s.w];
        for (a, b) in row.iter().zip(job) {
            assert_eq!(a.to_bits(), b.to_bits(), "{row:?} vs {job:?}");
        }
    }
}
