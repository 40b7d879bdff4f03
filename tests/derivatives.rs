//! The exact derivatives of the map (`Simulator::cycle_derivatives`)
//! against Richardson-extrapolated central differences of the map itself,
//! computed independently at a tight tolerance, on the committed sample
//! (`numerics::fixed_sample` through `numerics::sample::default_attractors`).

#![allow(clippy::unwrap_used)]

use oneblock::numerics::sample::default_attractors;
use oneblock::sim::cycles_in_lanes;
use oneblock::{Method, Params, Simulator, SolverSettings};

/// The map at a tight tolerance, for the differences.
fn reference(p: Params) -> Simulator {
    Simulator::new(p, SolverSettings::adaptive(Method::Dop853, 1e-13)).unwrap()
}

/// Richardson's extrapolation of the central difference of `g` at 0 with
/// steps h and h/2: (4 D(h/2) − D(h))/3, error O(h⁴). Also returns
/// |D(h/2) − D(h)|, a measure of how far from smooth g is over the step
/// (a jump of f in between shows up there).
fn richardson(g: impl Fn(f64) -> Option<f64>, h: f64) -> Option<(f64, f64)> {
    let d = |h: f64| Some((g(h)? - g(-h)?) / (2.0 * h));
    let (d1, d2) = (d(h)?, d(h / 2.0)?);
    Some(((4.0 * d2 - d1) / 3.0, (d2 - d1).abs()))
}

/// The parameter set moved by `e` along direction `dir` (as in
/// `MapDerivatives::named`).
fn moved(p: Params, dir: usize, e: f64) -> Params {
    let mut q = p;
    match dir {
        1 => q.theta_nu += e,
        2 => q.kappa += e,
        3 => q.gamma += e,
        4 => q.nu += e,
        5 => q.omega += e,
        _ => {}
    }
    q
}

/// Every exact derivative against its Richardson estimate, at the points
/// of each committed attractor. A point is compared when f is smooth over
/// the differences' steps (the two central differences agree to 1e-3
/// relative, else a jump lies in between); nearly all are.
fn check(
    settings: SolverSettings,
    tol_rel: f64,
    tol_nu: f64,
    stride: usize,
) -> (usize, usize, f64) {
    let (mut compared, mut skipped, mut worst) = (0, 0, 0.0_f64);
    for a in default_attractors() {
        let p = a.params;
        let sim = Simulator::new(p, settings).unwrap();
        let points = a.fixed.unwrap();
        for &theta in points.iter().step_by(stride) {
            let Ok((_, Ok(d), _)) = sim.cycle_derivatives(theta, 0.0) else {
                skipped += 1;
                continue;
            };
            let exact = d.named();
            for (dir, &(name, value)) in exact.iter().enumerate() {
                // Steps scaled to each direction's size.
                let h = match dir {
                    0 | 1 => 2e-4,
                    2 => 2e-4 * p.kappa,
                    3 => 2e-4 * p.gamma,
                    4 => 2e-3 * p.nu,
                    _ => 2e-4 * p.omega,
                };
                let g = |e: f64| {
                    let q = moved(p, dir, e);
                    let th = if dir == 0 { theta + e } else { theta };
                    let r = reference(q).cycle(th, 0.0, None).ok()?;
                    (!r.restarted).then_some(r.theta_next)
                };
                let Some((rich, spread)) = richardson(g, h) else {
                    skipped += 1;
                    continue;
                };
                if spread > 1e-3 * (1.0 + rich.abs()) {
                    skipped += 1;
                    continue;
                }
                let err = (value - rich).abs() / (1.0 + rich.abs());
                worst = worst.max(err);
                compared += 1;
                // ∂f/∂ν is checked more loosely: with ν = 1e-4 the
                // differences move ν by 2e-7 and the long stick phases
                // (~1/ν) amplify the map's error in them; measured worst
                // 1.3e-3 relative on the long-stick attractor, the other
                // directions 1e-6.
                let tol = if dir == 4 { tol_nu } else { tol_rel };
                assert!(
                    err <= tol,
                    "{} θ = {theta}: {name} exact {value:e}, Richardson {rich:e} (relative error {err:e})",
                    a.name
                );
            }
        }
    }
    (compared, skipped, worst)
}

#[test]
fn derivatives_match_richardson_extrapolated_differences() {
    let (compared, skipped, worst) = check(
        SolverSettings::adaptive(Method::Dop853, 1e-11),
        1e-5,
        3e-3,
        8,
    );
    eprintln!("compared {compared}, skipped {skipped}, worst relative error {worst:e}");
    assert!(
        compared >= 10 * skipped,
        "compared {compared}, skipped {skipped}"
    );
}

/// A cycle with derivatives is bitwise the plain cycle, alone or in lanes
/// (`sim::cycles_in_lanes`): the tangents never change a step.
#[test]
fn cycles_with_derivatives_are_bitwise_the_plain_cycles_and_the_lanes() {
    for a in default_attractors() {
        let sim = Simulator::new(a.params, SolverSettings::default()).unwrap();
        let points = &a.fixed.unwrap()[..30];
        let tasks: Vec<_> = points.iter().map(|&t| (&sim, t, 0.0)).collect();
        let lanes = cycles_in_lanes(&tasks);
        for (&theta, lane) in points.iter().zip(lanes) {
            let (ev, _, _) = sim.cycle_derivatives(theta, 0.0).unwrap();
            let plain = sim.cycle(theta, 0.0, None).unwrap();
            assert_eq!(
                format!("{ev:?}"),
                format!("{plain:?}"),
                "{} θ = {theta}",
                a.name
            );
            assert_eq!(
                format!("{ev:?}"),
                format!("{:?}", lane.unwrap()),
                "{} θ = {theta}",
                a.name
            );
        }
    }
}

