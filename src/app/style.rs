//! Colours chosen to read on a projector and to stay apart for the common
//! colour-vision deficiencies (blue / vermilion / orange, after Okabe–Ito).

use eframe::egui;
use egui::{Color32, Ui};
use egui_plot::MarkerShape;

pub const STICK: Color32 = Color32::from_rgb(0, 114, 178);
pub const ACCEL: Color32 = Color32::from_rgb(213, 94, 0);
pub const DECEL: Color32 = Color32::from_rgb(230, 159, 0);
pub const ONSET: Color32 = Color32::from_rgb(204, 0, 102);
pub const PULL: Color32 = Color32::from_rgb(0, 158, 115);
pub const CRITICAL: Color32 = Color32::from_rgb(120, 120, 120);
pub const CURRENT: Color32 = Color32::from_rgb(0, 158, 115);
pub const ERROR: Color32 = Color32::from_rgb(220, 30, 30);
/// f², f³, f⁴ on the return map (Okabe–Ito reddish purple, bluish green,
/// sky blue: apart from f's vermilion and from each other).
pub const POWERS: [Color32; 3] = [
    Color32::from_rgb(204, 121, 167),
    Color32::from_rgb(0, 158, 115),
    Color32::from_rgb(86, 180, 233),
];

fn figure_only_id() -> egui::Id {
    egui::Id::unique("oneblock-figure-only")
}

/// Draws only the figure in `ctx` from now on (title, axes, legend): no
/// buttons, sliders or switches. What a picture for a document is made of
/// (`oneblock figure`, the views' SVG and PNG buttons).
pub fn set_figure_only(ctx: &egui::Context, on: bool) {
    ctx.data_mut(|d| d.insert_temp(figure_only_id(), on));
}

fn folded_id() -> egui::Id {
    egui::Id::unique("oneblock-controls-folded")
}

/// Folds the views' controls away in `ctx` from now on (the tour's tiles:
/// the step sets what they would, and its plots need the room at a
/// projector's size), keeping their legends and the window's work.
pub fn set_controls_folded(ctx: &egui::Context, on: bool) {
    ctx.data_mut(|d| d.insert_temp(folded_id(), on));
}

/// Whether the views draw their controls in `ctx`: not in a figure
/// ([`set_figure_only`]), nor while folded ([`set_controls_folded`]).
pub fn controls_shown(ctx: &egui::Context) -> bool {
    !figure_only(ctx) && !controls_folded(ctx)
}

/// Whether the views' controls are folded in `ctx` (the tour's tiles).
pub fn controls_folded(ctx: &egui::Context) -> bool {
    ctx.data(|d| d.get_temp::<bool>(folded_id()).unwrap_or(false))
}

fn crosshair_id() -> egui::Id {
    egui::Id::unique("oneblock-figure-crosshair")
}

/// Whether a figure drawn in `ctx` marks the current parameters (the
/// current θν line, and κ on the phase diagram): only when asked for
/// (`oneblock figure --crosshair`); the window always marks them.
pub fn set_crosshair(ctx: &egui::Context, on: bool) {
    ctx.data_mut(|d| d.insert_temp(crosshair_id(), on));
}

/// Whether the views draw the current parameters' lines in `ctx`: always
/// in the window, in a figure only when asked for ([`set_crosshair`]).
pub fn draws_current(ctx: &egui::Context) -> bool {
    !figure_only(ctx) || ctx.data(|d| d.get_temp::<bool>(crosshair_id()).unwrap_or(false))
}

/// Whether `ctx` draws only the figure (see [`set_figure_only`]): the views
/// leave out their controls then.
pub fn figure_only(ctx: &egui::Context) -> bool {
    ctx.data(|d| d.get_temp::<bool>(figure_only_id()))
        .unwrap_or(false)
}

fn line_scale_id() -> egui::Id {
    egui::Id::unique("oneblock-line-scale")
}

