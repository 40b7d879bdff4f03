//! Axes fit for print, shared by every plot of the window (and by anything
//! else that draws a plot, such as a vector export): ticks at round values,
//! at least five per axis, labelled with units; angles in radians, degrees
//! or fractions of π.
//!
//! The tick computation is pure ([`ticks`], [`angle_ticks`],
//! [`log10_ticks`]); [`apply`] hands the same ticks to egui_plot as its
//! grid and labels, so what a picture shows and what a file writes agree.

use std::f64::consts::PI;

use eframe::egui;
use egui_plot::{AxisHints, GridInput, GridMark, Plot};

pub use super::settings::AngleUnit;

/// The fewest labelled ticks an axis shows.
pub const MIN_TICKS: usize = 5;

/// One labelled tick: where it is (in the plot's coordinates) and what it
/// says.
#[derive(Clone, Debug, PartialEq)]
pub struct Tick {
    /// The position on the axis, in the data's own coordinates (radians
    /// for angles, log10 of the value on a log axis).
    pub value: f64,
    /// The text written at it.
    pub label: String,
}

/// The narrowest span an axis labels, relative to the size of its ends:
/// below it the ticks' round values are no longer distinct doubles.
pub const MIN_RELATIVE_SPAN: f64 = 1e-12;
/// The narrowest and widest spans an axis labels at all: outside them a
/// 1-2-5 step (10^e) under- or overflows.
pub const MIN_SPAN: f64 = 1e-200;
pub const MAX_SPAN: f64 = 1e200;

/// Whether [lo, hi] (either order) is a range the tick code can label:
/// finite ends, a span within [`MIN_SPAN`, `MAX_SPAN`] and at least
/// [`MIN_RELATIVE_SPAN`] of the ends' size. Every public entry checks it,
/// whoever calls (a saved zoom of width 5e-324 once froze the window in
/// the step search, which started from log10(0) = −∞).
pub fn labelable(lo: f64, hi: f64) -> bool {
    let (a, b) = (lo.min(hi), lo.max(hi));
    let span = b - a;
    a.is_finite()
        && b.is_finite()
        && span.is_finite()
        && (MIN_SPAN..=MAX_SPAN).contains(&span)
        && span >= MIN_RELATIVE_SPAN * a.abs().max(b.abs())
}

/// The 1-2-5 steps (m · 10^e, m ∈ {1, 2, 5}) in increasing order, as
/// (mantissa index, exponent).
fn step_value(i: i32) -> f64 {
    let e = i.div_euclid(3);
    let m = [1.0, 2.0, 5.0][i.rem_euclid(3) as usize];
    m * 10f64.powi(e)
}

/// How many multiples of `step` lie in [lo, hi] (with a little slack, so
/// that an end on a tick counts).
fn count(lo: f64, hi: f64, step: f64) -> usize {
    let eps = 1e-9;
    let first = (lo / step - eps).ceil();
    let last = (hi / step + eps).floor();
    if last < first {
        0
    } else {
        (last - first) as usize + 1
    }
}

/// The largest 1-2-5 step that puts at least `min_count` multiples of
/// itself in [lo, hi]; `None` for a range that is not [`labelable`].
pub fn nice_step(lo: f64, hi: f64, min_count: usize) -> Option<f64> {
    if !labelable(lo, hi) {
        return None;
    }
    let (lo, hi) = (lo.min(hi), lo.max(hi));
    let span = hi - lo;
    // More ticks than this are never legible; the bound also keeps the
    // searches below short.
    let n = min_count.clamp(2, 1000);
    let raw = span / (n - 1) as f64;
    // Index of the largest 1-2-5 value at or below `raw`.
    // Each search is bounded: the guard above keeps `raw` within about
    // 1e-203 … 1e200, a few steps from this start.
    let mut i = (raw.log10().floor() as i32) * 3;
    for _ in 0..8 {
        if step_value(i + 1) > raw {
            break;
        }
        i += 1;
    }
    for _ in 0..8 {
        if step_value(i) <= raw {
            break;
        }
        i -= 1;
    }
    // A step of span/(n−1) may lose one tick to the ends' rounding.
    for _ in 0..6 {
        if count(lo, hi, step_value(i)) >= n {
            break;
        }
        i -= 1;
    }
    for _ in 0..8 {
        if count(lo, hi, step_value(i + 1)) < n {
            break;
        }
        i += 1;
    }
    Some(step_value(i))
}

