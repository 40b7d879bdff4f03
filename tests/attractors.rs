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

/// The seeded diagram's CSV rows (θν, θ, attractor); the followed
/// attractor's rows (label 0) carry the column's λ, the others none.
fn seeded_rows(args: &[&str]) -> Vec<(f64, f64, u8)> {
    let o = oneblock(args);
    assert_ok(&o);
    let out = stdout(&o);
    let mut lines = out.lines();
    assert_eq!(
        lines.next(),
        Some("theta_nu,theta,lyapunov,lyapunov_stderr,attractor")
    );
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let label: u8 = f[4].parse().unwrap();
            assert!(
                label == 0 || f[2].is_empty(),
                "λ on the followed attractor's rows only: {l}"
            );
            (f[0].parse().unwrap(), f[1].parse().unwrap(), label)
        })
        .collect()
}

#[test]
fn the_seeded_diagram_shows_both_branches_where_attractors_finds_two() {
    both_branches_with_seeds("16");
}

/// One seed a column misses the second branch at most columns of the
/// range; the neighbour pass continues each branch from the columns where
/// it was found (both ways) until it dies.
#[test]
fn one_seed_a_column_and_the_neighbour_pass_show_both_branches() {
    both_branches_with_seeds("1");
}

/// The seeded diagram over the hysteresis range, with `seeds` a column:
/// each column's attractors are those `attractors` finds from 32 other
/// seeds, and the multistable columns fill the range.
fn both_branches_with_seeds(seeds: &str) {
    let rows = seeded_rows(&[
        "bifurcation",
        "--kappa",
        "10",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--theta-nu-from",
        "1.33",
        "--theta-nu-to",
        "1.45",
        "--columns",
        "13",
        "--keep",
        "24",
        "--seeds",
        seeds,
    ]);
    let mut columns: Vec<f64> = rows.iter().map(|r| r.0).collect();
    columns.dedup();
    assert_eq!(columns.len(), 13);
    let mut multistable = vec![];
    for tn in columns {
        let labels: std::collections::BTreeSet<u8> =
            rows.iter().filter(|r| r.0 == tn).map(|r| r.2).collect();
        // Independently: full orbits from 32 other seeds, cycles by Newton.
        let found = attractors_default(params(tn), 32).unwrap();
        assert_eq!(labels.len(), found.len(), "theta-nu {tn}: {found:?}");
        if labels.len() > 1 {
            multistable.push(tn);
        }
        // Every labelled point is a point of one of the attractors found.
        for r in rows.iter().filter(|r| r.0 == tn) {
            assert!(
                found
                    .iter()
                    .any(|a| a.points.iter().any(|x| wrap_angle(x - r.1).abs() < 1e-5)),
                "theta-nu {tn}: {r:?} in none of {found:?}"
            );
        }
    }
    // The hysteresis range, 1.3708 (or the P2's second fold, 1.3640) to
    // 1.4202 (docs/attractors.md), and nothing outside it.
    assert!(
        multistable.iter().all(|&t| (1.364..1.4202).contains(&t)),
        "{multistable:?}"
    );
    assert!(multistable.len() >= 4, "{multistable:?}");
}

#[test]
fn the_seeded_phase_grid_counts_the_attractors_that_attractors_finds() {
    let o = oneblock(&[
        "phase",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--kappa-from",
        "10",
        "--kappa-to",
        "10",
        "--kappa-steps",
        "1",
        "--theta-nu-from",
        "1.33",
        "--theta-nu-to",
        "1.45",
        "--theta-nu-steps",
        "13",
        "--seeds",
        "16",
    ]);
    assert_ok(&o);
    let out = stdout(&o);
    let mut lines = out.lines();
    let header = lines.next().unwrap();
    assert!(header.ends_with(",attractors"), "{header}");
    let mut multistable = vec![];
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        let tn: f64 = f[0].parse().unwrap();
        let n: usize = f.last().unwrap().parse().unwrap();
        // Independently: full orbits from 32 other seeds, cycles by Newton.
        let found = attractors_default(params(tn), 32).unwrap();
        assert_eq!(n, found.len(), "theta-nu {tn}: {found:?}");
        if n > 1 {
            multistable.push(tn);
        }
    }
    assert!(
        multistable.iter().all(|&t| (1.364..1.4202).contains(&t)),
        "{multistable:?}"
    );
    assert!(multistable.len() >= 4, "{multistable:?}");
    assert!(stderr(&o).contains("multistable"), "{}", stderr(&o));
}

/// Just past the first flip (θν = 0.8702) every orbit drifts slowly onto a
/// P2 of small amplitude (multiplier ≈ 0.997): it was named a chaotic
/// attractor with a negative exponent. It is the P2 that Newton solves
/// separately.
#[test]
fn just_past_a_flip_the_slow_period_two_cycle_is_found() {
    let p = params(0.8704);
    let found = attractors_default(p, 8).unwrap();
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].period, Some(2), "{found:?}");
    let sim = Simulator::new(p, default_settings(1e-10)).unwrap();
    let c = oneblock::sim::solve_cycle(
        &sim,
        found[0].points[0],
        2,
        &oneblock::sim::CycleOptions::for_settings(&default_settings(1e-10)),
    )
    .unwrap();
    assert_eq!(c.minimal_period, 2);
    assert!(
        (c.multiplier - found[0].multiplier.unwrap()).abs() < 1e-6,
        "{c:?}"
    );
    assert!(c.multiplier > 0.99 && c.multiplier < 1.0, "{c:?}");
}

