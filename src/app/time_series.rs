//! The time series of the last cycles: x(t), y(t), the slip speed |v_r|(t)
//! and the elastic energy (κx² + y²)/2, one plot each on one time axis,
//! coloured by phase (stick, slip accelerating, slip decelerating), over
//! bands shading the stick and the slip phases.
//! Dragging or scrolling zooms and pans time in all four at once, so that a
//! slip lasting a few time units between stick phases of thousands can be
//! opened up: at the creep presets, where a slip moves the block by 0.004
//! and the plane shows a dot, |v_r| shows each slip as a spike. A double
//! click goes back to the whole of the last cycles.

use eframe::egui;
use egui::Ui;
use egui_plot::{Plot, PlotPoints, Span};

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
            Quantity::X => "x, position (F₀/k_y)",
            Quantity::Y => "y, position (F₀/k_y)",
            Quantity::SlipSpeed => "|v_r|, slip speed (F₀/√(m k_y))",
            Quantity::Energy => "E, elastic energy (F₀²/k_y)",
        }
    }

    /// The axis title short: its symbol and unit ("x (F₀/k_y)").
    pub fn short_title(self) -> &'static str {
        match self {
            Quantity::X => "x (F₀/k_y)",
            Quantity::Y => "y (F₀/k_y)",
            Quantity::SlipSpeed => "|v_r| (F₀/√(m k_y))",
            Quantity::Energy => "E (F₀²/k_y)",
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
    let point = |s: &Sample| Sample {
        x: s.t,
        y: q.of(p, s),
        ..*s
    };
    let mut as_xy: Vec<Sample> = Vec::with_capacity(samples.len());
    for (i, s) in samples.iter().enumerate() {
        as_xy.push(point(s));
        // In stick the block moves with the surface, (x, y) linear in t,
        // so the energy is a parabola in t, not the chord between the
        // stick's two samples (up to 0.011 too high): points along it.
        if q == Quantity::Energy
            && s.phase == Phase::Stick
            && let Some(next) = samples.get(i + 1)
        {
            // Segments enough for a chord error E''h²/8n² under 1e-5
            // (E'' = κV_x² + V_y²), at most STICK_POINTS.
            let (vx, vy) = (p.nu * p.theta_nu.cos(), p.nu * p.theta_nu.sin());
            let curvature = p.kappa * vx * vx + vy * vy;
            let h = next.t - s.t;
            let n = ((h * (curvature / 8e-5).sqrt()).ceil() as usize).clamp(1, STICK_POINTS);
            for k in 1..n {
                let f = k as f64 / n as f64;
                let at = Sample {
                    t: s.t + f * (next.t - s.t),
                    x: s.x + f * (next.x - s.x),
                    y: s.y + f * (next.y - s.y),
                    ..*s
                };
                as_xy.push(point(&at));
            }
        }
    }
    phase_polylines(&as_xy, 1.0)
}

/// Segments of the energy's parabola over one stick step (its chord
/// error falls as their number squared: 3e-6 of 0.011).
const STICK_POINTS: usize = 64;

/// The stick and slip phases over `samples` as time intervals
/// `(t0, t1, slip)`, in order. The step from one sample to the next
/// belongs to a slip unless it starts in stick (as the block view reads
/// it: a slip's first sample is its onset), and steps of one kind join.
pub fn phase_spans(samples: &[Sample]) -> Vec<(f64, f64, bool)> {
    let mut out: Vec<(f64, f64, bool)> = Vec::new();
    for w in samples.windows(2) {
        let slip = w[0].phase != Phase::Stick;
        match out.last_mut() {
            Some(last) if last.2 == slip => last.1 = w[1].t,
            _ => out.push((w[0].t, w[1].t, slip)),
        }
    }
    out
}

/// A band's fill: the phase's colour, faint.
fn shade(slip: bool) -> egui::Color32 {
    let c = if slip { style::DECEL } else { style::STICK };
    egui::Color32::from_rgba_unmultiplied(c.r(), c.g(), c.b(), if slip { 56 } else { 26 })
}

