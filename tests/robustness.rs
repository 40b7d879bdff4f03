//! Never a panic, never a hang: random valid parameters give a finite θ' or
//! a typed error within the step bound, and each bound says which it was.

#![allow(clippy::unwrap_used)]

use oneblock::integrate::IntegrateError;
use oneblock::model::{exit_arc, wrap_angle};
use oneblock::{Method, Params, SimError, Simulator, SolverSettings};
use proptest::prelude::*;

fn params() -> impl Strategy<Value = (Params, f64)> {
    (
        -1.3f64..2.0,
        0.1f64..10.0,
        -6.0f64..-1.0,
        0.0f64..std::f64::consts::TAU,
        0.0f64..3.0,
        -0.98f64..0.98,
    )
        .prop_map(|(lk, gamma, lnu, theta_nu, lom, frac)| {
            let p = Params {
                kappa: 10f64.powf(lk),
                gamma,
                nu: 10f64.powf(lnu),
                theta_nu,
                omega: 10f64.powf(lom),
            };
            let (psi, half) = exit_arc(p.kappa, p.theta_nu);
            (p, wrap_angle(psi + frac * half))
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, .. ProptestConfig::default() })]
    #[test]
    fn map_is_finite_or_a_typed_error((p, theta) in params(), method in prop_oneof![Just(Method::Dop853), Just(Method::Dp54)]) {
        let settings = SolverSettings { max_steps: 20_000, ..SolverSettings::adaptive(method, 1e-7) };
        let sim = Simulator::new(p, settings).unwrap();
        match sim.cycle(theta, 0.0, None) {
            Ok(ev) => {
                prop_assert!(ev.theta_next.is_finite() && ev.theta_next.abs() <= std::f64::consts::PI);
                prop_assert!(ev.steps <= 20_000);
                prop_assert!(ev.slip_duration > 0.0 && ev.stick_duration >= 0.0);
                prop_assert!(ev.stop_x.is_finite() && ev.stop_y.is_finite());
            }
            Err(e) => prop_assert!(matches!(e, SimError::Integrate { .. } | SimError::SlipTooLong { .. }), "{e}"),
        }
    }
}

#[test]
fn step_bound_is_reported_with_its_parameters() {
    let p = Params::default();
    let sim = Simulator::new(
        p,
        SolverSettings {
            max_steps: 5,
            ..SolverSettings::adaptive(Method::Dop853, 1e-10)
        },
    )
    .unwrap();
    let e = sim.map(0.5).unwrap_err();
    assert!(
        matches!(
            e,
            SimError::Integrate {
                source: IntegrateError::TooManySteps { max: 5 },
                ..
            }
        ),
        "{e}"
    );
    let msg = e.to_string();
    assert!(
        msg.contains("kappa = 18.95") && msg.contains("5 steps"),
        "{msg}"
    );
}

#[test]
fn slip_time_bound_is_reported() {
    let sim = Simulator::new(
        Params::default(),
        SolverSettings {
            max_slip_time: 0.5,
            ..SolverSettings::adaptive(Method::Dop853, 1e-8)
        },
    )
    .unwrap();
    assert!(matches!(sim.map(0.5).unwrap_err(), SimError::SlipTooLong { max, .. } if max == 0.5));
}

#[test]
fn onsets_off_the_exit_arc_are_rejected() {
    let sim = Simulator::new(Params::default(), SolverSettings::default()).unwrap();
    let (psi, _) = exit_arc(18.95, 1.0);
    let e = sim.map(wrap_angle(psi + 2.0)).unwrap_err();
    assert!(matches!(e, SimError::OffExitArc { .. }));
    assert_eq!(e.parameter(), Some("theta"));
    assert!(sim.map(f64::NAN).is_err());
}

#[test]
fn fixed_steps_too_large_for_the_events_are_errors_not_numbers() {
    // One RK4 step of 0.9 spans a whole phase: it must say so.
    let sim = Simulator::new(Params::default(), SolverSettings::fixed(Method::Rk4, 0.9)).unwrap();
    let e = sim.map(0.5).unwrap_err();
    assert!(matches!(e, SimError::StepTooLarge { .. }), "{e}");
    // A small step resolves them and lands near the accurate value.
    let fine = Simulator::new(Params::default(), SolverSettings::fixed(Method::Rk4, 2e-3)).unwrap();
    let f = fine.map(0.5).unwrap();
    assert!((f - 0.2037551562).abs() < 1e-4, "{f}");
}

#[test]
fn invalid_settings_name_the_setting() {
    let e = Simulator::new(
        Params::default(),
        SolverSettings::adaptive(Method::Dop853, 1e-1),
    )
    .unwrap_err();
    assert_eq!(e.parameter(), Some("tol"));
    let e =
        Simulator::new(Params::default(), SolverSettings::fixed(Method::Euler, 0.0)).unwrap_err();
    assert_eq!(e.parameter(), Some("step"));
}

/// Parameters anywhere in the documented ranges (docs/cli.md, "Common
/// flags"), log-uniform over their decades: κ in [1e-6, 1e3], γ in
/// [0.1, 1e4], ν in [1e-12, 0.1], Ω in (0, 1e8], any θν; θ on the exit arc.
/// Several at their ends together may still slide for good: a typed error.
fn documented_params() -> impl Strategy<Value = (Params, f64)> {
    (
        -6.0f64..=3.0,
        prop_oneof![
            Just(0.1),
            Just(1e4),
            (-1.0f64..=4.0).prop_map(|l| 10f64.powf(l).clamp(0.1, 1e4))
        ],
        -12.0f64..=-1.0,
        -10.0f64..10.0,
        -3.0f64..8.0,
        -0.98f64..0.98,
    )
        .prop_map(|(lk, gamma, lnu, theta_nu, lom, frac)| {
            let p = Params {
                // Clamped: powf need not land exactly on an end.
                kappa: 10f64.powf(lk).clamp(1e-6, 1e3),
                gamma,
                nu: 10f64.powf(lnu).clamp(1e-12, 0.1),
                theta_nu,
                omega: 10f64.powf(lom),
            };
            let (psi, half) = exit_arc(p.kappa, p.theta_nu);
            (p, wrap_angle(psi + frac * half))
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, .. ProptestConfig::default() })]
    /// Over the whole documented input space, wider than the paper's: a
    /// finite θ' (with a finite energy) or a typed error, within the step
    /// bound.
    #[test]
    fn map_over_the_documented_ranges_is_finite_or_a_typed_error((p, theta) in documented_params()) {
        prop_assert!(p.validate().is_ok(), "{p:?}");
        let settings = SolverSettings { max_steps: 20_000, ..SolverSettings::adaptive(Method::Dop853, 1e-7) };
        let sim = Simulator::new(p, settings).unwrap();
        match sim.cycle(theta, 0.0, None) {
            Ok(ev) => {
                prop_assert!(ev.theta_next.is_finite() && ev.theta_next.abs() <= std::f64::consts::PI);
                prop_assert!(ev.energy_released.is_finite() && ev.slip_duration.is_finite());
                prop_assert!(ev.stick_duration.is_finite() && ev.stick_duration >= 0.0);
                prop_assert!(ev.steps <= 20_000);
            }
            Err(e) => prop_assert!(
                matches!(e, SimError::Integrate { .. } | SimError::SlipTooLong { .. }),
                "{e}"
            ),
        }
    }
}
