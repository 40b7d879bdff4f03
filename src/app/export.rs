//! CSV in the command line's formats: events (every `SlipEvent` field, in
//! order, `restarted` as 0/1, as `formats::slip_event_row` writes them),
//! trajectory (`t,x,y,u,w,phase`), bifurcation (`theta_nu,theta,lyapunov,lyapunov_stderr`,
//! then `attractor` when seeded), phase
//! diagram (`oneblock phase --out`'s columns and rows). Floats
//! in Rust's shortest round-trip form, so parsing gives back the exact f64.
//! Each begins with the `#` lines of [`crate::provenance`] ([`header`]).

use super::data::SweepData;
use super::jobs::JobKind;
use super::phase_data::PhaseData;
use super::settings::Settings;
use crate::formats::{self, SLIP_EVENT_COLUMNS, phase_header, phase_row, slip_event_row};
use crate::sim::{Sample, SlipEvent};

/// The events CSV: the command line's header and rows, from the same code.
pub fn events_csv(events: &[SlipEvent]) -> String {
    let mut s = String::with_capacity(200 * (events.len() + 1));
    s.push_str(&SLIP_EVENT_COLUMNS.join(","));
    s.push('\n');
    for e in events {
        s.push_str(&slip_event_row(e));
        s.push('\n');
    }
    s
}

/// The trajectory CSV, as `oneblock trajectory` writes it.
pub fn trajectory_csv(samples: &[Sample]) -> String {
    formats::trajectory_csv(samples)
}

/// The diagram's computed columns, as `oneblock bifurcation` writes them:
/// with its `attractor` column when the columns were seeded.
pub fn bifurcation_csv(sweep: &SweepData) -> String {
    let columns = sweep.columns.iter().flatten();
    let seeded = columns.clone().any(|c| !c.attractor.is_empty());
    formats::bifurcation_csv(
        sweep.param,
        columns.map(|c| {
            (
                c.value,
                c.thetas.as_slice(),
                c.lyapunov,
                c.attractor.as_slice(),
            )
        }),
        seeded,
    )
}

/// The phase diagram as `oneblock phase --out` writes it (rows of
/// increasing κ, each along increasing θν), from the same code; cells not
/// computed yet are left out. The `attractors` column is there when any
/// cell's attractors were asked for (counted, or said why not).
pub fn phase_csv(phase: &PhaseData) -> String {
    let mut s = String::with_capacity(80 * (phase.filled + 1));
    let cells = || phase.cells.iter().flatten();
    let attractors = cells().any(|c| c.attractors.is_some() || c.uncounted.is_some());
    s.push_str(&phase_header(attractors));
    s.push('\n');
    for c in cells() {
        s.push_str(&phase_row(c, attractors));
        s.push('\n');
    }
    s
}

/// The `#` lines a CSV of the window's `view` begins with: the program,
/// the view, the model's parameters with the accuracy `kind`'s job ran
/// at (the varied parameter left out: the diagram's, or θν for the phase grid), and every setting of the window as
/// one line of a session's JSON (what "Open session" reads).
pub fn header(view: &str, s: &Settings, kind: JobKind) -> String {
    let solver = kind.solver(s).unwrap_or_else(|| s.custom_solver());
    let model = match kind {
        // The diagram's axis is left out and named as varied.
        JobKind::Sweep => {
            crate::provenance::model_line_varying(&s.params, &solver, s.diagram.param)
        }
        JobKind::Phase => crate::provenance::model_line(&s.params, &solver, false),
        _ => crate::provenance::model_line(&s.params, &solver, true),
    };
    let session = serde_json::to_string(s).unwrap_or_default();
    crate::provenance::header(
        Some(&format!("view: {view} (the window)")),
        &model,
        Some(&[format!("window settings: {session}")]),
    )
}

/// "YYYYMMDD-HHMMSS" in UTC, for file names.
pub fn timestamp() -> String {
    let secs = web_time::SystemTime::now()
        .duration_since(web_time::UNIX_EPOCH)
        .map(|d| d.as_secs() as i64)
        .unwrap_or(0);
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    // Howard Hinnant's civil_from_days.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}{m:02}{d:02}-{:02}{:02}{:02}",
        rem / 3600,
        (rem / 60) % 60,
        rem % 60
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A seeded diagram's CSV has the command line's `attractor` column:
    /// λ on the followed attractor's rows only.
    #[test]
    fn a_seeded_diagram_keeps_its_attractor_column() {
        use crate::app::data::Column;
        use crate::sim::column_lyapunov::ColumnLyapunov;
        let mut sweep = SweepData::new(1.0, 1.1, 2);
        let lyapunov = Some(ColumnLyapunov {
            lyapunov: -0.5,
            stderr: None,
            period: Some(1),
        });
        for (i, attractor) in [vec![0, 1], vec![]].into_iter().enumerate() {
            let thetas = if attractor.is_empty() {
                vec![0.3]
            } else {
                vec![0.2, 0.4]
            };
            sweep.insert(
                i,
                Column {
                    value: 1.0 + 0.1 * i as f64,
                    thetas,
                    coarse: false,
                    lyapunov,
                    attractor,
                    uncounted: None,
                },
            );
        }
        let csv = bifurcation_csv(&sweep);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(
            lines,
            [
                "theta_nu,theta,lyapunov,lyapunov_stderr,attractor",
                "1,0.2,-0.5,,0",
                "1,0.4,,,1",
                "1.1,0.3,-0.5,,0",
            ]
        );
        // Unseeded: the four columns only.
        let mut plain = SweepData::new(1.0, 1.1, 1);
        plain.insert(
            0,
            Column {
                value: 1.0,
                thetas: vec![0.2],
                coarse: false,
                lyapunov,
                attractor: vec![],
                uncounted: None,
            },
        );
        assert_eq!(
            bifurcation_csv(&plain),
            "theta_nu,theta,lyapunov,lyapunov_stderr\n1,0.2,-0.5,\n"
        );
    }

    #[test]
    fn timestamp_has_the_shape() {
        let t = timestamp();
        assert_eq!(t.len(), 15);
        assert_eq!(&t[8..9], "-");
    }
}
