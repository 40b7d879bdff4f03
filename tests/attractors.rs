//! Every attractor at one parameter point (docs/attractors.md): at κ = 10
//! inside the hysteresis range (θν from the fixed point's second flip,
//! 1.3708, to the P2 branch's fold, 1.4202) the fixed point and a P2 cycle
//! coexist,
//! each a cycle of the plain map with a positive basin fraction.

#![allow(clippy::unwrap_used)]

mod cli_support;

use cli_support::*;
use oneblock::model::{Params, wrap_angle};
use oneblock::sim::attractors::attractors_default;
use oneblock::sim::{Simulator, default_settings};

fn params(theta_nu: f64) -> Params {
    Params {
        kappa: 10.0,
        gamma: 6.5,
        nu: 1e-3,
        theta_nu,
        omega: 50.0,
    }
}

#[test]
fn a_fixed_point_and_a_p2_coexist_inside_the_hysteresis_range() {
    let p = params(1.40);
    let found = attractors_default(p, 64).unwrap();
    let periods: Vec<Option<usize>> = found.iter().map(|a| a.period).collect();
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(
        periods.contains(&Some(1)) && periods.contains(&Some(2)),
        "{found:?}"
    );
    let total: f64 = found.iter().map(|a| a.basin_fraction).sum();
    assert!((total - 1.0).abs() < 1e-12, "{total}");
    // Independently: each is a cycle of the plain map, and the stable one
    // Newton reports (|m| < 1).
    let sim = Simulator::new(p, default_settings(1e-10)).unwrap();
    for a in &found {
        assert!(a.basin_fraction > 0.0, "{a:?}");
        assert!(a.multiplier.unwrap().abs() < 1.0, "{a:?}");
        let n = a.points.len();
        for i in 0..n {
            let next = sim.map(a.points[i]).unwrap();
            assert!(
                wrap_angle(next - a.points[(i + 1) % n]).abs() < 1e-8,
                "{a:?}"
            );
        }
    }
    let p2 = found.iter().find(|a| a.period == Some(2)).unwrap();
    assert!(
        wrap_angle(p2.points[0] - p2.points[1]).abs() > 0.1,
        "{p2:?}"
    );
}

#[test]
fn outside_the_range_one_attractor_takes_every_seed() {
    let found = attractors_default(params(1.0), 16).unwrap();
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].period, Some(2));
    assert_eq!(found[0].basin_fraction, 1.0);
}

#[test]
fn the_json_has_the_issues_fields_and_bad_seeds_are_refused() {
    let o = oneblock(&[
        "attractors",
        "--kappa",
        "10",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--theta-nu",
        "1.40",
        "--seeds",
        "16",
        "--json",
    ]);
    assert_ok(&o);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let list = v["attractors"].as_array().unwrap();
    assert_eq!(list.len(), 2);
    for a in list {
        for key in [
            "period",
            "points",
            "multiplier",
            "lyapunov",
            "basin_fraction",
        ] {
            assert!(a.get(key).is_some(), "{a}");
        }
    }
    let sum: f64 = list
        .iter()
        .map(|a| a["basin_fraction"].as_f64().unwrap())
        .sum();
    assert!((sum - 1.0).abs() < 1e-12);
    let bad = oneblock(&["attractors", "--preset", "fig3b", "--seeds", "0"]);
    assert_eq!(bad.status.code(), Some(2));
    let err = stderr(&bad);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("--seeds"), "{err}");
}
