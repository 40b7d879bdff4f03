//! The event catalogue: the size of every slip (distance or energy) as a
//! time series over the onsets, and the intermittency statistics of the
//! events after the transient (`sim::intermittency`): the slip-size
//! distribution on log–log axes and the distribution of laminar lengths
//! (creep slips between two large slips).

use eframe::egui;
use egui::Ui;
use egui_plot::{Bar, BarChart, HLine, Plot, PlotPoints, Points};

use super::axes::{self, AxisSpec};
use super::jobs::Jobs;
use super::settings::{EventsPlot, Settings, SlipMeasure, ViewKind};
use super::style;
use super::view::{Action, View};
use crate::sim::SlipEvent;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use crossbeam_channel::Receiver;

use crate::integrate::{Method, SolverSettings};
use crate::model::Params;
use crate::sim::intermittency::{
    Intermittency, OnsetCounts, Regime, Scaling, TYPE_ONE_SLOPE, length_counts, scaling,
};

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

/// Events of the trajectory's start left out of the statistics: the
/// trajectory starts at θ = θν, off the attractor. A quarter of the events,
/// at most this many.
pub const STATS_TRANSIENT: usize = 50;

/// How many of `n` events the statistics leave out as the transient.
pub fn stats_transient(n: usize) -> usize {
    (n / 4).min(STATS_TRANSIENT)
}

/// The intermittency statistics of the events on screen, kept until the
/// events or the measure change.
#[derive(Default)]
struct StatsCache {
    key: Option<(u64, usize, bool)>,
    stats: Option<Intermittency>,
    /// Creep and stick-slip by where each kept slip starts.
    onsets: Option<OnsetCounts>,
    skipped: usize,
}

/// A scan of the mean laminar length against θν − θν_c, on a thread of
/// its own (a few dozen orbits, seconds): cancelled when the parameters
/// change or the view goes.
struct ScalingJob {
    params: Params,
    cancel: Arc<AtomicBool>,
    rx: Receiver<Result<Option<Scaling>, String>>,
}

impl Drop for ScalingJob {
    fn drop(&mut self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
}

/// The scan's accuracy: the orbits' slip sizes to ~1e-8.
fn scaling_settings() -> SolverSettings {
    SolverSettings::adaptive(Method::Dop853, 1e-8)
}

#[derive(Default)]
pub struct EventsView {
    cache: StatsCache,
    job: Option<ScalingJob>,
    /// The last scan's parameters and outcome.
    scaled: Option<(Params, Result<Option<Scaling>, String>)>,
}

impl EventsView {
    /// Starts the scan for `params` on a thread.
    fn start_scaling(&mut self, ctx: &egui::Context, params: Params) {
        let cancel = Arc::new(AtomicBool::new(false));
        let (tx, rx) = crossbeam_channel::bounded(1);
        let (c, ctx) = (cancel.clone(), ctx.clone());
        let spawned = std::thread::Builder::new()
            .name("oneblock-scaling".into())
            .spawn(move || {
                crate::worker::priority::lower_current_thread();
                let r = scaling(params, scaling_settings(), &|| c.load(Ordering::Relaxed))
                    .map_err(|e| e.to_string());
                tx.send(r).ok();
                ctx.request_repaint();
            });
        match spawned {
            Ok(_) => self.job = Some(ScalingJob { params, cancel, rx }),
            // Shown where the scan's result would be, not dropped.
            Err(e) => {
                self.job = None;
                self.scaled = Some((params, Err(format!("cannot start the scan's thread: {e}"))));
            }
        }
    }

    /// Collects the scan, or drops it when the parameters moved on.
    fn poll_scaling(&mut self, params: &Params) {
        let Some(job) = &self.job else { return };
        if job.params != *params {
            self.job = None;
            return;
        }
        if let Ok(r) = job.rx.try_recv() {
            self.scaled = Some((job.params, r));
            self.job = None;
        }
    }

