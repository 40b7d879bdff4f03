//! `oneblock orbit` without a CSV keeps only what its summary needs
//! (issue 56): before, every kept event and every ln|f'| was held, and the
//! λ error bar was recomputed over all of them at every progress batch, so
//! 10⁶ kept iterates took 2.2 s and 157 MB. The summary must not change:
//! with or without a CSV it is the same, and the exponent and its error
//! bar of the 10⁵ orbit are within the error bar the code gave
//! before the change. (The peak memory of 10⁶ iterates is checked by
//! tests/orbit_memory.rs, in a process of its own.)

#![allow(clippy::unwrap_used)]

use crate::cli_support::*;

/// The orbit: Fig. 3b's chaos from θ0 = 0.4.
const CHAOS: [&str; 12] = [
    "orbit",
    "--kappa",
    "18.95",
    "--gamma",
    "6.5",
    "--nu",
    "1e-3",
    "--theta-nu",
    "1.25",
    "--theta0",
    "0.4",
    "--json",
];

/// The JSON summary of `orbit` with `more` flags, its timing dropped.
fn summary(base: &[&str], more: &[&str]) -> serde_json::Value {
    let o = run(&with(base, more));
    assert_ok(&o);
    let mut v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    v.as_object_mut().unwrap().remove("seconds");
    v
}

#[test]
fn the_summary_is_the_same_with_or_without_the_csv() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("o.csv");
    let csv = csv.to_str().unwrap();
    // Chaos on the interpolant and integrated, and a fixed point solved.
    let cases: [&[&str]; 3] = [
        &[
            "--transient",
            "500",
            "--keep",
            "30000",
            "--theta-nu",
            "1.25",
        ],
        &[
            "--transient",
            "100",
            "--keep",
            "2000",
            "--theta-nu",
            "1.25",
            "--map",
            "direct",
        ],
        &["--transient", "100", "--keep", "500", "--theta-nu", "1.0"],
    ];
    let fig3b = ["orbit", "--preset", "fig3b", "--json"];
    for flags in cases {
        let alone = summary(&fig3b, flags);
        let with_csv = summary(&fig3b, &[flags, &["--out", csv, "--force"]].concat());
        assert_eq!(alone, with_csv, "{flags:?}");
        let keep: u64 = flags[3].parse().unwrap();
        assert_eq!(alone["keep"], keep);
        let rows = std::fs::read_to_string(csv).unwrap();
        assert_eq!(parse_csv(&rows).1.len() as u64, keep);
    }
}

#[test]
fn the_exponent_and_its_error_of_a_long_orbit_are_as_before() {
    // Before the change (commit e50c9f6): λ = 0.3515054477239907 ±
    // 4.8413650494279084e-4 (batch means of 8 batches), aperiodic.
    let (before, error) = (0.3515054477239907, 4.8413650494279084e-4);
    let v = summary(&CHAOS, &["--transient", "1000", "--keep", "100000"]);
    assert_eq!(v["period"], "aperiodic");
    let lambda = v["lyapunov"].as_f64().unwrap();
    let stderr = v["lyapunov_stderr"].as_f64().unwrap();
    assert!((lambda - before).abs() <= error, "λ = {lambda}");
    // Eight batches estimate a spread to about ±25 %.
    assert!((stderr / error - 1.0).abs() < 0.25, "error {stderr}");
}
