//! The window's λ is the command line's, to every digit it shows (issue
//! 53): at Fig. 3b θν = 1.0 under Auto accuracy, where the diagram's dots
//! come from a loose integrator (dp54 1e-4), the return map's line, the
//! side panel's regime line and the λ strip's column all print the λ that
//! `oneblock cycle` solves at tol 1e-10. Through the real worker, as the
//! user sees it.
#![cfg(feature = "gui")]
#![allow(clippy::unwrap_used)]

use std::sync::Arc;
use std::time::{Duration, Instant};

use egui_kittest::Harness;

use crate::cli_support::{assert_ok, oneblock, stdout};
use crate::window::painted_texts;
use oneblock::app::jobs::JobState;
use oneblock::app::settings::AccuracyMode;
use oneblock::app::{Explorer, Layout, Settings, ViewKind};
use oneblock::model::preset;
use oneblock::worker::{Worker, WorkerConfig};

/// λ of the fixed point at Fig. 3b's θν = `theta_nu`, from `oneblock cycle`.
fn cycle_lambda(theta_nu: f64) -> f64 {
    let tn = format!("{theta_nu}");
    let o = oneblock(&[
        "cycle",
        "--preset",
        "fig3b",
        "--theta-nu",
        &tn,
        "--period",
        "1",
        "--theta",
        "0.4",
    ]);
    assert_ok(&o);
    let out = stdout(&o);
    let line = out.lines().find(|l| l.starts_with("lyapunov")).unwrap();
    line.split_whitespace().nth(1).unwrap().parse().unwrap()
}

#[test]
fn lambda_in_the_window_is_the_command_lines_under_auto() {
    let mut params = preset("fig3b").unwrap().params;
    params.theta_nu = 1.0;
    let settings = Settings {
        params,
        accuracy: AccuracyMode::Auto,
        layout: Layout::Tabs,
        tab: ViewKind::ReturnMap,
        columns: 41,
        ..Settings::default()
    };
    let worker = Worker::spawn(WorkerConfig::default(), Arc::new(|| {}));
    let app = Explorer::new(Box::new(worker), settings);
    let mut h = Harness::builder()
        .with_size([1280.0, 800.0])
        .build_ui_state(
            |ui, app: &mut Explorer| {
                app.logic_step(ui.ctx());
                app.show(ui);
            },
            app,
        );
    let t0 = Instant::now();
    let done = |a: &Explorer| {
        a.jobs.iterate.state == JobState::Done
            && a.jobs.iterate.data.lyapunov.is_some()
            && a.jobs.sweep.state == JobState::Done
    };
    while !done(h.state()) {
        assert!(t0.elapsed() < Duration::from_secs(180), "timed out");
        h.step();
        std::thread::sleep(Duration::from_millis(20));
    }
    h.run_steps(2);
    let want = oneblock::text::lyapunov(cycle_lambda(1.0), None, true);
    // The return map's line and the side panel's regime line, as painted
    // (a wrapped label is its rows: compared without white space).
    let squeeze = |t: &str| t.split_whitespace().collect::<String>();
    let painted = squeeze(
        &painted_texts(&h)
            .into_iter()
            .map(|(t, _)| t)
            .collect::<Vec<_>>()
            .join(" "),
    );
    for (what, text) in [
        ("return map", format!("period 1 · Lyapunov exponent {want}")),
        ("regime line", format!("(Lyapunov exponent {want})")),
    ] {
        assert!(
            painted.contains(&squeeze(&text)),
            "{what}: no '{text}' in {painted}"
        );
    }
    // The strip's column nearest θν = 1.0, against `cycle` at its θν.
    let cols = &h.state().jobs.sweep.data.columns;
    let col = cols
        .iter()
        .flatten()
        .min_by(|a, b| (a.value - 1.0).abs().total_cmp(&(b.value - 1.0).abs()))
        .unwrap();
    let l = col.lyapunov.unwrap();
    assert!(l.stderr.is_none(), "a solved cycle: {l:?}");
    assert_eq!(
        oneblock::text::lyapunov(l.lyapunov, None, true),
        oneblock::text::lyapunov(cycle_lambda(col.value), None, true),
        "strip at θν = {}",
        col.value
    );
}
