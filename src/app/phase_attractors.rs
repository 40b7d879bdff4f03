//! The phase view's coexisting attractors (docs/attractors.md): the seeds
//! control (each cell's attractors counted from θ₀ spread over its exit
//! arc, `oneblock phase --seeds`), the mark of a multistable cell (a white
//! square a third of the cell, as `oneblock phase --png` draws it) with its
//! legend entry, and the list of a clicked multistable cell's attractors
//! (period or chaotic, multiplier or λ, basin fraction), as
//! `oneblock attractors` finds them.

use eframe::egui;
use egui::{Color32, RichText, Ui};
use egui_plot::{MarkerShape, PlotPoints, PlotUi, Points};

use super::phase_data::PhaseData;
use super::settings::Settings;
use crate::worker::ListedAttractor;

/// The legend's name for a cell with more than one attractor.
pub const MULTISTABLE: &str = "multistable";
/// The plot item's name of the marks (its hover is the cell's own text).
pub const MARKS: &str = "multistable cells";

/// The seeds control: every cell's attractors from the exit arc's cell
/// graph, or not (`--seeds`, any N > 0).
pub fn seeds_ui(ui: &mut Ui, s: &mut Settings) {
    let mut on = s.phase.seeds > 0;
    let r = ui.checkbox(&mut on, "every attractor").on_hover_text(
        "Count each cell's attractors from the exit arc's cell graph, with no orbit budget \
         (oneblock phase --seeds 1; recomputes the grid). Cells with more than one are \
         marked; a click on one lists them.",
    );
    if r.changed() {
        s.phase.seeds = usize::from(on);
    }
}

/// The mark's swatch: a white square on a grey cell, outlined.
pub fn multistable_legend_ui(ui: &mut Ui) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(14.0, 14.0), egui::Sense::hover());
    let p = ui.painter();
    p.rect_filled(rect, 0.0, Color32::from_gray(175));
    p.rect_filled(
        egui::Rect::from_center_size(rect.center(), egui::vec2(6.0, 6.0)),
        0.0,
        Color32::WHITE,
    );
    p.rect_stroke(
        rect,
        0.0,
        egui::Stroke::new(1.0, Color32::BLACK),
        egui::StrokeKind::Inside,
    );
    ui.label(MULTISTABLE);
}

/// The centres of the cells counted with more than one attractor.
pub fn multistable_centres(data: &PhaseData) -> Vec<[f64; 2]> {
    let (tns, ks) = (data.theta_nus(), data.kappas());
    data.cells
        .iter()
        .enumerate()
        .filter_map(|(i, c)| {
            let c = c.as_ref()?;
            (c.attractors > Some(1)).then(|| [tns[i % data.columns], ks[i / data.columns]])
        })
        .collect()
}

/// The marks over the grid: a white square, a third of a cell of
/// `cell_px` screen pixels, on a black one a pixel larger (visible over
/// the pale classes too).
pub fn marks(p: &mut PlotUi<'_>, data: &PhaseData, cell_px: f32) {
    let centres = multistable_centres(data);
    if centres.is_empty() {
        return;
    }
    let r = (cell_px / 6.0).max(2.0);
    for (colour, radius) in [(Color32::BLACK, r + 1.0), (Color32::WHITE, r)] {
        p.points(
            Points::new(MARKS, PlotPoints::from(centres.clone()))
                .shape(MarkerShape::Square)
                .filled(true)
                .color(colour)
                .radius(radius)
                .allow_hover(false),
        );
    }
}

/// The hover text's line on a counted cell's attractors, or on why they
/// were not counted ("" when not asked for).
pub fn count_line(count: Option<usize>, uncounted: Option<&str>) -> String {
    match (count, uncounted) {
        (Some(n), _) if n > 1 => format!("\n{n} attractors (multistable): a click lists them"),
        (Some(1), _) => "\none attractor from every seed".into(),
        (Some(_), _) => "\nno attractor reached".into(),
        (None, Some(why)) => format!("\nattractors not counted: {why}"),
        (None, None) => String::new(),
    }
}

/// One listed attractor as a row: kind, multiplier or λ, basin fraction.
pub fn row(a: &ListedAttractor) -> [String; 3] {
    let kind = match a.period {
        Some(1) => "FP".to_string(),
        Some(p) => format!("P{p}"),
        None => "chaotic".into(),
    };
    let stability = match (a.multiplier, a.lyapunov) {
        (Some(m), _) => format!("multiplier {m:.4}"),
        (None, Some((l, se))) => crate::text::lyapunov(l, se, false),
        (None, None) => "λ not computed".into(),
    };
    [
        kind,
        stability,
        format!("basin {:.0} %", 100.0 * a.basin_fraction),
    ]
}

/// The clicked cell's attractors, under the controls: nothing unless the
/// cell at `selected` (θν, κ) is multistable. Returns whether the list
/// was closed.
pub fn list_ui(ui: &mut Ui, data: &PhaseData, selected: (f64, f64)) -> bool {
    let point = egui_plot::PlotPoint::new(selected.0, selected.1);
    let Some((row_i, col)) = super::phase_raster::cell_at(data, point) else {
        return false;
    };
    let Some(cell) = data.cell(row_i, col) else {
        return false;
    };
    let Some(n) = cell.attractors.filter(|&n| n > 1) else {
        return false;
    };
    let mut closed = false;
    egui::Frame::group(ui.style()).show(ui, |ui| {
        ui.horizontal_wrapped(|ui| {
            ui.label(
                RichText::new(format!(
                    "Attractors at θν = {:.4}, κ = {:.4}: {n} counted",
                    cell.theta_nu, cell.kappa
                ))
                .strong(),
            );
            closed = ui.small_button("Close").clicked();
        });
        match data.listed(row_i, col) {
            Some(list) => {
                egui::Grid::new("cell attractors")
                    .striped(true)
                    .show(ui, |ui| {
                        for a in list {
                            for text in row(a) {
                                ui.label(text);
                            }
                            ui.end_row();
                        }
                    });
                ui.label(
                    RichText::new(
                        "as oneblock attractors finds them, from the exit arc's cell graph \
                         (cycles by Newton; basin: share of the arc)",
                    )
                    .weak(),
                );
            }
            None => {
                ui.label(RichText::new("not listed (the search failed or was stopped)").weak());
            }
        }
    });
    closed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_name_the_period_or_chaos_and_the_basin() {
        let fp = ListedAttractor {
            period: Some(1),
            multiplier: Some(-0.5),
            lyapunov: None,
            basin_fraction: 0.25,
        };
        assert_eq!(row(&fp), ["FP", "multiplier -0.5000", "basin 25 %"]);
        let chaos = ListedAttractor {
            period: None,
            multiplier: None,
            lyapunov: Some((0.12, Some(0.01))),
            basin_fraction: 0.75,
        };
        assert_eq!(row(&chaos), ["chaotic", "λ = 0.120 ± 0.010", "basin 75 %"]);
        assert!(count_line(Some(3), None).contains("3 attractors (multistable)"));
        assert_eq!(count_line(None, None), "");
        assert!(count_line(None, Some("the interpolant failed")).contains("not counted"));
    }
}
