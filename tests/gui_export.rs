//! CSV exports from the window: the events and the phase grid are written
//! into the chosen folder in the command line's formats, under a fresh
//! name, with a note on the accuracy of an Auto trajectory.
#![cfg(feature = "gui")]

#[path = "common/window.rs"]
mod window;

use egui_kittest::kittest::Queryable;

use oneblock::app::{Recorder, Settings};
use oneblock::worker::{Command, Update};
use window::{event, feed_phase, harness, phase_jobs, phase_tab, wait_for_csv};

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
