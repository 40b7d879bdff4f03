//! The watch against [`settled_period`] itself, the reference, at every
//! length of many sequences: its decisions must be the same, always.

use super::*;
use crate::integrate::{Method, SolverSettings};
use crate::model::Params;
use crate::sim::Simulator;

/// The watch's answer and the reference's at every length `step`, `2·step`,
/// … of `seq` (the watch given only the last `tail` values, at least
/// [`WINDOW_MAX`]); how many lengths had a period.
fn agree(seq: &[f64], tol: f64, step: usize, tail: usize) -> usize {
    let mut watch = PeriodWatch::new(tol);
    let mut periodic = 0;
    for n in (0..=seq.len()).step_by(step.max(1)) {
        let recent = &seq[n.saturating_sub(tail.max(WINDOW_MAX))..n];
        let got = watch.settled(recent, n);
        let want = settled_period(&seq[..n], tol);
        assert_eq!(got, want, "length {n}, tol {tol:e}, step {step}");
        // A second call at the same length says the same.
        assert_eq!(watch.settled(recent, n), want, "repeated at {n}");
        periodic += want.is_some() as usize;
    }
    periodic
}

/// Every length, every 7th, with the whole prefix and with a short tail.
fn agree_all_ways(seq: &[f64], tol: f64) -> usize {
    let periodic = agree(seq, tol, 1, usize::MAX);
    agree(seq, tol, 1, WINDOW_MAX);
    agree(seq, tol, 7, WINDOW_MAX + 5);
    agree(seq, tol, 300, WINDOW_MAX);
    periodic
}

/// x ↦ a fixed `cycle` approached with multiplier `m` per period, plus
/// `noise` from a fixed LCG.
fn approach(cycle: &[f64], m: f64, d0: f64, noise: f64, n: usize) -> Vec<f64> {
    let mut state: u64 = 99;
    let p = cycle.len();
    (0..n)
        .map(|i| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let e = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            cycle[i % p] + d0 * m.powi((i / p) as i32) + noise * e
        })
        .collect()
}

#[test]
fn the_same_periods_as_settled_period_on_synthetic_sequences() {
    let mut x: f64 = 0.3;
    let logistic: Vec<f64> = (0..2000)
        .map(|_| {
            x = 4.0 * x * (1.0 - x);
            x
        })
        .collect();
    assert_eq!(agree_all_ways(&logistic, 1e-6), 0);
    let cycles: [&[f64]; 5] = [
        &[0.3],
        &[0.1, 0.5],
        &[0.1, 0.5, -0.2],
        &[0.2, 0.21, 0.19, 0.4, 0.41, 0.39, 0.6],
        &[
            std::f64::consts::PI - 1e-9,
            -std::f64::consts::PI + 1e-9,
            0.0,
        ],
    ];
    let mut periodic = 0;
    for cycle in cycles {
        for m in [0.0, 0.3, -0.77, 0.95, -0.99, 1.002] {
            for (tol, noise) in [(1e-6, 0.0), (1e-9, 1e-10), (1e-7, 3e-7), (1e-12, 0.0)] {
                let seq = approach(cycle, m, 1e-3, noise, 500);
                periodic += agree_all_ways(&seq, tol);
            }
        }
    }
    assert!(periodic > 10_000, "{periodic} periodic lengths");
    // A 64-cycle, and one just beyond the longest period.
    for p in [64, 65] {
        let cycle: Vec<f64> = (0..p).map(|i| (i as f64 * 0.37).sin()).collect();
        agree_all_ways(&approach(&cycle, 0.5, 1e-4, 0.0, 600), 1e-8);
    }
    // Chaos that settles, and a cycle that breaks up.
    let mut joined = logistic[..500].to_vec();
    joined.extend(approach(&[0.1, 0.7], 0.6, 1e-2, 0.0, 300));
    joined.extend(&logistic[500..800]);
    assert!(agree_all_ways(&joined, 1e-8) > 0);
}

#[test]
fn values_the_filter_cannot_vouch_for_are_tested_in_full() {
    let mut seq = approach(&[0.1, 0.5], 0.5, 1e-3, 0.0, 400);
    seq[250] = f64::NAN;
    seq[300] = 1e6;
    seq[320] = f64::INFINITY;
    agree_all_ways(&seq, 1e-6);
    // Far from 0 (unwrapped angles) with a tolerance near rounding.
    let far: Vec<f64> = approach(&[100.1, 100.5], 0.3, 1e-6, 0.0, 400);
    agree_all_ways(&far, 1e-14);
    let far: Vec<f64> = approach(
        &[1e5, 1e5 + 2.0 * std::f64::consts::PI],
        0.3,
        1e-6,
        0.0,
        400,
    );
    agree_all_ways(&far, 1e-12);
}

/// Onsets of the map from θν, every cycle integrated.
fn map_orbit(params: Params, settings: SolverSettings, theta_nu: f64, n: usize) -> Vec<f64> {
    let sim = Simulator::new(params.with_theta_nu(theta_nu), settings).unwrap();
    let mut theta = theta_nu;
    (0..n)
        .map(|_| {
            let ev = sim.cycle(theta, 0.0, None).unwrap();
            theta = sim.next_onset(&ev);
            ev.theta
        })
        .collect()
}

#[test]
fn the_same_periods_as_settled_period_on_orbits_of_the_map() {
    let settings = SolverSettings::adaptive(Method::Dop853, 1e-8);
    let fig3b = Params::default();
    let mut periodic = 0;
    // Fig. 3b: fixed points, periods 2, 4 and 3, chaos, a slow approach
    // near the first flip, a window; at the sweep's tolerance (100·rtol)
    // and the orbit's (1e4·rtol).
    for tn in [0.3, 1.0, 1.12, 1.1929, 1.2, 1.2286, 1.25, 1.3] {
        let seq = map_orbit(fig3b, settings, tn, 500);
        for tol in [1e-6, 1e-4, 1e-9] {
            periodic += agree(&seq, tol, 1, usize::MAX);
            agree(&seq, tol, 5, WINDOW_MAX);
        }
    }
    assert!(periodic > 1000, "{periodic} periodic lengths");
}
