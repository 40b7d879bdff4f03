//! The accuracy selector: under Auto each job is sent the setting the
//! budget picks for its view, with the committed chart's estimate beside
//! it; under Custom every job gets the typed method and tolerance.
#![cfg(feature = "gui")]

use crate::window;

use eframe::egui;
use eframe::egui::accesskit::Role;
use egui_kittest::kittest::Queryable;
use oneblock::worker::Spec;

use oneblock::app::accuracy::job_estimates;
use oneblock::app::jobs::JobKind;
use oneblock::app::settings::AccuracyMode;
use oneblock::app::{Recorder, Settings};
use oneblock::integrate::{Method, SolverSettings};
use oneblock::worker::{Command, Lane, Outcome, Update};
use window::{harness, last_settings};

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
            JobKind::Trajectory.solver(&auto),
            JobKind::Sweep.solver(&auto)
        )
    );
    assert_eq!(
        JobKind::Iterate.solver(&auto),
        Some(SolverSettings::adaptive(Method::Dop853, 1e-10))
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
            Command::Run {
                generation,
                spec: Spec::Trajectory(..),
            } => Some(*generation),
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
        Command::Run {
            spec: Spec::Iterate(spec),
            ..
        } => Some(spec.settings),
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
