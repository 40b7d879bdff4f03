//! Continuation of cycles (docs/continuation.md): located period doublings
//! against independent bisections and orbit diagrams, the geometry of the
//! branches at a doubling, the paper's rows, and the command line's
//! refusals.

#![allow(clippy::unwrap_used)]

use crate::cli_support;

use cli_support::*;
use oneblock::model::{Params, wrap_angle};
use oneblock::sim::continuation::{
    ContOptions, ContParam, CurveKind, CurveOf, CurveOptions, FirstLevel, Problem, Reach,
    SpecialKind, Stop, cascade, cascade_reporting, continue_branch, continue_curve,
    continue_curves, curve_crossings, feigenbaum_ratios,
};
use oneblock::sim::{CycleOptions, OrbitOptions, Period, Simulator, default_settings, solve_cycle};

fn params(kappa: f64, theta_nu: f64) -> Params {
    Params {
        kappa,
        gamma: 6.5,
        nu: 1e-3,
        theta_nu,
        omega: 50.0,
    }
}

fn problem(kappa: f64, period: usize) -> Problem {
    Problem {
        base: params(kappa, 1.0),
        settings: default_settings(1e-10),
        param: ContParam::ThetaNu,
        period,
    }
}

/// The fixed point's multiplier at θν, by `solve_cycle` alone.
fn fp_multiplier(kappa: f64, theta_nu: f64, seed: f64) -> (f64, f64) {
    let sim = Simulator::new(params(kappa, theta_nu), default_settings(1e-10)).unwrap();
    let c = solve_cycle(&sim, seed, 1, &CycleOptions::for_settings(sim.settings())).unwrap();
    (c.multiplier, c.points[0])
}

fn fig3b_branch() -> oneblock::sim::continuation::Branch {
    let prob = problem(18.95, 1);
    let opts = ContOptions::for_range(&prob.settings, 1.0, 1.2);
    continue_branch(&prob, 1.0, 1.2, 0.4, &opts, &|| false).unwrap()
}

#[test]
fn pd_of_the_fixed_point_agrees_with_bisection_on_the_multiplier() {
    let b = fig3b_branch();
    assert_eq!(b.stop, Stop::Reached);
    let pds: Vec<_> = b.of_kind(SpecialKind::PeriodDoubling).collect();
    assert_eq!(pds.len(), 1, "{:?}", b.special);
    let pd = pds[0];
    // Bisection on θν of m + 1, each side solved on its own.
    let (mut lo, mut hi) = (1.08, 1.10);
    let mut seed = 0.42;
    assert!(fp_multiplier(18.95, lo, seed).0 > -1.0);
    assert!(fp_multiplier(18.95, hi, seed).0 < -1.0);
    while hi - lo > 1e-11 {
        let mid = 0.5 * (lo + hi);
        let (m, th) = fp_multiplier(18.95, mid, seed);
        seed = th;
        if m > -1.0 { lo = mid } else { hi = mid }
    }
    let bisected = 0.5 * (lo + hi);
    assert!(
        (pd.lambda - bisected).abs() < 1e-8,
        "continuation {} vs bisection {bisected}",
        pd.lambda
    );
    assert!((pd.multiplier + 1.0).abs() < 1e-6);
    // Its θ is the fixed point there.
    let (_, th) = fp_multiplier(18.95, pd.lambda, pd.theta);
    assert!(wrap_angle(th - pd.theta).abs() < 1e-8);
}

#[test]
fn pd_lies_between_the_orbit_diagrams_p1_and_p2_columns() {
    let pd = fig3b_branch()
        .of_kind(SpecialKind::PeriodDoubling)
        .next()
        .unwrap()
        .lambda;
    let opts = OrbitOptions {
        transient: 3000,
        keep: 64,
        lyapunov: false,
        period_tol: 1e-6,
    };
    let mut last_p1 = f64::NEG_INFINITY;
    let mut first_p2 = f64::INFINITY;
    for i in 0..=8 {
        let tn = 1.05 + 0.01 * i as f64;
        let sim = Simulator::new(params(18.95, tn), default_settings(1e-10)).unwrap();
        let orbit = sim.orbit(0.4, &opts, &|| false).unwrap();
        match orbit.period {
            Period::Periodic(1) => last_p1 = tn,
            Period::Periodic(2) => first_p2 = first_p2.min(tn),
            p => panic!("theta-nu = {tn}: period {p}"),
        }
    }
    assert!(
        last_p1 < pd && pd < first_p2,
        "{last_p1} < {pd} < {first_p2}"
    );
}

