//! The special points "Find bifurcations" located, as a table under the
//! bifurcation view's toolbar: kind, period, parameter value, θ and
//! multiplier to 9 significant digits, each row with a "Copy" button that
//! puts the row's `oneblock continue --points` line on the clipboard, and
//! "Copy all" for the header and every row; the cascade's doublings with
//! the ratios δₙ of their gaps (Feigenbaum's δ to compare, as `oneblock
//! continue --cascade` prints them); and the generalised flips of the
//! phase view's doubling curves.

use eframe::egui;
use egui::{RichText, Ui};

use super::branches::{BranchData, CSV_HEADER, CurveData, csv_line, sig9, special_rows};
use crate::sim::continuation::{ContParam, Curve, GeneralisedFlip, feigenbaum_ratios};

/// Feigenbaum's δ, the limit of the ratios of a cascade's gaps.
pub const FEIGENBAUM_DELTA: f64 = 4.669_201_609_102_99;

/// The cascade's table rows: n, period, bₙ, the gap bₙ − bₙ₋₁ and
/// δₙ₋₁ = (bₙ₋₁ − bₙ₋₂)/(bₙ − bₙ₋₁) (empty where there is none yet),
/// 9 significant digits (the CLI's [`feigenbaum_ratios`]).
pub fn cascade_rows(data: &BranchData) -> Vec<[String; 5]> {
    let b: Vec<f64> = data.doublings.iter().map(|d| d.lambda).collect();
    let ratios = feigenbaum_ratios(&b);
    data.doublings
        .iter()
        .enumerate()
        .map(|(i, d)| {
            let gap = if i > 0 {
                sig9(b[i] - b[i - 1])
            } else {
                String::new()
            };
            let ratio = if i >= 2 {
                format!("{:.4}", ratios[i - 2])
            } else {
                String::new()
            };
            [
                format!("{}", i + 1),
                format!("P{}", d.period),
                sig9(b[i]),
                gap,
                ratio,
            ]
        })
        .collect()
}

/// The collapsing "Cascade" section: the doublings of the cascade Find
/// bifurcations followed and the ratios of their gaps, against
/// Feigenbaum's δ (nothing before three doublings: no ratio yet).
pub fn cascade_ui(ui: &mut Ui, data: &BranchData) {
    let rows = cascade_rows(data);
    if rows.len() < 3 {
        return;
    }
    let param = data.param.unwrap_or(ContParam::ThetaNu);
    egui::CollapsingHeader::new(format!("Cascade δ ({} doublings)", rows.len()))
        .id_salt("cascade ratios")
        .show(ui, |ui| {
            egui::Grid::new("cascade grid")
                .striped(true)
                .num_columns(5)
                .show(ui, |ui| {
                    for h in ["n", "period", param.column(), "gap", "δ_n"] {
                        ui.label(RichText::new(h).strong());
                    }
                    ui.end_row();
                    for r in &rows {
                        for cell in r {
                            ui.label(cell);
                        }
                        ui.end_row();
                    }
                });
            let b: Vec<f64> = data.doublings.iter().map(|d| d.lambda).collect();
            if let Some(last) = feigenbaum_ratios(&b).last() {
                ui.label(
                    RichText::new(format!(
                        "Feigenbaum's δ is 4.6692…; the last ratio here is {last:.4} ({:+.1} %)",
                        100.0 * (last / FEIGENBAUM_DELTA - 1.0)
                    ))
                    .weak(),
                );
            }
        });
}

/// The table's most height, as a share of the view's.
const HEIGHT_SHARE: f32 = 0.35;

/// The lines "Copy all" puts on the clipboard: the header, then a row per
/// special point.
pub fn all_lines(data: &BranchData) -> String {
    let param = data.param.unwrap_or(ContParam::ThetaNu);
    let mut s = String::from(CSV_HEADER);
    for p in special_rows(data) {
        s.push('\n');
        s.push_str(&csv_line(param, p));
    }
    s.push('\n');
    s
}

/// The collapsing "Special points" section (nothing before any branch).
pub fn points_ui(ui: &mut Ui, data: &BranchData) {
    let rows = special_rows(data);
    if data.branches.is_empty() {
        return;
    }
    let param = data.param.unwrap_or(ContParam::ThetaNu);
    let max_height = ui.available_height() * HEIGHT_SHARE;
    egui::CollapsingHeader::new(format!("Special points ({})", rows.len()))
        .id_salt("special points")
        .show(ui, |ui| {
            if rows.is_empty() {
                ui.label(RichText::new("no doubling, fold or border on these branches").weak());
                return;
            }
            if ui
                .small_button("Copy all")
                .on_hover_text("Every row as CSV, with its header (oneblock continue --points)")
                .clicked()
            {
                ui.ctx().copy_text(all_lines(data));
            }
            egui::ScrollArea::vertical()
                .max_height(max_height)
                .show(ui, |ui| {
                    egui::Grid::new("special points grid")
                        .striped(true)
                        .num_columns(7)
                        .show(ui, |ui| {
                            for h in ["kind", "period", param.column(), "θ", "multiplier", "criticality", ""] {
                                ui.label(RichText::new(h).strong());
                            }
                            ui.end_row();
                            for p in &rows {
                                ui.label(p.kind.name());
                                ui.label(format!("{}", p.period));
                                ui.label(sig9(p.lambda));
                                ui.label(sig9(p.theta));
                                ui.label(sig9(p.multiplier));
                                ui.label(p.criticality_name());
                                if ui
                                    .small_button("Copy")
                                    .on_hover_text("This row as a CSV line: kind,period,parameter,value,theta,multiplier,criticality")
                                    .clicked()
                                {
                                    ui.ctx().copy_text(csv_line(param, p));
                                }
                                ui.end_row();
                            }
                        });
                });
        });
}

/// The generalised flips of the "Boundaries" curves, as a table under the
/// phase view's controls: the curve, (θν, κ) where the flip's coefficient
/// c crosses 0, and c at the decided points either side (nothing before
/// any curve has one).
pub fn generalised_flips_ui(ui: &mut Ui, data: &CurveData) {
    let rows: Vec<(&Curve, &GeneralisedFlip)> = data
        .curves
        .iter()
        .flat_map(|c| c.generalised_flips.iter().map(move |g| (c, g)))
        .collect();
    if rows.is_empty() {
        return;
    }
    egui::CollapsingHeader::new(format!("Generalised flips ({})", rows.len()))
        .id_salt("generalised flips")
        .show(ui, |ui| {
            egui::Grid::new("generalised flips grid")
                .striped(true)
                .num_columns(5)
                .show(ui, |ui| {
                    for h in ["curve", "theta_nu", "kappa", "c before", "c after"] {
                        ui.label(RichText::new(h).strong());
                    }
                    ui.end_row();
                    for (c, g) in rows {
                        ui.label(format!("P{} to P{}", c.period, 2 * c.period));
                        ui.label(sig9(g.lambda[0]));
                        ui.label(sig9(g.lambda[1]));
                        ui.label(sig9(g.coefficients[0]));
                        ui.label(sig9(g.coefficients[1]));
                        ui.end_row();
                    }
                });
            ui.label(
                RichText::new(
                    "where the doubling turns from supercritical (c > 0) to subcritical \
                     (c < 0) or back, c interpolated to 0 between decided points",
                )
                .weak(),
            );
        });
}
