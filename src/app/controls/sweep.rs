//! The bifurcation diagram's points per column, in the View section.

use eframe::egui;
use egui::Ui;

use crate::app::settings::Settings;
use crate::sim::MapChoice;

/// The choices offered; a saved value outside them is shown as it is.
const CHOICES: [usize; 4] = [128, 512, 2000, 5000];

/// A combo box for `sweep_keep`: the points each θν column keeps.
pub fn points_per_column_ui(ui: &mut Ui, s: &mut Settings) {
    let from = MapChoice::AUTO_COLUMN_KEEP;
    ui.horizontal(|ui| {
        ui.label("points per column");
        egui::ComboBox::from_id_salt("sweep_keep")
            .selected_text(s.sweep_keep.to_string())
            .show_ui(ui, |ui| {
                for n in CHOICES {
                    ui.selectable_value(&mut s.sweep_keep, n, n.to_string());
                }
            })
            .response
            .on_hover_text(format!(
                "Points each θν column of the bifurcation diagram keeps (recomputes \
                 it). From {from} on, a column that has not settled after its \
                 transient takes them from the map's verified interpolant, built \
                 for that column, instead of integrating each; where the \
                 interpolant is refused the column integrates."
            ));
    });
}
