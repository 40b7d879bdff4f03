//! The window's memory is bounded by the screen, not by the zoom or the
//! text size (issue 40): a property test over a session's numeric fields
//! at their documented extremes (text size, tiles, layout, window size,
//! the diagram's zoom down to a θ range 1e-9 wide) draws the window
//! headless (egui_kittest) and checks this process's peak resident size
//! stays under the window's budget of docs/gui.md. A flat zoom box (θν
//! over 0–π/2, θ 1e-5 wide) once drew the diagonal θ = θν as dots along
//! its whole length on screen, millions of them, and aborted the window;
//! text ×3 with the Block tile looped forever in a tile with no room.
//!
//! One test in this file: the peak is the process's, which must be this
//! test's alone.
#![cfg(all(feature = "gui", target_os = "linux"))]
#![allow(clippy::unwrap_used)]

use std::f64::consts::{FRAC_PI_2, PI};

use egui_kittest::Harness;
use proptest::prelude::*;

use oneblock::app::bifurcation::Zoom;
use oneblock::app::{Explorer, Layout, Recorder, Settings, ViewKind};

/// The window's memory budget (docs/gui.md), in MB.
const WINDOW_BUDGET_MB: f64 = 1024.0;

/// This process's peak resident size (VmHWM), in MB.
fn peak_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap();
    let kb: f64 = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap();
    kb / 1024.0
}

/// A θ range at one of the documented extremes of width, centred on the
/// diagonal's θ so that the line crosses it.
fn theta_range() -> impl Strategy<Value = (f64, f64)> {
    (
        prop_oneof![
            Just(1e-9),
            Just(1e-7),
            Just(1e-5),
            Just(1e-3),
            Just(2.0 * PI)
        ],
        -1.5..1.5f64,
    )
        .prop_map(|(w, c)| (c - w / 2.0, c + w / 2.0))
}

/// A θν range: the whole circle, the quarter, or a thin band.
fn theta_nu_range() -> impl Strategy<Value = (f64, f64)> {
    prop_oneof![
        Just((-PI, PI)),
        Just((0.0, FRAC_PI_2)),
        (0.0..1.5f64).prop_map(|a| (a, a + 1e-6)),
    ]
}

fn settings() -> impl Strategy<Value = Settings> {
    (
        prop_oneof![Just(0.5f32), Just(1.0f32), Just(3.0f32), 0.5..3.0f32],
        proptest::sample::subsequence(ViewKind::ALL.to_vec(), 1..=ViewKind::ALL.len()),
        any::<bool>(),
        prop_oneof![Just(20usize), Just(2000usize)],
    )
        .prop_map(|(font_scale, tiled, tabs, columns)| Settings {
            font_scale,
            layout: if tabs { Layout::Tabs } else { Layout::Tiles },
            tab: tiled[0],
            tiled,
            columns,
            ..Settings::default()
        })
}

fn window_size() -> impl Strategy<Value = [f32; 2]> {
    prop_oneof![
        Just([200.0, 200.0]),
        Just([800.0, 560.0]),
        Just([1280.0, 800.0]),
        Just([1920.0, 1200.0]),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn the_window_at_any_documented_extreme_stays_within_its_budget(
        s in settings(),
        size in window_size(),
        zoom in (theta_nu_range(), theta_range()),
    ) {
        let rec = Recorder::new();
        let app = Explorer::new(Box::new(rec.clone()), s);
        let mut h = Harness::builder().with_size(size).build_ui_state(
            |ui, app: &mut Explorer| {
                app.logic_step(ui.ctx());
                app.show(ui);
            },
            app,
        );
        h.state_mut().views.bifurcation.zoom.push(Zoom {
            theta_nu: zoom.0,
            theta: zoom.1,
        });
        h.state_mut().views.bifurcation.invalidate();
        h.run_steps(3);
        // The bifurcation diagram as one tab too, whatever was tiled.
        h.state_mut().settings.layout = Layout::Tabs;
        h.state_mut().settings.tab = ViewKind::Bifurcation;
        h.run_steps(3);
        let peak = peak_mb();
        prop_assert!(peak < WINDOW_BUDGET_MB, "peak {peak:.0} MB at {size:?}, zoom {zoom:?}");
    }
}
