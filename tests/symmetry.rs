//! The model's exact symmetries, checked on the computed map (strong tests:
//! they hold for every parameter set, in every regime):
//! - y → −y maps (θ, θν) to (−θ, −θν), so f(−θ; −θν) = −f(θ; θν);
//! - x → −x maps θ to π − θ and θν to π − θν.

#![allow(clippy::unwrap_used)]

use crate::common;
use common::fixture::preset;

use std::f64::consts::PI;

use oneblock::model::{is_on_exit_arc, wrap_angle};
use oneblock::{Method, Params, Simulator, SolverSettings};

fn map(p: Params, theta: f64) -> f64 {
    Simulator::new(p, SolverSettings::adaptive(Method::Dop853, 1e-12))
        .unwrap()
        .map(theta)
        .unwrap()
}

/// Parameter points in all three regimes, with onsets on their exit arcs.
fn cases() -> Vec<(Params, f64)> {
    vec![
        (preset("fig3b"), 0.5),
        (preset("chaos"), 1.1),
        (preset("fig3a"), 0.3),
        (preset("intermittent"), 0.25),
        (preset("creep"), 0.9),
        (
            Params {
                kappa: 10.0,
                theta_nu: 1.2,
                ..preset("fig3b")
            },
            1.0,
        ),
        (
            Params {
                kappa: 0.5,
                gamma: 0.9,
                theta_nu: 0.4,
                ..preset("fig3b")
            },
            0.2,
        ),
    ]
}

#[test]
fn reflection_in_y_negates_theta() {
    for (p, th) in cases() {
        assert!(is_on_exit_arc(p.kappa, -p.theta_nu, -th));
        let f = map(p, th);
        let g = map(p.with_theta_nu(-p.theta_nu), -th);
        assert!((g + f).abs() < 1e-12, "{p:?} θ={th}: f = {f}, mirrored {g}");
    }
}

#[test]
fn reflection_in_x_maps_theta_to_pi_minus_theta() {
    for (p, th) in cases() {
        let f = map(p, th);
        let g = map(p.with_theta_nu(PI - p.theta_nu), wrap_angle(PI - th));
        let d = wrap_angle(g - (PI - f));
        assert!(
            d.abs() < 1e-12,
            "{p:?} θ={th}: f = {f}, mirrored {g}, off by {d}"
        );
    }
}