#[test]
fn the_fixed_point_past_its_doubling_is_unstable_and_the_p2_branch_starts_at_it() {
    let b = fig3b_branch();
    let pd = b
        .of_kind(SpecialKind::PeriodDoubling)
        .next()
        .unwrap()
        .clone();
    for p in &b.points {
        if p.lambda > pd.lambda + 1e-6 {
            assert!(p.multiplier < -1.0 && !p.stable, "{p:?}");
        } else if p.lambda < pd.lambda - 1e-6 {
            assert!(p.multiplier > -1.0 && p.stable, "{p:?}");
        }
    }
    let prob = problem(18.95, 1);
    let opts = ContOptions::for_range(&prob.settings, 1.0, 1.3);
    let c = cascade(Reach::new(&prob, 1.0, 1.3, &opts), 0.4, 64, &|| false).unwrap();
    assert!(c.doublings.len() >= 2, "{}", c.stop);
    assert!((c.doublings[0].lambda - pd.lambda).abs() < 1e-8);
    let p2 = &c.branches[1];
    assert_eq!(p2.period, 2);
    let first = &p2.points[0];
    assert_eq!(first.minimal_period, 2);
    // Born at the fixed point: its two points straddle it, within the
    // square-root distance of the small step past the doubling.
    let (_, fp) = fp_multiplier(18.95, first.lambda, pd.theta);
    let d: Vec<f64> = first.points.iter().map(|t| wrap_angle(t - fp)).collect();
    assert!(d[0] * d[1] < 0.0, "{d:?}");
    let step = first.lambda - pd.lambda;
    assert!(step > 0.0 && step < 1e-2);
    assert!(
        d.iter().all(|x| x.abs() < 10.0 * step.sqrt()),
        "{d:?} {step}"
    );
    // Its multiplier starts near +1 (born stable) and ends at −1.
    assert!(
        first.multiplier > 0.5 && first.multiplier < 1.0,
        "{first:?}"
    );
    assert!(first.stable);
}

#[test]
fn the_paper_rows_kappa_10_twice_kappa_1_2_never() {
    for (kappa, expected) in [(10.0, 2), (1.2, 0)] {
        let prob = problem(kappa, 1);
        let opts = ContOptions::for_range(&prob.settings, 0.1, 1.55);
        let b = continue_branch(&prob, 0.1, 1.55, 0.1, &opts, &|| false).unwrap();
        assert_eq!(b.stop, Stop::Reached, "kappa {kappa}");
        let pds: Vec<_> = b.of_kind(SpecialKind::PeriodDoubling).collect();
        assert_eq!(pds.len(), expected, "kappa {kappa}: {:?}", b.special);
        // Between two doublings the fixed point is unstable, outside stable.
        if let [a, z] = pds[..] {
            for p in &b.points {
                let inside = p.lambda > a.lambda + 1e-6 && p.lambda < z.lambda - 1e-6;
                let outside = p.lambda < a.lambda - 1e-6 || p.lambda > z.lambda + 1e-6;
                assert!(!inside || !p.stable, "{p:?}");
                assert!(!outside || p.stable, "{p:?}");
            }
        } else {
            assert!(b.points.iter().all(|p| p.stable));
        }
    }
}