/// Inside Fig. 3b's P24 window (θν ≈ 1.2286, multiplier 0.66) an orbit
/// from θ₀ = 0.52 is still 1e-6 off its cycle after 500 + 100 iterates: a
/// seeded column takes it for the cycle it closes in on (the one its seeds
/// settle onto), not for a second, chaotic attractor; `attractors` finds
/// the one P24 too.
#[test]
fn a_column_closing_in_slowly_is_its_cycle_not_a_second_attractor() {
    let tn = "1.2285714285714286";
    let rows = seeded_rows(&[
        "bifurcation",
        "--preset",
        "fig3b",
        "--theta-nu-from",
        tn,
        "--theta-nu-to",
        tn,
        "--columns",
        "1",
        "--theta0",
        "0.52",
        "--keep",
        "100",
        "--seeds",
        "64",
    ]);
    assert_eq!(rows.len(), 100);
    assert!(rows.iter().all(|r| r.2 == 0), "a second attractor");
    let p = oneblock::model::Params {
        theta_nu: tn.parse().unwrap(),
        ..oneblock::model::presets::preset("fig3b").unwrap().params
    };
    let found = attractors_default(p, 64).unwrap();
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].period, Some(24), "{found:?}");
    // The column's points are the P24's, to its slow approach (1e-4).
    for r in &rows {
        let near = found[0]
            .points
            .iter()
            .any(|x| wrap_angle(x - r.1).abs() < 1e-4);
        assert!(near, "{r:?}");
    }
}

/// At the window's diagram accuracy (DP5(4) at 1e-4) the map is not
/// smooth below its error, and orbits settle onto points of one cycle a
/// few 1e-5 apart: they are one attractor there, so the multistable
/// columns are the hysteresis range's and no others (θν = 1.317 and 1.323,
/// on the P2 branch alone, were counted twice).
#[test]
fn on_a_loose_map_one_cycle_is_not_counted_twice() {
    let rows = seeded_rows(&[
        "bifurcation",
        "--kappa",
        "10",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--theta-nu-from",
        "1.30",
        "--theta-nu-to",
        "1.46",
        "--columns",
        "161",
        "--keep",
        "100",
        "--seeds",
        "16",
        "--method",
        "dp54",
        "--tol",
        "1e-4",
    ]);
    let multistable: std::collections::BTreeSet<u64> = rows
        .iter()
        .filter(|r| r.2 > 0)
        .map(|r| (r.0 * 1e6).round() as u64)
        .collect();
    let range = 1_363_000..1_421_000;
    assert!(
        multistable.iter().all(|t| range.contains(t)),
        "{multistable:?}"
    );
    assert!(multistable.len() >= 50, "{multistable:?}");
}

/// Inside Fig. 3b's periodic windows (a P10 at θν = 1.2345, a P8 at
/// 1.245, a P14 at 1.23617) the chaotic set is a transient: orbits wander
/// over it for hundreds of iterates, some longer than `attractors`'s
/// 400 + 128, then end on the window's cycle. `attractors` reported a
/// second, "chaotic" attractor at the first two and only chaos at the
/// P14 (its first orbit was still on the transient, and the seeds that
/// stayed in the set were told they had arrived). Checked against direct
/// orbits (DOP853 1e-10) from 16 seeds spread over the arc, each run for
/// 4 000 + 128 iterates: every one ends on the window's cycle.
#[test]
fn inside_a_periodic_window_the_transient_chaos_is_not_an_attractor() {
    use oneblock::sim::attractors::spread_seeds;
    use oneblock::sim::{OrbitOptions, Period};
    for (theta_nu, period) in [(1.2345, 10), (1.245, 8), (1.2361655303598935, 14)] {
        let p = Params {
            kappa: 18.95,
            ..params(theta_nu)
        };
        let found = attractors_default(p, 64).unwrap();
        assert_eq!(found.len(), 1, "θν {theta_nu}: {found:?}");
        assert_eq!(found[0].period, Some(period), "{found:?}");
        assert_eq!(found[0].basin_fraction, 1.0, "{found:?}");
        let sim = Simulator::new(p, default_settings(1e-10)).unwrap();
        let opts = OrbitOptions {
            transient: 4000,
            keep: 128,
            lyapunov: false,
            period_tol: OrbitOptions::period_tol_for(1e-10),
        };
        for theta0 in spread_seeds(&p, 16) {
            let o = sim.orbit(theta0, &opts, &|| false).unwrap();
            assert_eq!(o.period, Period::Periodic(period), "θ0 {theta0}");
        }
    }
    // The seeded Fig. 3b diagram (400 columns, 16 seeds) follows the P14
    // into its column at 1.23617, where a seed's orbit was still on the
    // transient: one attractor there, and in every column.
    let rows = seeded_rows(&[
        "bifurcation",
        "--preset",
        "fig3b",
        "--seeds",
        "16",
        "--columns",
        "400",
    ]);
    assert!(
        rows.iter()
            .any(|r| (r.0 - 1.2361655303598935).abs() < 1e-12)
    );
    assert!(
        rows.iter().all(|r| r.2 == 0),
        "a second attractor in a column"
    );
    // Where the set is chaos (θν = 1.2315: direct orbits are still
    // aperiodic after 20 000 iterates), it stays one.
    let p = Params {
        kappa: 18.95,
        ..params(1.2315)
    };
    let found = attractors_default(p, 64).unwrap();
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].period, None, "{found:?}");
}
