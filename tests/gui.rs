//! The window driven headless through AccessKit (egui_kittest): sliders,
//! presets, typed values and the regime badge, against a recording backend
//! that stands in for the worker, so each test sees exactly what was sent.
#![cfg(feature = "gui")]

use eframe::egui;
use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use egui_plot::PlotPoint;

use oneblock::app::accuracy::{AccuracyMode, JobKind, job_estimates};
use oneblock::app::data::JobState;
use oneblock::app::{Explorer, PRESETS, Recorder, Settings, View};
use oneblock::integrate::{Method, SolverSettings};
use oneblock::model::Params;
use oneblock::numerics::Row;
use oneblock::numerics::quick::{QUICK_POINTS, quick_subjects};
use oneblock::sim::phase::{CellClass, PhaseCell};
use oneblock::sim::{Phase, Sample, SlipEvent, theta_nu_grid};
use oneblock::worker::{
    Command, Generation, GridCell, Lane, Outcome, Update, Worker, WorkerConfig,
};

fn harness(rec: &Recorder, settings: Settings) -> Harness<'static, Explorer> {
    let app = Explorer::new(Box::new(rec.clone()), settings);
    Harness::builder()
        .with_size([1280.0, 1000.0])
        .build_ui_state(
            |ui, app: &mut Explorer| {
                app.logic_step(ui.ctx());
                app.show(ui);
            },
            app,
        )
}

/// The CSV an export writes into `dir` (on a thread of its own), stepping
/// the window while waiting for it; `None` after about 2 s.
fn wait_for_csv(
    h: &mut Harness<'static, Explorer>,
    dir: &std::path::Path,
) -> Option<std::path::PathBuf> {
    for _ in 0..100 {
        h.step();
        let found = std::fs::read_dir(dir)
            .expect("read dir")
            .flatten()
            .map(|e| e.path())
            .find(|p| p.extension().is_some_and(|e| e == "csv"));
        if found.is_some() {
            return found;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    None
}

/// The parameters of the latest trajectory command, if any.
fn last_trajectory(rec: &Recorder) -> Option<Params> {
    rec.commands().into_iter().rev().find_map(|c| match c {
        Command::Trajectory { spec, .. } => Some(spec.params),
        _ => None,
    })
}

fn last_sweep(rec: &Recorder) -> Option<Params> {
    rec.commands().into_iter().rev().find_map(|c| match c {
        Command::Sweep { spec, .. } => Some(spec.params),
        _ => None,
    })
}

#[test]
fn first_frame_starts_the_demo_jobs() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    let p = last_trajectory(&rec).expect("a trajectory was started");
    assert_eq!(p, Params::default());
    assert_eq!(
        (p.kappa, p.gamma, p.nu, p.theta_nu),
        (18.95, 6.5, 1e-3, 1.0)
    );
    assert!(last_sweep(&rec).is_some(), "a sweep was started");
}

#[test]
fn dragging_the_kappa_slider_sends_new_parameters() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    rec.clear();
    h.get_by_role_and_label(Role::Slider, "κ")
        .set_value_accesskit(30.0);
    h.run_steps(3);
    assert_eq!(h.state().settings.params.kappa, 30.0);
    let p = last_trajectory(&rec).expect("new trajectory");
    assert_eq!(p.kappa, 30.0);
    assert_eq!(p.gamma, 6.5);
    // κ is a sweep parameter: the diagram is recomputed too (after the debounce).
    let s = last_sweep(&rec).expect("new sweep");
    assert_eq!(s.kappa, 30.0);
}

#[test]
fn moving_theta_nu_only_restarts_the_orbit() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    rec.clear();
    h.get_by_role_and_label(Role::Slider, "θν")
        .set_value_accesskit(1.2);
    h.run_steps(4);
    assert_eq!(last_trajectory(&rec).map(|p| p.theta_nu), Some(1.2));
    assert!(
        last_sweep(&rec).is_none(),
        "θν is the diagram's x-axis: no new sweep"
    );
}