/// A cascade that goes on from a branch already followed past its
/// doubling (the window's Find bifurcations) finds the doublings a cascade
/// from the seed finds, and reports only the levels after the given one.
#[test]
fn a_cascade_from_a_given_branch_finds_the_same_doublings() {
    let prob = problem(18.95, 1);
    let opts = ContOptions::for_range(&prob.settings, 1.0, 1.3);
    let whole = continue_branch(&prob, 1.0, 1.3, 0.4, &opts, &|| false).unwrap();
    assert_eq!(whole.stop, Stop::Reached, "past its doubling");
    let fresh = cascade(Reach::new(&prob, 1.0, 1.3, &opts), 0.4, 8, &|| false).unwrap();
    let mut reported = vec![];
    let given = cascade_reporting(
        Reach::new(&prob, 1.0, 1.3, &opts),
        FirstLevel::Given(whole.clone()),
        8,
        &|| false,
        &mut |b| reported.push(b.period),
    )
    .unwrap();
    assert!(fresh.doublings.len() >= 3, "{}", fresh.stop);
    assert_eq!(given.doublings, fresh.doublings);
    assert_eq!(given.branches[0], whole);
    assert_eq!(given.branches[1..], fresh.branches[1..]);
    assert_eq!(reported, vec![2, 4, 8]);
}

#[test]
fn the_kappa_16_cascade_reaches_p8_with_shrinking_gaps() {
    let prob = problem(16.0, 1);
    let opts = ContOptions::for_range(&prob.settings, 1.0, 1.6);
    let c = cascade(Reach::new(&prob, 1.0, 1.6, &opts), 0.4, 64, &|| false).unwrap();
    let periods: Vec<usize> = c.doublings.iter().map(|d| d.period).collect();
    assert!(periods.len() >= 3, "{periods:?}: {}", c.stop);
    assert_eq!(&periods[..3], &[1, 2, 4]);
    // Each doubling is located on its own branch: multiplier −1 there, to
    // what a bracket of 1e-10 in θν leaves: m changes over a level's
    // length (the gap, ~9e-5 at P64) by about 2, so by ~2e-6 over 1e-10
    // at P64 and proportionally less at the shorter periods.
    for d in &c.doublings {
        let tol = 1e-6 * (d.period as f64 / 16.0).max(1.0);
        assert!((d.multiplier + 1.0).abs() < tol, "{d:?}");
    }
    let b: Vec<f64> = c.doublings.iter().map(|d| d.lambda).collect();
    for r in feigenbaum_ratios(&b) {
        assert!(r > 2.0 && r < 10.0, "{b:?}");
    }
}

#[test]
fn the_pd_curve_passes_through_the_located_doublings_at_other_kappas() {
    // The FP→P2 curve from the doubling at κ = 16, within κ ∈ [12, 20]:
    // where it crosses κ = 18.95 it must be the doubling located there by
    // a branch of its own.
    let prob = problem(16.0, 1);
    let opts = ContOptions::for_range(&prob.settings, 0.9, 1.2);
    let b = continue_branch(&prob, 0.9, 1.2, 0.4, &opts, &|| false).unwrap();
    let start = b
        .of_kind(SpecialKind::PeriodDoubling)
        .next()
        .unwrap()
        .clone();
    let copts = CurveOptions::for_box([[0.9, 1.2], [12.0, 20.0]]);
    let of = CurveOf {
        base: prob.base,
        settings: prob.settings,
        params: [ContParam::ThetaNu, ContParam::Kappa],
        period: 1,
        kind: CurveKind::PeriodDoubling,
    };
    let curve = continue_curve(&of, &start, &copts, &|| false);
    assert!(curve.points.len() > 10, "{:?}", curve.ends);
    for p in &curve.points {
        // The corrector's residual bound.
        assert!((p.multiplier + 1.0).abs() <= 1e-6, "{p:?}");
    }
    let pd_1895 = fig3b_branch()
        .of_kind(SpecialKind::PeriodDoubling)
        .next()
        .unwrap()
        .lambda;
    let w = curve
        .points
        .windows(2)
        .find(|w| (w[0].lambda[1] - 18.95) * (w[1].lambda[1] - 18.95) <= 0.0)
        .expect("the curve crosses kappa = 18.95");
    let f = (18.95 - w[0].lambda[1]) / (w[1].lambda[1] - w[0].lambda[1]);
    let tn = w[0].lambda[0] + f * (w[1].lambda[0] - w[0].lambda[0]);
    // Linear interpolation between curve points: a chord's error.
    assert!((tn - pd_1895).abs() < 1e-3, "{tn} vs {pd_1895}");
}

