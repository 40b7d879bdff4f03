//! The return map θ' = f(θ) on the exit arc: the graph of f over the
//! orbit's window (computed by the worker once the orbit is known), the
//! orbit's iterates as points, the trajectory's cycles (transient included)
//! as lighter points, the 45° line, the cobweb of the latest iterates, and
//! the detected period and Lyapunov exponent.

use eframe::egui;
use egui::{RichText, Ui};
use egui_plot::{HLine, LineStyle, MarkerShape, Plot, PlotPoints, VLine};

use super::axes::{self, AxisSpec};
use super::jobs::Jobs;
use super::map_basins::{BAND_WIDTH, BasinBand, DENSITY_WIDTH, density_colour};
use super::markers::{self, Marker};
use super::play::{CobwebSteps, cobweb_steps_ui};
use super::settings::{Settings, ViewKind};
use super::style;
use super::view::{Action, View};
use crate::model::Regime;
use crate::sim::{Period, return_map_window};

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

/// The graph's points cut into polylines at failed cycles (NaN) and at
/// jumps: f is discontinuous where the next onset switches between creep
/// and stick-slip, and a line drawn across such a jump would be a lie.
pub fn graph_pieces(graph: &[[f64; 2]], jump: f64) -> Vec<Vec<[f64; 2]>> {
    let mut pieces: Vec<Vec<[f64; 2]>> = Vec::new();
    let mut cur: Vec<[f64; 2]> = Vec::new();
    for &p in graph {
        if !(p[0].is_finite() && p[1].is_finite()) {
            if cur.len() > 1 {
                pieces.push(std::mem::take(&mut cur));
            }
            cur.clear();
            continue;
        }
        if let Some(last) = cur.last()
            && (p[1] - last[1]).abs() > jump
        {
            if cur.len() > 1 {
                pieces.push(std::mem::take(&mut cur));
            }
            cur.clear();
        }
        cur.push(p);
    }
    if cur.len() > 1 {
        pieces.push(cur);
    }
    pieces
}

/// The period and Lyapunov exponent as one line of text: λ with its
/// standard error where it is a mean ([`crate::text::lyapunov`]).
pub fn summary(period: Option<Period>, lyapunov: Option<f64>, stderr: Option<f64>) -> String {
    let p = match period {
        None => "period: computing…".to_string(),
        Some(Period::Periodic(n)) => format!("period {n}"),
        Some(Period::Aperiodic) => "aperiodic".to_string(),
    };
    let exact = matches!(period, Some(Period::Periodic(_)));
    match lyapunov {
        Some(l) => format!(
            "{p}   ·   Lyapunov exponent {}",
            crate::text::lyapunov(l, stderr, exact)
        ),
        None => p,
    }
}

/// The view's state: the cobweb's steps, and the axes when held.
#[derive(Default)]
pub struct ReturnMapView {
    pub steps: CobwebSteps,
    /// θ's window held whatever the attractor (a GIF of θν played holds
    /// it over the whole play, so that the fixed point is seen to move
    /// along the diagonal); `None`: the window follows the attractor.
    pub held: Option<(f64, f64)>,
    /// The plot's bounds at the last frame: what the legend lists is what
    /// is drawn inside them.
    shown: Option<egui_plot::PlotBounds>,
}

/// What the return map draws, in (θ, θ') before any change of axes.
struct MapData {
    /// The orbit's kept pairs (θk, θk+1).
    kept: Vec<[f64; 2]>,
    /// The trajectory's latest cycles (transient included).
    traj: Vec<[f64; 2]>,
    /// The cobweb of the latest iterates.
    web: Vec<[f64; 2]>,
    /// f's graph, cut at failures and jumps.
    pieces: Vec<Vec<[f64; 2]>>,
    /// f^k's graphs asked for and arrived: (k − 2, pieces).
    powers: Vec<(usize, Vec<Vec<[f64; 2]>>)>,
    /// θ's window, out to round values.
    window: (f64, f64),
    theta_c: Option<f64>,
    /// The cell graph's basins along the frame's foot and a chaotic
    /// attractor's density, once found at these parameters.
    band: BasinBand,
}

