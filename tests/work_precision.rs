//! The work-precision command and the accuracy budget built from its chart:
//! the cheap setting a bifurcation diagram gets must not change the
//! attractor (period and Lyapunov sign as at tol 1e-12).

#![allow(clippy::unwrap_used)]

use crate::common;
use common::fixture::preset;

use std::process::Command;

use oneblock::numerics::{Accuracy, budget_for, settings_for};
use oneblock::sim::{OrbitOptions, Period};
use oneblock::{Method, Params, Simulator, SolverSettings};

fn orbit(p: Params, s: SolverSettings) -> (Period, f64) {
    let sim = Simulator::new(p, s).unwrap();
    let o = sim
        .orbit(
            p.theta_nu,
            &OrbitOptions {
                transient: 400,
                keep: 200,
                lyapunov: true,
                // One test for both tolerances: what a diagram shows apart
                // (a tenth of its ~1e-3 pixel).
                period_tol: 1e-4,
            },
            &|| false,
        )
        .unwrap();
    (o.period, o.lyapunov.unwrap())
}

#[test]
fn bifurcation_budget_keeps_period_and_lyapunov_sign() {
    let (cheap, err, evals) = settings_for(Accuracy::BifurcationDiagram.target());
    let tight = SolverSettings::adaptive(Method::Dop853, 1e-12);
    println!(
        "bifurcation: {} tol {:e} (max map error {err:.1e}, {evals} RHS evaluations per iterate)",
        cheap.method, cheap.rtol
    );
    // At most 1/2.5 of the return map's evaluations: 224 against 605 on
    // the chart (2.7×) since the steps are capped inside the stability
    // interval of v̂_r's stiff turning, which costs loose tolerances most;
    // 195 against 620 (3.2×) before.
    assert!(err <= 1e-3 && evals < budget_for(1e-10).est_evals / 2.5);
    let cases = [
        // Fig. 3b (pure stick-slip): fixed point, period 2, period 4, chaos
        // (`chaos`), the period-3 window.
        preset("fig3b").with_theta_nu(0.5),
        preset("fig3b").with_theta_nu(1.1),
        preset("fig3b").with_theta_nu(1.2),
        preset("chaos"),
        preset("fig3b").with_theta_nu(1.3),
        // Fig. 3a (mixed): creep fixed point (`fig3a`),
        // intermittent chaos (`intermittent`), the fixed point near π/2.
        preset("fig3a"),
        preset("intermittent"),
        preset("fig3a").with_theta_nu(1.55),
        // The app's other presets as they open: `fig3b`, `fig4`, `creep`.
        preset("fig3b"),
        preset("fig4"),
        preset("creep"),
    ];
    for p in cases {
        let Params {
            kappa,
            gamma,
            theta_nu,
            ..
        } = p;
        let (pc, lc) = orbit(p, cheap);
        let (pt, lt) = orbit(p, tight);
        println!(
            "kappa {kappa} gamma {gamma} theta-nu {theta_nu}: period {pc} / {pt}, \
             lyapunov {lc:.4} / {lt:.4}"
        );
        assert_eq!(pc, pt, "kappa {kappa} gamma {gamma} theta-nu {theta_nu}");
        assert_eq!(
            lc > 0.0,
            lt > 0.0,
            "kappa {kappa} gamma {gamma} theta-nu {theta_nu}"
        );
    }
}

#[test]
fn the_views_get_the_settings_the_chart_says() {
    for a in [
        Accuracy::TrajectoryView,
        Accuracy::BifurcationDiagram,
        Accuracy::ReturnMap,
        Accuracy::PhaseDiagram,
    ] {
        let b = budget_for(a.target());
        println!(
            "{a:?}: {} tol {:e}, max error {:.1e}, {:.0} evaluations, {:.0} µs",
            b.settings.method, b.settings.rtol, b.est_error, b.est_evals, b.est_us
        );
        assert!(b.est_error <= a.target());
        b.settings.validate().unwrap();
    }
}

#[test]
fn work_precision_command_writes_csv_and_svg() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("wp.csv");
    let svg = dir.path().join("wp.svg");
    let o = Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args(["work-precision", "--points", "1", "--only", "dop853"])
        .args(["--min-time-ms", "0", "--out"])
        .arg(&csv)
        .arg("--svg")
        .arg(&svg)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert!(lines[0].starts_with("method,kind,setting"));
    // DOP853 and the peer's Dop853 over 11 tolerances each.
    assert_eq!(lines.len(), 1 + 22, "{text}");
    assert!(text.contains("reference DOP853 tol 1e-14"));
    assert!(text.contains("load average"));
    let svg = std::fs::read_to_string(&svg).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("ode_solvers-dop853"));

    // Bad input is a usage error naming the flag; an existing file is kept.
    let bad = Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args(["work-precision", "--points", "0", "--out"])
        .arg(&csv)
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--points"));
    let exists = Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args(["work-precision", "--points", "1", "--out"])
        .arg(&csv)
        .output()
        .unwrap();
    assert_eq!(exists.status.code(), Some(2));
}

/// The committed sample is what it says it is: each point is, to the
/// reference's accuracy, the reference map's image of the one before (the
/// orbit is chaotic, so this holds from point to point, not along the
/// list), and it lies on its attractor's exit arc (`map` rejects any other).
#[test]
fn the_committed_sample_is_a_reference_orbit() {
    use oneblock::numerics::sample::{default_attractors, reference_settings};
    for a in default_attractors() {
        let fixed = a.fixed.expect("every default attractor is committed");
        assert!(fixed.len() >= 64, "{}: {} points", a.name, fixed.len());
        let sim = Simulator::new(a.params, reference_settings()).unwrap();
        let mut worst = 0.0f64;
        for w in fixed.windows(2) {
            let next = sim.map(w[0]).unwrap();
            worst = worst.max(oneblock::model::wrap_angle(next - w[1]).abs());
        }
        println!("{}: worst |f(θ_i) − θ_(i+1)| = {worst:.1e}", a.name);
        assert!(worst < 1e-9, "{}: {worst:e}", a.name);
    }
}
