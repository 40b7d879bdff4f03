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

/// The colour of the line θ = θν, dotted.
fn diagonal_colour() -> egui::Color32 {
    style::CRITICAL.gamma_multiply(0.6)
}

impl Lines {
    /// The lines of a diagram in `param` over `bounds` (x from, to, θ lo,
    /// hi), as `ctx` draws them.
    pub fn of(
        ctx: &egui::Context,
        s: &Settings,
        bounds: (f64, f64, f64, f64),
        param: ContParam,
    ) -> Lines {
        let axis = XAxis::of(param);
        Lines {
            axis,
            theta_nu: s.params.theta_nu,
            bounds,
            current: style::draws_current(ctx).then_some(axis.x(axis.param.get(&s.params))),
            theta_c: theta_c(s, axis.param),
            width: style::width(ctx, 1.5),
        }
    }

    /// The pieces of θ = θν within the plot: the diagonal of a diagram in
    /// θν, the level line θ = θν in the others (none where θν is off the
    /// θ range).
    fn diagonal(&self) -> Vec<Vec<[f64; 2]>> {
        let (x0, x1, y0, y1) = self.bounds;
        let line = match self.axis.param {
            ContParam::ThetaNu => [[x0, x0], [x1, x1]],
            _ => [[x0, self.theta_nu], [x1, self.theta_nu]],
        };
        clip_polyline(&line, [x0, y0], [x1, y1])
    }

    /// ±θc where they lie within the plot's θ range.
    fn theta_c_levels(&self) -> Vec<f64> {
        let (_, _, y0, y1) = self.bounds;
        self.theta_c
            .map(|tc| [tc, -tc])
            .into_iter()
            .flatten()
            .filter(|y| (y0..=y1).contains(y))
            .collect()
    }

    pub fn draw(&self, p: &mut egui_plot::PlotUi<'_>) {
        // Dotted along its length on screen: cut to the frame first
        // (super::clip), or a thin θ zoom makes millions of dots.
        for part in self.diagonal() {
            p.line(
                style::line("θ = θν", PlotPoints::from(part))
                    .color(diagonal_colour())
                    .style(LineStyle::Dotted { spacing: 6.0 }),
            );
        }
        for y in self.theta_c_levels() {
            p.add(
                HLine::new("θc", y)
                    .color(style::ACCEL)
                    .style(LineStyle::Dashed { length: 10.0 })
                    .width(1.5),
            );
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

/// The legend of the lines drawn over the diagram, each only where it
/// crosses the plot, its key as it is drawn: θ = θν (dotted), the
/// critical angles ±θc and the current value.
pub fn lines_legend_ui(ui: &mut Ui, lines: &Lines) {
    let diagonal = !lines.diagonal().is_empty();
    let theta_c = !lines.theta_c_levels().is_empty();
    let current = lines
        .current
        .filter(|x| (lines.bounds.0..=lines.bounds.1).contains(x));
    if !(diagonal || theta_c || current.is_some()) {
        return;
    }
    style::legend_row(ui, |ui| {
        if diagonal {
            style::legend_dotted(ui, diagonal_colour(), "θ = θν");
        }
        if theta_c {
            style::legend_line(ui, style::ACCEL, true, "±θc");
        }
        if current.is_some() {
            style::legend_line(ui, style::CURRENT, false, current_name(lines.axis.param));
        }
    });
}