    fn scaling_row_ui(&mut self, ui: &mut Ui, params: &Params) {
        ui.horizontal_wrapped(|ui| {
            if self.job.is_some() {
                ui.spinner();
                ui.label("measuring the mean laminar length against θν − θν_c ...");
            } else if ui
                .small_button("Laminar length vs θν − θν_c")
                .on_hover_text(
                    "Locate the lower end θν_c of the intermittent window below θν (by \
                     bisection, to 1e-3) and measure the mean laminar length at θν_c + \
                     (θν − θν_c)/2^k, k = 0…6, on log–log axes beside type-I \
                     intermittency's slope −1/2 when the fitted slope is within 0.15 of it. \
                     About 20 orbits of 2300 iterates, on a thread of its own.",
                )
                .clicked()
            {
                self.start_scaling(ui.ctx(), *params);
            }
            match &self.scaled {
                Some((p, Ok(Some(sc)))) if p == params => {
                    let fit = sc.fit.map_or("no fit (under 3 points)".into(), |(s, _)| {
                        format!(
                            "slope {s:.2}: {}",
                            if sc.supports_type_one() {
                                "type-I (−1/2) supported"
                            } else {
                                "not type-I (−1/2)"
                            }
                        )
                    });
                    ui.label(format!("θν_c ≈ {:.3} · {fit}", sc.theta_nu_c));
                }
                Some((p, Ok(None))) if p == params => {
                    ui.label("not intermittent here, or no lower end within 0.4 below θν");
                }
                Some((p, Err(e))) if p == params => {
                    ui.colored_label(style::ERROR, format!("scan failed: {e}"));
                }
                _ => {}
            }
        });
    }

    fn stats(
        &mut self,
        jobs: &Jobs,
        m: SlipMeasure,
        params: &Params,
    ) -> (&Option<Intermittency>, Option<OnsetCounts>, usize) {
        let evs = &jobs.trajectory.data.events;
        let key = (
            jobs.trajectory.generation,
            evs.len(),
            m == SlipMeasure::Distance,
        );
        if self.cache.key != Some(key) {
            let skip = stats_transient(evs.len());
            let sizes: Vec<f64> = evs[skip..].iter().map(|e| slip_size(e, m)).collect();
            let onsets = OnsetCounts::of(
                params.kappa,
                params.gamma,
                evs[skip..].iter().map(|e| e.theta),
            );
            self.cache = StatsCache {
                key: Some(key),
                stats: Intermittency::of(&sizes, None),
                onsets: Some(onsets),
                skipped: skip,
            };
        }
        (&self.cache.stats, self.cache.onsets, self.cache.skipped)
    }