/// [lo, hi] widened to the multiples of the largest 1-2-5 step that then
/// holds at least `min_count` ticks, ends included: bounds for a plot
/// that frames its data itself, so that a short axis still gets five
/// labels at round values. Unchanged for a range that is not
/// [`labelable`].
pub fn nice_bounds(lo: f64, hi: f64, min_count: usize) -> (f64, f64) {
    if !labelable(lo, hi) {
        return (lo, hi);
    }
    let (a, b) = (lo.min(hi), lo.max(hi));
    let span = b - a;
    let n = min_count.clamp(2, 1000);
    let expanded = |s: f64| ((a / s + 1e-9).floor() * s, (b / s - 1e-9).ceil() * s);
    let ticks_in = |s: f64| {
        let (x, y) = expanded(s);
        ((y - x) / s).round() as usize + 1
    };
    let mut i = (span.log10().floor() as i32) * 3 + 2;
    for _ in 0..12 {
        if ticks_in(step_value(i)) >= n {
            break;
        }
        i -= 1;
    }
    expanded(step_value(i))
}

/// `v` written with as many decimals as `step` needs, in plain notation
/// unless the numbers are very large or very small; never "-0".
pub fn format_value(v: f64, step: f64) -> String {
    let step = step.abs();
    let v = if (v / step).abs() < 1e-6 { 0.0 } else { v };
    // The style is chosen by the step alone, so one axis never mixes them.
    if !(1e-4..1e5).contains(&step) {
        // Scientific, with the mantissa to the step's precision.
        if v == 0.0 {
            return "0".into();
        }
        let e = v.abs().log10().floor() as i32;
        let digits = (e - step.log10().floor() as i32).clamp(0, 6) as usize;
        let m = v / 10f64.powi(e);
        let m = format!("{m:.digits$}");
        return format!("{m}e{e}");
    }
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// At least `min_count` ticks over [lo, hi] at the multiples of the
/// largest 1-2-5 step that gives them, each labelled with as many decimals
/// as the step needs. Empty for an empty or non-finite range.
pub fn ticks(lo: f64, hi: f64, min_count: usize) -> Vec<Tick> {
    let Some(step) = nice_step(lo, hi, min_count) else {
        return Vec::new();
    };
    multiples(lo, hi, step)
        .map(|v| Tick {
            value: v,
            label: format_value(v, step),
        })
        .collect()
}

/// The multiples of `step` in [lo, hi].
fn multiples(lo: f64, hi: f64, step: f64) -> impl Iterator<Item = f64> {
    let (lo, hi) = (lo.min(hi), lo.max(hi));
    let first = (lo / step - 1e-9).ceil() as i64;
    let n = count(lo, hi, step) as i64;
    (first..first + n).map(move |k| k as f64 * step)
}

/// The fractions of π offered as steps, coarsest first.
const PI_DENOMINATORS: [u32; 9] = [1, 2, 3, 4, 6, 8, 12, 16, 24];

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// k·π/d written as a reduced fraction: "0", "π", "-π/2", "3π/4".
fn pi_fraction(k: i64, d: u32) -> String {
    if k == 0 {
        return "0".into();
    }
    let g = gcd(k.unsigned_abs(), d as u64) as i64;
    let (num, den) = (k / g, d as i64 / g);
    let sign = if num < 0 { "-" } else { "" };
    let num = num.abs();
    let top = if num == 1 {
        "π".to_string()
    } else {
        format!("{num}π")
    };
    if den == 1 {
        format!("{sign}{top}")
    } else {
        format!("{sign}{top}/{den}")
    }
}

/// At least `min_count` ticks over the angles [lo, hi] (radians), at round
/// values of `unit`: 1-2-5 steps of radians or of degrees, or fractions
/// π/d (d up to 24; narrower ranges fall back to 1-2-5 multiples of π,
/// "0.38π"). Each tick's `value` is in radians.
pub fn angle_ticks(lo: f64, hi: f64, min_count: usize, unit: AngleUnit) -> Vec<Tick> {
    match unit {
        AngleUnit::Radians => ticks(lo, hi, min_count),
        AngleUnit::Degrees => ticks(lo.to_degrees(), hi.to_degrees(), min_count)
            .into_iter()
            .map(|t| Tick {
                value: t.value.to_radians(),
                label: format!("{}°", t.label),
            })
            .collect(),
        AngleUnit::PiFractions => {
            let (a, b) = (lo.min(hi), lo.max(hi));
            if !labelable(a, b) {
                return Vec::new();
            }
            let n = min_count.max(2);
            if let Some(&d) = PI_DENOMINATORS
                .iter()
                .find(|&&d| count(a, b, PI / d as f64) >= n)
            {
                let step = PI / d as f64;
                let first = (a / step - 1e-9).ceil() as i64;
                return (first..first + count(a, b, step) as i64)
                    .map(|k| Tick {
                        value: k as f64 * step,
                        label: pi_fraction(k, d),
                    })
                    .collect();
            }
            ticks(a / PI, b / PI, min_count)
                .into_iter()
                .map(|t| Tick {
                    value: t.value * PI,
                    label: if t.label == "0" {
                        t.label
                    } else {
                        format!("{}π", t.label)
                    },
                })
                .collect()
        }
    }
}

/// Ticks on a log axis whose coordinate is log10 of the value: the
/// decades, then 1-3 and then 1-2-5 mantissas when the decades alone are
/// fewer than `min_count`, labelled with the value ("1e-6", "3e-6");
/// less than about a decade wide, 1-2-5 steps of the value itself.
pub fn log10_ticks(lo: f64, hi: f64, min_count: usize) -> Vec<Tick> {
    let (a, b) = (lo.min(hi), lo.max(hi));
    if !labelable(a, b) || b - a > 600.0 {
        return Vec::new();
    }
    let n = min_count.max(2);
    let mantissas: [&[u32]; 3] = [&[1], &[1, 3], &[1, 2, 5]];
    let eps = 1e-9;
    // Over many decades, every k-th one: the largest 1-2-5 stride that
    // still gives n, as on a linear axis.
    let decades = (b.floor() - a.ceil()) as usize + 1;
    let stride = [1, 2, 5, 10, 20, 50, 100]
        .into_iter()
        .rev()
        .find(|k| decades / k >= n)
        .unwrap_or(1) as i32;
    let mut best = Vec::new();
    for ms in mantissas {
        best.clear();
        let stride = if ms.len() == 1 { stride } else { 1 };
        for e in (a.floor() as i32)..=(b.ceil() as i32) {
            if e.rem_euclid(stride) != 0 {
                continue;
            }
            for &m in ms {
                let v = e as f64 + (m as f64).log10();
                if v >= a - eps && v <= b + eps {
                    best.push(Tick {
                        value: v,
                        // Counts and other values from 1 to 50,000 as
                        // plain integers ("2", not "2e0").
                        label: if (0..=4).contains(&e) {
                            (u64::from(m) * 10u64.pow(e as u32)).to_string()
                        } else if m == 1 {
                            format!("1e{e}")
                        } else {
                            format!("{m}e{e}")
                        },
                    });
                }
            }
        }
        if best.len() >= n {
            return best;
        }
    }
    // Less than about a decade wide: round values, placed at their log10.
    let (va, vb) = (10f64.powf(a), 10f64.powf(b));
    let Some(step) = nice_step(va, vb, n) else {
        return Vec::new();
    };
    multiples(va, vb, step)
        .filter(|v| *v > 0.0)
        .map(|v| Tick {
            value: v.log10(),
            label: format_value(v, step),
        })
        .collect()
}

/// How an axis is scaled and labelled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scale {
    /// Plain numbers at 1-2-5 steps.
    Linear,
    /// An angle in radians, labelled in the given unit.
    Angle(AngleUnit),
    /// The coordinate is log10 of the value.
    Log10,
}