impl MapData {
    fn of(s: &Settings, jobs: &Jobs, steps: &CobwebSteps) -> MapData {
        let it = &jobs.iterate.data;
        let kept: Vec<[f64; 2]> = it.thetas.windows(2).map(|w| [w[0], w[1]]).collect();
        // The latest cycles only: thousands of markers would cost frames.
        let evs = &jobs.trajectory.data.events;
        let traj: Vec<[f64; 2]> = evs[evs.len().saturating_sub(1500)..]
            .iter()
            .map(|e| [e.theta, e.theta_next])
            .collect();
        let tail = &it.thetas[it.thetas.len().saturating_sub(COBWEB)..];
        // A jump of more than a tenth of the window between neighbours 1/200
        // of it apart is a discontinuity, not a steep stretch of f.
        let span = it
            .graph
            .last()
            .zip(it.graph.first())
            .map_or(1.0, |(a, b)| (a[0] - b[0]).abs());
        let jump = 0.1 * span.max(1e-3);
        let powers = it
            .powers
            .iter()
            .enumerate()
            .filter(|(i, _)| s.map_powers.get(*i).copied().unwrap_or(false))
            .map(|(i, vals)| {
                let pts: Vec<[f64; 2]> =
                    it.graph.iter().zip(vals).map(|(g, &v)| [g[0], v]).collect();
                (i, graph_pieces(&pts, jump))
            })
            .collect();
        // Frame the attractor (the kept iterates; the transient may fall
        // outside) in the window the worker drew f over.
        let framed: &[[f64; 2]] = if kept.is_empty() { &traj } else { &kept };
        let flat: Vec<f64> = framed.iter().flat_map(|p| [p[0], p[1]]).collect();
        let th = s.params.theta_nu;
        let (lo, hi) = return_map_window(&flat).unwrap_or((th - 0.5, th + 0.5));
        MapData {
            band: BasinBand::of(s, jobs),
            web: if steps.on {
                cobweb(&steps.onsets(evs))
            } else {
                cobweb(tail)
            },
            pieces: graph_pieces(&it.graph, jump),
            powers,
            kept,
            traj,
            // Out to round values, so that even a short side has five ticks.
            window: axes::nice_bounds(lo, hi, axes::MIN_TICKS),
            theta_c: match Regime::of(s.params.kappa, s.params.gamma) {
                Regime::Mixed { theta_c } => Some(theta_c),
                _ => None,
            },
        }
    }

    /// Every point as (θ, θ' − θ): the distance of f from the diagonal.
    fn into_difference(mut self) -> MapData {
        // The basins' band and the density are drawn on the map only.
        self.band = BasinBand::default();
        let d = |v: &mut Vec<[f64; 2]>| v.iter_mut().for_each(|p| p[1] -= p[0]);
        d(&mut self.kept);
        d(&mut self.traj);
        self.pieces.iter_mut().for_each(d);
        for (_, pieces) in &mut self.powers {
            pieces.iter_mut().for_each(d);
        }
        // A cobweb has no meaning off the diagonal.
        self.web.clear();
        self
    }
}