#[test]
fn one_pd_curve_run_traces_the_fp_to_p2_boundary_that_the_branches_cross() {
    // One run from the two doublings of the fixed point at κ = 16 over
    // the box θν ∈ [0.1, 1.55] × κ ∈ [1, 42].
    let prob = problem(16.0, 1);
    let opts = ContOptions::for_range(&prob.settings, 0.1, 1.55);
    let b = continue_branch(&prob, 0.1, 1.55, 0.1, &opts, &|| false).unwrap();
    let starts: Vec<_> = b.of_kind(SpecialKind::PeriodDoubling).cloned().collect();
    assert_eq!(starts.len(), 2, "{:?}", b.special);
    let copts = CurveOptions::for_box([[0.1, 1.55], [1.0, 42.0]]);
    let params = [ContParam::ThetaNu, ContParam::Kappa];
    let kind = CurveKind::PeriodDoubling;
    let of = CurveOf {
        base: prob.base,
        settings: prob.settings,
        params,
        period: 1,
        kind,
    };
    let curves = continue_curves(&of, &starts, &copts, &|| false);
    assert!(!curves.is_empty() && curves.len() <= 2);
    for c in &curves {
        for p in &c.points {
            assert!((p.multiplier + 1.0).abs() <= 1e-6, "{p:?}");
        }
    }
    // Independently, at each κ: the doublings a branch in θν locates on
    // the fixed point's first sheet (before any fold or border, past
    // which other fixed points double on curves of their own) are the
    // curves' crossings of that κ, to 1e-6, and there are no others.
    // κ = 13: the right arm's S, four doublings along θν.
    for kappa in [1.25, 1.5, 2.0, 3.0, 10.0, 13.0, 25.0, 40.0] {
        let pk = problem(kappa, 1);
        let ok = ContOptions::for_range(&pk.settings, 0.1, 1.55);
        let br = continue_branch(&pk, 0.1, 1.55, 0.1, &ok, &|| false).unwrap();
        // The first sheet also ends where the fixed point runs into a
        // near-jump of f: its multiplier then dives through −1 to −10³
        // and beyond within 0.01 in θν, and the next special point is a
        // fold or a border, not a doubling back (κ = 1.5 near θν = 1.386).
        // That doubling is on a curve of its own, which a branch's steps
        // may or may not resolve, so it is left out here.
        let dives = |i: usize| {
            let (pd, next) = (&br.special[i], br.special.get(i + 1));
            let until = next
                .map_or(f64::INFINITY, |n| n.lambda)
                .min(pd.lambda + 0.01);
            next.is_none_or(|n| n.kind != SpecialKind::PeriodDoubling)
                && br
                    .points
                    .iter()
                    .any(|p| p.lambda > pd.lambda && p.lambda <= until && p.multiplier.abs() > 1e3)
        };
        let pds: Vec<f64> = br
            .special
            .iter()
            .enumerate()
            .take_while(|(i, s)| s.kind == SpecialKind::PeriodDoubling && !dives(*i))
            .map(|(_, s)| s.lambda)
            .collect();
        let mut crossings: Vec<f64> = curves
            .iter()
            .flat_map(|c| curve_crossings(&pk.base, &pk.settings, c, &copts, 1, kappa))
            .map(|p| p.lambda[0])
            .collect();
        crossings.sort_by(f64::total_cmp);
        assert_eq!(
            crossings.len(),
            pds.len(),
            "kappa {kappa}: {crossings:?} vs {pds:?}"
        );
        assert!(!pds.is_empty(), "kappa {kappa}");
        for (x, pd) in crossings.iter().zip(&pds) {
            assert!(
                (x - pd).abs() < 1e-6,
                "kappa {kappa}: curve {x} vs branch {pd}"
            );
        }
    }
    // The bottom: both arms come down to κ ≈ 1.21, so at κ = 1.2 the
    // fixed point does not double (the_paper_rows_… checks the branch).
    let lowest = curves
        .iter()
        .flat_map(|c| &c.points)
        .map(|p| p.lambda[1])
        .fold(f64::INFINITY, f64::min);
    assert!(lowest > 1.205 && lowest < 1.215, "{lowest}");
    let at_1_2 = problem(1.2, 1);
    for c in &curves {
        assert!(curve_crossings(&at_1_2.base, &at_1_2.settings, c, &copts, 1, 1.2).is_empty());
    }
}

