//! The side panel's View section: how the views look (cycles shown,
//! columns, text size and the projector preset, colours, smooth lines,
//! angle units).

use eframe::egui::{self, Slider, Ui};

use super::{PROJECTOR_FONT_SCALE, sweep};
use crate::app::settings::{AngleUnit, Settings};

/// How the views look: cycles shown, columns, text size, colours, lines,
/// angle units.
pub(super) fn view_options_ui(ui: &mut Ui, s: &mut Settings, software_gl: bool) {
    let was = s.projector;
    ui.checkbox(
        &mut s.projector,
        "projector: large text, thick lines, high contrast",
    )
    .on_hover_text("For a lecture hall: text ×1.5, lines twice as thick, black on white.");
    if s.projector != was {
        s.font_scale = if s.projector {
            PROJECTOR_FONT_SCALE
        } else {
            1.0
        };
        if s.projector {
            s.dark = false;
        }
    }
    ui.horizontal_wrapped(|ui| {
        ui.label("angles in");
        for (u, label, hover) in [
            (AngleUnit::Radians, "rad", "θν and θ axes in radians"),
            (AngleUnit::Degrees, "°", "θν and θ axes in degrees"),
            (
                AngleUnit::PiFractions,
                "π",
                "θν and θ axes in fractions of π (π/8, π/4, …)",
            ),
        ] {
            ui.selectable_value(&mut s.angle_unit, u, label)
                .on_hover_text(hover);
        }
    });
    ui.horizontal(|ui| {
        ui.label("cycles shown");
        ui.add(egui::DragValue::new(&mut s.keep_cycles).range(1..=1000))
            .on_hover_text("How many of the latest stick–slip cycles the plane keeps.");
    });
    ui.horizontal(|ui| {
        ui.label("diagram columns");
        ui.add(egui::DragValue::new(&mut s.columns).range(20..=2000))
            .on_hover_text("θν columns of the bifurcation diagram (recomputes it).");
    });
    sweep::points_per_column_ui(ui, s);
    ui.horizontal(|ui| {
        ui.label("text size");
        ui.add(
            Slider::new(&mut s.font_scale, 0.7..=2.5)
                .step_by(0.05)
                .text("×"),
        )
        .on_hover_text("Larger text for projectors (Ctrl + / Ctrl − also work).");
    });
    ui.checkbox(&mut s.dark, "dark background");
    smooth_lines_ui(ui, s, software_gl);
}

/// The anti-aliasing switch: Auto (off under software OpenGL), on, off.
fn smooth_lines_ui(ui: &mut Ui, s: &mut Settings, software_gl: bool) {
    ui.horizontal_wrapped(|ui| {
        ui.label("smooth lines");
        // What Auto would do here, whatever is selected now.
        let auto = if Settings::default().smooth_lines_on(software_gl) {
            "Auto (on)"
        } else {
            "Auto (off: software GL)"
        };
        for (v, label) in [(None, auto), (Some(true), "on"), (Some(false), "off")] {
            ui.selectable_value(&mut s.smooth_lines, v, label)
                .on_hover_text(
                    "Anti-aliased lines and shapes. Without a GPU (Mesa's llvmpipe) they \
                     cost about a third of each frame, so Auto turns them off there; text \
                     stays smooth either way.",
                );
        }
    });
}