#[test]
fn a_preset_sets_every_parameter() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    rec.clear();
    let fig3a = &PRESETS[0];
    assert_eq!(fig3a.key, "fig3a");
    h.get_by_label(fig3a.label).click();
    h.run_steps(3);
    let want = Params {
        kappa: 50.0,
        gamma: 6.5,
        nu: 1e-4,
        theta_nu: 0.3,
        omega: 50.0,
    };
    assert_eq!(h.state().settings.params, want);
    assert_eq!(last_trajectory(&rec), Some(want));
    assert_eq!(last_sweep(&rec), Some(want));
    // The badge follows: κ = 50, γ = 6.5 is mixed with θc = 0.4090.
    assert!(h.query_by_label_contains("mixed: θc = 0.4090").is_some());
}

#[test]
fn an_invalid_kappa_is_shown_in_red_and_not_sent() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    rec.clear();
    let field = h.get_by_role_and_label(Role::TextInput, "κ value");
    field.focus();
    field.set_text_value_accesskit("-3");
    h.run_steps(3);
    let err = h
        .state()
        .controls
        .error(oneblock::app::controls::Field::Kappa);
    assert_eq!(err, Some("κ must be a finite number > 0"));
    assert!(h.query_by_label("κ must be a finite number > 0").is_some());
    assert_eq!(h.state().settings.params.kappa, 18.95);
    assert!(
        rec.commands().is_empty(),
        "nothing sent: {:?}",
        rec.commands()
    );

    // A valid value goes through.
    let field = h.get_by_role_and_label(Role::TextInput, "κ value");
    field.set_text_value_accesskit("25");
    h.run_steps(3);
    assert_eq!(
        h.state()
            .controls
            .error(oneblock::app::controls::Field::Kappa),
        None
    );
    assert_eq!(last_trajectory(&rec).map(|p| p.kappa), Some(25.0));
}

#[test]
fn the_regime_badge_follows_gamma_and_kappa() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    // Fig. 3b: γ² = 42.25 > max(1, 18.95).
    assert!(h.query_by_label_contains("pure stick-slip").is_some());
    // γ = 0.5 with κ = 3: γ² < min(1, κ).
    h.get_by_role_and_label(Role::Slider, "γ")
        .set_value_accesskit(0.5);
    h.run_steps(2);
    h.get_by_role_and_label(Role::Slider, "κ")
        .set_value_accesskit(3.0);
    h.run_steps(2);
    assert!(h.query_by_label_contains("pure creep").is_some());
    // γ = 6.5, κ = 50: mixed, θc = 0.4090 (MODEL.md).
    h.get_by_role_and_label(Role::Slider, "γ")
        .set_value_accesskit(6.5);
    h.get_by_role_and_label(Role::Slider, "κ")
        .set_value_accesskit(50.0);
    h.run_steps(2);
    assert!(h.query_by_label_contains("mixed: θc = 0.4090").is_some());
    // γ² between 1 and κ < 1: mixed as well (κ = 0.5, γ = 0.9).
    h.get_by_role_and_label(Role::Slider, "κ")
        .set_value_accesskit(0.5);
    h.get_by_role_and_label(Role::Slider, "γ")
        .set_value_accesskit(0.9);
    h.run_steps(2);
    assert!(h.query_by_label_contains("mixed: θc").is_some());
}

fn event(theta: f64, next: f64, t: f64) -> SlipEvent {
    SlipEvent {
        theta,
        onset_x: theta.cos() / 18.95,
        onset_y: theta.sin(),
        onset_time: t,
        accel_duration: 1.0,
        slip_duration: 3.0,
        stop_x: 0.0,
        stop_y: 0.1,
        slip_distance: 0.9,
        peak_vr: 0.4,
        energy_released: 0.4,
        stick_duration: 100.0,
        theta_next: next,
        restarted: false,
        rhs_evals: 500,
        steps: 50,
    }
}

