//! `oneblock attractors` from the exit arc's cell graph (docs/attractors.md),
//! through the command a user runs, against independent computations:
//! direct orbits integrated from seeds, Newton's multiplier on the plain
//! map, and a long orbit's Lyapunov exponent from `oneblock orbit`.
//!
//! What broke before (issue 38): with orbits of 400 + 128 iterates from
//! seeds, pure creep at κ = 22.2 gave three attractors (two "chaotic" with
//! λ < 0), Fig. 3b's windows gave a second "chaotic" attractor beside
//! their cycle, and the chaos preset's λ was 0.03 low.

#![allow(clippy::unwrap_used)]

use crate::cli_support;

use cli_support::*;
use oneblock::model::{Params, wrap_angle};
use oneblock::sim::{OrbitOptions, Period, Simulator, default_settings};
use serde_json::Value;

/// `attractors --json` at the model flags given.
fn found(model: &[&str]) -> Value {
    let mut args = vec!["attractors"];
    args.extend_from_slice(model);
    args.push("--json");
    let o = oneblock(&args);
    assert_ok(&o);
    serde_json::from_str(&stdout(&o)).unwrap()
}

fn list(v: &Value) -> &Vec<Value> {
    v["attractors"].as_array().unwrap()
}

/// Every attractor labelled chaotic has λ > 0 both ways; every cycle is
/// stable; the basin fractions and the boundary sum to 1; the basins
/// cover the arc in order.
fn honest(v: &Value) {
    let mut total = v["boundary_fraction"].as_f64().unwrap();
    for a in list(v) {
        total += a["basin_fraction"].as_f64().unwrap();
        match a["verdict"].as_str().unwrap() {
            "chaotic" => {
                assert!(a["lyapunov"].as_f64().unwrap() > 0.0, "{a}");
                assert!(a["lyapunov_from_density"].as_f64().unwrap() > 0.0, "{a}");
                let d: f64 = a["density"]["values"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|x| x.as_f64().unwrap())
                    .sum();
                assert!((d - 1.0).abs() < 1e-9, "{d}");
            }
            "proved" | "cycle-in-set" => {
                assert!(a["multiplier"].as_f64().unwrap().abs() < 1.0, "{a}");
            }
            _ => {}
        }
    }
    assert!((total - 1.0).abs() < 1e-9, "{total}");
    let basins = v["basins"].as_array().unwrap();
    for w in basins.windows(2) {
        let (a, b) = (w[0]["to"].as_f64().unwrap(), w[1]["from"].as_f64().unwrap());
        assert!((a - b).abs() < 1e-12, "{a} {b}");
    }
    let r = &v["resolution"];
    assert!(r["cell_width"].as_f64().unwrap() > 0.0);
    assert!(r["epsilon"].as_f64().unwrap() > 0.0);
}

#[test]
fn pure_creep_has_exactly_one_attractor_over_kappa_and_nu() {
    for nu in ["1e-3", "1e-4"] {
        for kappa in ["1", "3", "10", "22.2", "42"] {
            for theta_nu in ["0.6", "1.2"] {
                let v = found(&[
                    "--kappa",
                    kappa,
                    "--gamma",
                    "0.5",
                    "--nu",
                    nu,
                    "--theta-nu",
                    theta_nu,
                ]);
                honest(&v);
                let l = list(&v);
                assert_eq!(l.len(), 1, "kappa {kappa} nu {nu} theta-nu {theta_nu}: {v}");
                assert_eq!(l[0]["period"], 1, "{v}");
                assert_eq!(l[0]["verdict"], "proved", "{v}");
                assert!((l[0]["basin_fraction"].as_f64().unwrap() - 1.0).abs() < 1e-9);
                // The fixed point lies by θν, as ν → 0 it must.
                let th = l[0]["points"][0].as_f64().unwrap();
                let tn: f64 = theta_nu.parse().unwrap();
                assert!((th - tn).abs() < 0.02, "{th} {tn}");
            }
        }
    }
}

/// The κ = 10 hysteresis point θν = 1.40: a P2 and the fixed point.
const KAPPA10_AT_140: [&str; 8] = [
    "--kappa",
    "10",
    "--gamma",
    "6.5",
    "--nu",
    "1e-3",
    "--theta-nu",
    "1.40",
];

fn kappa10(theta_nu: f64) -> Params {
    crate::common::seeded::kappa10_params(theta_nu)
}

