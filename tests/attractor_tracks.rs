//! `oneblock attractors --param P --from A --to B --columns N`: every
//! attractor of each column joined into tracks by basin overlap
//! (docs/attractors.md, issue 54), through the binary.

#![allow(clippy::unwrap_used)]

use crate::cli_support;

use cli_support::*;
use serde_json::Value;

/// The hysteresis window at κ = 10: θν from 1.35 to 1.43.
const KAPPA10: [&str; 14] = [
    "attractors",
    "--kappa",
    "10",
    "--gamma",
    "6.5",
    "--nu",
    "1e-3",
    "--param",
    "theta-nu",
    "--from",
    "1.35",
    "--to",
    "1.43",
    "--json",
];

fn json(args: &[&str]) -> Value {
    let o = oneblock(args);
    assert_ok(&o);
    serde_json::from_str(&stdout(&o)).unwrap()
}

fn periods(t: &Value) -> Vec<u64> {
    t["periods"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p.as_u64().unwrap())
        .collect()
}

/// Every column's basin fractions and its boundary sum to 1.
fn fractions_sum_to_one(j: &Value) {
    for c in j["columns"].as_array().unwrap() {
        let sum: f64 = c["attractors"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| a["basin_fraction"].as_f64().unwrap())
            .sum::<f64>()
            + c["boundary_fraction"].as_f64().unwrap();
        assert!((sum - 1.0).abs() < 1e-9, "column {}: {sum}", c["value"]);
    }
}

#[test]
fn the_hysteresis_window_at_kappa_10_is_two_tracks() {
    let args: Vec<&str> = KAPPA10.iter().copied().chain(["--columns", "81"]).collect();
    let j = json(&args);
    let step = 0.08 / 80.0;
    let tracks = j["tracks"].as_array().unwrap();
    assert_eq!(tracks.len(), 2, "{tracks:?}");
    // The large P2 over the window until its fold at 1.4202315.
    let big = tracks.iter().find(|t| periods(t) == [2]).unwrap();
    assert_eq!(big["kind"], "cycle");
    assert_eq!(big["start"]["cause"], "range start");
    assert_eq!(big["end"]["cause"], "unresolved");
    let end = big["end"]["value"].as_f64().unwrap();
    assert!((end - 1.4202315).abs() <= step, "{end}");
    // The small P2 born in a fold at 1.3639802 that halves into the fixed
    // point, which reaches the range's end.
    let small = tracks.iter().find(|t| periods(t) == [2, 1]).unwrap();
    assert_eq!(small["label"], "P2 → P1");
    let start = small["start"]["value"].as_f64().unwrap();
    assert_eq!(small["start"]["cause"], "unresolved");
    assert!((start - 1.3639802).abs() <= step, "{start}");
    assert_eq!(small["end"]["cause"], "range end");
    assert!((small["to"].as_f64().unwrap() - 1.43).abs() < 1e-12);
    // One event per start or end inside the range, between two columns.
    let events = j["events"].as_array().unwrap();
    assert_eq!(events.len(), 2, "{events:?}");
    for e in events {
        assert_eq!(e["cause"], "unresolved");
        let b = e["between"].as_array().unwrap();
        let (a, b) = (b[0].as_f64().unwrap(), b[1].as_f64().unwrap());
        assert!((b - a - step).abs() < 1e-9, "{e}");
        let v = e["value"].as_f64().unwrap();
        assert!((v - 0.5 * (a + b)).abs() < 1e-12, "{e}");
    }
    assert_eq!(j["columns"].as_array().unwrap().len(), 81);
    fractions_sum_to_one(&j);
}

#[test]
fn another_parameter_varies_too_fig3b_fixed_point_over_kappa() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("k.csv");
    let csv_arg = csv.to_str().unwrap();
    let args = [
        "attractors",
        "--preset",
        "fig3b",
        "--param",
        "kappa",
        "--from",
        "18.5",
        "--to",
        "19.5",
        "--columns",
        "5",
        "--json",
        "--out",
        csv_arg,
    ];
    let j = json(&args);
    let tracks = j["tracks"].as_array().unwrap();
    assert_eq!(tracks.len(), 1, "{tracks:?}");
    assert_eq!(periods(&tracks[0]), [1]);
    assert_eq!(tracks[0]["start"]["cause"], "range start");
    assert_eq!(tracks[0]["end"]["cause"], "range end");
    assert!(j["events"].as_array().unwrap().is_empty());
    fractions_sum_to_one(&j);
    // The CSV: provenance lines, one row per column and attractor and one
    // for its boundary; the columns spaced evenly in log κ.
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with("# oneblock"), "{text}");
    let (header, rows) = parse_csv(&text);
    assert_eq!(
        header,
        [
            "kappa",
            "track",
            "label",
            "period",
            "basin_fraction",
            "multiplier",
            "lyapunov"
        ]
    );
    let fp: Vec<_> = rows.iter().filter(|r| r[2] == "P1").collect();
    assert_eq!(fp.len(), 5, "{rows:?}");
    assert!(fp.iter().all(|r| r[1] == "0" && num(&r[6]) < 0.0));
    let mid = num(&fp[2][0]);
    assert!((mid - (18.5f64 * 19.5).sqrt()).abs() < 1e-9, "{mid}");
    // Never overwritten.
    let again = oneblock(&args);
    assert_eq!(again.status.code(), Some(2), "{}", stderr(&again));
}

#[test]
fn a_bad_range_is_one_line_naming_its_flag() {
    let base = [
        "attractors",
        "--kappa",
        "10",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--theta-nu",
        "1",
    ];
    let bad = |more: &[&str], flag: &str| assert_bad_input(&with(&base, more), flag);
    bad(
        &["--param", "kappa", "--from", "18", "--to", "18"],
        "--from",
    );
    bad(
        &[
            "--param",
            "kappa",
            "--from",
            "18",
            "--to",
            "19",
            "--columns",
            "1",
        ],
        "--columns",
    );
    bad(
        &[
            "--theta-nu-from",
            "1",
            "--theta-nu-to",
            "1.1",
            "--columns",
            "2001",
        ],
        "--columns",
    );
    bad(&["--param", "gamma", "--from", "1", "--to", "1e9"], "--to");
    bad(&["--param", "kappa"], "--param");
}
