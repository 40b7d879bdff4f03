//! Cycles solved rather than waited for: Newton's method on f^p(θ) = θ, the
//! exact exponent of a periodic orbit, and the classifiers (orbit, phase
//! grid, sweeps) that solve a slowly approached cycle instead of giving up.

use crate::common;

use common::fixture::preset;

use common::until_finished;
use oneblock::integrate::SolverSettings;
use oneblock::model::Params;
use oneblock::numerics::{Accuracy, budget_for};
use oneblock::sim::MapChoice;
use oneblock::sim::{
    CycleFailure, CycleOptions, OrbitOptions, Period, Simulator, default_settings, fixed_point,
    solve_cycle,
};
use oneblock::worker::{Axis, Command, Lane, Outcome, SweepSpec, Update, Worker, WorkerConfig};
use std::sync::Arc;

fn sim(p: Params) -> Simulator {
    Simulator::new(p, default_settings(1e-10)).expect("valid")
}

/// f'(θ) by a central difference with a step of its own (1e-4), independent
/// of the solver's.
fn slope(s: &Simulator, theta: f64) -> f64 {
    let h = 1e-4;
    (s.map(theta + h).expect("a value") - s.map(theta - h).expect("a value")) / (2.0 * h)
}

#[test]
fn newton_converges_quadratically_onto_a_fixed_point() {
    // Fig. 3b at θν = 1.0: a stable stick-slip fixed point.
    let s = sim(preset("fig3b"));
    let full = CycleOptions::for_settings(s.settings());
    let star = solve_cycle(&s, 0.45, 1, &full).expect("a fixed point");
    let th = star.points[0];
    assert!(
        (s.map(th).expect("a value") - th).abs() < 1e-9,
        "f(θ*) = θ*"
    );
    // The residual after k steps, from a seed 0.01 rad away: each at most
    // a fixed multiple of the square of the one before, and the ratio of
    // successive residuals falling (superlinear), down to the map's own
    // error.
    let seed = th + 0.01;
    let residual = |k: usize| match solve_cycle(
        &s,
        seed,
        1,
        &CycleOptions {
            tol: 0.0,
            floor: 0.0,
            max_iter: k,
            ..full
        },
    ) {
        Err(CycleFailure::NoConvergence { residual, .. }) => residual,
        other => panic!("after {k} steps: {other:?}"),
    };
    let r: Vec<f64> = (0..5).map(residual).collect();
    assert!(r[0] > 5e-3, "{r:?}");
    let mut quadratic_steps = 0;
    for k in 0..4 {
        if r[k + 1] < 1e-11 {
            break;
        }
        assert!(
            r[k + 1] <= 20.0 * r[k] * r[k],
            "step {k} is not quadratic: {r:?}"
        );
        if k > 0 {
            assert!(r[k + 1] / r[k] < r[k] / r[k - 1], "step {k}: {r:?}");
        }
        quadratic_steps += 1;
    }
    assert!(quadratic_steps >= 2, "{r:?}");
    // The multiplier is f'(θ*) by an independent difference.
    assert!((star.multiplier - slope(&s, th)).abs() < 1e-4);
    assert!(star.stable && star.multiplier.abs() < 1.0);
}

#[test]
fn a_period_two_orbit_has_the_exponent_ln_m_over_two() {
    let p = preset("fig3b").with_theta_nu(1.15);
    let s = sim(p);
    let opts = OrbitOptions {
        transient: 400,
        keep: 128,
        lyapunov: true,
        period_tol: OrbitOptions::period_tol_for(1e-10),
    };
    let o = s.orbit(p.theta_nu, &opts, &|| false).expect("an orbit");
    assert_eq!(o.period, Period::Periodic(2));
    let c = o.cycle.as_ref().expect("a solved cycle");
    assert_eq!(o.lyapunov_stderr, None, "an exact value has no error bar");
    // The multiplier from the two points' slopes, computed independently.
    let m = slope(&s, c.points[0]) * slope(&s, c.points[1]);
    assert!((c.multiplier - m).abs() < 1e-4, "{} vs {m}", c.multiplier);
    let l = o.lyapunov.expect("an exponent");
    assert!(
        (l - m.abs().ln() / 2.0).abs() < 1e-4,
        "{l} vs {}",
        m.abs().ln() / 2.0
    );
    // The two points are the orbit's, to the period tolerance.
    let last = &o.thetas()[o.events.len() - 2..];
    let near = |x: f64| c.points.iter().any(|q| (q - x).abs() < 1e-6);
    assert!(last.iter().all(|&x| near(x)), "{last:?} vs {:?}", c.points);
}

