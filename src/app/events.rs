//! The event catalogue: the size of every slip (distance or energy) as a
//! time series over the onsets, and its histogram.

use eframe::egui;
use egui::Ui;
use egui_plot::{Bar, BarChart, Plot, PlotPoints, Points};

use super::axes::{self, AxisSpec};
use super::jobs::Jobs;
use super::settings::{Settings, SlipMeasure, ViewKind};
use super::style;
use super::view::{Action, View};
use crate::sim::SlipEvent;

/// Bins of the histogram.
const BINS: usize = 40;
/// Beyond this many events the series is drawn as a min/max envelope.
const MAX_MARKERS: usize = 1500;

/// The series (index, value), reduced to min and max per bucket when
/// longer than `max` so the plot stays cheap with any number of events.
pub fn decimate(ys: &[f64], max: usize) -> Vec<[f64; 2]> {
    if ys.len() <= max {
        return ys.iter().enumerate().map(|(i, &v)| [i as f64, v]).collect();
    }
    let buckets = (max / 2).max(1);
    let per = ys.len().div_ceil(buckets);
    let mut out = Vec::with_capacity(2 * buckets);
    for (b, chunk) in ys.chunks(per).enumerate() {
        let i0 = (b * per) as f64;
        let (lo, hi) = chunk
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                (l.min(v), h.max(v))
            });
        out.push([i0, lo]);
        out.push([i0 + chunk.len() as f64 / 2.0, hi]);
    }
    out
}

/// The size of a slip under `m`.
pub fn slip_size(e: &SlipEvent, m: SlipMeasure) -> f64 {
    match m {
        SlipMeasure::Distance => e.slip_distance,
        SlipMeasure::Energy => e.energy_released,
    }
}

/// Counts of `xs` in `bins` equal bins over [min, max]: (left edges, width, counts).
pub fn histogram(xs: &[f64], bins: usize) -> (Vec<f64>, f64, Vec<usize>) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &x in xs.iter().filter(|x| x.is_finite()) {
        lo = lo.min(x);
        hi = hi.max(x);
    }
    if !lo.is_finite() || bins == 0 {
        return (vec![], 1.0, vec![]);
    }
    if hi - lo < 1e-12 * hi.abs().max(1e-300) {
        let w = (hi.abs() * 0.02).max(1e-12);
        return (vec![lo - w / 2.0], w, vec![xs.len()]);
    }
    let w = (hi - lo) / bins as f64;
    let mut c = vec![0usize; bins];
    for &x in xs.iter().filter(|x| x.is_finite()) {
        c[(((x - lo) / w) as usize).min(bins - 1)] += 1;
    }
    ((0..bins).map(|i| lo + i as f64 * w).collect(), w, c)
}

#[derive(Default)]
pub struct EventsView;

impl EventsView {
    fn show(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs) {
        let evs = &jobs.trajectory.data.events;
        ui.horizontal_wrapped(|ui| {
            ui.label(format!("{} slip events · size as", evs.len()));
            ui.selectable_value(&mut s.slip_measure, SlipMeasure::Distance, "slip distance")
                .on_hover_text("|stop − onset|: how far the block jumped");
            ui.selectable_value(&mut s.slip_measure, SlipMeasure::Energy, "energy released")
                .on_hover_text("½(κx² + y²) at onset minus at the stop");
        });
        let m = s.slip_measure;
        let unit = match m {
            SlipMeasure::Distance => "slip distance |Δr| (F₀/k_y)",
            SlipMeasure::Energy => "energy released ΔE (F₀²/k_y)",
        };
        let sizes: Vec<f64> = evs.iter().map(|e| slip_size(e, m)).collect();
        let series = decimate(&sizes, MAX_MARKERS);
        let markers = sizes.len() <= MAX_MARKERS;
        let (edges, w, counts) = histogram(&sizes, BINS);
        let bars: Vec<Bar> = edges
            .iter()
            .zip(&counts)
            .map(|(&e, &c)| Bar::new(e + w / 2.0, c as f64).width(w * 0.95))
            .collect();
        let h = ui.available_height();
        let width = ui.available_width();
        ui.horizontal(|ui| {
            ui.vertical(|ui| {
                ui.set_width(width * 0.58);
                let plot = Plot::new("events_series")
                    .show_background(false)
                    .height(h - 8.0);
                let r = axes::apply(
                    plot,
                    &AxisSpec::linear("event number n"),
                    &AxisSpec::linear(unit),
                )
                .show(ui, |p| {
                    if markers {
                        p.line(
                            style::line("size", PlotPoints::from(series.clone()))
                                .color(style::STICK.gamma_multiply(0.5)),
                        );
                        p.add(
                            Points::new("slips", PlotPoints::from(series))
                                .color(style::ACCEL)
                                .radius(2.5),
                        );
                    } else {
                        // Thousands of events: their envelope, not a marker each.
                        p.line(
                            style::line("size", PlotPoints::from(series))
                                .color(style::ACCEL)
                                .width(1.0),
                        );
                    }
                });
                axes::remember_frame(ui.ctx(), "events_series", *r.transform.frame());
            });
            ui.vertical(|ui| {
                let plot = Plot::new("events_hist")
                    .show_background(false)
                    .height(h - 8.0);
                let r = axes::apply(
                    plot,
                    &AxisSpec::linear(unit),
                    &AxisSpec::linear("count of events"),
                )
                .show(ui, |p| {
                    p.bar_chart(BarChart::new("histogram", bars).color(style::STICK));
                });
                axes::remember_frame(ui.ctx(), "events_hist", *r.transform.frame());
            });
        });
    }
}

impl View for EventsView {
    fn title(&self) -> &'static str {
        ViewKind::Events.title()
    }

    fn ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, _out: &mut Vec<Action>) {
        self.show(ui, s, jobs);
    }
}
