//! Issue 52, items 1–4, through `oneblock attractors` and `oneblock phase`:
//! basins that hold beside a steep repelling fixed point, a boundary that
//! shrinks with the resolution, λ from the density within its errors of a
//! long orbit's, and a phase cell classed by the graph's cycle.

#![allow(clippy::unwrap_used)]

use crate::cli_support;

use cli_support::*;
use oneblock::model::{Params, wrap_angle};
use oneblock::sim::{OrbitOptions, Period, Simulator, default_settings};
use serde_json::Value;

/// `attractors --json` with the flags given.
fn found(flags: &[&str]) -> Value {
    let mut args = vec!["attractors"];
    args.extend_from_slice(flags);
    args.push("--json");
    let o = oneblock(&args);
    assert_ok(&o);
    serde_json::from_str(&stdout(&o)).unwrap()
}

const KAPPA3: [&str; 8] = [
    "--kappa",
    "3",
    "--gamma",
    "10",
    "--nu",
    "1e-3",
    "--theta-nu",
    "1.3",
];

/// The attractor index the basins give θ, `None` on the boundary.
fn basin_at(v: &Value, theta: f64) -> Option<u64> {
    v["basins"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["from"].as_f64().unwrap() <= theta && theta < b["to"].as_f64().unwrap())
        .and_then(|b| b["attractor"].as_u64())
}

#[test]
fn basins_beside_a_steep_repelling_fixed_point_hold() {
    // The repelling fixed point 0.4511138 (m ≈ 49) separates the basins of
    // the fixed points 0.3664 (left) and 1.2655 (right). Onsets in
    // [0.4512, 0.4523] go right, as direct orbits show: none may be in the
    // basin of 0.3664.
    let v = found(&KAPPA3);
    let atts = v["attractors"].as_array().unwrap();
    let left = atts
        .iter()
        .position(|a| (a["points"][0].as_f64().unwrap() - 0.3664).abs() < 1e-3)
        .expect("the fixed point 0.3664");
    // The basins name an attractor by its id (the text's #1, #2, …).
    let left = atts[left]["id"].as_u64().unwrap();
    assert!(v["boundary_fraction"].as_f64().unwrap() < 0.02, "{v}");
    let p = Params {
        kappa: 3.0,
        gamma: 10.0,
        nu: 1e-3,
        theta_nu: 1.3,
        ..Params::default()
    };
    let sim = Simulator::new(p, default_settings(1e-10)).unwrap();
    let opts = OrbitOptions {
        transient: 400,
        keep: 16,
        lyapunov: false,
        period_tol: 1e-8,
    };
    for k in 0..12 {
        let theta = 0.4512 + 0.0011 * k as f64 / 11.0;
        assert_ne!(
            basin_at(&v, theta),
            Some(left),
            "{theta} in the basin of 0.3664"
        );
        // And the direct orbit agrees: it ends on 1.2655.
        let o = sim.orbit(theta, &opts, &|| false).unwrap();
        assert!(matches!(o.period, Period::Periodic(1)));
        assert!(wrap_angle(o.theta_last - 1.265482).abs() < 1e-5, "{theta}");
    }
    // The basins' edge is the repelling fixed point, to the cells'
    // resolution: the last stretch of 0.3664's basin ends within 1e-5 of it.
    let edge = v["basins"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|b| b["attractor"].as_u64() == Some(left))
        .map(|b| b["to"].as_f64().unwrap())
        .filter(|&t| (t - 0.4511).abs() < 0.01)
        .fold(f64::NAN, f64::max);
    assert!((edge - 0.451_113_8).abs() < 1e-5, "{edge}");
}

#[test]
fn the_boundary_shrinks_with_the_resolution() {
    for theta_nu in ["1.3", "1.31"] {
        let mut flags = KAPPA3.to_vec();
        flags[7] = theta_nu;
        let share = |res: &str| {
            let mut f = flags.clone();
            f.extend(["--resolution", res]);
            found(&f)["boundary_fraction"].as_f64().unwrap()
        };
        let (coarse, fine) = (share("1e-6"), share("1e-8"));
        assert!(
            fine <= 0.5 * coarse,
            "theta-nu {theta_nu}: {coarse} -> {fine}"
        );
    }
}

