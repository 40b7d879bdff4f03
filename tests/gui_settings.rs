//! Saved settings are sanitised on load: whatever a saved file holds (NaN,
//! infinities, negative or huge numbers in any field), the window opens on
//! values it can run, every spoiled field back to its default, every sound
//! one kept, and a message naming what was reset. A property test over
//! random mixes of sound and spoiled fields, and the message in the window.
#![cfg(feature = "gui")]

use crate::window;

use std::f64::consts::PI;

use egui_kittest::kittest::Queryable;
use proptest::prelude::*;

use oneblock::app::{Recorder, Settings};
use oneblock::model::Params;
use window::{harness, last_trajectory};

/// A float that is sound (in `lo..=hi`) or spoiled in one of the ways a
/// file can spoil it.
fn float(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => lo..=hi,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => -1e300..-1e-300f64,
        1 => Just(1e300),
    ]
}

/// A count that is sound (in `lo..=hi`) or zero or huge.
fn count(lo: usize, hi: usize) -> impl Strategy<Value = usize> {
    prop_oneof![4 => lo..=hi, 1 => Just(0usize), 1 => Just(usize::MAX), 1 => (hi + 1)..usize::MAX]
}

/// The ranges the window documents for each field (docs/gui.md, the
/// controls' hover texts), written out here independently of the code.
fn params_sound(p: &Params) -> bool {
    (1e-6..=1e3).contains(&p.kappa)
        && (0.1..=1e4).contains(&p.gamma)
        && (1e-12..=0.1).contains(&p.nu)
        && (-PI..=PI).contains(&p.theta_nu)
        && p.omega > 0.0
        && p.omega <= 1e8
}

prop_compose! {
    fn saved()(
        kappa in float(1e-6, 1e6), gamma in float(0.0, 1e6), nu in float(1e-12, 1e3),
        theta_nu in float(-PI, PI), omega in float(1e-3, 1e8),
        tol in float(1e-14, 1e-2), step in float(1e-9, 1.0),
        keep_cycles in count(1, 1000), trajectory_cycles in count(1, 100_000),
        columns in count(20, 2000), sweep_transient in count(0, 100_000),
        sweep_keep in count(1, 100_000),
        font_scale in float(0.5, 3.0), block_speed in float(0.1, 10.0),
    ) -> Settings {
        Settings {
            params: Params { kappa, gamma, nu, theta_nu, omega },
            tol, step, keep_cycles, trajectory_cycles, columns, sweep_transient, sweep_keep,
            font_scale: font_scale as f32,
            block_speed: block_speed as f32,
            ..Settings::default()
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn every_spoiled_field_loads_as_its_default_and_is_named(s in saved()) {
        let d = Settings::default();
        let (out, bad) = s.clone().sanitised();
        // Each field: kept if sound, else the default and named.
        let mut expect_bad = Vec::new();
        if params_sound(&s.params) {
            prop_assert_eq!(out.params, s.params);
        } else {
            prop_assert_eq!(out.params, d.params);
            expect_bad.push("parameters");
        }
        let checks: [(&str, bool, f64, f64, f64); 9] = [
            ("tolerance", (1e-14..=1e-2).contains(&s.tol), s.tol, out.tol, d.tol),
            ("step", s.step > 0.0 && s.step <= 1.0, s.step, out.step, d.step),
            ("cycles shown", (1..=1000).contains(&s.keep_cycles),
                s.keep_cycles as f64, out.keep_cycles as f64, d.keep_cycles as f64),
            ("trajectory cycles", (1..=100_000).contains(&s.trajectory_cycles),
                s.trajectory_cycles as f64, out.trajectory_cycles as f64,
                d.trajectory_cycles as f64),
            ("diagram columns", (20..=2000).contains(&s.columns),
                s.columns as f64, out.columns as f64, d.columns as f64),
            ("diagram transient", s.sweep_transient <= 100_000,
                s.sweep_transient as f64, out.sweep_transient as f64,
                d.sweep_transient as f64),
            ("diagram iterates kept", (1..=100_000).contains(&s.sweep_keep),
                s.sweep_keep as f64, out.sweep_keep as f64, d.sweep_keep as f64),
            ("text size", (0.5..=3.0).contains(&s.font_scale),
                s.font_scale as f64, out.font_scale as f64, d.font_scale as f64),
            ("block speed", (0.1..=10.0).contains(&s.block_speed),
                s.block_speed as f64, out.block_speed as f64, d.block_speed as f64),
        ];
        for (name, sound, before, after, default) in checks {
            if sound {
                prop_assert_eq!(after, before, "{} was sound", name);
            } else {
                prop_assert_eq!(after, default, "{} was spoiled", name);
                expect_bad.push(name);
            }
        }
        prop_assert_eq!(&bad, &expect_bad);
        // What comes out runs: the model and the solver accept it, and a
        // second pass finds nothing.
        prop_assert!(out.params.validate().is_ok());
        prop_assert!(out.custom_solver().validate().is_ok());
        prop_assert!(out.clone().sanitised().1.is_empty());
    }
}

#[test]
fn the_window_says_which_saved_values_it_reset_and_runs_the_defaults() {
    let rec = Recorder::new();
    let saved = Settings {
        params: Params {
            kappa: f64::NAN,
            ..Params::default()
        },
        columns: usize::MAX,
        tol: -1.0,
        ..Settings::default()
    };
    let mut h = harness(&rec, saved);
    h.run_steps(2);
    assert!(
        h.query_by_label_contains(
            "The saved settings held invalid values (parameters, tolerance, diagram columns)"
        )
        .is_some()
    );
    assert_eq!(last_trajectory(&rec), Some(Params::default()));
    assert_eq!(h.state().settings.columns, Settings::default().columns);
}
