//! Colours chosen to read on a projector and to stay apart for the common
//! colour-vision deficiencies (blue / vermilion / orange, after Okabe–Ito).

use eframe::egui;
use egui::{Color32, Ui};

pub const STICK: Color32 = Color32::from_rgb(0, 114, 178);
pub const ACCEL: Color32 = Color32::from_rgb(213, 94, 0);
pub const DECEL: Color32 = Color32::from_rgb(230, 159, 0);
pub const ONSET: Color32 = Color32::from_rgb(204, 0, 102);
pub const BLOCK: Color32 = Color32::from_rgb(40, 40, 40);
pub const PULL: Color32 = Color32::from_rgb(0, 158, 115);
pub const CRITICAL: Color32 = Color32::from_rgb(120, 120, 120);
pub const CURRENT: Color32 = Color32::from_rgb(0, 158, 115);
pub const ERROR: Color32 = Color32::from_rgb(220, 30, 30);

/// The colour of the main curves: dark on light, light on dark.
pub fn ink(dark: bool) -> Color32 {
    if dark {
        Color32::from_gray(230)
    } else {
        Color32::from_gray(20)
    }
}

/// A small coloured square and its label.
pub fn legend_swatch(ui: &mut Ui, color: Color32, label: &str) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(14.0, 14.0), egui::Sense::hover());
    ui.painter().rect_filled(rect, 2.0, color);
    ui.label(label);
}