#[test]
fn streamed_results_reach_every_view_and_stale_ones_are_dropped() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    let (traj_gen, sweep_gen) = {
        let cmds = rec.commands();
        let t = cmds.iter().find_map(|c| match c {
            Command::Trajectory { generation, .. } => Some(*generation),
            _ => None,
        });
        let s = cmds.iter().find_map(|c| match c {
            Command::Sweep { generation, spec } => Some((*generation, spec.theta_nu.steps)),
            _ => None,
        });
        (t.expect("trajectory"), s.expect("sweep"))
    };
    // A stale update (older generation) is dropped.
    rec.push(Update::Slip {
        generation: 0,
        event: event(0.5, 0.2, 0.0),
    });
    // A trajectory: 5 cycles of a small loop.
    for c in 0..5 {
        let t0 = c as f64 * 103.0;
        let samples: Vec<Sample> = (0..60)
            .map(|i| {
                let s = i as f64 / 59.0;
                Sample {
                    t: t0 + 3.0 * s,
                    x: 0.05 * (6.0 * s).cos(),
                    y: 0.5 - s,
                    u: 0.0,
                    w: -0.3,
                    phase: if s < 0.4 { Phase::Accel } else { Phase::Decel },
                }
            })
            .chain([Sample {
                t: t0 + 103.0,
                x: 0.05,
                y: 0.5,
                u: 0.0,
                w: 0.0,
                phase: Phase::Stick,
            }])
            .collect();
        rec.push(Update::TrajectoryChunk {
            generation: traj_gen,
            samples,
        });
        rec.push(Update::Slip {
            generation: traj_gen,
            event: event(0.5, 0.2, t0),
        });
    }
    let (g, n) = sweep_gen;
    for i in 0..n {
        rec.push(Update::Column {
            generation: g,
            index: i,
            theta_nu: i as f64 / (n - 1) as f64 * std::f64::consts::FRAC_PI_2,
            thetas: (0..200)
                .map(|k| 0.1 + 0.001 * (k % 7) as f64 + i as f64 * 1e-3)
                .collect(),
            coarse: i % 8 == 0,
        });
    }
    rec.push(Update::Finished {
        generation: g,
        lane: oneblock::worker::Lane::Sweep,
        outcome: oneblock::worker::Outcome::Completed,
    });
    h.run_steps(2);
    {
        let d = &h.state().data;
        assert_eq!(d.stale_dropped, 1);
        assert_eq!(d.trajectory.events.len(), 5);
        assert_eq!(d.sweep.filled, n);
        assert_eq!(d.sweep.state, JobState::Done);
        assert_eq!(d.sweep.points(), 200 * n);
    }
    // Every view draws with data in it.
    for v in View::ALL {
        h.state_mut().settings.layout = oneblock::app::Layout::Tabs;
        h.state_mut().settings.tab = v;
        h.run_steps(2);
    }
}

#[test]
fn a_box_drawn_on_the_diagram_recomputes_that_range() {
    let rec = Recorder::new();
    let settings = Settings {
        layout: oneblock::app::Layout::Tabs,
        tab: View::Bifurcation,
        ..Settings::default()
    };
    let mut h = harness(&rec, settings);
    h.run_steps(2);
    let full = rec
        .commands()
        .into_iter()
        .find_map(|c| match c {
            Command::Sweep { spec, .. } => Some((spec.theta_nu.from, spec.theta_nu.to)),
            _ => None,
        })
        .expect("first sweep");
    assert_eq!(full, (0.0, std::f64::consts::FRAC_PI_2));
    rec.clear();
    // Drag across the middle of the plot (the central area right of the panel).
    let (a, b) = (egui::pos2(700.0, 400.0), egui::pos2(950.0, 600.0));
    h.hover_at(a);
    h.step();
    h.drag_at(a);
    h.step();
    for i in 1..=5 {
        h.hover_at(a + (b - a) * (i as f32 / 5.0));
        h.step();
    }
    h.drop_at(b);
    h.run_steps(3);
    let zoomed = rec
        .commands()
        .into_iter()
        .find_map(|c| match c {
            Command::Sweep { spec, .. } => {
                Some((spec.theta_nu.from, spec.theta_nu.to, spec.params))
            }
            _ => None,
        })
        .expect("a zoom recomputes the diagram");
    assert!(
        zoomed.0 > full.0 && zoomed.1 < full.1 && zoomed.0 < zoomed.1,
        "{zoomed:?}"
    );
    assert_eq!(zoomed.2.kappa, 18.95);
    assert_eq!(h.state().bifurcation.zoom.len(), 1);
    // Back returns to the whole range.
    rec.clear();
    h.get_by_label("Back").click();
    h.run_steps(3);
    let back = rec.commands().into_iter().find_map(|c| match c {
        Command::Sweep { spec, .. } => Some((spec.theta_nu.from, spec.theta_nu.to)),
        _ => None,
    });
    assert_eq!(back, Some(full));
}

