//! Fine steps of θν: − and + buttons beside a chosen step (0.01 to
//! 0.0001 rad), for a finger on a phone, where the slider moves about
//! 0.01 rad a pixel and a narrow window (the P3 window is 0.01 wide at
//! θν ≈ 1.296) can otherwise be reached only by typing. The step chosen
//! is the window's (not saved with the settings).

use std::f64::consts::{FRAC_PI_2, PI};

use eframe::egui::{self, Ui};

use crate::app::settings::Settings;

/// The steps offered, in radians.
pub const STEPS: [f64; 3] = [1e-2, 1e-3, 1e-4];

/// θν moved by `k` steps of `step` from `theta_nu`, kept in its range
/// (0 … π/2, or −π … π on the full circle) and rounded to the step, so
/// that repeated steps land on round values.
pub fn stepped(theta_nu: f64, step: f64, k: f64, full_circle: bool) -> f64 {
    let (lo, hi) = if full_circle {
        (-PI, PI)
    } else {
        (0.0, FRAC_PI_2)
    };
    let v = ((theta_nu + k * step) / step).round() * step;
    v.clamp(lo, hi)
}

/// The row: "θν − +" and the step's choice, touch-sized buttons.
pub(super) fn fine_step_ui(ui: &mut Ui, s: &mut Settings) {
    let id = egui::Id::unique("theta_nu_fine_step");
    let mut step = ui.data(|d| d.get_temp::<f64>(id)).unwrap_or(STEPS[1]);
    ui.horizontal_wrapped(|ui| {
        let size = egui::vec2(2.2, 1.6) * ui.text_style_height(&egui::TextStyle::Body);
        for (label, k, hover) in [
            ("−", -1.0, "θν down by the step"),
            ("+", 1.0, "θν up by the step"),
        ] {
            let b = egui::Button::new(label).min_size(size);
            if ui.add(b).on_hover_text(hover).clicked() {
                s.params.theta_nu = stepped(s.params.theta_nu, step, k, s.full_circle);
            }
        }
        ui.label("step");
        for st in STEPS {
            let text = format!("{st}");
            if ui.selectable_label(step == st, text).clicked() {
                step = st;
            }
        }
    });
    ui.data_mut(|d| d.insert_temp(id, step));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_land_on_round_values_inside_the_range() {
        // 1.30 to the P3 window's 1.2961 by touch: four steps of 1e-3 down,
        // then one of 1e-4 up.
        let mut v = 1.3;
        for _ in 0..4 {
            v = stepped(v, 1e-3, -1.0, false);
        }
        v = stepped(v, 1e-4, 1.0, false);
        assert!((v - 1.2961).abs() < 1e-12, "{v}");
        assert_eq!(stepped(1.5705, 1e-2, 1.0, false), FRAC_PI_2);
        assert_eq!(stepped(0.004, 1e-2, -1.0, false), 0.0);
        assert!((stepped(-3.0, 1e-2, -1.0, true) + 3.01).abs() < 1e-12);
    }
}