#[test]
fn the_flip_of_fig_3b_lies_between_1_08_and_1_10() {
    // Fixed point from the stable side, then continued by Newton past the
    // flip, where iterating could not find it.
    let opts = CycleOptions::for_settings(&default_settings(1e-10));
    let a = sim(preset("fig3b").with_theta_nu(1.08));
    let fa = solve_cycle(&a, 1.0, 1, &opts).expect("a fixed point at 1.08");
    let b = sim(preset("fig3b").with_theta_nu(1.10));
    let fb = solve_cycle(&b, fa.points[0], 1, &opts).expect("a fixed point at 1.10");
    assert!(fa.multiplier > -1.0 && fa.stable, "{}", fa.multiplier);
    assert!(fb.multiplier < -1.0 && !fb.stable, "{}", fb.multiplier);
    for (s, c) in [(&a, &fa), (&b, &fb)] {
        let th = c.points[0];
        assert!((s.map(th).expect("a value") - th).abs() < 1e-9);
        assert!((c.multiplier - slope(s, th)).abs() < 1e-4);
    }
}

#[test]
fn the_fig_3a_point_is_a_fixed_point_within_the_default_budget() {
    let p = preset("fig3a");
    let s = sim(p);
    let opts = OrbitOptions {
        transient: 400,
        keep: 128,
        lyapunov: true,
        period_tol: OrbitOptions::period_tol_for(1e-10),
    };
    let o = s.orbit(p.theta_nu, &opts, &|| false).expect("an orbit");
    assert_eq!(o.period, Period::Periodic(1));
    let c = o.cycle.expect("solved");
    // The secant solver, started afresh, lands on the same point.
    let (star, m) = fixed_point(&s, p.theta_nu, 1e-11)
        .expect("no error")
        .expect("a fixed point");
    assert!(
        (c.points[0] - star).abs() < 1e-6,
        "{} vs {star}",
        c.points[0]
    );
    assert!((c.multiplier - m).abs() < 1e-4);
    // Slow: iterating alone leaves it undecided.
    assert!(c.multiplier > 0.98 && c.multiplier < 1.0);
}

/// Issue 38: the creep grid run as the user runs it, through `oneblock
/// phase` (the grid's job), not the core's `phase_grid` beside it.
#[test]
fn the_creep_grid_has_no_undecided_cell() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args([
            "phase",
            "--gamma",
            "0.5",
            "--nu",
            "1e-3",
            "--kappa-from",
            "1",
            "--kappa-to",
            "42",
            "--kappa-steps",
            "30",
            "--theta-nu-from",
            "0",
            "--theta-nu-to",
            "1.5707963267948966",
            "--theta-nu-steps",
            "30",
        ])
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = String::from_utf8(out.stdout).expect("utf-8");
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).expect(name);
    let (tn, kappa, class, lambda) = (col("theta_nu"), col("kappa"), col("class"), col("lyapunov"));
    let cells: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(cells.len(), 900);
    // Pure creep: every cell is a fixed point that attracts (none left
    // undecided).
    for c in &cells {
        assert_eq!(c[class], "FP", "κ {} θν {}", c[kappa], c[tn]);
        assert!(c[lambda].parse::<f64>().is_ok_and(|l| l < 0.0), "{c:?}");
    }
    // Its exponent is ln|f'| at the fixed point the secant solver finds
    // from θν (a few cells across the grid).
    for c in cells.iter().step_by(97) {
        let (k, t): (f64, f64) = (c[kappa].parse().unwrap(), c[tn].parse().unwrap());
        let s = sim(Params {
            kappa: k,
            ..preset("creep").with_theta_nu(t)
        });
        let (star, _) = fixed_point(&s, t, 1e-12)
            .expect("no error")
            .expect("a fixed point");
        let expected = slope(&s, star).abs().ln();
        let got: f64 = c[lambda].parse().unwrap();
        assert!(
            (got - expected).abs() < 1e-5 + 1e-3 * expected.abs(),
            "κ {k} θν {t}: λ {got} vs {expected}"
        );
    }
}

