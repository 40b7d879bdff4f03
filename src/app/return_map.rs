//! The return map θ' = f(θ) on the exit arc: the orbit's iterates as
//! points, the trajectory's cycles (transient included) as lighter points
//! that trace more of the map's graph, the 45° line, the cobweb of the
//! latest iterates, and the detected period and Lyapunov exponent.

use eframe::egui;
use egui::{RichText, Ui};
use egui_plot::{HLine, Legend, Line, LineStyle, Plot, PlotPoints, Points, VLine};

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
        let kept: Vec<[f64; 2]> = it.thetas.windows(2).map(|w| [w[0], w[1]]).collect();
        let traj: Vec<[f64; 2]> = data
            .trajectory
            .events
            .iter()
            .map(|e| [e.theta, e.theta_next])
            .collect();
        let tail = &it.thetas[it.thetas.len().saturating_sub(COBWEB)..];
        let web = cobweb(tail);
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in kept.iter().chain(&traj) {
            lo = lo.min(p[0]).min(p[1]);
            hi = hi.max(p[0]).max(p[1]);
        }
        if !lo.is_finite() {
            lo = s.params.theta_nu - 0.5;
            hi = s.params.theta_nu + 0.5;
        }
        let pad = ((hi - lo) * 0.08).max(0.02);
        let (lo, hi) = (lo - pad, hi + pad);
        let theta_c = match Regime::of(s.params.kappa, s.params.gamma) {
            Regime::Mixed { theta_c } => Some(theta_c),
            _ => None,
        };
        let dark = s.dark;
        Plot::new("return_map")
            .data_aspect(1.0)
            .x_axis_label("θ (this onset)")
            .y_axis_label("θ' (next onset)")
            .legend(Legend::default().position(egui_plot::Corner::LeftTop))
            .include_x(lo)
            .include_x(hi)
            .include_y(lo)
            .include_y(hi)
            .show(ui, |p| {
                p.line(
                    Line::new("θ' = θ", PlotPoints::from(vec![[lo, lo], [hi, hi]]))
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
                    Line::new("cobweb", PlotPoints::from(web))
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