fn continue_args(more: &[&str]) -> Vec<String> {
    with(
        &[
            "continue", "--preset", "fig3b", "--param", "theta-nu", "--from", "1.0", "--to", "1.2",
            "--period", "1",
        ],
        more,
    )
}

#[test]
fn bad_input_names_the_flag_and_exits_with_2() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b.csv");
    let out = out.to_str().unwrap();
    let base = continue_args(&["--out", out]);
    let refs: Vec<&str> = base.iter().map(String::as_str).collect();
    assert_bad_input(&set(base.clone(), "--to", "1.0"), "--to");
    assert_bad_input(&set(base.clone(), "--period", "0"), "--period");
    assert_bad_input(&set(base.clone(), "--period", "65"), "--period");
    assert_bad_input(&set(base.clone(), "--param", "tau"), "--param");
    assert_bad_input(&set(base.clone(), "--from", "NaN"), "--from");
    assert_bad_input(&with(&refs, &["--theta", "2.5"]), "--theta");
    // On the exit arc but on no 3-cycle near it (the attractor is P1).
    assert_bad_input(
        &set(with(&refs, &["--theta", "0.1"]), "--period", "3"),
        "--theta",
    );
    // No seed and an attractor of another period.
    assert_bad_input(&set(base.clone(), "--period", "2"), "--theta");
    let curve = |kind: &str, params: &str| {
        with(
            &[
                "continue", "--preset", "fig3b", "--from", "1.0", "--to", "1.2", "--period", "1",
            ],
            &[
                "--out", out, "--curve", kind, "--params", params, "--from2", "10", "--to2", "20",
            ],
        )
    };
    assert_bad_input(&curve("hopf", "theta-nu,kappa"), "--curve");
    assert_bad_input(&curve("pd", "theta-nu,tau"), "--params");
    assert_bad_input(&curve("pd", "kappa,kappa"), "--params");
    assert_bad_input(&set(curve("pd", "theta-nu,kappa"), "--to2", "10"), "--to2");
    let kappa = set(base.clone(), "--param", "kappa");
    assert_bad_input(&set(set(kappa, "--from", "0"), "--to", "1"), "--from");
    assert!(!std::path::Path::new(out).exists(), "nothing written");
}

#[test]
fn the_cli_writes_branches_and_points_and_keeps_existing_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b.csv");
    let pts = dir.path().join("p.csv");
    let args = continue_args(&[
        "--out",
        out.to_str().unwrap(),
        "--points",
        pts.to_str().unwrap(),
    ]);
    assert_ok(&run(&args));
    let (header, rows) = parse_csv(&std::fs::read_to_string(&out).unwrap());
    assert_eq!(
        header,
        ["theta_nu", "period", "theta_1", "multiplier", "stable"]
    );
    assert!(rows.len() > 10);
    assert_eq!(num(&rows[0][0]), 1.0);
    assert_eq!(num(&rows[rows.len() - 1][0]), 1.2);
    let (header, rows) = parse_csv(&std::fs::read_to_string(&pts).unwrap());
    assert_eq!(
        header,
        [
            "kind",
            "period",
            "parameter",
            "value",
            "theta",
            "multiplier",
            "criticality"
        ]
    );
    let kinds: Vec<&str> = rows.iter().map(|r| r[0].as_str()).collect();
    assert_eq!(kinds, ["PD", "end"]);
    // Fig. 3b's first flip is supercritical (tests/criticality.rs).
    assert_eq!(rows[0][6], "supercritical");
    assert_eq!(rows[1][6], "");
    assert_eq!(rows[0][2], "theta-nu");
    // A second run without --force refuses, naming the flag.
    let again = run(&args);
    assert_eq!(again.status.code(), Some(2));
    assert!(stderr(&again).contains("--out"), "{}", stderr(&again));
}