impl Scale {
    /// The ticks of this scale over [lo, hi].
    pub fn ticks(self, lo: f64, hi: f64, min_count: usize) -> Vec<Tick> {
        match self {
            Scale::Linear => ticks(lo, hi, min_count),
            Scale::Angle(u) => angle_ticks(lo, hi, min_count, u),
            Scale::Log10 => log10_ticks(lo, hi, min_count),
        }
    }
}

/// An angle axis' title: the quantity and its symbol, then the unit.
pub fn angle_title(quantity: &str, unit: AngleUnit) -> String {
    let u = match unit {
        AngleUnit::Radians => "rad",
        AngleUnit::Degrees => "°",
        AngleUnit::PiFractions => "rad",
    };
    format!("{quantity} ({u})")
}

/// One axis of a plot: its title (quantity, symbol and unit) and scale.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisSpec {
    /// "θν, pull direction (rad)".
    pub title: String,
    pub scale: Scale,
}

impl AxisSpec {
    /// A linear axis titled `title`.
    pub fn linear(title: impl Into<String>) -> AxisSpec {
        AxisSpec {
            title: title.into(),
            scale: Scale::Linear,
        }
    }

    /// An angle axis: `quantity` ("θν, pull direction") with its unit.
    pub fn angle(quantity: &str, unit: AngleUnit) -> AxisSpec {
        AxisSpec {
            title: angle_title(quantity, unit),
            scale: Scale::Angle(unit),
        }
    }

