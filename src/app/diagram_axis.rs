//! The bifurcation diagram's x axis in the parameter it varies, and the
//! selector that picks it. θν is an angle axis, γ a linear one; κ, ν and
//! Ω span decades and are drawn on a log axis (the plot's coordinate is
//! log10 of the value), as their sliders move on a log scale. The sweep
//! job spaces its columns evenly in that coordinate
//! ([`crate::sim::param_grid`]), so each texel column of the diagram is
//! one column of the job.

use eframe::egui;
use egui::Ui;

use super::axes::AxisSpec;
use super::settings::{AngleUnit, DiagramAxis, Settings};
use crate::sim::continuation::ContParam;

/// The diagram's x axis: values of `param` to plot coordinates and back.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct XAxis {
    pub param: ContParam,
}

impl XAxis {
    /// The axis of a diagram over `param`.
    pub fn of(param: ContParam) -> XAxis {
        XAxis { param }
    }

    /// Whether the plot's coordinate is log10 of the value.
    pub fn is_log(self) -> bool {
        self.param.spans_decades()
    }

    /// The plot coordinate of the value `v`.
    pub fn x(self, v: f64) -> f64 {
        if self.is_log() { v.log10() } else { v }
    }

    /// The value at the plot coordinate `x`.
    pub fn value(self, x: f64) -> f64 {
        if self.is_log() { 10f64.powf(x) } else { x }
    }

    /// The axis' title and scale.
    pub fn spec(self, unit: AngleUnit) -> AxisSpec {
        match self.param {
            ContParam::ThetaNu => AxisSpec::angle("θν, pull direction", unit),
            ContParam::Gamma => AxisSpec::linear(title(self.param)),
            p => AxisSpec::log10(format!("{} (log scale)", title(p))),
        }
    }
}

/// The parameter's symbol and what it is, as the selector and the axis
/// name it.
pub fn title(p: ContParam) -> &'static str {
    match p {
        ContParam::ThetaNu => "θν, pull direction",
        ContParam::Kappa => "κ, spring anisotropy",
        ContParam::Gamma => "γ, friction weakening",
        ContParam::Nu => "ν, pulling speed",
        ContParam::Omega => "Ω, friction memory",
    }
}

/// The selector's accessible name.
pub const SELECTOR: &str = "Diagram in";

/// The parameter the diagram varies (a change recomputes it, and clears
/// the branches of another parameter) and, for one other than θν, its
/// range: two fields, each taking a value only where the model has one
/// and the range stays increasing.
pub fn selector_ui(ui: &mut Ui, s: &mut Settings) {
    let before = s.diagram.param;
    // The label is the combo box's own: its accessible name.
    egui::ComboBox::new("diagram-param", SELECTOR)
        .selected_text(before.symbol())
        .show_ui(ui, |ui| {
            for p in ContParam::ALL {
                ui.selectable_value(&mut s.diagram.param, p, title(p));
            }
        })
        .response
        .on_hover_text(
            "The parameter the diagram varies, the others held at the sliders' values \
             (oneblock bifurcation --param). κ, ν and Ω are drawn on a log axis. \
             Find bifurcations follows the cycle in it.",
        );
    let param = s.diagram.param;
    let Some((mut lo, mut hi)) = s.diagram.range(param) else {
        return;
    };
    let log = param.spans_decades();
    let field = |v: &mut f64, name: &str, ui: &mut Ui| {
        let speed = if log { *v * 0.01 } else { 0.01 };
        ui.add(
            egui::DragValue::new(v)
                .speed(speed)
                .custom_formatter(|x, _| crate::text::short(x)),
        )
        .on_hover_text(format!("The diagram's {name} {}", param.symbol()))
    };
    let changed = field(&mut lo, "first", ui).changed() | field(&mut hi, "last", ui).changed();
    if changed && DiagramAxis::is_valid_range(param, (lo, hi)) {
        s.diagram.set_range(param, (lo, hi));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_axes_map_decades_to_unit_steps_and_back() {
        let k = XAxis::of(ContParam::Kappa);
        assert!(k.is_log());
        assert_eq!(k.x(100.0), 2.0);
        assert!((k.value(k.x(18.95)) - 18.95).abs() < 1e-12);
        let g = XAxis::of(ContParam::Gamma);
        assert!(!g.is_log());
        assert_eq!((g.x(6.5), g.value(6.5)), (6.5, 6.5));
        assert_eq!(
            XAxis::of(ContParam::Nu).spec(AngleUnit::Radians).title,
            "ν, pulling speed (log scale)"
        );
    }
}