#[test]
fn the_period_3_window_opens_at_a_fold() {
    // Fig. 3b's period-3 window: the orbit diagram has P3 at θν = 1.3 and
    // chaos at 1.295. Followed down from 1.3, the stable 3-cycle turns at
    // a fold (multiplier +1) and comes back as the unstable one.
    let prob = problem(18.95, 3);
    let opts = ContOptions::for_range(&prob.settings, 1.3, 1.28);
    let b = continue_branch(&prob, 1.3, 1.28, 0.2087, &opts, &|| false).unwrap();
    assert_eq!(b.stop, Stop::Returned, "{}", b.stop_message());
    let folds: Vec<_> = b.of_kind(SpecialKind::Fold).collect();
    assert_eq!(folds.len(), 1, "{:?}", b.special);
    let fold = folds[0];
    assert!(fold.lambda > 1.295 && fold.lambda < 1.3, "{fold:?}");
    assert!(b.points.iter().all(|p| p.lambda >= fold.lambda - 1e-9));
    // Independently: just past the fold two 3-cycles near θ_fold, one on
    // each side of multiplier 1; just before it, none near θ_fold.
    let cyc = |tn: f64, seed: f64| {
        let sim = Simulator::new(params(18.95, tn), default_settings(1e-10)).unwrap();
        solve_cycle(&sim, seed, 3, &CycleOptions::for_settings(sim.settings())).ok()
    };
    let after = fold.lambda + 1e-4;
    let ms: Vec<f64> = [fold.theta - 0.02, fold.theta + 0.02]
        .iter()
        .filter_map(|&s| cyc(after, s))
        .filter(|c| c.minimal_period == 3)
        .map(|c| c.multiplier)
        .collect();
    assert!(
        ms.iter().any(|&m| m < 1.0) && ms.iter().any(|&m| m > 1.0),
        "{ms:?}"
    );
    let before = fold.lambda - 1e-4;
    if let Some(c) = cyc(before, fold.theta) {
        let near = c
            .points
            .iter()
            .any(|t| wrap_angle(t - fold.theta).abs() < 1e-3);
        assert!(!near || c.minimal_period != 3, "{c:?}");
    }
}

#[test]
fn a_branch_whose_slope_diverges_ends_at_a_border() {
    // κ = 1.22: the fixed point, followed up from θν = 0.5, doubles once
    // and then reaches a point where f's slope diverges (f is not smooth
    // there: the continuation cannot pass it).
    let prob = problem(1.22, 1);
    let opts = ContOptions::for_range(&prob.settings, 0.5, 1.2);
    let b = continue_branch(&prob, 0.5, 1.2, 0.45, &opts, &|| false).unwrap();
    assert_eq!(b.stop, Stop::Border, "{}", b.stop_message());
    assert_eq!(b.of_kind(SpecialKind::PeriodDoubling).count(), 1);
    let border = b.of_kind(SpecialKind::Border).next().unwrap();
    assert!(border.multiplier.abs() > 1e6, "{border:?}");
    // Independently: a central difference of the plain map at the border's
    // point, over ±1e-7, is as steep.
    let sim = Simulator::new(params(1.22, border.lambda), default_settings(1e-10)).unwrap();
    let h = 1e-7;
    let fd = wrap_angle(sim.map(border.theta + h).unwrap() - sim.map(border.theta - h).unwrap())
        / (2.0 * h);
    assert!(fd.abs() > 1e4, "{fd} at {border:?}");
    // Before it the slope is moderate.
    let calm = b.points.iter().filter(|p| p.lambda < border.lambda - 0.05);
    assert!(calm.clone().count() > 5);
    assert!(calm.into_iter().all(|p| p.multiplier.abs() < 1e3));
}
