//! Two independent integrators at tight tolerance agree on the map:
//! DP5(4) at 1e-12 and DOP853 at 1e-13 within 1e-10, at points in all three
//! regimes (including a long stick phase near θν = π/2, where errors in the
//! stop's x are amplified by about tan θν on the way back to C).

#![allow(clippy::unwrap_used)]

use crate::common;
use common::fixture::preset;

use oneblock::sim::OrbitOptions;
use oneblock::{Method, Params, Regime, Simulator, SolverSettings};

#[test]
fn dp54_and_dop853_agree_on_the_map() {
    let points = [
        (preset("creep"), "pure creep"),
        (
            Params {
                kappa: 0.5,
                gamma: 0.9,
                theta_nu: 0.4,
                ..preset("fig3b")
            },
            "mixed",
        ),
        (preset("fig3a"), "mixed"),
        (preset("intermittent"), "mixed"),
        (preset("fig3a").with_theta_nu(1.55), "mixed"),
        (preset("chaos"), "pure stick-slip"),
        (
            Params {
                kappa: 10.0,
                theta_nu: 1.2,
                ..preset("fig3b")
            },
            "pure stick-slip",
        ),
    ];
    let mut worst = 0.0f64;
    for (params, regime) in points {
        assert_eq!(Regime::of(params.kappa, params.gamma).name(), regime);
        let fine = Simulator::new(params, SolverSettings::adaptive(Method::Dop853, 1e-13)).unwrap();
        let other = Simulator::new(params, SolverSettings::adaptive(Method::Dp54, 1e-12)).unwrap();
        // Onsets on the attractor (where the map is used), plus its start.
        let orbit = fine
            .orbit(
                params.theta_nu,
                &OrbitOptions {
                    transient: 20,
                    keep: 6,
                    lyapunov: false,
                    period_tol: 1e-9,
                },
                &|| false,
            )
            .unwrap();
        for th in std::iter::once(params.theta_nu).chain(orbit.thetas()) {
            let a = fine.map(th).unwrap();
            let b = other.map(th).unwrap();
            worst = worst.max((a - b).abs());
            assert!(
                (a - b).abs() < 1e-10,
                "{params:?} θ = {th}: dop853 {a} vs dp54 {b}"
            );
        }
    }
    eprintln!("largest DP5(4)/DOP853 difference: {worst:e}");
}
