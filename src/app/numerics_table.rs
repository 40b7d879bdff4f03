//! The Numerics view's table: a row per measured setting, the settings
//! the jobs run with in bold, and a failed row's reason in words.

use eframe::egui;
use egui::{RichText, Ui};

use super::jobs::JobKind;
use super::settings::Settings;
use super::style;
use crate::numerics::{Row, Subject};

/// The table under the chart, with the rows the jobs run marked.
pub fn table_ui(ui: &mut Ui, rows: &[Row], s: &Settings) {
    let used: Vec<(JobKind, Subject)> = JobKind::SOLVED
        .iter()
        .filter_map(|&j| Some((j, Subject::Own(j.solver(s)?))))
        .collect();
    egui::ScrollArea::vertical()
        .id_salt("work_precision_table")
        .auto_shrink([false, false])
        .show(ui, |ui| {
            egui::Grid::new("work_precision_rows")
                .striped(true)
                .spacing([10.0, 1.0])
                .show(ui, |ui| {
                    for h in [
                        "method",
                        "setting",
                        "max error",
                        "median error",
                        "µs / iterate",
                        "evals / iterate",
                        "failed",
                        "used by",
                    ] {
                        ui.label(RichText::new(h).small().strong());
                    }
                    ui.end_row();
                    for r in rows {
                        let users: Vec<&str> = used
                            .iter()
                            .filter(|(_, sub)| {
                                let (k, v) = sub.setting();
                                sub.method_name() == r.method
                                    && k == r.kind
                                    && ((v - r.setting) / r.setting).abs() < 1e-9
                            })
                            .map(|(j, _)| j.label())
                            .collect();
                        let cell = |ui: &mut Ui, t: String| {
                            let mut t = RichText::new(t).small().monospace();
                            if !users.is_empty() {
                                t = t.strong();
                            }
                            ui.label(t);
                        };
                        ui.label(
                            RichText::new(r.method)
                                .small()
                                .color(style::method_color(r.method)),
                        );
                        cell(ui, format!("{} {:e}", r.kind, r.setting));
                        for t in row_numbers(r) {
                            cell(ui, t);
                        }
                        let fr =
                            ui.label(RichText::new(failed_text(r)).small().color(style::ERROR));
                        if let Some(f) = &r.failure {
                            fr.on_hover_text(f);
                        }
                        cell(ui, users.join(", "));
                        ui.end_row();
                    }
                });
        });
}

/// The most characters of a failure's reason the table shows (the whole
/// reason is on hover).
const REASON_CHARS: usize = 60;

/// A row's max and median error, µs and evaluations per iterate as the
/// table writes them: a dash where no point succeeded (never "NaN").
pub fn row_numbers(r: &Row) -> [String; 4] {
    let num = |v: f64, f: &dyn Fn(f64) -> String| {
        if v.is_finite() && r.failed < r.points {
            f(v)
        } else {
            "—".to_string()
        }
    };
    [
        num(r.max_error, &|v| format!("{v:.2e}")),
        num(r.median_error, &|v| format!("{v:.2e}")),
        num(r.median_us, &|v| format!("{v:.1}")),
        num(r.evals_per_iterate, &|v| format!("{v:.0}")),
    ]
}

/// How many points of a row failed, and why (the first failure's reason,
/// shortened).
pub fn failed_text(r: &Row) -> String {
    if r.failed == 0 {
        return String::new();
    }
    let count = if r.failed >= r.points {
        format!("all {}", r.points)
    } else {
        format!("{} of {}", r.failed, r.points)
    };
    match &r.failure {
        Some(why) => {
            let mut short: String = why.chars().take(REASON_CHARS).collect();
            if why.chars().count() > REASON_CHARS {
                short.push('…');
            }
            format!("{count}: {short}")
        }
        None => count,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numerics::committed::default_rows;

    #[test]
    fn a_failed_row_says_why_and_shows_no_nan() {
        let mut r = default_rows()[0].clone();
        r.failed = r.points;
        r.failure =
            Some("step 0.9 exceeds the stability limit 1/sqrt(kappa) = 0.23 of this method".into());
        r.max_error = f64::NAN;
        r.median_error = f64::NAN;
        r.median_us = f64::NAN;
        r.evals_per_iterate = -0.0;
        let shown = row_numbers(&r).join(" ");
        assert!(!shown.contains("NaN") && !shown.contains("-0"), "{shown}");
        let why = failed_text(&r);
        assert!(
            why.starts_with(&format!("all {}: step 0.9 exceeds", r.points)),
            "{why}"
        );
        assert!(why.ends_with('…') && why.chars().count() < 80, "{why}");
    }
}