/// The time-series view (its zoom is egui_plot's, linked across the four).
#[derive(Default)]
pub struct TimeSeriesView;

impl TimeSeriesView {
    /// One quantity's plot, `height` points tall.
    fn plot_ui(ui: &mut Ui, s: &Settings, samples: &[Sample], q: Quantity, height: f32) {
        let [stick, accel, decel] = series(&s.params, samples, q);
        let spans = phase_spans(samples);
        let w = style::width(ui.ctx(), 1.5);
        let last = q == Quantity::Energy;
        let row = ui.text_style_height(&egui::TextStyle::Body);
        // The time axis's labels and title only under the last plot: the
        // others' frames are their whole height.
        let frame = if last { height - 3.0 * row } else { height };
        let plot = Plot::new(q.plot_id())
            .height(height)
            .show_axes([last, true])
            .link_axis(egui::Id::unique("time-series-time"), [true, false])
            .link_cursor(egui::Id::unique("time-series-time"), [true, false])
            .allow_zoom([true, false])
            .allow_drag([true, false])
            .allow_scroll([true, false])
            .allow_boxed_zoom(false)
            .show_background(false)
            .y_axis_min_width(5.5 * ui.text_style_height(&egui::TextStyle::Body));
        // Time in √(m/k_y), the model's unit (docs/model.md).
        let x_title = if last {
            axes::fitting_width(
                ui,
                "t, time (√(m/k_y))",
                "t (√(m/k_y))",
                ui.available_width(),
            )
        } else {
            ""
        };
        let resp = axes::apply(
            ui.ctx(),
            plot,
            &AxisSpec::linear(x_title),
            &AxisSpec::linear(fitting(ui, q, frame)),
        )
        .show(ui, |p| {
            // A slip lasts a few time units between stick phases of
            // thousands: its band is widened to two points so that it
            // shows at any zoom.
            let least = 2.0 * p.transform().dvalue_dpos()[0].abs();
            for &(t0, t1, slip) in &spans {
                let pad = ((least - (t1 - t0)) / 2.0).max(0.0);
                p.span(Span::new("", (t0 - pad)..=(t1 + pad)).fill(shade(slip)));
            }
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
        axes::remember_shown(ui, q.plot_id(), *resp.transform.frame());
    }
}

/// `q`'s title if it fits turned on its side along a frame `height`
/// points tall, else its symbol and unit ("x (F₀/k_y)"), else its symbol
/// alone, so that it never runs past its plot into the one above or below
/// (projector text, a column's figure).
fn fitting(ui: &Ui, q: Quantity, height: f32) -> &'static str {
    let font = egui::TextStyle::Body.resolve(ui.style());
    let fits = |t: &str| {
        let width = ui.fonts_mut(|f| {
            f.layout_no_wrap(t.to_owned(), font.clone(), egui::Color32::WHITE)
                .size()
                .x
        });
        width <= height - 4.0
    };
    if fits(q.title()) {
        q.title()
    } else if fits(q.short_title()) {
        q.short_title()
    } else {
        axes::short_name(q.title())
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
        style::legend_row(ui, |ui| {
            style::legend_line(ui, style::STICK, false, "stick");
            style::legend_line(ui, style::ACCEL, false, "slip, accelerating");
            style::legend_line(ui, style::DECEL, false, "slip, decelerating");
            style::legend_swatch(ui, shade(false), "stick phase");
            style::legend_swatch(ui, shade(true), "slip phase");
            if style::controls_shown(ui.ctx()) {
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
        // Room for the top tick label, centred on the first frame's top edge.
        ui.add_space(0.5 * row);
        // Between two frames, room for the tick labels at a frame's top
        // and bottom edges, which stand out by about 0.4 of a row each.
        let gap = (0.8 * row - ui.spacing().item_spacing.y).max(0.0);
        let gaps = 3.0 * (gap + ui.spacing().item_spacing.y);
        // Four frames of one height, and the time axis's labels and title
        // (3 rows) under the last; in the window, frames too short for
        // legible ticks (under seven rows) keep seven and scroll instead;
        // a figure and the tour's tiles (controls folded) show all four
        // whole whatever their height, as a step speaks of any of them.
        let fit = ((ui.available_height() - gaps - 3.0 * row) / 4.0).max(row);
        let least = 7.0 * row;
        if fit >= least || !style::controls_shown(ui.ctx()) {
            Self::plots_ui(ui, s, samples, fit, gap);
        } else {
            egui::ScrollArea::vertical()
                .id_salt("time-series-plots")
                .show(ui, |ui| Self::plots_ui(ui, s, samples, least, gap));
        }
    }
}

impl TimeSeriesView {
    /// The four plots, each frame `each` points tall, `gap` apart.
    fn plots_ui(ui: &mut Ui, s: &Settings, samples: &[Sample], each: f32, gap: f32) {
        let row = ui.text_style_height(&egui::TextStyle::Body);
        for q in Quantity::ALL {
            let h = if q == Quantity::Energy {
                each + 3.0 * row
            } else {
                each
            };
            if q != Quantity::X {
                ui.add_space(gap);
            }
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

    #[test]
    fn the_energy_during_a_stick_is_its_parabola_not_a_chord() {
        let p = Params {
            kappa: 18.95,
            gamma: 6.5,
            nu: 1e-3,
            theta_nu: 1.0,
            omega: 50.0,
        };
        let (vx, vy) = (p.nu * p.theta_nu.cos(), p.nu * p.theta_nu.sin());
        let at = |t: f64, phase: Phase| Sample {
            t,
            x: -0.003 + vx * t,
            y: 0.1 + vy * t,
            u: vx,
            w: vy,
            phase,
        };
        // A stick of 400 time units between two samples.
        let samples = [at(0.0, Phase::Stick), at(400.0, Phase::Accel)];
        let [stick, _, _] = series(&p, &samples, Quantity::Energy);
        let exact = |t: f64| Quantity::Energy.of(&p, &at(t, Phase::Stick));
        let chord_mid = 0.5 * (exact(0.0) + exact(400.0));
        assert!(
            (chord_mid - exact(200.0)).abs() > 1e-3,
            "the chord would pass"
        );
        // Every drawn point lies on the parabola, and the drawn line is
        // within 1e-4 of it between them.
        let line: Vec<[f64; 2]> = stick.concat();
        assert!(line.len() > 8, "{}", line.len());
        for w in line.windows(2) {
            for pt in w {
                assert!((pt[1] - exact(pt[0])).abs() < 1e-12);
            }
            let mid = 0.5 * (w[0][0] + w[1][0]);
            assert!((0.5 * (w[0][1] + w[1][1]) - exact(mid)).abs() < 1e-4);
        }
    }

    #[test]
    fn phase_spans_join_steps_of_one_kind_and_cover_the_samples() {
        let at = |t: f64, phase: Phase| Sample {
            t,
            x: 0.0,
            y: 0.0,
            u: 0.0,
            w: 0.0,
            phase,
        };
        // Stick from 0 to 10 (onset at 10), accelerating then decelerating
        // to 13, stuck again at 13 until 20.
        let s = [
            at(0.0, Phase::Stick),
            at(10.0, Phase::Accel),
            at(11.0, Phase::Accel),
            at(12.0, Phase::Decel),
            at(13.0, Phase::Stick),
            at(20.0, Phase::Accel),
        ];
        assert_eq!(
            phase_spans(&s),
            vec![(0.0, 10.0, false), (10.0, 13.0, true), (13.0, 20.0, false)]
        );
        assert!(phase_spans(&s[..1]).is_empty());
    }
}
