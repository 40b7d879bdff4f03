//! Play θν in the window, on both hosts the window runs its jobs on: the
//! threaded worker (the desktop) and `LocalWorker` (the browser's single
//! thread, pumped a slice of each frame). The harness's clock is the play
//! clock (`Play::tick` takes the ui time): each step is 50 ms of it. Play
//! is started by its button; θν must move at the chosen speed, turn at
//! the end of the diagram's range, and the orbit's jobs must follow: new
//! generations while it plays, and once paused, the trajectory and the
//! return map's orbit are those of the θν it stopped at (the same numbers
//! a fresh job model computes there), not of the θν it started from.
#![cfg(feature = "gui")]

use std::sync::Arc;
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

use oneblock::app::jobs::kind::JobKind;
use oneblock::app::jobs::stale::Bound;
use oneblock::app::jobs::{JobState, Jobs, Shown};
use oneblock::app::{Backend, Explorer, Layout, Settings, ViewKind};
use oneblock::worker::{LocalWorker, Worker, WorkerConfig};

/// Seconds of play clock per harness step.
const STEP: f32 = 0.05;

/// Fig. 3b near the end of the diagram's range, a small diagram and a
/// short trajectory, the fast speed; the views that follow θν tiled.
fn settings() -> Settings {
    let mut s = Settings {
        columns: 24,
        sweep_transient: 60,
        sweep_keep: 20,
        trajectory_cycles: 20,
        layout: Layout::Tiles,
        tiled: vec![
            ViewKind::Bifurcation,
            ViewKind::ReturnMap,
            ViewKind::Plane,
            ViewKind::Block,
        ],
        play_speed: 0.06,
        ..Settings::default()
    };
    // 0.012 rad below the end: four ticks of 0.003 reach it.
    s.params.theta_nu = s.sweep_range().1 - 0.012;
    s
}

fn harness(backend: Box<dyn Backend>) -> Harness<'static, Explorer> {
    let app = Explorer::new(backend, settings());
    Harness::builder()
        .with_size([1280.0, 800.0])
        .with_step_dt(STEP)
        .build_ui_state(
            |ui, app: &mut Explorer| {
                app.logic_step(ui.ctx());
                app.show(ui);
            },
            app,
        )
}

/// Whether the orbit views are complete at the window's current settings:
/// trajectory and orbit analysis done and bound to its θν.
fn orbit_done_here(app: &Explorer) -> bool {
    let s = &app.settings;
    let range = s.sweep_range();
    let here = |k: JobKind| Some(Bound::of(k, s, range));
    let j = &app.jobs;
    j.trajectory.state == JobState::Done
        && j.iterate.state == JobState::Done
        && j.trajectory.bound == here(JobKind::Trajectory)
        && j.iterate.bound == here(JobKind::Iterate)
        && !j.trajectory.data.events.is_empty()
}

/// Steps (and, for the threaded worker, waits) until the orbit views are
/// complete at the current θν.
fn settle(h: &mut Harness<'static, Explorer>, what: &str) {
    let start = Instant::now();
    while !orbit_done_here(h.state()) {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "{what}: the orbit views never completed ({:?}, {:?})",
            h.state().jobs.trajectory.state,
            h.state().jobs.iterate.state
        );
        h.step();
        std::thread::sleep(Duration::from_millis(2));
    }
}

/// The trajectory's slips and the orbit's iterates a fresh job model (on
/// the single-threaded host) computes at `s`.
fn reference(s: &Settings) -> (Vec<f64>, Vec<f64>) {
    let mut jobs = Jobs::new(Box::new(LocalWorker::default()));
    let start = Instant::now();
    let mut now = 0.0;
    loop {
        jobs.sync(
            s,
            Shown {
                now,
                sweep_zoom: None,
                phase: false,
            },
        );
        jobs.pump(Duration::from_millis(50));
        jobs.receive();
        if jobs.trajectory.state == JobState::Done && jobs.iterate.state == JobState::Done {
            break;
        }
        assert!(start.elapsed() < Duration::from_secs(120), "no reference");
        now += 1.0;
    }
    let onsets = jobs
        .trajectory
        .data
        .events
        .iter()
        .map(|e| e.theta)
        .collect();
    (onsets, jobs.iterate.data.thetas.clone())
}