/// Where a direct orbit of 600 + 64 integrated iterates from θ₀ ends: the
/// index of the cycle among `cycles` its last iterate lies on (to 1e-6).
fn ends_on(sim: &Simulator, theta0: f64, cycles: &[Vec<f64>]) -> Option<usize> {
    let opts = OrbitOptions {
        transient: 600,
        keep: 64,
        lyapunov: false,
        period_tol: 1e-8,
    };
    let o = sim.orbit(theta0, &opts, &|| false).ok()?;
    assert!(matches!(o.period, Period::Periodic(_)), "{theta0}");
    let last = o.theta_last;
    cycles
        .iter()
        .position(|c| c.iter().any(|&x| wrap_angle(x - last).abs() < 1e-6))
}

#[test]
fn kappa_10_hysteresis_basins_agree_with_direct_orbits() {
    let p = kappa10(1.40);
    let v = found(&KAPPA10_AT_140);
    honest(&v);
    let l = list(&v);
    let periods: Vec<i64> = l.iter().map(|a| a["period"].as_i64().unwrap()).collect();
    assert_eq!(periods, vec![1, 2], "{v}");
    let cycles: Vec<Vec<f64>> = l
        .iter()
        .map(|a| {
            a["points"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        })
        .collect();
    // Each a cycle of the plain map with Newton's multiplier.
    let sim = Simulator::new(p, default_settings(1e-10)).unwrap();
    for (a, c) in l.iter().zip(&cycles) {
        for i in 0..c.len() {
            let next = sim.map(c[i]).unwrap();
            assert!(wrap_angle(next - c[(i + 1) % c.len()]).abs() < 1e-8, "{a}");
        }
        assert!(a["basin_fraction"].as_f64().unwrap() > 0.1, "{a}");
    }
    // 64 seeds spread over the arc: each in a basin ends where its basin
    // says; the boundary (a few 1e-4 rad) holds none of them.
    let basins = v["basins"].as_array().unwrap();
    let (psi, half) = oneblock::model::exit_arc(p.kappa, p.theta_nu);
    let mut checked = 0;
    for i in 0..64 {
        let th = psi - half + 2.0 * half * (i as f64 + 0.5) / 64.0;
        let b = basins
            .iter()
            .find(|b| b["from"].as_f64().unwrap() <= th && th < b["to"].as_f64().unwrap());
        let Some(k) = b.and_then(|b| b["attractor"].as_u64()) else {
            continue;
        };
        // Basins name attractors by id, numbered from 1 as in the text.
        assert_eq!(
            ends_on(&sim, th, &cycles),
            Some(k as usize - 1),
            "seed {th}"
        );
        checked += 1;
    }
    assert!(checked >= 60, "{checked}");
}

#[test]
fn outside_the_hysteresis_range_the_p2_takes_the_whole_arc() {
    // At 0.8704, just past the first flip (m = −1.0008 at the fixed
    // point), every seed reaches the P2 of multiplier 0.9967; no set sits
    // on the fixed point.
    for (tn, m) in [("1.0", None), ("0.8704", Some(0.9967))] {
        let k10 = ["--kappa", "10", "--gamma", "6.5", "--nu", "1e-3"];
        let v = found(&[&k10[..], &["--theta-nu", tn]].concat());
        honest(&v);
        let l = list(&v);
        assert_eq!(l.len(), 1, "{v}");
        assert_eq!(l[0]["period"], 2);
        if let Some(m) = m {
            assert!(
                (l[0]["multiplier"].as_f64().unwrap() - m).abs() < 1e-3,
                "{v}"
            );
        }
    }
}

#[test]
fn fig3b_windows_have_their_cycle_alone() {
    for (tn, period) in [("1.2345", 10), ("1.245", 8), ("1.23617", 14)] {
        let v = found(&["--preset", "fig3b", "--theta-nu", tn]);
        honest(&v);
        let l = list(&v);
        assert_eq!(l.len(), 1, "{tn}: {v}");
        assert_eq!(l[0]["period"], period, "{tn}: {v}");
        assert_eq!(l[0]["verdict"], "proved", "{tn}: {v}");
    }
}

#[test]
fn the_chaos_preset_lambda_from_the_density_matches_a_long_orbit() {
    let v = found(&["--preset", "chaos"]);
    honest(&v);
    let l = list(&v);
    assert_eq!(l.len(), 1, "{v}");
    assert_eq!(l[0]["verdict"], "chaotic", "{v}");
    let from_density = l[0]["lyapunov_from_density"].as_f64().unwrap();
    // 10⁵ iterates of `oneblock orbit` (on its verified interpolant).
    let o = oneblock(&[
        "orbit",
        "--preset",
        "chaos",
        "--transient",
        "1000",
        "--keep",
        "100000",
        "--json",
    ]);
    assert_ok(&o);
    let orbit: Value = serde_json::from_str(&stdout(&o)).unwrap();
    let reference = orbit["lyapunov"].as_f64().unwrap();
    assert!(
        (from_density - reference).abs() < 0.01,
        "{from_density} {reference}"
    );
}

#[test]
fn fig3a_near_pi_over_2_agrees_with_direct_orbits() {
    // Chaos at 1.550. At 1.556 the fixed point and a chaotic attractor
    // coexist (six seeds spread over the arc all reached the fixed point,
    // and the seed search called it alone): direct orbits of 20 000
    // iterates from the middle of each basin stretch end where their
    // basin says.
    let v = found(&["--preset", "fig3a", "--theta-nu", "1.550"]);
    honest(&v);
    assert_eq!(list(&v)[0]["verdict"], "chaotic", "{v}");
    let v = found(&["--preset", "fig3a", "--theta-nu", "1.556"]);
    honest(&v);
    let l = list(&v);
    let fixed = l.iter().position(|a| a["period"] == 1).expect("the P1");
    assert_eq!(l[fixed]["verdict"], "proved", "{v}");
    assert_eq!(l.len(), 2, "{v}");
    let chaos = &l[1 - fixed];
    assert_eq!(chaos["verdict"], "chaotic", "{v}");
    let hull = |k: usize| chaos["points"][k].as_f64().unwrap();
    let p = Params {
        theta_nu: 1.556,
        ..oneblock::model::preset("fig3a").unwrap().params
    };
    let sim = Simulator::new(p, default_settings(1e-10)).unwrap();
    let fp = l[fixed]["points"][0].as_f64().unwrap();
    let opts = OrbitOptions {
        transient: 20_000,
        keep: 8,
        lyapunov: false,
        period_tol: 1e-8,
    };
    let mut told = [0, 0];
    for b in v["basins"].as_array().unwrap() {
        let (from, to) = (b["from"].as_f64().unwrap(), b["to"].as_f64().unwrap());
        // Basins name attractors by id, numbered from 1 as in the text.
        let Some(a) = b["attractor"].as_u64().map(|a| a as usize - 1) else {
            continue;
        };
        if to - from < 0.02 || told[usize::from(a != fixed)] >= 4 {
            continue;
        }
        told[usize::from(a != fixed)] += 1;
        let t0 = 0.5 * (from + to);
        let o = sim.orbit(t0, &opts, &|| false).unwrap();
        let on_fixed = wrap_angle(o.theta_last - fp).abs() < 1e-6;
        assert_eq!(on_fixed, a == fixed, "theta0 = {t0}: {}", o.theta_last);
        if a != fixed {
            let t = o.theta_last;
            assert!(hull(0) - 1e-3 <= t && t <= hull(1) + 1e-3, "{t0}: {t}");
        }
    }
    assert_eq!(told, [4, 4], "basin stretches told");
}

#[test]
fn a_bad_resolution_is_one_line_and_exit_2() {
    for (flag, value) in [
        ("--resolution", "0"),
        ("--resolution", "1"),
        ("--max-cells", "10"),
    ] {
        let o = oneblock(&["attractors", "--preset", "fig3b", flag, value]);
        assert_eq!(o.status.code(), Some(2));
        let err = stderr(&o);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(flag), "{err}");
    }
}

