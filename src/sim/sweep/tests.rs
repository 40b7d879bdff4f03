use super::*;
use crate::integrate::Method;
use crate::model::wrap_angle;

/// Every cycle integrated: the reference the early exit must reproduce.
fn brute_force(
    params: Params,
    settings: SolverSettings,
    theta_nu: f64,
    opts: &SweepOptions,
) -> Vec<f64> {
    let sim = Simulator::new(params.with_theta_nu(theta_nu), settings).unwrap();
    let mut theta = theta_nu;
    let mut kept = vec![];
    for i in 0..opts.transient + opts.keep {
        let ev = sim.cycle(theta, 0.0, None).unwrap();
        if i >= opts.transient {
            kept.push(ev.theta);
        }
        theta = sim.next_onset(&ev);
    }
    kept
}

#[test]
fn settled_columns_match_full_integration() {
    let params = Params::default();
    let settings = SolverSettings::adaptive(Method::Dop853, 1e-8);
    let opts = SweepOptions {
        transient: 300,
        keep: 200,
        map: crate::sim::MapChoice::Direct,
    };
    // Fig. 3b: fixed points, period 2 and 4, chaos, period 3.
    for tn in [0.3, 1.0, 1.12, 1.2, 1.25, 1.3] {
        let col = Column::run(params, settings, tn, tn, &opts, &|| false);
        let reference = brute_force(params, settings, tn, &opts);
        assert_eq!(col.thetas.len(), reference.len());
        let worst = col
            .thetas
            .iter()
            .zip(&reference)
            .map(|(a, b)| wrap_angle(a - b).abs())
            .fold(0.0, f64::max);
        // Chaotic columns never settle, so they are bit-identical; the
        // others agree to far below a pixel (1e-3 of the θ range).
        assert!(worst < 1e-5, "θν = {tn}: early exit differs by {worst:e}");
    }
}

/// A slow pure-creep fixed point (multiplier ≈ 0.99): the column is its
/// solved fixed point, which the whole integration only approaches.
#[test]
fn a_slow_column_is_its_solved_fixed_point() {
    let settings = SolverSettings::adaptive(Method::Dop853, 1e-10);
    let opts = SweepOptions {
        transient: 300,
        keep: 200,
        map: crate::sim::MapChoice::Direct,
    };
    let creep = Params {
        kappa: 3.0,
        gamma: 0.5,
        nu: 1e-3,
        theta_nu: 0.7,
        omega: 50.0,
    };
    let tn = creep.theta_nu;
    let col = Column::run(creep, settings, tn, tn, &opts, &|| false);
    let sim = Simulator::new(creep, settings).unwrap();
    let (star, _) = crate::sim::fixed_point(&sim, tn, 1e-12).unwrap().unwrap();
    let off = |xs: &[f64]| xs.iter().map(|x| (x - star).abs()).fold(0.0, f64::max);
    assert_eq!(col.thetas.len(), opts.keep);
    assert!(off(&col.thetas) < 1e-7, "{:e}", off(&col.thetas));
    assert!((col.theta_last - star).abs() < 1e-7);
    let reference = brute_force(creep, settings, tn, &opts);
    assert!(off(&reference) > off(&col.thetas));
}

#[test]
fn grids_over_the_widest_ranges_stay_finite() {
    let g = theta_nu_grid(-1e308, 1e308, 5);
    assert!(g.iter().all(|v| v.is_finite()), "{g:?}");
    assert_eq!((g[0], g[2], g[4]), (-1e308, 0.0, 1e308));
    assert_eq!(theta_nu_grid(0.0, 1.0, 3), [0.0, 0.5, 1.0]);
}

/// κ, ν, Ω columns are evenly spaced in log10 of the value, their ends
/// exact; γ's and θν's evenly in the value.
#[test]
fn grids_in_parameters_that_span_decades_are_logarithmic() {
    use crate::sim::continuation::ContParam;
    let g = param_grid(ContParam::Kappa, 1.0, 100.0, 3);
    assert_eq!((g[0], g[2]), (1.0, 100.0));
    assert!((g[1] - 10.0).abs() < 1e-12, "{g:?}");
    let g = param_grid(ContParam::Nu, 1e-5, 1e-2, 7);
    let ratios: Vec<f64> = g.windows(2).map(|w| w[1] / w[0]).collect();
    assert!(
        ratios.iter().all(|r| (r - 10f64.sqrt()).abs() < 1e-12),
        "{ratios:?}"
    );
    assert_eq!((g[0], g[6]), (1e-5, 1e-2));
    assert_eq!(param_grid(ContParam::Gamma, 1.0, 2.0, 3), [1.0, 1.5, 2.0]);
    assert_eq!(param_grid(ContParam::Omega, 50.0, 50.0, 1), [50.0]);
}

/// A long transient is streamed: a column holds the settle window and
/// its kept iterates, not the transient, and keeps the same iterates
/// as a short transient from the same settled state would.
#[test]
fn long_transients_are_streamed() {
    let params = Params::default();
    let settings = SolverSettings::adaptive(Method::Dop853, 1e-8);
    // Chaos (θν = 1.25) never settles, so every transient iterate is
    // integrated and dropped as the column goes.
    let sim = Simulator::new(params.with_theta_nu(1.25), settings).unwrap();
    let opts = SweepOptions {
        transient: 3000,
        keep: 5,
        map: crate::sim::MapChoice::Direct,
    };
    let mut run = ColumnRun::new(&sim, 1.25, None, &opts);
    let mut most = 0;
    while let Some(theta) = run.next_onset(&sim, &|| false) {
        run.take(&sim, sim.cycle(theta, 0.0, None));
        most = most.max(run.onsets.len());
    }
    assert!(
        most <= 5 * SETTLE_WINDOW + opts.keep + 1,
        "held {most} onsets"
    );
    let col = run.finish();
    assert_eq!(col.thetas.len(), 5);
    assert_eq!(col.thetas, brute_force(params, settings, 1.25, &opts));
    // A fixed point settles early; the transient's end is reached by
    // repeating the cycle, without a vector the transient's length.
    let huge = SweepOptions {
        transient: 1 << 40,
        keep: 3,
        map: crate::sim::MapChoice::Direct,
    };
    let col = Column::run(params, settings, 0.3, 0.3, &huge, &|| false);
    assert!(col.error.is_none());
    assert_eq!(col.thetas.len(), 3);
    assert!(col.thetas.iter().all(|t| (t - col.thetas[0]).abs() < 1e-9));
}