    fn show(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs) {
        let evs = &jobs.trajectory.data.events;
        let params = s.params;
        let (stats, onsets, skipped) = self.stats(jobs, s.slip_measure, &params);
        let stats = stats.clone();
        self.poll_scaling(&params);
        let scaled = match &self.scaled {
            Some((p, Ok(Some(sc)))) if *p == params => Some(sc.clone()),
            _ => None,
        };
        // All plots side by side need room for five ticks on each axis of
        // each: about 36 lines of text across, and 8 down per stacked plot.
        let em = ui.text_style_height(&egui::TextStyle::Body);
        let stacked = if scaled.is_some() { 3.0 } else { 2.0 };
        let wide = ui.available_width() >= 36.0 * em
            && ui.available_height() >= (stacked * 8.0 + 4.0) * em;
        let figure = style::figure_only(ui.ctx());
        header_ui(ui, s, evs.len(), figure, wide);
        let m = s.slip_measure;
        // The axis title: the quantity in full where there is room.
        let unit = match (m, wide) {
            (SlipMeasure::Distance, true) => "slip distance |Δr| (F₀/k_y)",
            (SlipMeasure::Energy, true) => "energy released ΔE (F₀²/k_y)",
            (SlipMeasure::Distance, false) => "|Δr| (F₀/k_y)",
            (SlipMeasure::Energy, false) => "ΔE (F₀²/k_y)",
        };
        let plots = Plots {
            sizes: evs.iter().map(|e| slip_size(e, m)).collect(),
            stats: stats.as_ref(),
            unit,
            scaled: scaled.as_ref(),
        };
        if let Some(st) = &stats {
            // The full text is formatted only while the summary is hovered.
            let kinds = onsets.map_or(String::new(), |o| format!("{} · ", o.describe()));
            ui.label(kinds.clone() + &summary(st, skipped, unit, wide))
                .on_hover_ui(|ui| {
                    ui.label(kinds + &summary(st, skipped, unit, true) + "\n\n" + STATS_HELP);
                });
        }
        if wide {
            if !figure {
                self.scaling_row_ui(ui, &params);
            }
            let h = ui.available_height();
            let width = ui.available_width();
            ui.horizontal(|ui| {
                ui.vertical(|ui| {
                    ui.set_width(width * 0.5);
                    plots.series_ui(ui, h - 8.0);
                });
                ui.vertical(|ui| {
                    let part = (h - 8.0 * stacked) / stacked;
                    plots.sizes_ui(ui, part);
                    plots.laminar_ui(ui, part);
                    plots.scaling_ui(ui, part);
                });
            });
            return;
        }
        if s.events_plot == EventsPlot::Scaling && !figure {
            self.scaling_row_ui(ui, &params);
        }
        let h = ui.available_height() - 4.0;
        match s.events_plot {
            EventsPlot::Series => plots.series_ui(ui, h),
            EventsPlot::Sizes => plots.sizes_ui(ui, h),
            EventsPlot::Laminar => plots.laminar_ui(ui, h),
            EventsPlot::Scaling => plots.scaling_ui(ui, h),
        }
    }
}

/// The count of events and, in the window, the choices: as buttons where
/// all plots fit, else in two menus on one row (one plot at a time).
fn header_ui(ui: &mut Ui, s: &mut Settings, events: usize, figure: bool, wide: bool) {
    if figure {
        // A picture has no menus: the count only.
        ui.label(format!("{events} slip events"));
    } else if wide {
        measure_ui(ui, s, events);
    } else {
        ui.horizontal_wrapped(|ui| {
            ui.label(format!("{events} slips"));
            egui::ComboBox::from_id_salt("events_measure")
                .selected_text(measure_name(s.slip_measure))
                .show_ui(ui, |ui| {
                    for m in [SlipMeasure::Distance, SlipMeasure::Energy] {
                        ui.selectable_value(&mut s.slip_measure, m, measure_name(m));
                    }
                });
            egui::ComboBox::from_id_salt("events_plot")
                .selected_text(plot_name(s.events_plot))
                .show_ui(ui, |ui| {
                    for v in EventsPlot::ALL {
                        ui.selectable_value(&mut s.events_plot, v, plot_name(v));
                    }
                });
        });
    }
}

/// The count of events and the choice of size measure, as buttons.
fn measure_ui(ui: &mut Ui, s: &mut Settings, events: usize) {
    ui.horizontal_wrapped(|ui| {
        ui.label(format!("{events} slip events · size as"));
        ui.selectable_value(&mut s.slip_measure, SlipMeasure::Distance, "slip distance")
            .on_hover_text("|stop − onset|: how far the block jumped");
        ui.selectable_value(&mut s.slip_measure, SlipMeasure::Energy, "energy released")
            .on_hover_text("½(κx² + y²) at onset minus at the stop");
    });
}

fn measure_name(m: SlipMeasure) -> &'static str {
    match m {
        SlipMeasure::Distance => "slip distance",
        SlipMeasure::Energy => "energy released",
    }
}

fn plot_name(p: EventsPlot) -> &'static str {
    match p {
        EventsPlot::Series => "series",
        EventsPlot::Sizes => "size distribution",
        EventsPlot::Laminar => "laminar lengths",
        EventsPlot::Scaling => "laminar vs θν − θν_c",
    }
}

/// What the summary's hover adds: the definitions.
const STATS_HELP: &str = "A slip is creep or stick-slip by where it starts, the model's \
     criterion: creep where γ² < A(θ) = κ cos²θ + sin²θ. Large and small are \
     sizes: a slip is large when its size is at least a quarter of the largest \
     (the intermittent orbit's sizes are bimodal: small slips of a few \
     thousandths, large ones of tenths). A laminar phase is the run of small \
     slips between two large ones. The trajectory's first events (its \
     transient) are left out; `oneblock orbit --stats` writes the same \
     statistics as CSV.";