fn onsets(app: &Explorer) -> Vec<f64> {
    app.jobs
        .trajectory
        .data
        .events
        .iter()
        .map(|e| e.theta)
        .collect()
}

fn click_play(h: &mut Harness<'static, Explorer>, label: &str) {
    // The top bar's button (the panel has one too).
    h.get_all_by_label(label)
        .next()
        .unwrap_or_else(|| panic!("no {label} button"))
        .click();
    h.step();
}

fn plays_and_the_views_follow(backend: Box<dyn Backend>) {
    let mut h = harness(backend);
    settle(&mut h, "before play");
    let start_tn = h.state().settings.params.theta_nu;
    let hi = h.state().settings.sweep_range().1;
    let before = (
        onsets(h.state()),
        h.state().jobs.iterate.data.thetas.clone(),
    );
    let first_generation = h.state().jobs.trajectory.generation;

    click_play(&mut h, "Play θν");
    assert!(h.state().play.on, "the button did not start play");
    let mut path = vec![start_tn];
    let mut generations = vec![first_generation];
    // Frames 50 ms apart: while θν plays an orbit restarts once the last
    // one is done (its views show it meanwhile), so the worker is given
    // the time a real frame gives it.
    for _ in 0..24 {
        h.step();
        std::thread::sleep(Duration::from_millis(50));
        path.push(h.state().settings.params.theta_nu);
        generations.push(h.state().jobs.trajectory.generation);
    }
    click_play(&mut h, "Pause");
    assert!(!h.state().play.on, "Pause did not stop play");
    let end_tn = h.state().settings.params.theta_nu;

    // Up at 0.06 rad/s (0.003 a step) to the range's end, then back down.
    let top = path.iter().copied().fold(f64::MIN, f64::max);
    let turn = path.iter().position(|&x| x == top).expect("a top");
    assert!(
        top <= hi && hi - top < 0.004,
        "θν never reached {hi}: {path:?}"
    );
    assert!(
        path[1..=turn].windows(2).all(|w| w[1] > w[0]),
        "θν did not rise to the end: {path:?}"
    );
    assert!(
        turn + 3 < path.len() && path[turn..].windows(2).all(|w| w[1] < w[0]),
        "θν did not turn at the end: {path:?}"
    );
    let step = path[2] - path[1];
    assert!((step - 0.06 * f64::from(STEP)).abs() < 1e-6, "step {step}");
    assert!((end_tn - start_tn).abs() > 0.01, "θν ended where it began");

    // The orbit restarted as θν moved, not once at the end.
    generations.dedup();
    assert!(
        generations.len() >= 4,
        "the trajectory restarted only {} times while playing",
        generations.len() - 1
    );

    // Paused: the trajectory and the return map's orbit end up at the new
    // θν, exactly as a fresh computation there.
    settle(&mut h, "after play");
    assert_eq!(h.state().settings.params.theta_nu, end_tn);
    let (want_onsets, want_iterates) = reference(&h.state().settings);
    let app = h.state();
    assert_eq!(
        onsets(app),
        want_onsets,
        "the trajectory is not at θν {end_tn}"
    );
    assert_eq!(
        app.jobs.iterate.data.thetas, want_iterates,
        "the return map's orbit is not at θν {end_tn}"
    );
    assert_ne!(
        (onsets(app), app.jobs.iterate.data.thetas.clone()),
        before,
        "the views show what they showed before play"
    );
}

#[test]
fn theta_nu_plays_and_the_views_follow_on_the_threaded_worker() {
    let worker = Worker::spawn(WorkerConfig::default(), Arc::new(|| {}));
    plays_and_the_views_follow(Box::new(worker));
}

#[test]
fn theta_nu_plays_and_the_views_follow_on_the_single_threaded_host() {
    plays_and_the_views_follow(Box::new(LocalWorker::default()));
}