/// The smallest kick out of each basin at κ = 10, θν = 1.40 (the JSON's
/// `min_kick`) against direct orbits: onsets stepped away from each cycle
/// point by 5e-4 rad, each followed 664 iterates; the first that ends on
/// the other cycle is the kick the orbits see.
#[test]
fn kappa_10_smallest_kick_agrees_with_direct_orbits() {
    let p = kappa10(1.40);
    let v = found(&KAPPA10_AT_140);
    let l = list(&v);
    assert_eq!(l.len(), 2, "{v}");
    let cycles: Vec<Vec<f64>> = l
        .iter()
        .map(|a| {
            a["points"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        })
        .collect();
    let sim = Simulator::new(p, default_settings(1e-10)).unwrap();
    const STEP: f64 = 5e-4;
    for (i, a) in l.iter().enumerate() {
        let kick = a["min_kick"].as_f64().unwrap();
        let width = a["min_kick_width"].as_f64().unwrap();
        assert!(kick > 0.01 && width < 1e-4, "{a}");
        // The first onset, on either side of any cycle point, whose
        // orbit ends elsewhere.
        let mut direct = f64::INFINITY;
        for &x in &cycles[i] {
            for side in [-1.0, 1.0] {
                let mut d = STEP;
                while d < direct.min(kick + 0.01) {
                    if ends_on(&sim, x + side * d, &cycles) != Some(i) {
                        direct = direct.min(d);
                        break;
                    }
                    d += STEP;
                }
            }
        }
        assert!(
            direct >= kick - 1e-9 && direct <= kick + width + STEP + 1e-9,
            "attractor {i}: min_kick {kick} (+{width}), direct orbits {direct}"
        );
    }
}