#[test]
fn export_writes_the_events_csv_into_the_chosen_folder() {
    let dir = tempfile::tempdir().expect("temp dir");
    let rec = Recorder::new();
    let settings = Settings {
        save_dir: dir.path().display().to_string(),
        ..Settings::default()
    };
    let mut h = harness(&rec, settings);
    h.run_steps(2);
    let g = rec
        .commands()
        .into_iter()
        .find_map(|c| match c {
            Command::Trajectory { generation, .. } => Some(generation),
            _ => None,
        })
        .expect("trajectory");
    for i in 0..3 {
        rec.push(Update::Slip {
            generation: g,
            event: event(0.5, 0.2, 103.0 * i as f64),
        });
    }
    h.run_steps(2);
    h.get_by_label("Export data").click();
    h.run_steps(2);
    h.get_by_label("Events CSV").click();
    // The file is written on a thread of its own.
    let path = wait_for_csv(&mut h, dir.path()).expect("an events CSV was written");
    // Under Auto the events come at the trajectory's accuracy: the window
    // says so, since the CSV cannot.
    h.run_steps(2);
    assert!(
        h.query_by_label_contains("computed at Auto's trajectory accuracy (dp54 tol 1e-5")
            .is_some()
    );
    let text = std::fs::read_to_string(&path).expect("read csv");
    let mut lines = text.lines();
    // The command line's header, spelled out as `oneblock orbit` writes it.
    assert_eq!(
        lines.next(),
        Some(
            "theta,onset_x,onset_y,onset_time,accel_duration,slip_duration,stop_x,stop_y,\
slip_distance,peak_vr,energy_released,stick_duration,theta_next,restarted,rhs_evals,steps"
        )
    );
    assert_eq!(lines.count(), 3);
    assert!(
        path.file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with("oneblock-events-"))
    );
}

/// The solver settings of the latest command of each job kind.
fn last_settings(rec: &Recorder) -> (Option<SolverSettings>, Option<SolverSettings>) {
    let cmds = rec.commands();
    let traj = cmds.iter().rev().find_map(|c| match c {
        Command::Trajectory { spec, .. } => Some(spec.settings),
        _ => None,
    });
    let sweep = cmds.iter().rev().find_map(|c| match c {
        Command::Sweep { spec, .. } => Some(spec.settings),
        _ => None,
    });
    (traj, sweep)
}

#[test]
fn the_accuracy_selector_switches_between_auto_and_custom() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    // Auto: each job its own setting, the chart's estimate beside it.
    assert_eq!(h.state().settings.accuracy, AccuracyMode::Auto);
    // (Auto's choices and the figures beside them come from the committed
    // chart, which moves when it is re-measured: the budget's own tests pin
    // them; here the window must send and show what the budget says.)
    let auto = Settings::default();
    assert_eq!(
        last_settings(&rec),
        (
            Some(auto.solver_for(JobKind::Trajectory)),
            Some(auto.solver_for(JobKind::Sweep))
        )
    );
    assert_eq!(
        auto.solver_for(JobKind::Iterate),
        SolverSettings::adaptive(Method::Dop853, 1e-10)
    );
    // One short row per job: setting, the chart's max error, evaluations.
    for e in job_estimates(&auto) {
        let cells = e.cells();
        assert!(
            cells[1].starts_with("err ") && cells[2].ends_with(" ev"),
            "{cells:?}"
        );
        for text in cells {
            // Two jobs may share a setting (and so its cells).
            assert!(h.query_all_by_label(&text).count() >= 1, "{text}");
        }
    }
    // The map iterates wait for the trajectory, then run at 1e-10's setting.
    let g = rec
        .commands()
        .iter()
        .find_map(|c| match c {
            Command::Trajectory { generation, .. } => Some(*generation),
            _ => None,
        })
        .expect("trajectory");
    rec.push(Update::Finished {
        generation: g,
        lane: Lane::Orbit,
        outcome: Outcome::Completed,
    });
    h.run_steps(2);
    let iterate = rec.commands().iter().rev().find_map(|c| match c {
        Command::Iterate { spec, .. } => Some(spec.settings),
        _ => None,
    });
    assert_eq!(
        iterate,
        Some(SolverSettings::adaptive(Method::Dop853, 1e-10))
    );

    // Custom: the controls' method and tolerance for every job.
    rec.clear();
    h.get_by_label("Custom").click();
    h.run_steps(2);
    h.state_mut().flush(&egui::Context::default());
    h.run_steps(2);
    assert_eq!(h.state().settings.accuracy, AccuracyMode::Custom);
    let custom = SolverSettings::adaptive(Method::Dop853, 1e-9);
    assert_eq!(last_settings(&rec), (Some(custom), Some(custom)));
    let line = "dop853 1e-9";
    assert_eq!(h.query_all_by_label(line).count(), 4);
    let evals = job_estimates(&h.state().settings)[0].cells()[2].clone();
    assert_eq!(h.query_all_by_label(&evals).count(), 4, "{evals}");
    // A tolerance between two measured ones is interpolated.
    let field = h.get_by_role_and_label(Role::TextInput, "tolerance value");
    field.focus();
    field.set_text_value_accesskit("3e-10");
    h.run_steps(3);
    assert_eq!(h.state().settings.tol, 3e-10);
    assert_eq!(h.query_all_by_label("dop853 3e-10").count(), 4);
    assert_eq!(
        h.query_all_by_label_contains("err ≈").count(),
        4,
        "interpolated estimate shown for every job"
    );

    // Back to Auto.
    h.get_by_label("Auto").click();
    h.run_steps(2);
    assert_eq!(h.state().settings.accuracy, AccuracyMode::Auto);
    // Under Auto no row keeps Custom's 1e-9, and only the phase diagram's
    // runs at DOP853 1e-8.
    assert_eq!(h.query_all_by_label(line).count(), 0);
    assert_eq!(h.query_all_by_label("dop853 1e-8").count(), 1);
}