/// One line: the counts, and the mean laminar length when the orbit is
/// intermittent or why it is not; `full` adds the threshold and the
/// events left out.
fn summary(st: &Intermittency, skipped: usize, unit: &str, full: bool) -> String {
    let regime = st.regime();
    let verdict = if regime.is_intermittent() {
        let mean = match (st.mean_laminar, st.mean_laminar_stderr) {
            (Some(m), Some(e)) => format!("mean laminar length {m:.1} ± {e:.1}"),
            (Some(m), None) => format!("mean laminar length {m:.1}"),
            _ => "no complete laminar phase".into(),
        };
        format!("{} laminar phases, {mean}", st.laminar.len())
    } else {
        regime.describe()
    };
    if !full && !regime.is_intermittent() {
        return format!(
            "{} large, {} small · {}",
            st.large,
            st.creep,
            short_reason(regime)
        );
    }
    let counts = format!("{} large, {} small · {verdict}", st.large, st.creep);
    if full {
        format!(
            "large slip: {unit} ≥ {:.3} · {counts} · first {skipped} events left out",
            st.threshold
        )
    } else {
        counts
    }
}

/// Why an orbit is not intermittent, in a few words.
fn short_reason(r: Regime) -> &'static str {
    match r {
        Regime::NoCreep => "not intermittent: no small slips",
        Regime::NoLargeSlips => "not intermittent: no large slips",
        Regime::TooFewPhases => "too few laminar phases",
        Regime::Alternating => "not intermittent: alternating",
        Regime::Periodic { .. } => "not intermittent: periodic",
        Regime::Intermittent => "intermittent",
    }
}

/// The view's plots over one catalogue.
struct Plots<'a> {
    /// Every event's size, the transient included (the series shows it).
    sizes: Vec<f64>,
    stats: Option<&'a Intermittency>,
    unit: &'a str,
    scaled: Option<&'a Scaling>,
}

impl Plots<'_> {
    /// The size of every slip against its number, with the large-slip
    /// threshold.
    fn series_ui(&self, ui: &mut Ui, h: f32) {
        let series = decimate(&self.sizes, MAX_MARKERS);
        let markers = self.sizes.len() <= MAX_MARKERS;
        let threshold = self.stats.map(|s| s.threshold);
        let r = axes::apply(
            Plot::new("events_series").show_background(false).height(h),
            &AxisSpec::linear("event number n"),
            &AxisSpec::linear(self.unit),
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
            if let Some(t) = threshold {
                p.hline(
                    HLine::new("large slip", t)
                        .color(style::CRITICAL)
                        .style(egui_plot::LineStyle::dashed_loose()),
                );
            }
        });
        axes::remember_frame(ui.ctx(), "events_series", *r.transform.frame());
    }

    fn sizes_ui(&self, ui: &mut Ui, h: f32) {
        size_distribution_ui(ui, self.stats, self.unit, h);
    }

    fn laminar_ui(&self, ui: &mut Ui, h: f32) {
        laminar_ui(ui, self.stats, h);
    }

    /// The scan's plot, once there is one.
    fn scaling_ui(&self, ui: &mut Ui, h: f32) {
        if let Some(sc) = self.scaled {
            scaling_ui(ui, sc, h);
        }
    }
}

/// The slip-size distribution on log–log axes (log10 bins of the size,
/// log10 of the count), the transient left out.
fn size_distribution_ui(ui: &mut Ui, st: Option<&Intermittency>, unit: &str, h: f32) {
    let bars: Vec<Bar> = st
        .map(|st| {
            st.sizes
                .iter()
                .filter(|b| b.count > 0)
                .map(|b| {
                    let (lo, hi) = (b.lo.log10(), b.hi.log10());
                    // log10(count + 1) so that a single event still shows.
                    Bar::new((lo + hi) / 2.0, (b.count as f64 + 1.0).log10())
                        .width((hi - lo) * 0.95)
                })
                .collect()
        })
        .unwrap_or_default();
    // The rotated y title runs past a short plot's frame into the plot
    // below (projector text, stacked plots): the short form then.
    let y_title = axes::fitting_title(ui, "count + 1 (log scale)", "count + 1", h);
    let r = axes::apply(
        Plot::new("events_hist").show_background(false).height(h),
        &AxisSpec::log10(format!("{unit} (log scale)")),
        &AxisSpec::log10(y_title),
    )
    .show(ui, |p| {
        p.bar_chart(BarChart::new("slip sizes", bars).color(style::STICK));
    });
    axes::remember_frame(ui.ctx(), "events_hist", *r.transform.frame());
}

