//! Cascades that keep going (issue 52, item 6). At κ = 15, γ = 4,
//! ν = 1e-3 the cascade from the fixed point ended just past the P4's
//! flip ("Newton's corrector did not converge"): 5e-5 past its birth the
//! P8 meets a jump of f^8 of ~1e-6 (G jumps by 2e-6 over 5e-11 in θ), and
//! the corrector, halving its step, never left it. The walk now steps
//! over a small jump where the cycle goes on past it (a `jump` row), and
//! the cascade reaches the P8's flip, checked against a bisection of the
//! P8's multiplier from `solve_cycle` alone at tol 1e-12; at κ = 19,
//! γ = 10 it no longer ends at the first doubling with "not the one
//! born" (its born cycle is now checked at the tolerance the doubling
//! was located with).
#![allow(clippy::unwrap_used)]

use crate::cli_support;

use cli_support::*;
use oneblock::model::Params;
use oneblock::sim::{CycleOptions, Simulator, default_settings, solve_cycle};

/// `continue --cascade` from the fixed point over θν ∈ [1.0, 1.6] at
/// (κ, γ), ν = 1e-3: (stderr, special-point rows).
fn cascade(kappa: &str, gamma: &str) -> (String, Vec<Vec<String>>) {
    let (o, _, rows) = continue_run(&[
        "--kappa",
        kappa,
        "--gamma",
        gamma,
        "--nu",
        "1e-3",
        "--theta-nu",
        "1.0",
        "--param",
        "theta-nu",
        "--from",
        "1.0",
        "--to",
        "1.6",
        "--period",
        "1",
        "--cascade",
    ]);
    (stderr(&o), rows)
}

/// The PD rows of period `p`.
fn doublings(rows: &[Vec<String>], p: &str) -> Vec<(f64, f64)> {
    rows.iter()
        .filter(|r| r[0] == "PD" && r[1] == p)
        .map(|r| (num(&r[3]), num(&r[4])))
        .collect()
}

#[test]
fn the_kappa_15_gamma_4_cascade_reaches_the_p8_flip() {
    let (err, rows) = cascade("15", "4");
    let p8 = doublings(&rows, "8");
    assert_eq!(p8.len(), 1, "{err}");
    let (b8, theta) = p8[0];
    // m of the P8 through `theta`, alone, at tol 1e-12, bisected on −1.
    let settings = default_settings(1e-12);
    let opts = CycleOptions::for_settings(&settings);
    let base = Params {
        kappa: 15.0,
        gamma: 4.0,
        nu: 1e-3,
        ..Params::default()
    };
    let mut seed = theta;
    let mut m_plus_1 = |tn: f64| {
        let p = Params {
            theta_nu: tn,
            ..base
        };
        let c = solve_cycle(&Simulator::new(p, settings).unwrap(), seed, 8, &opts).unwrap();
        assert_eq!(c.minimal_period, 8);
        seed = c.points[0];
        c.multiplier + 1.0
    };
    let (mut lo, mut hi) = (b8 - 1e-5, b8 + 1e-5);
    let f_lo = m_plus_1(lo);
    assert!(f_lo > 0.0 && m_plus_1(hi) < 0.0);
    while hi - lo > 1e-10 {
        let mid = 0.5 * (lo + hi);
        if m_plus_1(mid) > 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    assert!((b8 - 0.5 * (lo + hi)).abs() < 1e-8, "{b8} vs {lo}");
    assert!((b8 - 1.1806674).abs() < 1e-6, "{b8}");
    // The jump of f^8 it stepped over is told as what it is.
    assert!(rows.iter().any(|r| r[0] == "jump" && r[1] == "8"), "{err}");
    // δ from the P2, P4 and P8 flips, as the run from 1.178.
    let b: Vec<f64> = ["2", "4", "8"]
        .iter()
        .map(|p| doublings(&rows, p)[0].0)
        .collect();
    let delta = (b[1] - b[0]) / (b[2] - b[1]);
    assert!((delta - 4.666).abs() < 0.01, "{delta}");
    assert!(!err.contains("did not converge"), "{err}");
}

#[test]
fn the_kappa_19_gamma_10_cascade_switches_at_its_first_flip() {
    let (err, rows) = cascade("19", "10");
    assert!(!err.contains("not the one born"), "{err}");
    assert_eq!(doublings(&rows, "1").len(), 1, "{err}");
    assert_eq!(doublings(&rows, "2").len(), 1, "{err}");
    assert_eq!(doublings(&rows, "4").len(), 1, "{err}");
}