    /// A log axis (the coordinate is log10 of the value).
    pub fn log10(title: impl Into<String>) -> AxisSpec {
        AxisSpec {
            title: title.into(),
            scale: Scale::Log10,
        }
    }
}

/// The ticks an axis drew last, shared by its grid spacer (which computes
/// them) and its label formatter (which writes them), so that the labels
/// are exactly the ticks' whatever range egui hands the formatter.
type Shared = std::rc::Rc<std::cell::RefCell<Vec<Tick>>>;

/// egui_plot's smallest grid spacing in points (its default, which
/// [`apply`] keeps): its `GridInput::base_step_size` is this many points
/// in the axis's values.
const GRID_MIN_POINTS: f64 = 8.0;

/// The characters tick labels are made of, whose widths [`clear_frames`]
/// measures.
const LABEL_CHARS: &str = "0123456789.-e°π/";

/// The tick labels' font, as [`clear_frames`] measured it for the frame
/// being drawn.
#[derive(Clone, Copy)]
struct LabelFont {
    /// Row height, points.
    row: f64,
    /// Width of each of [`LABEL_CHARS`], points.
    widths: [f64; 16],
    /// Width of any other character (the widest digit's, doubled).
    other: f64,
}

thread_local! {
    static LABEL_FONT: std::cell::Cell<LabelFont> = const {
        std::cell::Cell::new(LabelFont { row: 14.5, widths: [7.0; 16], other: 14.0 })
    };
}

/// The room a tick's label needs along its axis, in points: its row height
/// on a y axis, its width on an x axis.
fn label_room(axis: egui_plot::Axis, t: &Tick) -> f64 {
    let f = LABEL_FONT.with(|c| c.get());
    match axis {
        egui_plot::Axis::Y => f.row,
        egui_plot::Axis::X => t
            .label
            .chars()
            .map(|c| {
                LABEL_CHARS
                    .chars()
                    .position(|l| l == c)
                    .map_or(f.other, |i| f.widths[i])
            })
            .sum(),
    }
}

