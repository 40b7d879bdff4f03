//! The file formats every front end writes, so that the command line and the
//! window export the same bytes: the slip-event CSV, the trajectory CSV, the
//! bifurcation CSV, the phase-diagram CSV, and the phase classes' names and
//! colours. Numbers are written in Rust's shortest round-trip form, so
//! parsing gives back the exact f64.

use std::fmt::Write as _;

use crate::sim::column_lyapunov::ColumnLyapunov;
use crate::sim::continuation::ContParam;
use crate::sim::phase::{CellClass, PhaseCell};
use crate::sim::{Sample, SlipEvent};

/// The CSV columns of a slip event: every `SlipEvent` field, in order.
pub const SLIP_EVENT_COLUMNS: [&str; 16] = [
    "theta",
    "onset_x",
    "onset_y",
    "onset_time",
    "accel_duration",
    "slip_duration",
    "stop_x",
    "stop_y",
    "slip_distance",
    "peak_vr",
    "energy_released",
    "stick_duration",
    "theta_next",
    "restarted",
    "rhs_evals",
    "steps",
];

/// One CSV row of a slip event (no newline). Numbers are written with
/// Rust's shortest round-trip formatting, so parsing gives back the exact
/// f64; `restarted` is 0 or 1 so that the whole file is numeric.
pub fn slip_event_row(e: &SlipEvent) -> String {
    csv_line(&[
        e.theta.to_string(),
        e.onset_x.to_string(),
        e.onset_y.to_string(),
        e.onset_time.to_string(),
        e.accel_duration.to_string(),
        e.slip_duration.to_string(),
        e.stop_x.to_string(),
        e.stop_y.to_string(),
        e.slip_distance.to_string(),
        e.peak_vr.to_string(),
        e.energy_released.to_string(),
        e.stick_duration.to_string(),
        e.theta_next.to_string(),
        u8::from(e.restarted).to_string(),
        e.rhs_evals.to_string(),
        e.steps.to_string(),
    ])
}

/// One CSV record without its newline, quoted by the csv crate where a
/// field needs it (numbers and class names never do, so the bytes are the
/// fields joined by commas).
pub fn csv_line(fields: &[String]) -> String {
    let mut w = csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .from_writer(Vec::new());
    // Writing to memory cannot fail, and the fields are UTF-8.
    if w.write_record(fields).is_err() {
        return fields.join(",");
    }
    let bytes = w.into_inner().unwrap_or_default();
    let mut line = String::from_utf8(bytes).unwrap_or_default();
    line.pop();
    line
}

/// The trajectory CSV's header.
pub const TRAJECTORY_HEADER: &str = "t,x,y,u,w,phase";

/// The trajectory CSV (`t,x,y,u,w,phase`, one row per sample).
pub fn trajectory_csv(samples: &[Sample]) -> String {
    let mut s = String::with_capacity(64 * (samples.len() + 1));
    s.push_str(TRAJECTORY_HEADER);
    s.push('\n');
    trajectory_rows(&mut s, samples);
    s
}

/// The trajectory CSV's rows of `samples`, appended to `s`.
pub fn trajectory_rows(s: &mut String, samples: &[Sample]) {
    for p in samples {
        writeln!(
            s,
            "{},{},{},{},{},{}",
            p.t,
            p.x,
            p.y,
            p.u,
            p.w,
            p.phase.name()
        )
        .ok();
    }
}

/// The bifurcation CSV's header.
pub const BIFURCATION_COLUMNS: &str = "theta_nu,theta,lyapunov,lyapunov_stderr";

/// One column of a bifurcation diagram: the varied parameter's value, the
/// kept θ, λ, and (seeded) the attractor of each θ (0: the followed one).
pub type DiagramColumn<'a> = (f64, &'a [f64], Option<ColumnLyapunov>, &'a [u8]);

/// The bifurcation CSV ([`BIFURCATION_COLUMNS`], its first column named
/// for the varied `param`: `kappa,theta,…` for a diagram in κ): one row
/// per kept iterate,
/// column by column in the order given. Every row of a column repeats its
/// λ ([`crate::sim::column_lyapunov`]); `lyapunov_stderr` is empty where λ
/// is exact (a solved cycle), both are empty where λ was not computed.
/// A `seeded` diagram's rows end with their attractor's label (an
/// `attractor` column); λ is the followed attractor's, so it is given on
/// its rows only (empty on the others').
pub fn bifurcation_csv<'a>(
    param: ContParam,
    columns: impl Iterator<Item = DiagramColumn<'a>> + Clone,
    seeded: bool,
) -> String {
    let rows: usize = columns.clone().map(|c| c.1.len()).sum();
    let mut s = String::with_capacity(60 * (rows + 1));
    let rest = BIFURCATION_COLUMNS.trim_start_matches("theta_nu");
    s.push_str(param.column());
    s.push_str(rest);
    s.push_str(if seeded { ",attractor\n" } else { "\n" });
    let opt = |v: Option<f64>| v.map_or(String::new(), |x| x.to_string());
    for (theta_nu, thetas, lyap, labels) in columns {
        let l = opt(lyap.map(|l| l.lyapunov));
        let se = opt(lyap.and_then(|l| l.stderr));
        for (i, t) in thetas.iter().enumerate() {
            if !seeded {
                writeln!(s, "{theta_nu},{t},{l},{se}").ok();
                continue;
            }
            match labels.get(i).copied().unwrap_or(0) {
                0 => writeln!(s, "{theta_nu},{t},{l},{se},0").ok(),
                a => writeln!(s, "{theta_nu},{t},,,{a}").ok(),
            };
        }
    }
    s
}