/// Fewer directions give the same numbers: f' alone
/// (`Simulator::cycle_slope`) and any subset of the six in any order
/// (`Simulator::cycle_partials`, as continuation asks for f' with one or
/// two parameters) are bitwise the matching entries of all six, each
/// direction's arithmetic being its own.
#[test]
fn fewer_directions_are_bitwise_the_same_derivatives() {
    use oneblock::sim::variational::{D_GAMMA, D_KAPPA, D_NU, D_OMEGA, D_THETA, D_THETA_NU};
    for a in default_attractors() {
        let sim = Simulator::new(a.params, SolverSettings::default()).unwrap();
        for &theta in a.fixed.unwrap().iter().step_by(10) {
            let (ev, all, n) = sim.cycle_derivatives(theta, 0.0).unwrap();
            let Ok(all) = all else { continue };
            let (ev1, slope, n1) = sim.cycle_slope(theta, 0.0).unwrap();
            assert_eq!(format!("{ev:?}"), format!("{ev1:?}"));
            assert_eq!((slope.unwrap().to_bits(), n1), (all.d_theta.to_bits(), n));
            let dirs = [D_OMEGA, D_THETA, D_NU, D_KAPPA, D_THETA_NU, D_GAMMA];
            let named = all.named();
            for param in [D_THETA_NU, D_KAPPA, D_GAMMA, D_NU, D_OMEGA] {
                let some = [D_THETA, param];
                let (_, d, _) = sim.cycle_partials(theta, 0.0, some).unwrap();
                for (slot, &dir) in some.iter().enumerate() {
                    assert_eq!(d.unwrap()[slot].to_bits(), named[dir].1.to_bits(), "{dir}");
                }
            }
            let (_, d, _) = sim.cycle_partials(theta, 0.0, dirs).unwrap();
            for (slot, &dir) in dirs.iter().enumerate() {
                assert_eq!(d.unwrap()[slot].to_bits(), named[dir].1.to_bits(), "{dir}");
            }
        }
    }
}

/// f' at a fixed point is its multiplier: at the Fig. 3b parameters
/// (κ = 18.95, γ = 6.5, ν = 1e-3) the fixed point loses stability by a
/// period doubling between θν = 1.08 and 1.10 (f' crosses −1 there).
#[test]
fn the_fixed_point_multiplier_crosses_minus_one_at_the_period_doubling() {
    let m = |theta_nu: f64| {
        let p = Params {
            kappa: 18.95,
            gamma: 6.5,
            nu: 1e-3,
            theta_nu,
            omega: 50.0,
        };
        let sim = Simulator::new(p, SolverSettings::adaptive(Method::Dop853, 1e-11)).unwrap();
        // Seeded between the attractor's last two iterates (the fixed
        // point, or the period-2 orbit around it once it has doubled).
        let mut th = theta_nu;
        let mut prev = th;
        for _ in 0..300 {
            prev = th;
            th = sim.map(th).unwrap();
        }
        let seed = 0.5 * (th + prev);
        let (star, mult) = oneblock::sim::fixed_point(&sim, seed, 1e-12)
            .unwrap()
            .unwrap();
        let (_, d, _) = sim.cycle_derivatives(star, 0.0).unwrap();
        assert_eq!(mult.to_bits(), d.unwrap().d_theta.to_bits());
        mult
    };
    let (before, after) = (m(1.08), m(1.10));
    assert!(
        before > -1.0 && after < -1.0,
        "f' = {before} at 1.08, {after} at 1.10"
    );
}

/// On a symmetry axis (θν = 0, onsets at and next to θ = 0) the slip has
/// no turn of v_r, so the error control cannot see that stiff mode; f' and
/// ∂f/∂θν must still match the differences there, for the isotropic and an
/// anisotropic spring (they were off by up to 1e27 when the steps outgrew
/// the mode's stability limit).
#[test]
fn derivatives_on_the_x_axis_match_richardson_extrapolated_differences() {
    for kappa in [1.0, 2.0] {
        let p = Params {
            kappa,
            gamma: 0.5,
            nu: 1e-3,
            theta_nu: 0.0,
            omega: 50.0,
        };
        let sim = Simulator::new(p, SolverSettings::adaptive(Method::Dop853, 1e-10)).unwrap();
        for theta in [0.0, 1e-12, 1e-8] {
            let (ev, d, _) = sim.cycle_derivatives(theta, 0.0).unwrap();
            assert!(!ev.restarted, "κ = {kappa}, θ = {theta}");
            let d = d.unwrap();
            let along = |dir: usize| {
                move |e: f64| {
                    let th = if dir == 0 { theta + e } else { theta };
                    let r = reference(moved(p, dir, e)).cycle(th, 0.0, None).ok()?;
                    (!r.restarted).then_some(r.theta_next)
                }
            };
            for (dir, exact) in [(0, d.d_theta), (1, d.d_theta_nu)] {
                let (rich, spread) = richardson(along(dir), 2e-4).unwrap();
                assert!(spread < 1e-4, "κ = {kappa}, θ = {theta}: not smooth");
                assert!(
                    (exact - rich).abs() <= 1e-6 * rich.abs().max(1e-2),
                    "κ = {kappa}, θ = {theta}, direction {dir}: {exact} vs {rich}"
                );
            }
        }
    }
}
