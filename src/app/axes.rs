//! Axes fit for print, shared by every plot of the window (and by anything
//! else that draws a plot, such as a vector export): ticks at round values,
//! at least five per axis, labelled with units; angles in radians, degrees
//! or fractions of π.
//!
//! The tick computation is pure ([`ticks`], [`angle_ticks`],
//! [`log10_ticks`]); [`apply`] hands the same ticks to egui_plot as its
//! grid and labels, so what a picture shows and what a file writes agree.

use eframe::egui;
use egui_plot::{AxisHints, GridInput, GridMark, Plot};

pub use super::settings::AngleUnit;

mod ends;
mod ticks;

pub use ends::{END_REACH, reach_ends};
pub use ticks::*;

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

    /// This axis as a y axis `height` points tall can title it: the whole
    /// title, else its symbol and unit ("θ (rad)"), else its symbol; a
    /// rotated title longer than its plot runs over what is above it (a
    /// tile's check boxes at a projector's text size).
    pub fn fitted_along(mut self, ui: &egui::Ui, height: f32) -> AxisSpec {
        let name = short_name(&self.title);
        let with_unit = match self.title.rfind(" (") {
            Some(i) if self.title.ends_with(')') && i > name.len() => {
                format!("{name}{}", &self.title[i..])
            }
            _ => name.to_owned(),
        };
        let shorter = fitting_title(ui, &with_unit, name, height).to_owned();
        self.title = fitting_title(ui, &self.title, &shorter, height).to_owned();
        self
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
/// are exactly the ticks' whatever range egui hands the formatter; and
/// whether its first label stands on the frame's low corner (an x axis's,
/// where the y axis's lowest label would be drawn over it).
#[derive(Default)]
struct Drawn {
    ticks: Vec<Tick>,
    corner: bool,
}

type Shared = std::rc::Rc<std::cell::RefCell<Drawn>>;

/// egui_plot's margin between a y label and the frame, points.
const SIDE_MARGIN: f64 = 4.0;

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
    /// Whether the plots being drawn are a figure's ([`super::style::figure_only`]):
    /// a figure's y axis leaves the bottom-left corner to the x axis's
    /// label, the window's x axis leaves it to the y axis's.
    static FIGURE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
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
/// with the most labels shown. An x label counts as shown with a quarter
/// of a digit free beside it: egui draws labels that touch ("27002710…").
fn legible_ticks(
    scale: Scale,
    axis: egui_plot::Axis,
    (lo, hi): (f64, f64),
    points_per_value: f64,
) -> Vec<Tick> {
    let pad = match axis {
        egui_plot::Axis::X => {
            0.25 * LABEL_FONT.with(|c| c.get()).widths[..10]
                .iter()
                .copied()
                .fold(0.0, f64::max)
        }
        egui_plot::Axis::Y => 0.0,
    };
    let shown = |t: &[Tick]| {
        (0..t.len())
            .filter(|&i| gap(t, i, hi - lo) * points_per_value >= label_room(axis, &t[i]) + pad)
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
/// none between: a printed figure's grid), with a label within
/// [`END_REACH`] of each end ([`reach_ends`]). egui would draw an x and a
/// y label on the frame's bottom-left corner over each other: in a figure
/// the y axis leaves the corner to the x axis's first label (`other`'s)
/// when that stands there; in the window the x axis leaves it.
fn grid_marks(
    scale: Scale,
    axis: egui_plot::Axis,
    input: GridInput,
    (drawn, other): (&Shared, &Shared),
) -> Vec<GridMark> {
    let (lo, hi) = input.bounds;
    let points_per_value = GRID_MIN_POINTS / input.base_step_size;
    let t = legible_ticks(scale, axis, (lo, hi), points_per_value);
    let f = LABEL_FONT.with(|c| c.get());
    let digit = f.widths[..10].iter().copied().fold(0.0, f64::max);
    let figure = FIGURE.with(|c| c.get());
    let low_from = match axis {
        egui_plot::Axis::Y if figure && other.borrow().corner => 0.6 * f.row / points_per_value,
        _ => 0.0,
    };
    // egui draws a label only as far from its nearer neighbour as it is
    // wide (x) or tall (y).
    let apart = |a: &Tick, b: &Tick| match axis {
        egui_plot::Axis::Y => f.row / points_per_value,
        egui_plot::Axis::X => {
            (label_room(axis, a).max(label_room(axis, b)) + 0.25 * digit) / points_per_value
        }
    };
    let mut t = reach_ends(scale, (lo, hi), t, low_from, apart);
    // The window keeps five labels an axis: there the x axis gives up its
    // corner label where it has labels to spare, its grid line staying.
    if !figure
        && axis == egui_plot::Axis::X
        && t.len() > MIN_TICKS
        && (t[0].value - lo) * points_per_value < 0.5 * label_room(axis, &t[0])
    {
        t[0].label.clear();
    }
    let corner = axis == egui_plot::Axis::X
        && t.first().is_some_and(|first| {
            (first.value - lo) * points_per_value < 0.5 * label_room(axis, first) + SIDE_MARGIN
        });
    // The spacing egui fits each label into: the gap to its nearer
    // neighbour (on a log axis the gaps differ), so that a crowded label
    // is dropped alone rather than all of them.
    let marks = (0..t.len())
        .map(|i| GridMark {
            value: t[i].value,
            step_size: gap(&t, i, hi - lo),
        })
        .collect();
    *drawn.borrow_mut() = Drawn { ticks: t, corner };
    marks
}

/// The label of the tick at `mark`: the one the spacer computed there.
fn tick_label(mark: GridMark, drawn: &Shared) -> String {
    drawn
        .borrow()
        .ticks
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

/// An unlabelled axis on the right that only keeps room: the last x tick's
/// label is centred on the frame's right edge, and without this half of it
/// fell outside the plot and was clipped ("1.4", "0.7" for "1.45", "0.72").
fn right_margin<'a>() -> AxisHints<'a> {
    let f = LABEL_FONT.with(|c| c.get());
    let digit = f.widths[..10].iter().copied().fold(0.0, f64::max);
    AxisHints::new_y()
        .placement(egui_plot::HPlacement::Right)
        .min_thickness((3.0 * digit) as f32)
        .formatter(|_, _| String::new())
}

/// `plot` with these axes: titles, grid lines and labels at [`Scale::ticks`].
/// In a play's frames, under the bounds held over the play
/// ([`super::hold::plot`]).
pub fn apply<'a>(ctx: &egui::Context, plot: Plot<'a>, x: &AxisSpec, y: &AxisSpec) -> Plot<'a> {
    let plot = super::hold::plot(ctx, plot);
    let (sx, sy) = (x.scale, y.scale);
    let (dx, dy) = (Shared::default(), Shared::default());
    let (gx, gy) = (dx.clone(), dy.clone());
    let (ox, oy) = (dy.clone(), dx.clone());
    let (hx, hy) = (x.clone(), y.clone());
    plot.label_formatter(move |pos| hover_label(&hx, &hy, pos))
        .custom_x_axes(vec![hints(x, egui_plot::Axis::X, dx)])
        .custom_y_axes(vec![hints(y, egui_plot::Axis::Y, dy), right_margin()])
        .x_grid_spacer(move |i| grid_marks(sx, egui_plot::Axis::X, i, (&gx, &ox)))
        .y_grid_spacer(move |i| grid_marks(sy, egui_plot::Axis::Y, i, (&gy, &oy)))
}

/// `long` if a y axis's title fits along a plot `height` points tall (its
/// frame, without the x axis's labels and title below it), else `short`.
pub fn fitting_title<'t>(ui: &egui::Ui, long: &'t str, short: &'t str, height: f32) -> &'t str {
    let font = egui::TextStyle::Body.resolve(ui.style());
    let width = ui.fonts_mut(|f| {
        f.layout_no_wrap(long.to_owned(), font.clone(), egui::Color32::WHITE)
            .size()
            .x
    });
    let row = ui.text_style_height(&egui::TextStyle::Body);
    if width <= height - 3.0 * row {
        long
    } else {
        short
    }
}

/// `long` if an x axis's title fits under a plot in `width` points beside
/// its y axis (about six rows of text), else `short`.
pub fn fitting_width<'t>(ui: &egui::Ui, long: &'t str, short: &'t str, width: f32) -> &'t str {
    let font = egui::TextStyle::Body.resolve(ui.style());
    let text = ui.fonts_mut(|f| {
        f.layout_no_wrap(long.to_owned(), font.clone(), egui::Color32::WHITE)
            .size()
            .x
    });
    let row = ui.text_style_height(&egui::TextStyle::Body);
    if text <= width - 6.0 * row {
        long
    } else {
        short
    }
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
pub fn hover_value(scale: Scale, v: f64) -> String {
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

/// Records plot `name`'s `frame` when it is wholly on screen (`ui`'s clip
/// rectangle): a plot scrolled partly away is not one the window shows.
pub fn remember_shown(ui: &egui::Ui, name: &'static str, frame: egui::Rect) {
    if ui.clip_rect().contains_rect(frame.expand(-1.0)) {
        remember_frame(ui.ctx(), name, frame);
    }
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
    FIGURE.with(|c| c.set(super::style::figure_only(ctx)));
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
