use super::*;

/// ẋ = v, v̇ = −x (and a decoupled copy): x = cos t.
fn oscillator(y: &State) -> State {
    [y[1], -y[0], y[3], -y[2]]
}

fn integrate(settings: SolverSettings, t_end: f64) -> (State, Solver, u64) {
    let mut evals = 0u64;
    let mut f = |y: &State| {
        evals += 1;
        oscillator(y)
    };
    let mut s = Solver::new(settings, [1.0; 4], 1e-3);
    let mut y = [1.0, 0.0, 0.0, 1.0];
    let mut k = f.eval(&y);
    let mut t = 0.0;
    while t < t_end {
        let (tn, yn, kn) = s.step(&mut f, t, &y, &k, t_end - t).unwrap();
        t = tn;
        y = yn;
        k = kn;
    }
    (y, s, evals)
}

fn err(y: &State, t: f64) -> f64 {
    (y[0] - t.cos()).abs().max((y[2] - t.sin()).abs())
}

#[test]
fn fixed_step_orders() {
    // Halving h divides RK4's error by ≈ 16 and Euler's by ≈ 2.
    for (m, order, h) in [(Method::Rk4, 4.0, 0.05), (Method::Euler, 1.0, 1e-3)] {
        let e1 = err(&integrate(SolverSettings::fixed(m, h), 5.0).0, 5.0);
        let e2 = err(&integrate(SolverSettings::fixed(m, h / 2.0), 5.0).0, 5.0);
        let p = (e1 / e2).log2();
        assert!((p - order).abs() < 0.15, "{m}: observed order {p}");
    }
}

#[test]
fn adaptive_methods_meet_their_tolerance() {
    for m in [Method::Dp54, Method::Dop853] {
        for tol in [1e-4, 1e-6, 1e-8, 1e-10, 1e-12] {
            let (y, s, _) = integrate(SolverSettings::adaptive(m, tol), 10.0);
            let e = err(&y, 10.0);
            // Global error over ~1.6 periods within a small factor of tol.
            assert!(e < 30.0 * tol, "{m} tol {tol}: error {e}");
            assert!(s.stats.accepted > 0);
        }
    }
}

/// On an approach like the one to a stop (the solution's time scale
/// shrinking step after step: here y = (1 − t)^(3/2), integrated to
/// within 1e-6 of t = 1 with steps capped at 0.7 of the time left), the
/// predictive controller carries the shrinking forward: fewer rejected
/// steps than the PI controller alone, for the same accuracy.
#[test]
fn the_predictive_controller_avoids_rejections_on_a_shrinking_approach() {
    let run = |predictive: bool| {
        let mut f = |y: &State| [-1.5 * y[1], -0.5 / y[1], 0.0, 0.0];
        let mut s = Solver::new(
            SolverSettings::adaptive(Method::Dop853, 1e-10),
            [1.0; 4],
            1e-3,
        );
        s.predictive = predictive;
        // y[0] = (1 − t)^1.5, y[1] = (1 − t)^0.5.
        let mut y = [1.0, 1.0, 0.0, 0.0];
        let mut k = f(&y);
        let mut t = 0.0;
        while 1.0 - t > 1e-6 {
            let (tn, yn, kn) = s.step(&mut f, t, &y, &k, 0.7 * (1.0 - t)).unwrap();
            (t, y, k) = (tn, yn, kn);
        }
        let err = (y[0] - (1.0 - t).powf(1.5)).abs();
        (s.stats, err)
    };
    let (pi, e_pi) = run(false);
    let (pred, e_pred) = run(true);
    assert!(e_pi < 1e-8 && e_pred < 1e-8, "{e_pi:e} {e_pred:e}");
    assert!(
        2 * pred.rejected < pi.rejected,
        "rejected: {} predictive, {} PI ({} and {} accepted)",
        pred.rejected,
        pi.rejected,
        pred.accepted,
        pi.accepted
    );
}

#[test]
fn dense_output_is_accurate_inside_steps() {
    for (m, tol) in [(Method::Dp54, 1e-10), (Method::Dop853, 1e-12)] {
        let mut f = |y: &State| oscillator(y);
        let mut s = Solver::new(SolverSettings::adaptive(m, tol), [1.0; 4], 0.5);
        let y = [1.0, 0.0, 0.0, 1.0];
        let k = f.eval(&y);
        let (t1, _, _) = s.step(&mut f, 0.0, &y, &k, 1.0).unwrap();
        let d = s.dense(&mut f);
        for i in 0..=10 {
            let t = t1 * i as f64 / 10.0;
            let yi = d.at(t);
            assert!(
                (yi[0] - t.cos()).abs() < 1e3 * tol,
                "{m} at {t}: {}",
                yi[0] - t.cos()
            );
        }
    }
}