/// Sets how much thicker than usual every plot line is drawn (the
/// projector preset's thick lines).
pub fn set_line_scale(ctx: &egui::Context, scale: f32) {
    ctx.data_mut(|d| d.insert_temp(line_scale_id(), scale));
}

/// A line width: `base` points times the window's line scale.
pub fn width(ctx: &egui::Context, base: f32) -> f32 {
    base * ctx
        .data(|d| d.get_temp::<f32>(line_scale_id()))
        .unwrap_or(1.0)
}

/// The colour of the main curves: dark on light, light on dark.
pub fn ink(dark: bool) -> Color32 {
    if dark {
        Color32::from_gray(230)
    } else {
        Color32::from_gray(20)
    }
}

/// One legend entry: its key drawn by `key` in a `size` rectangle, then
/// its label. In a wrapping row the entry starts a new row when key and
/// label do not both fit in what is left of this one, so that a legend
/// never leaves a key at the end of one row and its label on the next.
/// The key's shapes are `key`'s for the rectangle and the key scale.
pub fn legend_entry(
    ui: &mut Ui,
    size: egui::Vec2,
    label: &str,
    key: impl FnOnce(egui::Rect, f32) -> Vec<egui::Shape>,
) {
    if !legend_shown(ui.ctx()) {
        return;
    }
    let k = key_scale(ui.ctx());
    super::hold::entry(ui, size * k, label, |rect| key(rect, k));
}

/// In a wrapping row, starts a new row unless a legend key `key_width`
/// wide and its `label` both fit in what is left of this one.
pub fn keep_key_with_label(ui: &mut Ui, key_width: f32, label: &str) {
    if ui.layout().main_wrap {
        let font = egui::TextStyle::Body.resolve(ui.style());
        let text = ui.fonts_mut(|f| {
            f.layout_no_wrap(label.to_owned(), font, Color32::WHITE)
                .size()
                .x
        });
        let need = key_width + ui.spacing().item_spacing.x + text;
        let left = ui.available_size_before_wrap().x;
        let at_start = left >= ui.max_rect().width() - 0.5;
        if need > left && !at_start {
            ui.end_row();
        }
    }
}

/// Where a figure's legends go: above the plot they describe (the
/// window's, and a figure's by default), inside it in a corner (`figure
/// --legend inside[-CORNER]`, see [`super::legend`]), or nowhere
/// (`figure --legend none`: a caption says it).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LegendPlace {
    #[default]
    Outside,
    Inside(super::legend::Corner),
    Hidden,
}

fn legend_place_id() -> egui::Id {
    egui::Id::unique("oneblock-legend-place")
}

/// Puts the views' legends in `ctx` at `place` from now on.
pub fn set_legend_place(ctx: &egui::Context, place: LegendPlace) {
    ctx.data_mut(|d| d.insert_temp(legend_place_id(), place));
}

/// Where the views put their legends in `ctx` ([`set_legend_place`]).
pub fn legend_place(ctx: &egui::Context) -> LegendPlace {
    ctx.data(|d| d.get_temp::<LegendPlace>(legend_place_id()))
        .unwrap_or_default()
}

/// Whether the views draw their legends in `ctx` ([`set_legend_place`]).
pub fn legend_shown(ctx: &egui::Context) -> bool {
    legend_place(ctx) != LegendPlace::Hidden
}

/// Whether the legends go inside their plots in `ctx` (they take no room
/// of the view's then).
pub fn legend_inside(ctx: &egui::Context) -> bool {
    matches!(legend_place(ctx), LegendPlace::Inside(_))
}

/// A row of legend entries (wrapping) above the plot, or a box of them
/// inside it ([`super::legend::inside`]), unless the legends are hidden.
pub fn legend_row<R>(ui: &mut Ui, add: impl FnOnce(&mut Ui) -> R) -> Option<R> {
    match legend_place(ui.ctx()) {
        LegendPlace::Hidden => None,
        LegendPlace::Outside => Some(super::legend::outside(ui, add)),
        LegendPlace::Inside(_) => Some(super::legend::inside(ui, add)),
    }
}

