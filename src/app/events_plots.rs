//! The Events view's plots: the size of every slip as a series (creep and
//! stick-slip slips in their own colours), the slip-size distribution, the
//! laminar lengths (runs of creep slips) and, after a scan, the mean
//! laminar length against the distance to a located tangency.

use eframe::egui;
use egui::Ui;
use egui_plot::{Bar, BarChart, Plot, PlotPoints, Points};

use super::axes::{self, AxisSpec};
use super::style;
use crate::sim::intermittency::{Intermittency, Regime, Scaling, TYPE_ONE_SLOPE, length_counts};

/// Beyond this many events the series is drawn as a min/max envelope.
pub const MAX_MARKERS: usize = 1500;

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

/// The view's plots over one catalogue.
pub struct Plots<'a> {
    /// Every event's size, the transient included (the series shows it).
    pub sizes: Vec<f64>,
    /// Whether each event is a creep slip (by where it starts).
    pub creep: Vec<bool>,
    pub stats: Option<&'a Intermittency>,
    pub unit: &'a str,
    pub scaled: Option<&'a Scaling>,
}

impl Plots<'_> {
    /// The size of every slip against its number, creep and stick-slip
    /// slips in their own colours.
    pub fn series_ui(&self, ui: &mut Ui, h: f32) {
        let series = decimate(&self.sizes, MAX_MARKERS);
        let markers = self.sizes.len() <= MAX_MARKERS;
        // Room for five labelled ticks on the size axis.
        let line = ui.text_style_height(&egui::TextStyle::Body);
        let h = if markers && h > 12.0 * line && style::legend_shown(ui.ctx()) {
            // What the markers' colours say, on a row above the plot (left
            // out in a tile too short for it and the plot's ticks), or
            // inside it, taking no room.
            let top = ui.cursor().top();
            style::legend_row(ui, |ui| {
                style::legend_swatch(ui, style::PULL, "creep");
                style::legend_swatch(ui, style::ACCEL, "stick-slip");
            });
            h - (ui.cursor().top() - top)
        } else {
            h
        };
        let r = axes::apply(
            ui.ctx(),
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
                let (mut creep, mut stick) = (Vec::new(), Vec::new());
                for (q, c) in series.iter().zip(&self.creep) {
                    if *c { creep.push(*q) } else { stick.push(*q) }
                }
                p.add(
                    Points::new("creep", PlotPoints::from(creep))
                        .color(style::PULL)
                        .radius(2.5),
                );
                p.add(
                    Points::new("stick-slip", PlotPoints::from(stick))
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
    }

    pub fn sizes_ui(&self, ui: &mut Ui, h: f32) {
        size_distribution_ui(ui, self.stats, self.unit, h);
    }

    pub fn laminar_ui(&self, ui: &mut Ui, h: f32) {
        laminar_ui(ui, self.stats, h);
    }

    /// The scan's plot, once there is one with points.
    pub fn scaling_ui(&self, ui: &mut Ui, h: f32) {
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
        ui.ctx(),
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
/// intermittent and its phases are no pattern of it (no creep, say), no
/// bars but the reason.
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
        ui.ctx(),
        plot,
        &AxisSpec::linear("laminar length (creep slips in a run)"),
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
            p.text(egui_plot::Text::new("why", centre, r.short_reason()));
        }
    });
    axes::remember_frame(ui.ctx(), "events_laminar", *r.transform.frame());
}

/// The mean laminar length and the channel passage against ε, the
/// distance to the located fold, on log–log axes, with the fitted line,
/// and the type-I slope −1/2 through the points' centre when the fit
/// supports it. Nothing is drawn without a tangency (the row above says
/// why).
fn scaling_ui(ui: &mut Ui, sc: &Scaling, h: f32) {
    let Scaling::Fitted { points, fit, .. } = sc else {
        return;
    };
    let log = |e: f64, v: Option<f64>| v.filter(|v| *v > 0.0).map(|v| [e.log10(), v.log10()]);
    let pts: Vec<[f64; 2]> = points.iter().filter_map(|q| log(q.eps, q.mean)).collect();
    let pass: Vec<[f64; 2]> = points
        .iter()
        .filter_map(|q| log(q.eps, q.passage))
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
        ui.ctx(),
        Plot::new("events_scaling").show_background(false).height(h),
        &AxisSpec::log10("ε = |θν − θν_fold| (rad, log scale)"),
        &AxisSpec::log10("laminar length (log scale)"),
    )
    .show(ui, |p| {
        p.add(
            Points::new("mean laminar length", PlotPoints::from(pts.clone()))
                .color(style::ACCEL)
                .radius(3.0),
        );
        p.add(
            Points::new("channel passage", PlotPoints::from(pass))
                .color(style::PULL)
                .shape(egui_plot::MarkerShape::Diamond)
                .radius(3.0),
        );
        if let Some((slope, icpt)) = *fit {
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