/// The ticks of [lo, hi] as [`Scale::ticks`] gives them (at least
/// [`MIN_TICKS`]), unless the axis is too short (`points_per_value` of it)
/// for their labels: egui drops every label closer to its nearer
/// neighbour than its size, so a plot squeezed small would show grid lines
/// and no number at all. Then, unless [`MIN_TICKS`] of their labels show
/// anyway (egui drops a crowded one alone), the first of the tick sets
/// for 4, 3 and 2 ticks at least whose labels all show, or else the set
/// with the most labels shown.
fn legible_ticks(
    scale: Scale,
    axis: egui_plot::Axis,
    (lo, hi): (f64, f64),
    points_per_value: f64,
) -> Vec<Tick> {
    let shown = |t: &[Tick]| {
        (0..t.len())
            .filter(|&i| gap(t, i, hi - lo) * points_per_value >= label_room(axis, &t[i]))
            .count()
    };
    let mut best = scale.ticks(lo, hi, MIN_TICKS);
    let mut most = shown(&best);
    for n in (2..MIN_TICKS).rev() {
        if most == best.len() || most >= MIN_TICKS {
            break;
        }
        let t = scale.ticks(lo, hi, n);
        let k = shown(&t);
        if k == t.len() || k > most {
            (best, most) = (t, k);
        }
    }
    best
}

/// The distance from tick `i` to its nearer neighbour (`span` alone).
fn gap(t: &[Tick], i: usize, span: f64) -> f64 {
    let prev = i.checked_sub(1).map(|j| t[i].value - t[j].value);
    let next = t.get(i + 1).map(|n| n.value - t[i].value);
    match (prev, next) {
        (Some(p), Some(n)) => p.min(n),
        (Some(g), None) | (None, Some(g)) => g,
        (None, None) => span,
    }
}

/// The ticks as egui_plot grid marks (a grid line at each labelled tick,
/// none between: a printed figure's grid).
fn grid_marks(
    scale: Scale,
    axis: egui_plot::Axis,
    input: GridInput,
    drawn: &Shared,
) -> Vec<GridMark> {
    let (lo, hi) = input.bounds;
    let points_per_value = GRID_MIN_POINTS / input.base_step_size;
    let t = legible_ticks(scale, axis, (lo, hi), points_per_value);
    // The spacing egui fits each label into: the gap to its nearer
    // neighbour (on a log axis the gaps differ), so that a crowded label
    // is dropped alone rather than all of them.
    let marks = (0..t.len())
        .map(|i| GridMark {
            value: t[i].value,
            step_size: gap(&t, i, hi - lo),
        })
        .collect();
    *drawn.borrow_mut() = t;
    marks
}

/// The label of the tick at `mark`: the one the spacer computed there.
fn tick_label(mark: GridMark, drawn: &Shared) -> String {
    drawn
        .borrow()
        .iter()
        .find(|t| t.value == mark.value)
        .map(|t| t.label.clone())
        .unwrap_or_default()
}

fn hints<'a>(spec: &AxisSpec, axis: egui_plot::Axis, drawn: Shared) -> AxisHints<'a> {
    let h = match axis {
        egui_plot::Axis::X => AxisHints::new_x(),
        egui_plot::Axis::Y => AxisHints::new_y(),
    };
    // Every tick is labelled whatever its spacing (egui only drops a label
    // that would overlap its neighbour).
    h.label(spec.title.clone())
        .label_spacing(0.5..=1.0)
        .formatter(move |m, _| tick_label(m, &drawn))
}

/// `plot` with these axes: titles, grid lines and labels at [`Scale::ticks`].
pub fn apply<'a>(plot: Plot<'a>, x: &AxisSpec, y: &AxisSpec) -> Plot<'a> {
    let (sx, sy) = (x.scale, y.scale);
    let (dx, dy) = (Shared::default(), Shared::default());
    let (gx, gy) = (dx.clone(), dy.clone());
    let (hx, hy) = (x.clone(), y.clone());
    plot.label_formatter(move |pos| hover_label(&hx, &hy, pos))
        .custom_x_axes(vec![hints(x, egui_plot::Axis::X, dx)])
        .custom_y_axes(vec![hints(y, egui_plot::Axis::Y, dy)])
        .x_grid_spacer(move |i| grid_marks(sx, egui_plot::Axis::X, i, &gx))
        .y_grid_spacer(move |i| grid_marks(sy, egui_plot::Axis::Y, i, &gy))
}