#[test]
fn the_numerics_view_shows_the_committed_chart_and_run_sends_the_job() {
    let rec = Recorder::new();
    let settings = Settings {
        layout: oneblock::app::Layout::Tabs,
        tab: View::Numerics,
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
            Command::WorkPrecision { generation, spec } => {
                Some((generation, spec.params, spec.points, spec.subjects))
            }
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
    assert_eq!(h.state().numerics.run.rows.len(), 1);
    assert_eq!(h.state().data.stale_dropped, 0);
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
    assert_eq!(h.state().numerics.run.state, JobState::Cancelled);
    // The y switch.
    h.get_by_label("RHS evaluations per iterate").click();
    h.run_steps(2);
    assert!(h.state().numerics.y_evals);
}

#[test]
fn run_for_current_parameters_fills_the_chart_from_the_real_worker() {
    let worker = Worker::spawn(WorkerConfig::default(), std::sync::Arc::new(|| {}));
    let settings = Settings {
        layout: oneblock::app::Layout::Tabs,
        tab: View::Numerics,
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
    while h.state().numerics.run.rows.len() < 3 {
        assert!(
            start.elapsed() < std::time::Duration::from_secs(120),
            "no rows: {:?}",
            h.state().numerics.run
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
        h.step();
    }
    let run = &h.state().numerics.run;
    assert_eq!(run.state, JobState::Running);
    assert_eq!(run.points, QUICK_POINTS);
    assert_eq!(run.rows[0].method, "euler");
    assert!(run.rows.iter().all(|r| r.points == QUICK_POINTS));
    h.get_by_label("Stop").click();
    h.run_steps(2);
    let n = h.state().numerics.run.rows.len();
    // Nothing of the stopped job arrives after the stop.
    for _ in 0..10 {
        std::thread::sleep(std::time::Duration::from_millis(20));
        h.step();
    }
    let run = &h.state().numerics.run;
    assert_eq!(run.state, JobState::Cancelled);
    assert_eq!(run.rows.len(), n);
    assert!(n < run.total);
}

/// A phase command's generation, θν range and steps, κ range and steps.
#[derive(Clone, Copy, Debug, PartialEq)]
struct PhaseJob {
    generation: Generation,
    theta_nu: (f64, f64, usize),
    kappa: (f64, f64, usize),
    params: Params,
}

fn phase_jobs(rec: &Recorder) -> Vec<PhaseJob> {
    rec.commands()
        .into_iter()
        .filter_map(|c| match c {
            Command::Phase { generation, spec } => Some(PhaseJob {
                generation,
                theta_nu: (spec.theta_nu.from, spec.theta_nu.to, spec.theta_nu.steps),
                kappa: (spec.kappa.from, spec.kappa.to, spec.kappa.steps),
                params: spec.params,
            }),
            _ => None,
        })
        .collect()
}

fn phase_cancels(rec: &Recorder) -> usize {
    rec.commands()
        .iter()
        .filter(|c| {
            matches!(
                c,
                Command::Cancel {
                    lane: Some(Lane::Phase),
                    ..
                }
            )
        })
        .count()
}

fn phase_tab() -> Settings {
    Settings {
        layout: oneblock::app::Layout::Tabs,
        tab: View::Phase,
        ..Settings::default()
    }
}

/// Answers a phase job with every cell, coarse half first: FP below
/// θν = 0.8, P2 above, chaos in the top right corner.
fn feed_phase(rec: &Recorder, job: &PhaseJob) {
    let tns = theta_nu_grid(job.theta_nu.0, job.theta_nu.1, job.theta_nu.2);
    let ks = theta_nu_grid(job.kappa.0, job.kappa.1, job.kappa.2);
    let mut cells = Vec::new();
    for (row, &kappa) in ks.iter().enumerate() {
        for (column, &theta_nu) in tns.iter().enumerate() {
            let class = if kappa > 30.0 && theta_nu > 1.2 {
                CellClass::Chaos
            } else if theta_nu > 0.8 {
                CellClass::Periodic(2)
            } else {
                CellClass::Periodic(1)
            };
            cells.push(GridCell {
                row,
                column,
                cell: PhaseCell {
                    theta_nu,
                    kappa,
                    class,
                    lyapunov: Some(if class == CellClass::Chaos { 0.3 } else { -0.2 }),
                    lyapunov_stderr: (class == CellClass::Chaos).then_some(0.05),
                    regime: None,
                    iterates: 40,
                    rhs_evals: 20_000,
                    theta_last: theta_nu,
                    error: None,
                },
            });
        }
    }
    let half = cells.len() / 2;
    let rest = cells.split_off(half);
    rec.push(Update::PhaseCells {
        generation: job.generation,
        cells,
        coarse: true,
    });
    rec.push(Update::PhaseCells {
        generation: job.generation,
        cells: rest,
        coarse: false,
    });
    rec.push(Update::Finished {
        generation: job.generation,
        lane: Lane::Phase,
        outcome: Outcome::Completed,
    });
}

/// Where the centre of the phase cell (row, column) of `job` is on screen.
fn phase_cell_pos(
    h: &Harness<'static, Explorer>,
    job: &PhaseJob,
    row: usize,
    column: usize,
) -> egui::Pos2 {
    let tns = theta_nu_grid(job.theta_nu.0, job.theta_nu.1, job.theta_nu.2);
    let ks = theta_nu_grid(job.kappa.0, job.kappa.1, job.kappa.2);
    let t = h.state().phase.transform.expect("the phase plot was drawn");
    t.position_from_point(&PlotPoint::new(tns[column], ks[row]))
}

#[test]
fn the_phase_diagram_is_computed_only_while_its_view_is_shown() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(3);
    assert!(phase_jobs(&rec).is_empty(), "not shown: no grid");
    // Shown as a tab: the paper's grid at the sliders' γ, ν, Ω.
    h.state_mut().settings.layout = oneblock::app::Layout::Tabs;
    h.state_mut().settings.tab = View::Phase;
    h.run_steps(2);
    let jobs = phase_jobs(&rec);
    assert_eq!(jobs.len(), 1);
    let j = jobs[0];
    assert_eq!(j.theta_nu, (0.0, std::f64::consts::FRAC_PI_2, 30));
    assert_eq!(j.kappa, (1.0, 42.0, 30));
    assert_eq!(
        (j.params.gamma, j.params.nu, j.params.omega),
        (6.5, 1e-3, 50.0)
    );
    assert!(h.query_by_label_contains("0/900 cells").is_some());
    // Hidden while running: stopped; shown again: started afresh.
    h.state_mut().settings.tab = View::Plane;
    h.run_steps(2);
    assert_eq!(phase_cancels(&rec), 1);
    assert_eq!(phase_jobs(&rec).len(), 1);
    h.state_mut().settings.tab = View::Phase;
    h.run_steps(2);
    let jobs = phase_jobs(&rec);
    assert_eq!(jobs.len(), 2);
    assert!(jobs[1].generation > jobs[0].generation);
    // Moving κ or θν only moves the cross-hair; γ recomputes the grid.
    rec.clear();
    h.state_mut().settings.params.kappa = 30.0;
    h.state_mut().settings.params.theta_nu = 0.4;
    let ctx = h.ctx.clone();
    h.state_mut().flush(&ctx);
    h.run_steps(2);
    assert!(phase_jobs(&rec).is_empty());
    h.state_mut().settings.params.gamma = 6.0;
    h.run_steps(1);
    let ctx = h.ctx.clone();
    h.state_mut().flush(&ctx);
    h.run_steps(1);
    let jobs = phase_jobs(&rec);
    assert_eq!(jobs.len(), 1);
    assert_eq!(jobs[0].params.gamma, 6.0);
    // Stop: stays stopped.
    rec.clear();
    h.get_by_label("Stop").click();
    h.run_steps(2);
    let ctx = h.ctx.clone();
    h.state_mut().flush(&ctx);
    h.run_steps(2);
    assert_eq!(phase_cancels(&rec), 1);
    assert!(phase_jobs(&rec).is_empty());
    assert!(h.query_by_label_contains("stopped").is_some());
    h.get_by_label("Compute").click();
    h.run_steps(2);
    assert_eq!(phase_jobs(&rec).len(), 1);
}

#[test]
fn the_phase_view_draws_the_cells_and_a_click_sets_theta_nu_and_kappa() {
    let rec = Recorder::new();
    let mut h = harness(&rec, phase_tab());
    h.run_steps(2);
    let job = phase_jobs(&rec)[0];
    // A stale batch (an older generation) is dropped.
    rec.push(Update::PhaseCells {
        generation: 0,
        cells: vec![],
        coarse: true,
    });
    feed_phase(&rec, &job);
    h.run_steps(3);
    {
        let d = &h.state().data;
        assert_eq!(d.phase.filled, 900);
        assert_eq!(d.phase.state, JobState::Done);
        assert_eq!(d.stale_dropped, 1);
    }
    assert!(h.query_by_label_contains("900/900 cells · done").is_some());
    // The legend names every class.
    for name in ["FP", "P2", "P6+", "chaos", "undecided", "failed"] {
        assert!(h.query_by_label(name).is_some(), "legend {name}");
    }

    // Click the cell at row 20, column 7.
    rec.clear();
    let (row, column) = (20, 7);
    let pos = phase_cell_pos(&h, &job, row, column);
    h.hover_at(pos);
    h.run_steps(3);
    // Hovering tells the cell (θν = 7·(π/2)/29, κ = 1 + 20·41/29: FP here).
    assert!(
        h.query_by_label_contains("θν = 0.3792, κ = 29.2759")
            .is_some(),
        "the hovered cell is described"
    );
    assert!(h.query_by_label_contains("FP (fixed point)").is_some());
    assert!(h.query_by_label_contains("40 iterates").is_some());
    h.drag_at(pos);
    h.step();
    h.drop_at(pos);
    h.run_steps(3);
    let want_tn = theta_nu_grid(0.0, std::f64::consts::FRAC_PI_2, 30)[column];
    let want_k = theta_nu_grid(1.0, 42.0, 30)[row];
    let p = h.state().settings.params;
    assert_eq!((p.theta_nu, p.kappa), (want_tn, want_k));
    assert!(
        h.state().settings.phase.zoom.is_empty(),
        "a click is not a zoom"
    );
    // The sliders show it and the orbit restarts there.
    let slider = |s: &str| {
        h.get_by_role_and_label(Role::Slider, s)
            .accesskit_node()
            .numeric_value()
    };
    assert_eq!(slider("κ"), Some(want_k));
    assert_eq!(slider("θν"), Some(want_tn));
    let t = last_trajectory(&rec).expect("the orbit restarts at the cell");
    assert_eq!((t.theta_nu, t.kappa), (want_tn, want_k));
    // κ and θν are the grid's axes: no new grid.
    assert!(phase_jobs(&rec).is_empty());
}

#[test]
fn a_box_on_the_phase_diagram_recomputes_that_range_and_back_restores_it() {
    let rec = Recorder::new();
    let mut h = harness(&rec, phase_tab());
    h.run_steps(2);
    let full = phase_jobs(&rec)[0];
    feed_phase(&rec, &full);
    h.run_steps(3);
    rec.clear();
    let (a, b) = (
        phase_cell_pos(&h, &full, 5, 4),
        phase_cell_pos(&h, &full, 22, 25),
    );
    h.hover_at(a);
    h.step();
    h.drag_at(a);
    h.step();
    for i in 1..=5 {
        h.hover_at(a + (b - a) * (i as f32 / 5.0));
        h.step();
    }
    h.drop_at(b);
    h.run_steps(3);
    let jobs = phase_jobs(&rec);
    assert_eq!(jobs.len(), 1, "a zoom recomputes at once");
    let z = jobs[0];
    let tns = theta_nu_grid(0.0, std::f64::consts::FRAC_PI_2, 30);
    let ks = theta_nu_grid(1.0, 42.0, 30);
    let near = |x: f64, y: f64, tol: f64| (x - y).abs() < tol;
    assert!(
        near(z.theta_nu.0, tns[4], 0.01) && near(z.theta_nu.1, tns[25], 0.01),
        "{z:?}"
    );
    assert!(
        near(z.kappa.0, ks[5], 0.2) && near(z.kappa.1, ks[22], 0.2),
        "{z:?}"
    );
    // At full resolution, not a magnified picture.
    assert_eq!((z.theta_nu.2, z.kappa.2), (30, 30));
    assert_eq!(h.state().settings.phase.zoom.len(), 1);
    // The view now shows the zoomed grid, computing.
    assert_eq!(h.state().data.phase.kappa, (z.kappa.0, z.kappa.1));
    // Back returns to the whole range.
    rec.clear();
    h.get_by_label("Back").click();
    h.run_steps(3);
    let jobs = phase_jobs(&rec);
    assert_eq!(jobs.len(), 1);
    assert_eq!(
        (jobs[0].theta_nu, jobs[0].kappa),
        (full.theta_nu, full.kappa)
    );
    assert!(h.state().settings.phase.zoom.is_empty());
}

#[test]
fn export_writes_the_phase_grid_as_oneblock_phase_does() {
    let dir = tempfile::tempdir().expect("temp dir");
    let rec = Recorder::new();
    let settings = Settings {
        save_dir: dir.path().display().to_string(),
        ..phase_tab()
    };
    let mut h = harness(&rec, settings);
    h.run_steps(2);
    let job = phase_jobs(&rec)[0];
    feed_phase(&rec, &job);
    h.run_steps(2);
    h.get_by_label("Export data").click();
    h.run_steps(2);
    h.get_by_label("Phase diagram CSV (oneblock phase)").click();
    let path = wait_for_csv(&mut h, dir.path()).expect("a phase CSV was written");
    assert!(
        path.file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with("oneblock-phase-"))
    );
    let text = std::fs::read_to_string(&path).expect("read csv");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[0],
        "theta_nu,kappa,period,lyapunov,regime,iterates,class,lyapunov_stderr"
    );
    assert_eq!(lines.len(), 901);
    // Rows of increasing κ, each along increasing θν.
    assert_eq!(lines[1], "0,1,1,-0.2,,40,FP,");
    assert!(lines[900].starts_with("1.5707963267948966,42,0,0.3,,40,chaos,0.05"));
}

#[test]
fn smooth_lines_follow_the_switch_and_auto_drops_them_on_software_gl() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    let feathering = |h: &Harness<'static, Explorer>| h.ctx.tessellation_options(|o| o.feathering);
    // A GPU (or unknown renderer): Auto means anti-aliased.
    assert_eq!(h.state().settings.smooth_lines, None);
    assert!(h.query_by_label("Auto (on)").is_some());
    assert!(feathering(&h));
    h.get_by_label("off").click();
    h.run_steps(2);
    assert_eq!(h.state().settings.smooth_lines, Some(false));
    assert!(!feathering(&h));
    // Software OpenGL: Auto turns them off, and says why.
    h.state_mut().set_software_gl(true);
    h.run_steps(1);
    h.get_by_label("Auto (off: software GL)").click();
    h.run_steps(2);
    assert_eq!(h.state().settings.smooth_lines, None);
    assert!(h.query_by_label("Auto (off: software GL)").is_some());
    assert!(!feathering(&h));
    h.get_by_label("on").click();
    h.run_steps(2);
    assert!(feathering(&h));
}