impl ReturnMapView {
    fn show(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs) {
        let it = &jobs.iterate.data;
        let mut data = MapData::of(s, jobs, &self.steps);
        if let Some(w) = self.held {
            data.window = w;
        }
        let shown = self.shown.unwrap_or_else(|| {
            let (lo, hi) = data.window;
            egui_plot::PlotBounds::from_min_max([lo, lo], [hi, hi])
        });
        legend_ui(
            ui,
            it.period,
            (it.lyapunov, it.lyapunov_stderr),
            s,
            (&data, shown),
        );
        // Room for the top tick label, centred on the frame's top edge.
        ui.add_space(0.5 * ui.text_style_height(&egui::TextStyle::Body));
        let (x, y) = (
            AxisSpec::angle("θ, this onset", s.angle_unit),
            fitting(ui, AxisSpec::angle("θ', next onset", s.angle_unit)),
        );
        let resp = if s.map_difference {
            let y = fitting(
                ui,
                AxisSpec::angle("f(θ) − θ, distance from the diagonal", s.angle_unit),
            );
            let data = data.into_difference();
            let plot = axes::apply(
                ui.ctx(),
                Plot::new("return_map").show_background(false),
                &x,
                &y,
            );
            let bounds = difference_bounds(&data);
            plot.show(ui, |p| {
                p.set_plot_bounds(bounds);
                draw_map(p, s, &data, 0.0)
            })
        } else {
            let plot = Plot::new("return_map")
                .show_background(false)
                .data_aspect(1.0)
                .allow_double_click_reset(false);
            let (lo, hi) = data.window;
            axes::apply(ui.ctx(), plot, &x, &y).show(ui, |p| {
                frame_square(p, lo, hi);
                draw_map(p, s, &data, 1.0)
            })
        };
        axes::remember_frame(ui.ctx(), "return_map", *resp.transform.frame());
        self.shown = Some(*resp.transform.bounds());
    }
}

/// `axis` with its title shortened to its symbol where it would run past
/// the plot turned on its side (a short tile, text ×1.5, the powers' row).
fn fitting(ui: &Ui, mut axis: AxisSpec) -> AxisSpec {
    let long = axis.title.clone();
    let title = axes::fitting_title(ui, &long, axes::short_name(&long), ui.available_height());
    axis.title = title.to_owned();
    axis
}

/// The difference plot's bounds: θ's window, and every value of f − θ in
/// it, 0 included.
fn difference_bounds(d: &MapData) -> egui_plot::PlotBounds {
    let (lo, hi) = d.window;
    let (mut ylo, mut yhi) = (0.0f64, 0.0f64);
    let all = d.pieces.iter().flatten().chain(&d.kept);
    for p in all.filter(|p| p[0] >= lo && p[0] <= hi && p[1].is_finite()) {
        ylo = ylo.min(p[1]);
        yhi = yhi.max(p[1]);
    }
    let pad = ((yhi - ylo) * 0.08).max(1e-6);
    egui_plot::PlotBounds::from_min_max([lo, ylo - pad], [hi, yhi + pad])
}

/// The plot's items: f (and its powers), the diagonal θ' = slope·θ (slope
/// 1 for the map, 0 for f − θ), θc, the cycles, the cobweb, the orbit.
fn draw_map(p: &mut egui_plot::PlotUi<'_>, s: &Settings, d: &MapData, slope: f64) {
    let (lo, hi) = d.window;
    let lw = style::width(p.ctx(), 1.0);
    let name = if slope == 1.0 {
        "θ' = θ"
    } else {
        "f − θ = 0"
    };
    // Dashed: cut to the plot's bounds first (a deep zoom would dash the
    // whole window at the zoom's scale).
    let b = p.plot_bounds();
    let diagonal = [[lo, slope * lo], [hi, slope * hi]];
    for part in super::clip::clip_polyline(&diagonal, b.min(), b.max()) {
        p.line(
            style::line(name, PlotPoints::from(part))
                .color(style::CRITICAL)
                .style(LineStyle::Dashed { length: 8.0 }),
        );
    }
    if let Some(tc) = d.theta_c
        && slope == 1.0
    {
        critical_angles(p, tc, lo, hi);
    }
    d.band.draw(p);
    for (i, pieces) in &d.powers {
        let i = (*i).min(2);
        for piece in pieces {
            p.line(
                style::line(["f²", "f³", "f⁴"][i], PlotPoints::from(piece.clone()))
                    .color(style::POWERS[i])
                    .width(1.5 * lw),
            );
        }
    }
    for piece in &d.pieces {
        p.line(
            style::line("f", PlotPoints::from(piece.clone()))
                .color(style::ACCEL)
                .width(2.0 * lw),
        );
    }
    // Only the transient points inside the frame: one far off would be
    // drawn past the frame's edge in a picture, which does not clip.
    let b = p.plot_bounds();
    let (bmin, bmax) = (b.min(), b.max());
    let inside: Vec<[f64; 2]> = d
        .traj
        .iter()
        .copied()
        .filter(|q| (bmin[0]..=bmax[0]).contains(&q[0]) && (bmin[1]..=bmax[1]).contains(&q[1]))
        .collect();
    let [iterates, cycles] = map_markers(s.dark);
    p.add(cycles.points(TRANSIENT, PlotPoints::from(inside)));
    p.line(
        style::line("cobweb", PlotPoints::from(d.web.clone()))
            .color(style::DECEL)
            .width(COBWEB_WIDTH * lw),
    );
    p.add(iterates.points(ITERATES, PlotPoints::from(d.kept.clone())));
}