/// An axis's quantity in short: its title up to the first ", " or " ("
/// ("θν" of "θν, pull direction (rad)").
pub fn short_name(title: &str) -> &str {
    let end = [title.find(", "), title.find(" (")]
        .into_iter()
        .flatten()
        .min()
        .unwrap_or(title.len());
    &title[..end]
}

/// A coordinate as its axis reads it: a log axis's value, not its log10.
fn hover_value(scale: Scale, v: f64) -> String {
    match scale {
        Scale::Log10 => format!("{:.3e}", 10f64.powf(v)),
        _ => format!("{v:.4}"),
    }
}

/// The hover label of a plot: the item's name, then each axis's quantity
/// and value ("θν = 1.0950, θ = 0.2580"), not egui_plot's "x = …, y = …".
pub fn hover_label(
    x: &AxisSpec,
    y: &AxisSpec,
    pos: &egui_plot::HoverPosition<'_>,
) -> Option<String> {
    let (name, p) = match pos {
        egui_plot::HoverPosition::NearDataPoint {
            plot_name,
            position,
            ..
        } => (*plot_name, position),
        egui_plot::HoverPosition::Elsewhere { position } => ("", position),
    };
    let xy = format!(
        "{} = {}\n{} = {}",
        short_name(&x.title),
        hover_value(x.scale, p.x),
        short_name(&y.title),
        hover_value(y.scale, p.y)
    );
    Some(if name.is_empty() {
        xy
    } else {
        format!("{name}\n{xy}")
    })
}

/// Where each plot's frame was drawn last frame, by plot name: for tests
/// and for anything that crops a picture to one plot.
#[derive(Clone, Debug, Default)]
pub struct PlotFrames(pub Vec<(&'static str, egui::Rect)>);

fn frames_id() -> egui::Id {
    egui::Id::unique("oneblock-plot-frames")
}

/// Records that plot `name` was drawn in `frame` this frame.
pub fn remember_frame(ctx: &egui::Context, name: &'static str, frame: egui::Rect) {
    ctx.data_mut(|d| {
        let f = d.get_temp_mut_or_default::<PlotFrames>(frames_id());
        f.0.retain(|(n, _)| *n != name);
        f.0.push((name, frame));
    });
}

/// Starts a frame's plots: forgets the recorded frames (so that a plot no
/// longer shown is not listed), and takes the tick labels' text size from
/// the context's style.
pub fn clear_frames(ctx: &egui::Context) {
    ctx.data_mut(|d| d.remove::<PlotFrames>(frames_id()));
    let font = egui::TextStyle::Body.resolve(&ctx.global_style());
    let measured = ctx.fonts_mut(|f| {
        let mut widths = [0.0; 16];
        for (w, ch) in widths.iter_mut().zip(LABEL_CHARS.chars()) {
            *w = f64::from(f.glyph_width(&font, ch));
        }
        let widest = widths[..10].iter().copied().fold(0.0, f64::max);
        LabelFont {
            row: f64::from(f.row_height(&font)),
            widths,
            other: 2.0 * widest,
        }
    });
    LABEL_FONT.with(|c| c.set(measured));
}

/// The plots drawn since the last [`clear_frames`], with their frames.
pub fn plot_frames(ctx: &egui::Context) -> Vec<(&'static str, egui::Rect)> {
    ctx.data(|d| {
        d.get_temp::<PlotFrames>(frames_id())
            .map(|f| f.0)
            .unwrap_or_default()
    })
}

#[cfg(test)]
mod tests;
