//! The status bar: where each job stands, the worker's speed, and the
//! last error it reported.

use eframe::egui;
use egui::{RichText, Ui};

use super::jobs::{JobState, Jobs};
use super::screenshot::Toast;
use super::style;

/// The status bar of the jobs `j`, on one line at any width: the job
/// words and bars first, then the continuation's and the last error's
/// lines, cut to the room left with "…" (the whole line on hover). The
/// toasts (a file saved, a link's values refused) come first, newest
/// first, each on a tinted ground: the bar never grows, so a message
/// never covers data nor moves the views.
pub fn status_ui(ui: &mut Ui, j: &Jobs, toasts: &[Toast]) {
    ui.horizontal(|ui| {
        for t in toasts.iter().rev() {
            toast_ui(ui, t);
        }
        if busy(j) {
            ui.spinner();
        }
        let [traj, orbit] = orbit_labels(j);
        ui.label(traj);
        ui.separator();
        ui.label(orbit);
        ui.separator();
        progress_bars(ui, j);
        ui.label(format!(
            "{:.0} iterates/s",
            j.sweep.progress.iterates_per_second
                + j.orbit_progress().iterates_per_second
                + j.phase.progress.iterates_per_second
        ));
        let mut tail: Vec<RichText> = Vec::new();
        if let Some(e) = &j.last_error {
            tail.push(RichText::new(format!("error: {e}")).color(style::ERROR));
        }
        for (name, slot) in [
            ("bifurcations", &j.branches.head),
            ("boundaries", &j.curves.head),
        ] {
            let line = continuation_status(
                name,
                &slot.state,
                slot.progress.fraction,
                slot.summary.as_deref(),
            );
            tail.extend(line.map(RichText::new));
        }
        for text in tail {
            if ui.available_width() < 24.0 {
                break;
            }
            ui.separator();
            ui.add(egui::Label::new(text).truncate());
        }
    });
}

/// One toast in the bar: its text cut to at most 60 % of the width left
/// (all of it on hover), red when it reports an error.
fn toast_ui(ui: &mut Ui, t: &Toast) {
    let color = if t.error {
        style::ERROR
    } else {
        ui.visuals().strong_text_color()
    };
    let width = ui.available_width() * 0.6;
    egui::Frame::new()
        .fill(ui.visuals().extreme_bg_color)
        .stroke(ui.visuals().widgets.noninteractive.bg_stroke)
        .corner_radius(3.0)
        .inner_margin(egui::Margin::symmetric(4, 0))
        .show(ui, |ui| {
            ui.set_max_width(width);
            ui.add(egui::Label::new(RichText::new(&t.text).color(color)).truncate());
        });
    ui.separator();
}

/// Whether any job runs.
fn busy(j: &Jobs) -> bool {
    [
        &j.trajectory.state,
        &j.iterate.state,
        &j.sweep.state,
        &j.phase.state,
        &j.branches.state,
        &j.curves.state,
    ]
    .iter()
    .any(|s| matches!(s, JobState::Running))
}

/// The title of the browser tab: the app's name, and while jobs run, how
/// far the diagram is ("computing: diagram 37 %"); the browser test waits
/// on it.
pub fn title(j: &Jobs) -> String {
    const NAME: &str = "oneblock: one-block earthquake model";
    if !busy(j) {
        return NAME.into();
    }
    let sweep = &j.sweep.data;
    if matches!(j.sweep.state, JobState::Running) && !sweep.columns.is_empty() {
        let pct = 100 * sweep.filled / sweep.columns.len();
        format!("oneblock · computing: diagram {pct} %")
    } else {
        "oneblock · computing".into()
    }
}

/// The trajectory's and the orbit analysis's words.
fn orbit_labels(j: &Jobs) -> [String; 2] {
    let (traj, it) = (&j.trajectory.data, &j.iterate.data);
    let traj = match &j.trajectory.state {
        JobState::Running => format!("trajectory: {} cycles…", traj.events.len()),
        JobState::Done => format!("trajectory: {} cycles", traj.events.len()),
        s => format!("trajectory: {}", state_word(s)),
    };
    let orbit = match (&j.iterate.state, it.period) {
        (JobState::Running, _) => format!(
            "orbit analysis {:.0}%",
            100.0 * j.orbit_progress().fraction.clamp(0.0, 1.0)
        ),
        (_, Some(p)) => format!("period {p}"),
        (s, None) => format!("orbit: {}", state_word(s)),
    };
    [traj, orbit]
}

/// The diagram's and the phase grid's progress bars.
fn progress_bars(ui: &mut Ui, j: &Jobs) {
    let (sweep, phase) = (&j.sweep.data, &j.phase.data);
    let frac = if sweep.columns.is_empty() {
        0.0
    } else {
        sweep.filled as f32 / sweep.columns.len() as f32
    };
    ui.label("diagram");
    ui.add(
        egui::ProgressBar::new(frac)
            .desired_width(120.0)
            .text(format!("{}/{}", sweep.filled, sweep.columns.len())),
    );
    let phase_cells = phase.rows * phase.columns;
    if phase_cells > 0 {
        ui.label("phase");
        ui.add(
            egui::ProgressBar::new(phase.filled as f32 / phase_cells as f32)
                .desired_width(100.0)
                .text(format!("{}/{phase_cells}", phase.filled)),
        );
    }
}

/// "bifurcations 40%: 1 PD, 0 fold, 0 border · following the cascade…",
/// or what the finished job said (`None` before any job).
pub fn continuation_status(
    name: &str,
    state: &JobState,
    fraction: f64,
    summary: Option<&str>,
) -> Option<String> {
    let summary = summary.unwrap_or("");
    Some(match state {
        JobState::Idle if summary.is_empty() => return None,
        JobState::Running => format!(
            "{name} {:.0}%: {}",
            100.0 * fraction.clamp(0.0, 1.0),
            if summary.is_empty() {
                "starting…"
            } else {
                summary
            }
        ),
        JobState::Failed(m) => format!("{name}: failed: {m}"),
        _ if summary.is_empty() => format!("{name}: {}", state_word(state)),
        _ => format!("{name}: {summary}"),
    })
}

fn state_word(s: &JobState) -> String {
    match s {
        JobState::Idle => "idle".into(),
        JobState::Running => "running".into(),
        JobState::Done => "done".into(),
        JobState::Cancelled => "cancelled".into(),
        JobState::Failed(m) => format!("failed: {m}"),
    }
}