/// The cobweb's width, in lines (`style::width`).
const COBWEB_WIDTH: f32 = 1.5;

/// The critical angles' colour.
fn theta_c_colour() -> egui::Color32 {
    style::ACCEL.gamma_multiply(0.6)
}

/// The names of the map's points (legend and hover).
const ITERATES: &str = "orbit iterates";
const TRANSIENT: &str = "cycles incl. transient";

/// The map's markers: the orbit's iterates, and every cycle of the
/// trajectory with its transient (paler, smaller).
fn map_markers(dark: bool) -> [Marker; 2] {
    [
        Marker::new(MarkerShape::Circle, style::ink(dark), 3.5, true),
        Marker::new(
            MarkerShape::Circle,
            style::STICK.gamma_multiply(0.45),
            2.5,
            true,
        ),
    ]
}

/// Follows the attractor as it changes: the plot's bounds a square around
/// [`lo`, `hi`] that fits the frame.
fn frame_square(p: &mut egui_plot::PlotUi<'_>, lo: f64, hi: f64) {
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
}

/// The critical angles ±θc (where creep onsets meet stick-slip onsets) as
/// dashed lines across both axes, where they fall inside [`lo`, `hi`].
fn critical_angles(p: &mut egui_plot::PlotUi<'_>, theta_c: f64, lo: f64, hi: f64) {
    for v in [theta_c, -theta_c] {
        if v > lo && v < hi {
            p.add(
                VLine::new("θc", v)
                    .color(theta_c_colour())
                    .style(LineStyle::Dashed { length: 6.0 }),
            );
            p.add(
                HLine::new("θc", v)
                    .color(theta_c_colour())
                    .style(LineStyle::Dashed { length: 6.0 }),
            );
        }
    }
}

/// The f², f³, f⁴ switches, each with its colour, and whether it is still
/// being computed.
fn powers_ui(ui: &mut Ui, s: &mut Settings, arrived: &[Vec<f64>]) {
    {
        ui.label("also draw:");
        for (i, name) in ["f²", "f³", "f⁴"].into_iter().enumerate() {
            let (rect, _) = ui.allocate_exact_size(egui::vec2(18.0, 14.0), egui::Sense::hover());
            ui.painter().line_segment(
                [rect.left_center(), rect.right_center()],
                egui::Stroke::new(2.0, style::POWERS[i]),
            );
            ui.checkbox(&mut s.map_powers[i], name).on_hover_text(
                "The graph of the map composed with itself, each point from \
                 k cycles integrated in turn: a period-k orbit is where it \
                 meets θ' = θ, and a tangency marks a period-k window's birth.",
            );
        }
        let want = s.graph_power();
        if want >= 2 && arrived.len() + 1 < want {
            ui.weak("computing…");
        }
    }
}

