//! The return map θ' = f(θ) on the exit arc: the orbit's iterates as
//! points, the trajectory's cycles (transient included) as lighter points
//! that trace more of the map's graph, the 45° line, the cobweb of the
//! latest iterates, and the detected period and Lyapunov exponent.

use eframe::egui;
use egui::{RichText, Ui};
use egui_plot::{HLine, LineStyle, Plot, PlotPoints, Points, VLine};

use super::data::Data;
use super::settings::Settings;
use super::style;
use crate::model::Regime;
use crate::sim::Period;

/// Iterates the cobweb follows.
const COBWEB: usize = 40;

/// The cobweb polyline of `thetas`: (θ0, θ0) → (θ0, θ1) → (θ1, θ1) → …
pub fn cobweb(thetas: &[f64]) -> Vec<[f64; 2]> {
    let mut out = Vec::with_capacity(2 * thetas.len());
    for w in thetas.windows(2) {
        out.push([w[0], w[0]]);
        out.push([w[0], w[1]]);
    }
    if let Some(&l) = thetas.last() {
        out.push([l, l]);
    }
    out
}

/// The period and Lyapunov exponent as one line of text.
pub fn summary(period: Option<Period>, lyapunov: Option<f64>) -> String {
    let p = match period {
        None => "period: computing…".to_string(),
        Some(Period::Periodic(n)) => format!("period {n}"),
        Some(Period::Aperiodic) => "aperiodic".to_string(),
    };
    match lyapunov {
        Some(l) => format!("{p}   ·   Lyapunov exponent λ = {l:.4}"),
        None => p,
    }
}

#[derive(Default)]
pub struct ReturnMapView;

impl ReturnMapView {
    pub fn ui(&mut self, ui: &mut Ui, s: &Settings, data: &Data) {
        let it = &data.iterate;
        ui.label(RichText::new(summary(it.period, it.lyapunov)).strong());
        ui.horizontal_wrapped(|ui| {
            style::legend_marker(ui, style::ink(s.dark), "orbit iterates");
            style::legend_marker(
                ui,
                style::STICK.gamma_multiply(0.6),
                "cycles incl. transient",
            );
            style::legend_line(ui, style::DECEL, false, "cobweb");
            style::legend_line(ui, style::CRITICAL, true, "θ' = θ");
        });
        let kept: Vec<[f64; 2]> = it.thetas.windows(2).map(|w| [w[0], w[1]]).collect();
        // The latest cycles only: thousands of markers would cost frames.
        let evs = &data.trajectory.events;
        let traj: Vec<[f64; 2]> = evs[evs.len().saturating_sub(1500)..]
            .iter()
            .map(|e| [e.theta, e.theta_next])
            .collect();
        let tail = &it.thetas[it.thetas.len().saturating_sub(COBWEB)..];
        let web = cobweb(tail);
        // Frame the attractor (the kept iterates); the transient may fall outside.
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let framed: &[[f64; 2]] = if kept.is_empty() { &traj } else { &kept };
        for p in framed {
            lo = lo.min(p[0]).min(p[1]);
            hi = hi.max(p[0]).max(p[1]);
        }
        if !lo.is_finite() {
            lo = s.params.theta_nu - 0.5;
            hi = s.params.theta_nu + 0.5;
        }
        let pad = ((hi - lo) * 0.25).max(0.02);
        let (lo, hi) = (lo - pad, hi + pad);
        let theta_c = match Regime::of(s.params.kappa, s.params.gamma) {
            Regime::Mixed { theta_c } => Some(theta_c),
            _ => None,
        };
        let dark = s.dark;
        Plot::new("return_map")
            .show_background(false)
            .data_aspect(1.0)
            .x_axis_label("θ (this onset)")
            .y_axis_label("θ' (next onset)")
            .allow_double_click_reset(false)
            .show(ui, |p| {
                // Follow the attractor as it changes, in a square that fits.
                let f = *p.transform().frame();
                if f.height() > 0.0 {
                    let asp = (f.width() / f.height()) as f64;
                    let (c, h) = ((lo + hi) / 2.0, (hi - lo) / 2.0);
                    let (hx, hy) = if asp >= 1.0 {
                        (h * asp, h)
                    } else {
                        (h, h / asp)
                    };
                    p.set_plot_bounds(egui_plot::PlotBounds::from_min_max(
                        [c - hx, c - hy],
                        [c + hx, c + hy],
                    ));
                }
                p.line(
                    style::line("θ' = θ", PlotPoints::from(vec![[lo, lo], [hi, hi]]))
                        .color(style::CRITICAL)
                        .style(LineStyle::Dashed { length: 8.0 }),
                );
                if let Some(tc) = theta_c {
                    for v in [tc, -tc] {
                        if v > lo && v < hi {
                            p.add(
                                VLine::new("θc", v)
                                    .color(style::ACCEL.gamma_multiply(0.6))
                                    .style(LineStyle::Dashed { length: 6.0 }),
                            );
                            p.add(
                                HLine::new("θc", v)
                                    .color(style::ACCEL.gamma_multiply(0.6))
                                    .style(LineStyle::Dashed { length: 6.0 }),
                            );
                        }
                    }
                }
                p.add(
                    Points::new("trajectory cycles (with transient)", PlotPoints::from(traj))
                        .color(style::STICK.gamma_multiply(0.45))
                        .radius(2.5),
                );
                p.line(
                    style::line("cobweb", PlotPoints::from(web))
                        .color(style::DECEL)
                        .width(1.5),
                );
                p.add(
                    Points::new("orbit iterates", PlotPoints::from(kept))
                        .color(style::ink(dark))
                        .radius(3.5)
                        .filled(true),
                );
            });
    }
}