/// The phase CSV's header without the `attractors` column.
pub const PHASE_COLUMNS: &str =
    "theta_nu,kappa,period,lyapunov,regime,iterates,class,lyapunov_stderr";

/// The phase CSV's header: [`PHASE_COLUMNS`], and `attractors` when the
/// cells' attractors were asked for (`phase --seeds`).
pub fn phase_header(attractors: bool) -> String {
    if attractors {
        format!("{PHASE_COLUMNS},attractors")
    } else {
        PHASE_COLUMNS.to_string()
    }
}

/// One CSV row under [`phase_header`]`(attractors)`, with as many fields:
/// numbers in Rust's shortest round-trip form; `lyapunov`,
/// `lyapunov_stderr` and `regime` are empty when not computed, and so is
/// `attractors` where they were not counted (a failed cell, or one whose
/// exit arc's graph could not be built).
pub fn phase_row(c: &PhaseCell, attractors: bool) -> String {
    let opt = |v: Option<f64>| v.map_or(String::new(), |x| x.to_string());
    let mut fields = vec![
        c.theta_nu.to_string(),
        c.kappa.to_string(),
        c.class.period().to_string(),
        opt(c.lyapunov),
        c.regime.map_or("", |r| r.name()).to_string(),
        c.iterates.to_string(),
        c.class.label().to_string(),
        opt(c.lyapunov_stderr),
    ];
    if attractors {
        fields.push(c.attractors.map_or(String::new(), |n| n.to_string()));
    }
    csv_line(&fields)
}

/// The picture's classes and colours, in legend order.
pub const PHASE_LEGEND: [(&str, [u8; 3]); 9] = [
    ("FP", [49, 104, 181]),
    ("P2", [82, 170, 84]),
    ("P3", [240, 140, 30]),
    ("P4", [150, 80, 180]),
    ("P5", [230, 205, 40]),
    ("P6+", [220, 110, 170]),
    ("CHAOS", [20, 20, 20]),
    ("UNDECIDED", [175, 175, 175]),
    ("FAILED", [210, 30, 30]),
];

pub fn legend_class(c: CellClass) -> &'static str {
    match c {
        CellClass::Periodic(1) => "FP",
        CellClass::Periodic(2) => "P2",
        CellClass::Periodic(3) => "P3",
        CellClass::Periodic(4) => "P4",
        CellClass::Periodic(5) => "P5",
        CellClass::Periodic(_) => "P6+",
        CellClass::Chaos => "CHAOS",
        CellClass::Undecided => "UNDECIDED",
        CellClass::Failed => "FAILED",
    }
}

/// The colour of a class, the same in the PNG and in the window.
pub fn class_colour(c: CellClass) -> [u8; 3] {
    let l = legend_class(c);
    PHASE_LEGEND
        .iter()
        .find(|(n, _)| *n == l)
        .map_or([255, 0, 255], |(_, c)| *c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_columns_are_the_slip_event_fields() {
        let e = SlipEvent {
            theta: 0.5,
            onset_x: 0.1,
            onset_y: 0.2,
            onset_time: 0.3,
            accel_duration: 0.4,
            slip_duration: 0.6,
            stop_x: 0.7,
            stop_y: 0.8,
            slip_distance: 0.9,
            peak_vr: 1.1,
            energy_released: 1.2,
            stick_duration: 1.3,
            theta_next: 1.4,
            restarted: true,
            rhs_evals: 15,
            steps: 16,
        };
        let json = serde_json::to_value(e).expect("a SlipEvent serializes");
        let obj = json.as_object().expect("an object");
        assert_eq!(obj.len(), SLIP_EVENT_COLUMNS.len());
        let row = slip_event_row(&e);
        let record = csv::ReaderBuilder::new()
            .has_headers(false)
            .from_reader(row.as_bytes())
            .into_records()
            .next()
            .expect("one record")
            .expect("valid CSV");
        let cells: Vec<&str> = record.iter().collect();
        assert_eq!(cells.len(), SLIP_EVENT_COLUMNS.len());
        for (name, cell) in SLIP_EVENT_COLUMNS.iter().zip(cells) {
            let v = &obj[*name];
            let expected = match v {
                serde_json::Value::Bool(b) => u8::from(*b).to_string(),
                other => other.to_string(),
            };
            assert_eq!(
                cell.parse::<f64>().ok(),
                expected.parse::<f64>().ok(),
                "{name}"
            );
        }
    }
}