/// The period and λ, and the legend above the plot: an entry for each
/// thing `d` draws inside the plot's bounds `shown` (the last frame's),
/// its key styled as it is drawn.
fn legend_ui(
    ui: &mut Ui,
    period: Option<Period>,
    (lyapunov, stderr): (Option<f64>, Option<f64>),
    s: &Settings,
    (d, shown): (&MapData, egui_plot::PlotBounds),
) {
    ui.horizontal_wrapped(|ui| {
        ui.label(RichText::new(summary(period, lyapunov, stderr)).strong());
    });
    let difference = s.map_difference;
    let (lo, hi) = (shown.min()[0], shown.max()[0]);
    // The points as drawn: (θ, θ') or (θ, θ' − θ).
    let inside = |q: &&[f64; 2]| {
        let y = if difference { q[1] - q[0] } else { q[1] };
        (lo..=hi).contains(&q[0]) && (shown.min()[1]..=shown.max()[1]).contains(&y)
    };
    style::legend_row(ui, |ui| {
        if !d.pieces.is_empty() {
            let name = if difference { "f − θ" } else { "f" };
            style::legend_line(ui, style::ACCEL, false, name);
        }
        let [iterates, cycles] = map_markers(s.dark);
        if !d.kept.is_empty() {
            markers::legend(ui, &[iterates], ITERATES);
        }
        if d.traj.iter().any(|q| inside(&q)) {
            markers::legend(ui, &[cycles], TRANSIENT);
        }
        if !difference && d.web.len() > 1 {
            style::legend_stroke(ui, (style::DECEL, COBWEB_WIDTH), false, "cobweb");
        }
        style::legend_line(
            ui,
            style::CRITICAL,
            true,
            if difference { "0" } else { "θ' = θ" },
        );
        let (wlo, whi) = d.window;
        if let Some(tc) = d.theta_c.filter(|_| !difference)
            && [tc, -tc].iter().any(|v| *v > wlo && *v < whi)
        {
            style::legend_stroke(ui, (theta_c_colour(), 1.0), true, "±θc");
        }
        // The band and the density are drawn on the map only.
        if difference {
            return;
        }
        for (c, name) in d.band.drawn(lo, hi) {
            style::legend_stroke(ui, (c, BAND_WIDTH), false, &name);
        }
        if d.band.density_drawn(lo, hi) {
            let key = (density_colour(), DENSITY_WIDTH);
            style::legend_stroke(ui, key, false, "invariant density");
        }
    });
}

impl View for ReturnMapView {
    fn title(&self) -> &'static str {
        ViewKind::ReturnMap.title()
    }

    /// One row for the switches (f(θ) − θ, the powers, the cobweb's
    /// steps): a row less taken from the plot.
    fn controls_ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, _out: &mut Vec<Action>) {
        ui.horizontal_wrapped(|ui| {
            ui.checkbox(&mut s.map_difference, "f(θ) − θ")
                .on_hover_text(
                    "Draw f(θ) − θ against θ: the map's distance from the diagonal, \
                 too small to see where f hugs it (creep; the paper's Fig. 3a inset). \
                 A fixed point is where it crosses 0.",
                );
            powers_ui(ui, s, &jobs.iterate.data.powers);
            if !s.map_difference {
                let available = jobs.trajectory.data.events.len();
                cobweb_steps_ui(ui, &mut self.steps, available);
            }
        });
    }

    fn ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, _out: &mut Vec<Action>) {
        self.show(ui, s, jobs);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn graph_is_cut_at_failed_cycles_and_at_jumps() {
        let g = [
            [0.0, 0.0],
            [0.1, 0.1],
            [0.2, 0.2],
            [0.3, f64::NAN],
            [0.4, 0.4],
            [0.5, 0.5],
            [0.6, 2.0],
            [0.7, 2.1],
            [0.8, 9.0],
        ];
        let pieces = graph_pieces(&g, 0.5);
        let firsts: Vec<f64> = pieces.iter().map(|p| p[0][0]).collect();
        let lens: Vec<usize> = pieces.iter().map(Vec::len).collect();
        // The lone point after the last jump is not a line.
        assert_eq!(firsts, [0.0, 0.4, 0.6]);
        assert_eq!(lens, [3, 2, 2]);
    }
}