/// How many laminar phases had each length; where the orbit is not
/// intermittent and its phases are no pattern of it (every slip large, say),
/// no bars but the reason.
fn laminar_ui(ui: &mut Ui, st: Option<&Intermittency>, h: f32) {
    let regime = st.map(Intermittency::regime);
    let meaningful = matches!(regime, Some(Regime::Intermittent | Regime::Periodic { .. }));
    let bars: Vec<Bar> = st
        .filter(|_| meaningful)
        .map(|st| {
            length_counts(&st.laminar)
                .into_iter()
                .map(|(l, c)| Bar::new(l as f64, c as f64).width(0.9))
                .collect()
        })
        .unwrap_or_default();
    // Lengths from 0 and counts from 0 to at least 10 and 5: whole
    // numbers have whole ticks then (a step of at least 1), and no phases
    // at all get these axes, not egui_plot's ±0.4 around nothing.
    let plot = Plot::new("events_laminar")
        .show_background(false)
        .height(h)
        .include_x(0.0)
        .include_x(10.0)
        .include_y(0.0)
        .include_y(5.0);
    let r = axes::apply(
        plot,
        &AxisSpec::linear("laminar length (creep slips)"),
        &AxisSpec::linear("phases"),
    )
    .show(ui, |p| {
        p.bar_chart(BarChart::new("laminar lengths", bars).color(style::DECEL));
        if let Some(r) = regime.filter(|_| !meaningful) {
            let b = p.plot_bounds();
            let centre = egui_plot::PlotPoint::new(
                0.5 * (b.min()[0] + b.max()[0]),
                0.5 * (b.min()[1] + b.max()[1]),
            );
            p.text(egui_plot::Text::new("why", centre, short_reason(r)));
        }
    });
    axes::remember_frame(ui.ctx(), "events_laminar", *r.transform.frame());
}

/// The mean laminar length against θν − θν_c on log–log axes, with the fitted line, and the
/// type-I slope −1/2 through the points' centre when the fit supports it.
fn scaling_ui(ui: &mut Ui, sc: &Scaling, h: f32) {
    let pts: Vec<[f64; 2]> = sc
        .points
        .iter()
        .map(|&(e, m)| [e.log10(), m.log10()])
        .collect();
    let span = |f: &dyn Fn(f64) -> f64| -> Vec<[f64; 2]> {
        let (a, b) = pts
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p[0]), b.max(p[0]))
            });
        vec![[a, f(a)], [b, f(b)]]
    };
    let r = axes::apply(
        Plot::new("events_scaling").show_background(false).height(h),
        &AxisSpec::log10("θν − θν_c (rad, log scale)"),
        &AxisSpec::log10("mean laminar length (log scale)"),
    )
    .show(ui, |p| {
        p.add(
            Points::new("mean laminar length", PlotPoints::from(pts.clone()))
                .color(style::ACCEL)
                .radius(3.0),
        );
        if let Some((slope, icpt)) = sc.fit {
            p.line(
                style::line("fit", PlotPoints::from(span(&|x| icpt + slope * x)))
                    .color(style::STICK),
            );
            if sc.supports_type_one() && !pts.is_empty() {
                let n = pts.len() as f64;
                let (mx, my) = (
                    pts.iter().map(|q| q[0]).sum::<f64>() / n,
                    pts.iter().map(|q| q[1]).sum::<f64>() / n,
                );
                p.line(
                    style::line(
                        "type I: −1/2",
                        PlotPoints::from(span(&|x| my + TYPE_ONE_SLOPE * (x - mx))),
                    )
                    .color(style::CRITICAL)
                    .style(egui_plot::LineStyle::dashed_loose()),
                );
            }
        }
    });
    axes::remember_frame(ui.ctx(), "events_scaling", *r.transform.frame());
}

impl View for EventsView {
    fn title(&self) -> &'static str {
        ViewKind::Events.title()
    }

    fn ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, _out: &mut Vec<Action>) {
        self.show(ui, s, jobs);
    }
}
