//! The criticality of period doublings (issue 28): the flip's normal-form
//! coefficient from G and the exact multiplier at θ* ± H, checked against
//! the doubled cycle that Newton solves on its own a little past the flip
//! (its half-width, its stability and the side it lies on).

#![allow(clippy::unwrap_used)]

use oneblock::model::{Params, wrap_angle};
use oneblock::sim::continuation::{
    ContOptions, ContParam, Criticality, Problem, SpecialKind, SpecialPoint, continue_branch,
};
use oneblock::sim::{CycleOptions, Simulator, default_settings, solve_cycle};

fn problem(kappa: f64, nu: f64) -> Problem {
    Problem {
        base: Params {
            kappa,
            gamma: 6.5,
            nu,
            theta_nu: 1.0,
            omega: 50.0,
        },
        settings: default_settings(1e-10),
        param: ContParam::ThetaNu,
        period: 1,
    }
}

/// The first PD of the fixed point followed from `from` to `to`.
fn first_pd(prob: &Problem, from: f64, to: f64, seed: f64) -> SpecialPoint {
    let opts = ContOptions::for_range(&prob.settings, from, to);
    let b = continue_branch(prob, from, to, seed, &opts, &|| false).unwrap();
    b.of_kind(SpecialKind::PeriodDoubling)
        .next()
        .cloned()
        .unwrap()
}

/// The 2p-cycle Newton finds at `lambda` from the predicted point: its
/// half-width |θ_p − θ₀|/2 (the two points that split from θ*) and its
/// multiplier.
fn doubled(prob: &Problem, pd: &SpecialPoint, lambda: f64, eta: f64) -> (f64, f64) {
    let sim = Simulator::new(prob.param.set(&prob.base, lambda), prob.settings).unwrap();
    let opts = CycleOptions::for_settings(sim.settings());
    let p = prob.period;
    let c = solve_cycle(&sim, pd.theta + eta, 2 * p, &opts).unwrap();
    assert_eq!(c.minimal_period, 2 * p, "{c:?}");
    (
        0.5 * wrap_angle(c.points[p] - c.points[0]).abs(),
        c.multiplier,
    )
}

/// The stable 2p-cycle Newton solves at each distance `deltas` above the
/// supercritical flip `pd` has the predicted half-width, within 1 %.
fn grows_as_predicted(prob: &Problem, pd: &SpecialPoint, deltas: [f64; 2]) {
    let f = pd.flip.unwrap();
    for delta in deltas {
        let lambda = pd.lambda + delta;
        let eta = f.predicted(pd.lambda, lambda).unwrap();
        let (measured, m) = doubled(prob, pd, lambda, eta);
        assert!(m.abs() < 1.0, "the born cycle is stable: m = {m}");
        assert!(
            (measured / eta - 1.0).abs() < 0.01,
            "delta {delta}: measured half-width {measured} vs predicted {eta}"
        );
    }
}

#[test]
fn fig3b_p8_flip_predicts_the_p16_cycle() {
    // Deep in the cascade g = f^8 bends on a small scale: its differences
    // take a step of 1/8 the fixed point's. The P8 cycle at θν = 1.2235,
    // followed up to its flip near 1.22399.
    let mut prob = problem(18.95, 1e-3);
    prob.period = 8;
    let sim = Simulator::new(prob.param.set(&prob.base, 1.2235), prob.settings).unwrap();
    let opts = CycleOptions::for_settings(sim.settings());
    let p8 = solve_cycle(&sim, 0.4537, 8, &opts).unwrap();
    assert_eq!(p8.minimal_period, 8, "{p8:?}");
    let pd = first_pd(&prob, 1.2235, 1.2245, p8.points[0]);
    assert!((pd.lambda - 1.223_99).abs() < 1e-4, "{pd:?}");
    let f = pd.flip.unwrap();
    assert_eq!(f.criticality(), Criticality::Supercritical, "{f:?}");
    assert_eq!(f.side(), 1.0, "the P8 loses stability upwards: {f:?}");
    grows_as_predicted(&prob, &pd, [1e-6, 1e-5]);
}

#[test]
fn fig3b_first_flip_is_supercritical_and_its_cycle_grows_as_predicted() {
    let prob = problem(18.95, 1e-3);
    let pd = first_pd(&prob, 1.0, 1.2, 0.4);
    assert!((pd.lambda - 1.0896).abs() < 1e-3, "{pd:?}");
    let f = pd.flip.unwrap();
    assert_eq!(f.criticality(), Criticality::Supercritical, "{f:?}");
    // The fixed point loses stability upwards (m < −1 above): the stable
    // P2 cycle is born above.
    assert_eq!(f.side(), 1.0);
    grows_as_predicted(&prob, &pd, [1e-5, 1e-4]);
    // Nothing on the other side.
    assert!(f.predicted(pd.lambda, pd.lambda - 1e-4).is_none());
}

