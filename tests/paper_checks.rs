//! The paper's checks (section 3, figures 3 and 4), as docs/model.md lists them.

#![allow(clippy::unwrap_used)]

use crate::common;
use common::fixture::preset;

use oneblock::model::{OnsetCharacter, critical_angles, onset_character};
use oneblock::sim::{OrbitOptions, Period, fixed_point};
use oneblock::{Method, Params, Regime, Simulator, SolverSettings};

fn sim(p: Params, tol: f64) -> Simulator {
    Simulator::new(p, SolverSettings::adaptive(Method::Dop853, tol)).unwrap()
}

fn orbit(s: &Simulator, transient: usize, keep: usize, lyapunov: bool) -> oneblock::sim::Orbit {
    let opts = OrbitOptions {
        transient,
        keep,
        lyapunov,
        period_tol: 1e-6,
    };
    s.orbit(s.params().theta_nu, &opts, &|| false).unwrap()
}

#[test]
fn critical_angle_of_fig3a() {
    let tc = critical_angles(50.0, 6.5).unwrap();
    assert!((tc - 0.4090).abs() < 5e-5, "θc = {tc}");
    assert_eq!(Regime::of(50.0, 6.5), Regime::Mixed { theta_c: tc });
}

/// Pure creep (γ = 0.5, κ = 3): the fixed point θ* approaches θν as ν → 0,
/// with θ* − θν roughly proportional to ν. The multiplier is 1 − O(ν), so θ*
/// is found by solving f(θ) = θ rather than by iterating.
#[test]
fn pure_creep_fixed_point_approaches_theta_nu_linearly_in_nu() {
    let theta_nu = 0.7;
    let mut gaps = vec![];
    for nu in [1e-3, 3e-4, 1e-4] {
        let s = sim(
            Params {
                nu,
                theta_nu,
                ..preset("creep")
            },
            1e-12,
        );
        let (th, mult) = fixed_point(&s, theta_nu, 1e-12)
            .unwrap()
            .expect("fixed point");
        eprintln!(
            "ν = {nu:e}: θ* − θν = {:e}, f'(θ*) = {mult}, (θ* − θν)/ν = {}",
            th - theta_nu,
            (th - theta_nu) / nu
        );
        assert!(mult.abs() < 1.0, "the creep fixed point is stable");
        assert!(1.0 - mult < 100.0 * nu, "multiplier 1 − O(ν): {mult}");
        gaps.push(((th - theta_nu) / nu, nu));
    }
    // Proportional to ν: the ratio changes by less than 20 % over a decade.
    let (r0, r2) = (gaps[0].0, gaps[2].0);
    assert!(
        r0.signum() == r2.signum() && ((r0 - r2) / r2).abs() < 0.2,
        "gaps/ν: {gaps:?}"
    );
}

/// γ = 6.5, κ = 50 (mixed): for θν ≤ 0.4 the attractor is a fixed point
/// below θν, whose gap shrinks as ν goes 1e-4 → 1e-6 (slowly: docs/model.md).
#[test]
fn fig3a_creep_fixed_point_below_theta_nu() {
    for theta_nu in [0.2, 0.3, 0.4] {
        let mut last_gap = f64::INFINITY;
        for nu in [1e-4, 1e-5, 1e-6] {
            let s = sim(
                Params {
                    nu,
                    theta_nu,
                    ..preset("fig3a")
                },
                1e-11,
            );
            let (th, mult) = fixed_point(&s, theta_nu, 1e-11)
                .unwrap()
                .expect("fixed point");
            let gap = theta_nu - th;
            eprintln!("θν = {theta_nu}, ν = {nu:e}: θ* = {th}, gap {gap:e}, f' = {mult}");
            assert!(mult.abs() < 1.0, "attracting: f'(θ*) = {mult}");
            assert!(gap > 0.0, "θ* below θν");
            assert!(gap < last_gap, "gap shrinks as ν decreases");
            last_gap = gap;
        }
        // And iterating from θν approaches it monotonically: the attractor is
        // that fixed point (f'(θ*) ≈ 0.99 here, too slow for a period test).
        let s = sim(preset("fig3a").with_theta_nu(theta_nu), 1e-11);
        let (star, _) = fixed_point(&s, theta_nu, 1e-11).unwrap().unwrap();
        let o = orbit(&s, 0, 300, false);
        let d: Vec<f64> = o.events.iter().map(|e| (e.theta - star).abs()).collect();
        assert!(
            d.windows(2).all(|w| w[1] <= w[0] + 1e-9),
            "θν = {theta_nu}: not monotone"
        );
        assert!(
            d[299] < 0.5 * d[0],
            "θν = {theta_nu}: {} → {}",
            d[0],
            d[299]
        );
    }
}

/// γ = 6.5, κ = 50, ν = 1e-4: beyond the fixed points, a period ≥ 2 or
/// aperiodic orbit exists somewhere in θν ∈ (1.1, 1.55).
#[test]
fn fig3a_complex_orbits_at_large_theta_nu() {
    let found: Vec<(f64, Period)> = [1.2, 1.3, 1.4, 1.5]
        .iter()
        .map(|&tn| {
            (
                tn,
                orbit(
                    &sim(preset("fig3a").with_theta_nu(tn), 1e-10),
                    300,
                    128,
                    false,
                )
                .period,
            )
        })
        .collect();
    eprintln!("{found:?}");
    assert!(
        found.iter().any(|(_, p)| *p != Period::Periodic(1)),
        "{found:?}"
    );
}

/// γ = 6.5, κ = 18.95, ν = 1e-3 (Fig. 3b, pure stick-slip): every onset is
/// stick-slip, and along θν a fixed point gives way to period 2 before chaos.
#[test]
fn fig3b_period_doubling_to_chaos() {
    assert_eq!(Regime::of(18.95, 6.5), Regime::PureStickSlip);
    let mut kinds = vec![];
    for i in 0..=26 {
        let tn = 0.2 + 0.05 * i as f64;
        let o = orbit(
            &sim(preset("fig3b").with_theta_nu(tn), 1e-10),
            300,
            128,
            false,
        );
        for e in &o.events {
            assert_eq!(
                onset_character(18.95, 6.5, e.theta),
                OnsetCharacter::StickSlip
            );
        }
        kinds.push((tn, o.period));
    }
    eprintln!("{kinds:?}");
    assert_eq!(kinds[0].1, Period::Periodic(1), "a fixed point at small θν");
    let first_p2 = kinds
        .iter()
        .position(|k| k.1 == Period::Periodic(2))
        .expect("a period-2 orbit");
    let first_chaos = kinds
        .iter()
        .position(|k| k.1 == Period::Aperiodic)
        .expect("an aperiodic orbit");
    assert!(
        first_p2 < first_chaos,
        "period 2 comes before chaos: {kinds:?}"
    );
    assert!(kinds[..first_p2].iter().any(|k| k.1 == Period::Periodic(1)));
    // The aperiodic orbit at θν = 1.25 is chaos: positive Lyapunov exponent.
    let o = orbit(&sim(preset("chaos"), 1e-10), 200, 300, true);
    let (l, se) = (o.lyapunov.unwrap(), o.lyapunov_stderr.unwrap());
    eprintln!("λ(θν = 1.25) = {l} ± {se}");
    assert!(l > 3.0 * se && l > 0.05, "λ = {l} ± {se}");
}
