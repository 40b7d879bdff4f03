//! The Numerics view: the committed work-precision chart with the jobs'
//! settings marked; Run sends a measurement on the current parameters whose
//! rows replace the chart as they stream in (from a recording backend, and
//! from the real worker); Stop cancels the numerics lane only.
#![cfg(feature = "gui")]

use crate::window;

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

use oneblock::app::jobs::JobState;
use oneblock::app::{Explorer, Recorder, Settings, ViewKind};
use oneblock::model::Params;
use oneblock::numerics::Row;
use oneblock::numerics::quick::{QUICK_POINTS, quick_subjects};
use oneblock::worker::Spec;
use oneblock::worker::{Command, Lane, Update, Worker, WorkerConfig};
use window::harness;

#[test]
fn the_numerics_view_shows_the_committed_chart_and_run_sends_the_job() {
    let rec = Recorder::new();
    let settings = Settings {
        layout: oneblock::app::Layout::Tabs,
        tab: ViewKind::Numerics,
        ..Settings::default()
    };
    let mut h = harness(&rec, settings);
    h.run_steps(2);
    assert!(
        h.query_by_label_contains("Committed chart: 65 points")
            .is_some()
    );
    // The legend of the markers and the table's "used by" column name the
    // jobs' settings.
    assert_eq!(h.query_all_by_label("map iterates").count(), 2);
    assert!(h.query_by_label("settings in use (Auto):").is_some());
    rec.clear();
    h.get_by_label("Run for current parameters").click();
    h.run_steps(2);
    let (g, params, points, subjects) = rec
        .commands()
        .into_iter()
        .find_map(|c| match c {
            Command::Run {
                generation,
                spec: Spec::Numerics(spec),
            } => Some((
                generation,
                spec.attractors[0].params,
                spec.points,
                spec.subjects,
            )),
            _ => None,
        })
        .expect("the job was sent");
    assert_eq!(params, Params::default());
    assert_eq!(points, QUICK_POINTS);
    assert_eq!(subjects, quick_subjects());
    // Rows stream in: the chart switches to them; other updates pass by.
    let row = Row {
        method: "dop853",
        kind: "tol",
        setting: 1e-6,
        points: 12,
        failed: 0,
        failure: None,
        max_error: 2e-6,
        median_error: 1e-7,
        max_stop_error: 1e-6,
        max_duration_error: 1e-5,
        median_us: 30.0,
        evals_per_iterate: 450.0,
    };
    rec.push(Update::WorkPrecisionSample {
        generation: g,
        points: 12,
        reference_spread: 3e-12,
    });
    rec.push(Update::WorkPrecisionRow {
        generation: g,
        index: 0,
        total: subjects.len(),
        row,
    });
    h.run_steps(2);
    assert_eq!(h.state().jobs.numerics.data.rows.len(), 1);
    assert_eq!(h.state().jobs.stale_dropped, 0);
    assert!(h.query_by_label_contains("Run on κ = 18.95").is_some());
    assert!(h.query_by_label_contains("1/57 settings").is_some());
    // Stop cancels the numerics lane only.
    rec.clear();
    h.get_by_label("Stop").click();
    h.run_steps(2);
    assert!(matches!(
        rec.commands().as_slice(),
        [Command::Cancel {
            lane: Some(Lane::Numerics),
            ..
        }]
    ));
    assert_eq!(h.state().jobs.numerics.state, JobState::Cancelled);
    // The y switch.
    h.get_by_label("RHS evaluations per iterate").click();
    h.run_steps(2);
    assert!(h.state().views.numerics.y_evals);
}

#[test]
fn run_for_current_parameters_fills_the_chart_from_the_real_worker() {
    let worker = Worker::spawn(WorkerConfig::default(), std::sync::Arc::new(|| {}));
    let settings = Settings {
        layout: oneblock::app::Layout::Tabs,
        tab: ViewKind::Numerics,
        columns: 20,
        trajectory_cycles: 20,
        ..Settings::default()
    };
    let app = Explorer::new(Box::new(worker), settings);
    let mut h = Harness::builder()
        .with_size([1280.0, 1000.0])
        .build_ui_state(
            |ui, app: &mut Explorer| {
                app.logic_step(ui.ctx());
                app.show(ui);
            },
            app,
        );
    h.run_steps(2);
    h.get_by_label("Run for current parameters").click();
    // Rows arrive on the worker's numerics lane, one setting at a time.
    let start = std::time::Instant::now();
    while h.state().jobs.numerics.data.rows.len() < 3 {
        assert!(
            start.elapsed() < std::time::Duration::from_secs(120),
            "no rows: {:?}",
            h.state().jobs.numerics
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
        h.step();
    }
    let run = &h.state().jobs.numerics;
    assert_eq!(run.state, JobState::Running);
    assert_eq!(run.data.points, QUICK_POINTS);
    assert_eq!(run.data.rows[0].method, "euler");
    assert!(run.data.rows.iter().all(|r| r.points == QUICK_POINTS));
    h.get_by_label("Stop").click();
    h.run_steps(2);
    let n = h.state().jobs.numerics.data.rows.len();
    // Nothing of the stopped job arrives after the stop.
    for _ in 0..10 {
        std::thread::sleep(std::time::Duration::from_millis(20));
        h.step();
    }
    let run = &h.state().jobs.numerics;
    assert_eq!(run.state, JobState::Cancelled);
    assert_eq!(run.data.rows.len(), n);
    assert!(n < run.data.total);
}