#[test]
fn fig3a_last_flip_of_the_fixed_point_is_subcritical() {
    // Fig. 3a (κ = 50, ν = 1e-4): the fixed point, stable at θν = 1.56
    // (m = −0.31), followed down to its flip near 1.552.
    let prob = problem(50.0, 1e-4);
    let pd = first_pd(&prob, 1.56, 1.50, 1.0);
    assert!((pd.lambda - 1.552).abs() < 1e-3, "{pd:?}");
    let f = pd.flip.unwrap();
    assert_eq!(f.criticality(), Criticality::Subcritical, "{f:?}");
    // The doubled cycle lies on the fixed point's stable side (above), and
    // is unstable there: the reverse cascade does not end in a doubling.
    assert_eq!(f.side(), 1.0);
    let lambda = pd.lambda + 1e-5;
    let eta = f.predicted(pd.lambda, lambda).unwrap();
    let (measured, m) = doubled(&prob, &pd, lambda, eta);
    assert!(
        m.abs() > 1.0,
        "the P2 cycle next to a subcritical flip is unstable: m = {m}"
    );
    assert!(
        (measured / eta - 1.0).abs() < 0.01,
        "measured half-width {measured} vs predicted {eta}"
    );
}

#[test]
fn a_cascade_at_a_subcritical_flip_follows_the_unstable_cycle_to_its_fold() {
    let prob = problem(50.0, 1e-4);
    let opts = ContOptions::for_range(&prob.settings, 1.56, 1.50);
    let c = oneblock::sim::continuation::cascade(
        oneblock::sim::continuation::Reach::new(&prob, 1.56, 1.50, &opts),
        1.0,
        64,
        &|| false,
    )
    .unwrap();
    // The flip is a doubling of the fixed point, but nothing is switched
    // onto: the cascade ends there and says so.
    assert_eq!(c.doublings.len(), 1, "{}", c.stop);
    assert!(
        c.stop.starts_with("subcritical flip of the P1 cycle"),
        "{}",
        c.stop
    );
    let b = c.branches.last().unwrap();
    assert_eq!(b.period, 2);
    // The P2 cycle next to the flip is unstable, and it turns at a real
    // fold above the flip (m = +1 there).
    assert!(!b.points[0].stable, "{:?}", b.points[0]);
    let fold = b.of_kind(SpecialKind::Fold).next().unwrap();
    assert!(fold.lambda > c.doublings[0].lambda, "{fold:?}");
    assert!((fold.multiplier - 1.0).abs() <= oneblock::sim::continuation::M_ACCURACY);
    assert!(c.stop.contains("turns at a fold"), "{}", c.stop);
}

/// The generalised flip on the fixed point's PD curve near Fig. 3b's κ:
/// following the flip near θν = 1.538 in (θν, κ), its coefficient changes
/// sign once between κ = 17 and 21, near κ = 19.0; the flips located on
/// their own, along θν at κ = 18.8 and 19.2, are supercritical and
/// subcritical.
#[test]
fn a_pd_curve_marks_where_its_criticality_changes() {
    use oneblock::sim::continuation::{CurveKind, CurveOf, CurveOptions, continue_curve};
    let below = problem(18.8, 1e-3);
    let above = problem(19.2, 1e-3);
    let crit = |prob: &Problem| {
        let pd = first_pd(prob, 1.56, 1.50, 1.0);
        (pd.flip.unwrap().criticality(), pd)
    };
    let (c_below, pd) = crit(&below);
    let (c_above, _) = crit(&above);
    assert_eq!(c_below, Criticality::Supercritical);
    assert_eq!(c_above, Criticality::Subcritical);
    let of = CurveOf {
        base: below.base,
        settings: below.settings,
        params: [ContParam::ThetaNu, ContParam::Kappa],
        period: 1,
        kind: CurveKind::PeriodDoubling,
    };
    let copts = CurveOptions::for_box([[1.50, 1.56], [17.0, 21.0]]);
    let curve = continue_curve(&of, &pd, &copts, &|| false);
    assert!(curve.points.len() > 10, "{curve:?}");
    let gf = &curve.generalised_flips;
    assert_eq!(gf.len(), 1, "{gf:?}");
    let [theta_nu, kappa] = gf[0].lambda;
    assert!(kappa > 18.8 && kappa < 19.2, "{gf:?}");
    assert!(theta_nu > 1.53 && theta_nu < 1.545, "{gf:?}");
    let [a, b] = gf[0].coefficients;
    assert!(a * b < 0.0, "{gf:?}");
}
