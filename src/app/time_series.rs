//! The time series of the last cycles: x(t), y(t), the slip speed |v_r|(t)
//! and the elastic energy (κx² + y²)/2, one plot each on one time axis,
//! coloured by phase (stick, slip accelerating, slip decelerating).
//! Dragging or scrolling zooms and pans time in all four at once, so that a
//! slip lasting a few time units between stick phases of thousands can be
//! opened up: at the creep presets, where a slip moves the block by 0.004
//! and the plane shows a dot, |v_r| shows each slip as a spike. A double
//! click goes back to the whole of the last cycles.

use eframe::egui;
use egui::Ui;
use egui_plot::{Plot, PlotPoints};

use super::axes::{self, AxisSpec};
use super::jobs::Jobs;
use super::plane::phase_polylines;
use super::settings::{Settings, ViewKind};
use super::style;
use super::view::{Action, View};
use crate::model::Params;
use crate::sim::{Phase, Sample};

/// One quantity plotted against time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    X,
    Y,
    SlipSpeed,
    Energy,
}

impl Quantity {
    pub const ALL: [Quantity; 4] = [
        Quantity::X,
        Quantity::Y,
        Quantity::SlipSpeed,
        Quantity::Energy,
    ];

    /// The axis title, with its symbol.
    pub fn title(self) -> &'static str {
        match self {
            Quantity::X => "x, position",
            Quantity::Y => "y, position",
            Quantity::SlipSpeed => "|v_r|, slip speed",
            Quantity::Energy => "E, elastic energy",
        }
    }

    /// Its value at a sample: |v_r| = |(u, w) − V| with V the surface's
    /// velocity; E = (κx² + y²)/2, the springs' energy.
    pub fn of(self, p: &Params, s: &Sample) -> f64 {
        match self {
            Quantity::X => s.x,
            Quantity::Y => s.y,
            Quantity::SlipSpeed => {
                let (vx, vy) = (p.nu * p.theta_nu.cos(), p.nu * p.theta_nu.sin());
                (s.u - vx).hypot(s.w - vy)
            }
            Quantity::Energy => 0.5 * (p.kappa * s.x * s.x + s.y * s.y),
        }
    }

    fn plot_id(self) -> &'static str {
        match self {
            Quantity::X => "time-series-x",
            Quantity::Y => "time-series-y",
            Quantity::SlipSpeed => "time-series-vr",
            Quantity::Energy => "time-series-energy",
        }
    }
}

/// The quantity's series over `samples` as runs of one phase each
/// (`[stick, accel, decel]`, decimated as the plane's path, phase
/// boundaries kept): points (t, value).
pub fn series(p: &Params, samples: &[Sample], q: Quantity) -> [Vec<Vec<[f64; 2]>>; 3] {
    let as_xy: Vec<Sample> = samples
        .iter()
        .map(|s| Sample {
            x: s.t,
            y: q.of(p, s),
            ..*s
        })
        .collect();
    phase_polylines(&as_xy, 1.0)
}

/// The time-series view (its zoom is egui_plot's, linked across the four).
#[derive(Default)]
pub struct TimeSeriesView;

impl TimeSeriesView {
    /// One quantity's plot, `height` points tall.
    fn plot_ui(ui: &mut Ui, s: &Settings, samples: &[Sample], q: Quantity, height: f32) {
        let [stick, accel, decel] = series(&s.params, samples, q);
        let w = style::width(ui.ctx(), 1.5);
        let last = q == Quantity::Energy;
        let plot = Plot::new(q.plot_id())
            .height(height)
            .link_axis(egui::Id::unique("time-series-time"), [true, false])
            .link_cursor(egui::Id::unique("time-series-time"), [true, false])
            .allow_zoom([true, false])
            .allow_drag([true, false])
            .allow_scroll([true, false])
            .allow_boxed_zoom(false)
            .show_background(false)
            .y_axis_min_width(5.5 * ui.text_style_height(&egui::TextStyle::Body));
        let x_title = if last { "t, time" } else { "" };
        let resp = axes::apply(
            plot,
            &AxisSpec::linear(x_title),
            &AxisSpec::linear(q.title()),
        )
        .show(ui, |p| {
            let runs = [
                (stick, "stick", style::STICK),
                (accel, "slip, accelerating", style::ACCEL),
                (decel, "slip, decelerating", style::DECEL),
            ];
            for (runs, name, color) in runs {
                for run in runs {
                    p.line(
                        style::line(name, PlotPoints::from(run))
                            .color(color)
                            .width(w),
                    );
                }
            }
        });
        axes::remember_frame(ui.ctx(), q.plot_id(), *resp.transform.frame());
    }
}

/// The samples of the last `keep` cycles.
fn recent(jobs: &Jobs, keep: usize) -> &[Sample] {
    let data = &jobs.trajectory.data;
    &data.samples[data.recent_start(keep)..]
}

impl View for TimeSeriesView {
    fn title(&self) -> &'static str {
        ViewKind::TimeSeries.title()
    }

    fn ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, _out: &mut Vec<Action>) {
        let samples = recent(jobs, s.keep_cycles);
        ui.horizontal_wrapped(|ui| {
            style::legend_line(ui, style::STICK, false, "stick");
            style::legend_line(ui, style::ACCEL, false, "slip, accelerating");
            style::legend_line(ui, style::DECEL, false, "slip, decelerating");
            if !style::figure_only(ui.ctx()) {
                ui.label(
                    egui::RichText::new("drag / scroll: pan and zoom time · double click: all")
                        .weak(),
                );
            }
        });
        if samples.iter().all(|x| x.phase == Phase::Stick) && samples.len() < 2 {
            ui.label("No cycles yet.");
        }
        let row = ui.text_style_height(&egui::TextStyle::Body);
        let gaps = 3.0 * ui.spacing().item_spacing.y;
        let each = ((ui.available_height() - gaps) / 4.0).max(4.0 * row);
        for q in Quantity::ALL {
            // The time axis's title and ticks only under the last plot.
            let h = if q == Quantity::Energy {
                each + 1.5 * row
            } else {
                each - 0.5 * row
            };
            Self::plot_ui(ui, s, samples, q, h);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slip_speed_is_zero_in_stick_and_energy_is_the_springs() {
        let p = Params {
            kappa: 4.0,
            gamma: 6.5,
            nu: 1e-3,
            theta_nu: 0.6,
            omega: 50.0,
        };
        let stick = Sample {
            t: 1.0,
            x: 0.1,
            y: 0.2,
            u: p.nu * 0.6f64.cos(),
            w: p.nu * 0.6f64.sin(),
            phase: Phase::Stick,
        };
        assert!(Quantity::SlipSpeed.of(&p, &stick) < 1e-18);
        assert!((Quantity::Energy.of(&p, &stick) - 0.5 * (4.0 * 0.01 + 0.04)).abs() < 1e-15);
        let slip = Sample {
            t: 2.0,
            x: 0.15,
            u: stick.u + 0.3,
            w: stick.w - 0.4,
            phase: Phase::Accel,
            ..stick
        };
        assert!((Quantity::SlipSpeed.of(&p, &slip) - 0.5).abs() < 1e-12);
        // Runs by phase on the time axis, the stick run closed at the slip.
        let [st, ac, de] = series(&p, &[stick, slip], Quantity::X);
        let run = vec![vec![[1.0, 0.1], [2.0, 0.15]]];
        assert_eq!((st, ac, de.len()), (run.clone(), run, 0));
    }
}