/// Every column of `a` within `tol` of the column of `b` at the same θν
/// (as sets of values).
fn worst_gap(a: &[(f64, Vec<f64>)], b: &[(f64, Vec<f64>)]) -> f64 {
    let dist = |x: f64, set: &[f64]| {
        set.iter()
            .map(|y| (x - y).abs())
            .fold(f64::INFINITY, f64::min)
    };
    a.iter()
        .zip(b)
        .map(|((ta, ca), (tb, cb))| {
            assert_eq!(ta, tb);
            assert!(!ca.is_empty() && !cb.is_empty());
            let ab = ca.iter().map(|&x| dist(x, cb)).fold(0.0, f64::max);
            let ba = cb.iter().map(|&x| dist(x, ca)).fold(0.0, f64::max);
            ab.max(ba)
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_creep_diagram_at_auto_accuracy_is_the_reference_to_a_pixel() {
    let p = preset("creep");
    let columns = 400;
    let (from, to) = (0.0, std::f64::consts::FRAC_PI_2);
    // The window: its sweep at Auto accuracy, 300 + 200 iterates a column.
    let auto = budget_for(Accuracy::BifurcationDiagram.target()).settings;
    let w = Worker::spawn(WorkerConfig::default(), Arc::new(|| {}));
    assert!(w.send(Command::run(
        1,
        SweepSpec {
            params: p,
            settings: auto,
            param: oneblock::sim::continuation::ContParam::ThetaNu,
            axis: Axis::new(from, to, columns),
            transient: 300,
            keep: 200,
            map: MapChoice::Auto,
            theta0: None,
            seeds: 0,
        }
    )));
    let (ups, outcome) = until_finished(&w, 1, Lane::Sweep);
    assert_eq!(outcome, Outcome::Completed);
    w.shutdown();
    let mut window: Vec<(f64, Vec<f64>)> = vec![(f64::NAN, vec![]); columns];
    for u in ups {
        if let Update::Column {
            index,
            value: theta_nu,
            thetas,
            ..
        } = u
        {
            window[index] = (theta_nu, thetas);
        }
    }
    // `oneblock bifurcation` at tol 1e-10 (its defaults: 500 + 100), the
    // same sweep job without the interpolant.
    let reference_settings = SolverSettings::adaptive(oneblock::Method::Dop853, 1e-10);
    let spec = SweepSpec {
        params: p,
        settings: reference_settings,
        param: oneblock::sim::continuation::ContParam::ThetaNu,
        axis: Axis::new(from, to, columns),
        transient: 500,
        keep: 100,
        map: MapChoice::Direct,
        theta0: None,
        seeds: 0,
    };
    let ups = oneblock::jobs::run_collect(oneblock::jobs::Spec::Sweep(spec), 2, |_| {}, || false)
        .expect("the reference sweep completes");
    let mut reference: Vec<(f64, Vec<f64>)> = vec![(f64::NAN, vec![]); columns];
    for u in ups {
        if let Update::Column {
            index,
            value: theta_nu,
            thetas,
            ..
        } = u
        {
            reference[index] = (theta_nu, thetas);
        }
    }
    let all = reference.iter().flat_map(|(_, t)| t.iter().copied());
    let (lo, hi) = all.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    let pixel = (hi - lo) / columns as f64;
    let gap = worst_gap(&window, &reference);
    assert!(
        gap <= pixel,
        "{gap:e} > one pixel {pixel:e} (Auto = {auto:?})"
    );
}

/// `oneblock cycle` with `args` after the Fig. 3b preset (θν = 1.0).
fn cycle_cli(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args(["cycle", "--preset", "fig3b"])
        .args(args)
        .output()
        .expect("the binary runs")
}

#[test]
fn the_cycle_command_solves_and_refuses_bad_input_in_one_line() {
    let ok = cycle_cli(&["--period", "1", "--theta", "0.45", "--json"]);
    assert_eq!(ok.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&ok.stdout).expect("JSON");
    let th = v["points"][0].as_f64().expect("a point");
    let s = sim(preset("fig3b"));
    assert!((s.map(th).expect("a value") - th).abs() < 1e-9);
    assert_eq!(v["stable"], true);
    for (args, flag) in [
        (["--period", "0", "--theta", "0.45"], "--period"),
        (["--period", "65", "--theta", "0.45"], "--period"),
        (["--period", "-2", "--theta", "0.45"], "--period"),
        (["--period", "1", "--theta", "NaN"], "--theta"),
        (["--period", "1", "--theta", "3.0"], "--theta"),
    ] {
        let o = cycle_cli(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.starts_with("error: ") && err.contains(flag), "{err}");
    }
}

#[test]
fn a_failed_solve_is_one_line_with_its_reason_and_exit_1() {
    // The intermittent orbit's map jumps where its large slips start: from
    // this seed Newton stalls against the jump.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args([
            "cycle",
            "--kappa",
            "50",
            "--gamma",
            "6.5",
            "--nu",
            "1e-4",
            "--theta-nu",
            "1.4",
            "--period",
            "1",
            "--theta",
            "0.5",
        ])
        .output()
        .expect("the binary runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("no 1-cycle from theta = 0.5") && err.contains("convergence"));
    assert!(o.stdout.is_empty());
}

/// Issue 28: where f hugs the identity (creep, multiplier 0.99998) a
/// residual below the floor is still 3e-6 from the fixed point; Newton
/// goes on until its step |g/(1 − m)| is within the tolerance, and lands
/// on the zero of f(θ) − θ that a bisection of the plain map finds.
#[test]
fn the_creep_fixed_point_is_where_bisection_on_the_map_puts_it() {
    let s = sim(Params {
        kappa: 18.95,
        gamma: 0.5,
        nu: 1e-5,
        theta_nu: 0.2,
        omega: 50.0,
    });
    let opts = CycleOptions::for_settings(s.settings());
    let c = solve_cycle(&s, 0.2, 1, &opts).expect("a fixed point");
    assert!((c.multiplier - 1.0).abs() < 1e-3, "{c:?}");
    assert!(c.step <= opts.tol, "{c:?}");
    assert!(c.iterations >= 1, "{c:?}");
    // Bisection on g(θ) = f(θ) − θ over a bracket round the seed.
    let g = |th: f64| oneblock::model::wrap_angle(s.map(th).expect("a value") - th);
    let (mut a, mut b) = (0.2 - 1e-3, 0.2 + 1e-3);
    let (mut ga, gb) = (g(a), g(b));
    assert!(ga * gb < 0.0, "{ga} {gb}");
    for _ in 0..60 {
        let m = 0.5 * (a + b);
        let gm = g(m);
        if gm * ga > 0.0 {
            (a, ga) = (m, gm);
        } else {
            b = m;
        }
    }
    let bisected = 0.5 * (a + b);
    // Within the map's own error over the slope: |g| ~ 1e-13 / 2e-5.
    assert!(
        (c.points[0] - bisected).abs() < 1e-7,
        "Newton {} vs bisection {bisected}",
        c.points[0]
    );
}