/// How much smaller than the window's a legend's keys are drawn: a
/// figure's line scale (below 1 for small text or a column's size, see
/// `svg_render`), 1 in the window.
pub fn key_scale(ctx: &egui::Context) -> f32 {
    if figure_only(ctx) {
        width(ctx, 1.0).min(1.0)
    } else {
        1.0
    }
}

/// What a figure left out or changed, to be said on stderr by `oneblock
/// figure` (each once).
static FIGURE_NOTES: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());

/// Notes `what` for the figure being drawn in `ctx` (nothing in the
/// window).
pub fn figure_note(ctx: &egui::Context, what: &str) {
    if !figure_only(ctx) {
        return;
    }
    if let Ok(mut n) = FIGURE_NOTES.lock()
        && !n.iter().any(|x| x == what)
    {
        n.push(what.to_owned());
    }
}

/// The notes of the figures drawn since the last call.
pub fn take_figure_notes() -> Vec<String> {
    FIGURE_NOTES
        .lock()
        .map(|mut n| std::mem::take(&mut *n))
        .unwrap_or_default()
}

/// The body text's size relative to egui's default (the window's text
/// size, or a figure's `--font-size`): the factor for text a view sizes
/// itself, such as the block's labels.
pub fn text_scale(ui: &Ui) -> f32 {
    let body = |s: &egui::Style| {
        s.text_styles
            .get(&egui::TextStyle::Body)
            .map_or(13.0, |f| f.size)
    };
    body(ui.style()) / body(&egui::Style::default())
}

/// A small coloured square and its label.
pub fn legend_swatch(ui: &mut Ui, color: Color32, label: &str) {
    legend_entry(ui, egui::vec2(14.0, 14.0), label, |rect, k| {
        vec![egui::Shape::rect_filled(rect, 2.0 * k, color)]
    });
}

/// A short line (dashed if asked) and its label.
pub fn legend_line(ui: &mut Ui, color: Color32, dashed: bool, label: &str) {
    legend_stroke(ui, (color, 2.0), dashed, label);
}

/// A short line `width` (times the key scale) wide, dashed if asked, and
/// its label: the key of a plot line drawn `width` times the line scale
/// wide ([`width`]), such as the return map's basin band.
pub fn legend_stroke(ui: &mut Ui, (color, width): (Color32, f32), dashed: bool, label: &str) {
    legend_entry(ui, egui::vec2(22.0, 14.0), label, |rect, k| {
        line_key(rect, k, egui::Stroke::new(width * k, color), dashed)
    });
}

/// A dotted line, as egui_plot draws `LineStyle::Dotted { spacing: 6 }`
/// of the default width (dots of radius 1.5, 6 points apart), and its label.
pub fn legend_dotted(ui: &mut Ui, color: Color32, label: &str) {
    legend_entry(ui, egui::vec2(22.0, 14.0), label, |rect, k| {
        let y = rect.center().y;
        (0..4)
            .map(|i| {
                let x = rect.left() + (2.0 + i as f32 * 6.0) * k;
                egui::Shape::circle_filled(egui::pos2(x, y), 1.5 * k, color)
            })
            .collect()
    });
}

/// A legend's short line across `rect` in `stroke`, dashed if asked
/// (dashes of 5, 8 apart, times the key scale `k`).
fn line_key(rect: egui::Rect, k: f32, stroke: egui::Stroke, dashed: bool) -> Vec<egui::Shape> {
    let y = rect.center().y;
    if dashed {
        (0..3)
            .map(|i| {
                let x = rect.left() + i as f32 * 8.0 * k;
                egui::Shape::line_segment([egui::pos2(x, y), egui::pos2(x + 5.0 * k, y)], stroke)
            })
            .collect()
    } else {
        vec![egui::Shape::line_segment(
            [egui::pos2(rect.left(), y), egui::pos2(rect.right(), y)],
            stroke,
        )]
    }
}

