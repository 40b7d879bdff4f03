//! What is drawn over the bifurcation diagram besides its points and the
//! branches: the level or diagonal θ = θν, ±θc where they do not move
//! along the axis, the line at the current value of the varied parameter,
//! and their legend.

use eframe::egui;
use egui::Ui;
use egui_plot::{HLine, LineStyle, PlotPoints, VLine};

use super::clip::clip_polyline;
use super::diagram_axis::XAxis;
use super::settings::Settings;
use super::style;
use crate::model::Regime;
use crate::sim::continuation::ContParam;

/// The name of the line at the current value of the varied parameter.
pub fn current_name(p: ContParam) -> &'static str {
    match p {
        ContParam::ThetaNu => "current θν",
        ContParam::Kappa => "current κ",
        ContParam::Gamma => "current γ",
        ContParam::Nu => "current ν",
        ContParam::Omega => "current Ω",
    }
}

/// ±θc when the regime is mixed over the whole diagram: θc depends on κ
/// and γ, so a diagram in either has none drawn.
pub fn theta_c(s: &Settings, param: ContParam) -> Option<f64> {
    match (param, Regime::of(s.params.kappa, s.params.gamma)) {
        (ContParam::Kappa | ContParam::Gamma, _) => None,
        (_, Regime::Mixed { theta_c }) => Some(theta_c),
        _ => None,
    }
}

/// The lines drawn over the diagram: θ = θν (the diagonal of a diagram in
/// θν, a level line in the others), ±θc and the current value.
pub struct Lines {
    pub axis: XAxis,
    /// θν, where it is held fixed.
    pub theta_nu: f64,
    /// The plot's bounds (x from, to, θ lo, hi): the diagonal is cut to them.
    pub bounds: (f64, f64, f64, f64),
    /// The current value's coordinate, where it is drawn
    /// ([`style::draws_current`]).
    pub current: Option<f64>,
    pub theta_c: Option<f64>,
    pub width: f32,
}

impl Lines {
    pub fn draw(&self, p: &mut egui_plot::PlotUi<'_>) {
        // Dotted along its length on screen: cut to the frame first
        // (super::clip), or a thin θ zoom makes millions of dots.
        let (x0, x1, y0, y1) = self.bounds;
        let line = match self.axis.param {
            ContParam::ThetaNu => [[x0, x0], [x1, x1]],
            _ => [[x0, self.theta_nu], [x1, self.theta_nu]],
        };
        for part in clip_polyline(&line, [x0, y0], [x1, y1]) {
            p.line(
                style::line("θ = θν", PlotPoints::from(part))
                    .color(style::CRITICAL.gamma_multiply(0.6))
                    .style(LineStyle::Dotted { spacing: 6.0 }),
            );
        }
        if let Some(tc) = self.theta_c {
            for y in [tc, -tc] {
                p.add(
                    HLine::new("θc", y)
                        .color(style::ACCEL)
                        .style(LineStyle::Dashed { length: 10.0 })
                        .width(1.5),
                );
            }
        }
        if let Some(x) = self.current {
            p.add(
                VLine::new(current_name(self.axis.param), x)
                    .color(style::CURRENT)
                    .width(2.0),
            );
        }
    }
}

/// The legend of the lines drawn over the diagram: θ = θν, the critical
/// angles ±θc (where drawn) and the current value.
pub fn lines_legend_ui(ui: &mut Ui, s: &Settings) {
    ui.horizontal_wrapped(|ui| {
        style::legend_line(ui, style::CRITICAL, true, "θ = θν");
        if theta_c(s, s.diagram.param).is_some() {
            style::legend_line(ui, style::ACCEL, true, "±θc");
        }
        if style::draws_current(ui.ctx()) {
            style::legend_line(ui, style::CURRENT, false, current_name(s.diagram.param));
        }
    });
}
