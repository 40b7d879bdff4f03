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

/// `attractors --json` over the κ = 10 window at `columns` columns.
fn kappa10(columns: &str) -> Value {
    let args: Vec<&str> = KAPPA10
        .iter()
        .copied()
        .chain(["--columns", columns])
        .collect();
    json(&args)
}

/// The independent integrator's values (issue 54): the large P2's fold,
/// the small P2's fold and its flip onto the fixed point.
const BIG_FOLD: f64 = 1.4202315;
const SMALL_FOLD: f64 = 1.3639802;
const FLIP: f64 = 1.3707590;

#[test]
fn the_hysteresis_window_at_kappa_10_is_two_tracks_born_and_dying_in_folds() {
    let j = kappa10("161");
    let tracks = j["tracks"].as_array().unwrap();
    assert_eq!(tracks.len(), 2, "{tracks:?}");
    let events = j["events"].as_array().unwrap();
    let value = |v: &Value| v["value"].as_f64().unwrap();
    // The large P2 over the window until its fold.
    let big = tracks.iter().find(|t| periods(t) == [2]).unwrap();
    assert_eq!(big["kind"], "cycle");
    assert_eq!(big["start"]["cause"], "edge");
    assert_eq!(big["end"]["cause"], "fold");
    assert!((value(&big["end"]) - BIG_FOLD).abs() < 1e-7, "{big}");
    // The small P2 born in a fold, halving into the fixed point in a
    // flip without ending, on to the range's end.
    let small = tracks.iter().find(|t| periods(t) == [2, 1]).unwrap();
    assert_eq!(small["label"], "P2 → P1");
    assert_eq!(small["start"]["cause"], "fold");
    assert!(
        (value(&small["start"]) - SMALL_FOLD).abs() < 1e-7,
        "{small}"
    );
    assert_eq!(small["end"]["cause"], "edge");
    assert!((small["to"].as_f64().unwrap() - 1.43).abs() < 1e-12);
    // Three events: each located, each in the JSON once, each naming
    // its track; the flip is supercritical (the P2 shrinks onto the
    // fixed point).
    let got: Vec<(&str, f64)> = events
        .iter()
        .map(|e| (e["cause"].as_str().unwrap(), value(e)))
        .collect();
    assert_eq!(got.len(), 3, "{events:?}");
    for (e, (cause, at)) in
        events
            .iter()
            .zip([("fold", SMALL_FOLD), ("flip", FLIP), ("fold", BIG_FOLD)])
    {
        assert_eq!(e["cause"], cause, "{e}");
        assert!((value(e) - at).abs() < 1e-7, "{e}");
        assert!(e["error"].as_f64().unwrap() <= 1e-8, "{e}");
        let b = e["between"].as_array().unwrap();
        assert!(
            b[0].as_f64().unwrap() <= value(e) && value(e) <= b[1].as_f64().unwrap(),
            "{e}"
        );
        let id = if at == BIG_FOLD {
            &big["id"]
        } else {
            &small["id"]
        };
        assert_eq!(e["tracks"], serde_json::json!([id]), "{e}");
    }
    assert_eq!(events[1]["criticality"], "supercritical");
    assert_eq!(events[1]["period"], 1);
    assert_eq!(j["columns"].as_array().unwrap().len(), 161);
    fractions_sum_to_one(&j);
}

#[test]
fn eighty_one_and_321_columns_give_the_same_tracks_and_events() {
    let (coarse, fine) = (kappa10("81"), kappa10("321"));
    let labels = |j: &Value| -> Vec<String> {
        j["tracks"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| {
                format!(
                    "{} {} {}",
                    t["label"], t["start"]["cause"], t["end"]["cause"]
                )
            })
            .collect()
    };
    assert_eq!(labels(&coarse), labels(&fine));
    let (a, b) = (
        coarse["events"].as_array().unwrap(),
        fine["events"].as_array().unwrap(),
    );
    assert_eq!(a.len(), b.len(), "{a:?}\n{b:?}");
    for (x, y) in a.iter().zip(b) {
        assert_eq!(x["cause"], y["cause"]);
        let (u, v) = (x["value"].as_f64().unwrap(), y["value"].as_f64().unwrap());
        assert!((u - v).abs() < 1e-7, "{x}\n{y}");
    }
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
    assert_eq!(tracks[0]["start"]["cause"], "edge");
    assert_eq!(tracks[0]["end"]["cause"], "edge");
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
            "min_kick",
            "multiplier",
            "lyapunov"
        ]
    );
    let fp: Vec<_> = rows.iter().filter(|r| r[2] == "P1").collect();
    assert_eq!(fp.len(), 5, "{rows:?}");
    assert!(fp.iter().all(|r| r[1] == "0" && num(&r[7]) < 0.0));
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

/// A column of a range starts f's interpolant from its parent column's
/// layout (docs/attractors.md, "Cost"); the same point asked for alone
/// starts from nothing. Both are checked the same way, so they find the
/// same attractors, periods, points and basins: here at Fig. 3b, where f
/// has jumps that move from column to column and attractors are cycles,
/// windows and chaos.
#[test]
fn a_column_started_from_its_neighbour_finds_what_the_point_alone_finds() {
    // Fig. 3b's model, as a range and as single points.
    let fig3b = |more: &[&str]| {
        let mut args = vec!["attractors", "--preset", "fig3b"];
        args.extend_from_slice(more);
        args.push("--json");
        json(&args)
    };
    let range = fig3b(&[
        "--param",
        "theta-nu",
        "--from",
        "1.3",
        "--to",
        "1.5",
        "--columns",
        "9",
    ]);
    for c in range["columns"].as_array().unwrap() {
        let v = c["value"].as_f64().unwrap();
        // The range's own column options: cells to 1e-5, at most 8192.
        let alone = fig3b(&[
            "--theta-nu",
            &v.to_string(),
            "--resolution",
            "1e-5",
            "--max-cells",
            "8192",
        ]);
        let (a, b) = (
            c["attractors"].as_array().unwrap(),
            alone["attractors"].as_array().unwrap(),
        );
        assert_eq!(a.len(), b.len(), "θν = {v}: {a:?}\n{b:?}");
        for (x, y) in a.iter().zip(b) {
            assert_eq!(x["period"], y["period"], "θν = {v}");
            let (fx, fy) = (
                x["basin_fraction"].as_f64().unwrap(),
                y["basin_fraction"].as_f64().unwrap(),
            );
            assert!((fx - fy).abs() < 1e-3, "θν = {v}: basin {fx} alone {fy}");
            let pts = |z: &Value| -> Vec<f64> {
                z["points"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|p| p.as_f64().unwrap())
                    .collect()
            };
            for (p, q) in pts(x).iter().zip(pts(y)) {
                // A cycle's points to Newton's accuracy; a chaotic set's
                // hull to the cells' width.
                assert!((p - q).abs() < 1e-4, "θν = {v}: {p} alone {q}");
            }
        }
        let (bx, by) = (
            c["boundary_fraction"].as_f64().unwrap(),
            alone["boundary_fraction"].as_f64().unwrap(),
        );
        assert!((bx - by).abs() < 1e-3, "θν = {v}: boundary {bx} alone {by}");
    }
}