/// A plot line drawn as a polyline. egui_plot's default "band" shortcut
/// (for lines with many points per pixel column) loses sparse segments such
/// as a stick phase's two ends, so it is turned off.
pub fn line<'a>(name: &str, points: egui_plot::PlotPoints<'a>) -> egui_plot::Line<'a> {
    egui_plot::Line::new(name, points).allow_band(false)
}

/// The box being dragged out to zoom a plot, from `a` to the pointer `b`:
/// shared by the views that zoom by box (bifurcation, phase diagram).
pub fn zoom_box(a: egui_plot::PlotPoint, b: egui_plot::PlotPoint) -> egui_plot::Polygon<'static> {
    egui_plot::Polygon::new(
        "zoom box",
        egui_plot::PlotPoints::from(vec![[a.x, a.y], [b.x, a.y], [b.x, b.y], [a.x, b.y]]),
    )
    .fill_color(CURRENT.gamma_multiply(0.15))
    .stroke(egui::Stroke::new(1.5, CURRENT))
}

/// The x and y ranges (low, high) of the box with corners `a` and `b`.
pub fn box_ranges(a: egui_plot::PlotPoint, b: egui_plot::PlotPoint) -> ((f64, f64), (f64, f64)) {
    ((a.x.min(b.x), a.x.max(b.x)), (a.y.min(b.y), a.y.max(b.y)))
}

/// The colour of a path segment in a phase of the cycle.
pub fn phase_color(p: crate::sim::Phase) -> Color32 {
    match p {
        crate::sim::Phase::Stick => STICK,
        crate::sim::Phase::Accel => ACCEL,
        crate::sim::Phase::Decel => DECEL,
    }
}

/// The colour of a method's curve (Okabe–Ito, one hue each: no two blues);
/// the peer's are dashed.
pub fn method_color(method: &str) -> Color32 {
    match method {
        "euler" => Color32::from_rgb(204, 121, 167),
        "rk4" => Color32::from_rgb(230, 159, 0),
        "dp54" => Color32::from_rgb(86, 180, 233),
        "dop853" => Color32::from_rgb(0, 158, 115),
        "ode_solvers-dopri5" => Color32::from_rgb(120, 120, 120),
        "ode_solvers-dop853" => Color32::from_rgb(213, 94, 0),
        _ => Color32::GRAY,
    }
}

/// The marker of a method's points: a shape each, so that the curves part
/// in grey print and for any colour vision.
pub fn method_marker(method: &str) -> MarkerShape {
    match method {
        "euler" => MarkerShape::Cross,
        "rk4" => MarkerShape::Square,
        "dp54" => MarkerShape::Diamond,
        "dop853" => MarkerShape::Circle,
        "ode_solvers-dopri5" => MarkerShape::Down,
        "ode_solvers-dop853" => MarkerShape::Up,
        _ => MarkerShape::Plus,
    }
}

/// Below this width (points) the window is a phone's: one view, the panel
/// a drawer, a view chooser instead of tabs.
pub const NARROW: f32 = 640.0;

/// Whether the window is a phone's (narrower than [`NARROW`]).
pub fn is_narrow(ctx: &egui::Context) -> bool {
    ctx.content_rect().width() < NARROW
}

/// egui's fonts with DejaVu Sans (the figures' font, committed under
/// assets/fonts) behind them, for the glyphs they lack: the arrow of a
/// track's name ("P2 → P1") drew as a box.
pub fn install_fonts(ctx: &egui::Context) {
    let mut fonts = egui::FontDefinitions::default();
    let name = "DejaVu Sans".to_string();
    fonts.font_data.insert(
        name.clone(),
        std::sync::Arc::new(egui::FontData::from_static(crate::figure::FONT)),
    );
    for family in [egui::FontFamily::Proportional, egui::FontFamily::Monospace] {
        fonts.families.entry(family).or_default().push(name.clone());
    }
    ctx.set_fonts(fonts);
}
