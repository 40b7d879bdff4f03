//! The window's CSV exports: the data of a job into a fresh file in the
//! save folder, written on a thread (see [`Shots::write`]), with a toast
//! when there is nothing to export yet, and a note on the accuracy a
//! trajectory was computed with.

use super::accuracy::job_estimates;
use super::export;
use super::files::fresh_path;
use super::jobs::{JobKind, Jobs};
use super::screenshot::Shots;
use super::settings::{AccuracyMode, Settings};
use super::view::Export;

/// Writes the CSV of `what` into the save folder of `s`; `now` is the ui
/// time (for the toasts).
pub fn export_csv(what: Export, s: &Settings, jobs: &Jobs, shots: &mut Shots, now: f64) {
    let dir = &s.save_dir;
    let (name, csv, empty) = match what {
        Export::Events => (
            "events",
            (!jobs.trajectory.data.events.is_empty())
                .then(|| export::events_csv(&jobs.trajectory.data.events)),
            "No events to export yet",
        ),
        Export::Trajectory => (
            "trajectory",
            (!jobs.trajectory.data.samples.is_empty())
                .then(|| export::trajectory_csv(&jobs.trajectory.data.samples)),
            "No trajectory to export yet",
        ),
        Export::Bifurcation => (
            "bifurcation",
            (jobs.sweep.data.filled > 0).then(|| export::bifurcation_csv(&jobs.sweep.data)),
            "No diagram columns to export yet",
        ),
        Export::Phase => (
            "phase",
            (jobs.phase.data.filled > 0).then(|| export::phase_csv(&jobs.phase.data)),
            "No phase-diagram cells to export yet",
        ),
    };
    let Some(csv) = csv else {
        shots.toast(empty.into(), true, now);
        return;
    };
    let kind = match what {
        Export::Events | Export::Trajectory => JobKind::Trajectory,
        Export::Bifurcation => JobKind::Sweep,
        Export::Phase => JobKind::Phase,
    };
    let csv = crate::provenance::with_header(&export::header(name, s, kind), &csv);
    shots.write(fresh_path(dir, name, "csv"), csv.into_bytes());
    if matches!(what, Export::Events | Export::Trajectory) {
        accuracy_note(name, s, shots, now);
    }
}

/// Says with what accuracy an exported trajectory or its events were
/// computed: under Auto that is the (x, y) view's, far coarser than the
/// command line's default, and a CSV does not show it.
fn accuracy_note(what: &str, s: &Settings, shots: &mut Shots, now: f64) {
    if s.accuracy != AccuracyMode::Auto {
        return;
    }
    let Some(e) = job_estimates(s)
        .into_iter()
        .find(|e| e.job == JobKind::Trajectory)
    else {
        return;
    };
    let msg = format!(
        "The {what} was computed at Auto's trajectory accuracy ({}); pick Custom, or \
         use `oneblock orbit` / `trajectory` (tol 1e-10), for a tighter one.",
        e.text()
    );
    shots.toast(msg, false, now);
}