/// λ from the density and its error, and a 10⁵-iterate orbit's λ and
/// standard error (through `oneblock orbit`).
fn lambdas(flags: &[&str]) -> ((f64, f64), (f64, f64)) {
    let v = found(flags);
    let a = &v["attractors"][0];
    assert_eq!(a["verdict"], "chaotic", "{v}");
    let d = (
        a["lyapunov_from_density"].as_f64().unwrap(),
        a["lyapunov_density_error"].as_f64().unwrap(),
    );
    let mut args = vec!["orbit"];
    args.extend_from_slice(flags);
    args.extend(["--transient", "1000", "--keep", "100000", "--json"]);
    let o = oneblock(&args);
    assert_ok(&o);
    let o: Value = serde_json::from_str(&stdout(&o)).unwrap();
    let l = (
        o["lyapunov"].as_f64().unwrap(),
        o["lyapunov_stderr"].as_f64().unwrap(),
    );
    (d, l)
}

#[test]
fn lambda_from_the_density_agrees_within_its_errors() {
    for flags in [
        [
            "--kappa",
            "19",
            "--gamma",
            "10",
            "--nu",
            "1e-3",
            "--theta-nu",
            "1.4",
        ],
        [
            "--kappa",
            "23",
            "--gamma",
            "4",
            "--nu",
            "1e-3",
            "--theta-nu",
            "1.3",
        ],
    ] {
        let ((d, de), (l, le)) = lambdas(&flags);
        // Two standard errors of the difference, the density's
        // discretisation error counted as one.
        let both = (de * de + le * le).sqrt();
        assert!(
            (d - l).abs() <= 2.0 * both,
            "{flags:?}: {d} +- {de} against {l} +- {le}"
        );
        // The error is an error, not a blanket: under a tenth of λ at
        // κ = 23, where Ulam's grids converge.
        if flags[1] == "23" {
            assert!(de < 0.1 * d, "{de}");
        }
    }
}

#[test]
fn a_phase_cell_with_every_attractor_takes_the_graphs_cycle() {
    // κ = 38, θν = 1.5: the cell graph proves one P12 with basin 1.
    let v = found(&[
        "--kappa",
        "38",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--theta-nu",
        "1.5",
    ]);
    let a = &v["attractors"].as_array().unwrap();
    assert_eq!(a.len(), 1, "{v}");
    assert_eq!(a[0]["period"], 12, "{v}");
    assert_eq!(a[0]["verdict"], "proved", "{v}");
    // At the window's loose setting for a grid (dp54 1e-5) the cell's
    // 400 + 128 iterates do not outlast the transient chaos; the graph
    // (which integrates at 1e-10 whatever the cell's setting) proves the
    // P12, and with every attractor asked for its class is the cell's.
    let grid = |seeds: &str| {
        let o = oneblock(&[
            "phase",
            "--gamma",
            "6.5",
            "--nu",
            "1e-3",
            "--kappa-from",
            "37",
            "--kappa-to",
            "39",
            "--kappa-steps",
            "3",
            "--theta-nu-from",
            "1.4",
            "--theta-nu-to",
            "1.6",
            "--theta-nu-steps",
            "5",
            "--transient",
            "400",
            "--keep",
            "128",
            "--method",
            "dp54",
            "--tol",
            "1e-5",
            "--seeds",
            seeds,
            "--out",
            "-",
        ]);
        assert_ok(&o);
        let (head, rows) = parse_csv(&stdout(&o));
        let col = |name: &str| head.iter().position(|h| h == name).unwrap();
        let row = rows
            .iter()
            .find(|r| num(&r[col("theta_nu")]) == 1.5 && num(&r[col("kappa")]) == 38.0)
            .expect("the cell")
            .clone();
        (row[col("class")].clone(), num(&row[col("lyapunov")]))
    };
    // The orbit alone: its class is not the P12 (what the issue found).
    assert_ne!(grid("0").0, "P12");
    let (class, lambda) = grid("1");
    assert_eq!(class, "P12");
    // λ = ln|m|/12 of the proved cycle.
    let m = a[0]["multiplier"].as_f64().unwrap();
    assert!((lambda - m.abs().ln() / 12.0).abs() < 1e-3, "{lambda}");
}
