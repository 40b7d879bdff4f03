//! The views drawn once more, off screen, for a vector picture: a fresh
//! egui context with the window's theme and text size runs a few passes of
//! the same view code over the same settings and results, and the last
//! pass's shapes go to [`super::svg::SvgWriter`]. Nothing integrates here:
//! the views only draw what the jobs already hold.

use eframe::egui;
use egui::{Color32, Rect, RichText, Vec2};

use super::axes;
use super::bifurcation::Zoom;
use super::jobs::Jobs;
use super::legend;
use super::settings::{Layout, Settings, ViewKind};
use super::style;
use super::svg::{SvgWriter, Textures};
use super::views::{Views, tile_rects};

/// Passes before the shapes are taken: plots settle their bounds and
/// labels over the first ones.
const PASSES: usize = 4;

/// How a picture looks: the window's, or a page's (`oneblock figure`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Look {
    /// The window's look: its theme's background, each view in a rounded
    /// frame under its name. Otherwise a journal's: the light theme on
    /// white, no frame, and no title but [`Look::title`].
    pub window: bool,
    /// A title over the figure (a page's look; the window's names its view).
    pub title: Option<String>,
    /// Every text's size in points, else the window's sizes.
    pub font_size: Option<f32>,
    /// Where the legends go (above their plots, or none).
    pub legend: style::LegendPlace,
    /// The text's font family (a name, or serif, sans-serif, monospace),
    /// else the sans-serif faces of [`super::svg_text::FONT_FAMILY`].
    pub font: Option<String>,
}

impl Look {
    /// The window's own look.
    pub fn window() -> Look {
        Look {
            window: true,
            ..Look::default()
        }
    }
}

/// The SVG of `views` (one view, or the tiles in the window's tile layout)
/// drawn over `size` points from `settings` and `jobs`, the bifurcation
/// diagram at `zoom` (its zoom stack), with the window's look; the current
/// parameters' lines only with `crosshair` ([`style::set_crosshair`]).
pub fn render_svg(
    views: &[ViewKind],
    settings: &Settings,
    jobs: &Jobs,
    zoom: &[Zoom],
    size: Vec2,
    crosshair: bool,
) -> String {
    let look = Look::window();
    render_svg_as(views, settings, jobs, (zoom, size), crosshair, &look)
}

/// [`render_svg`] with the look `look`, over `size` points at `zoom`.
pub fn render_svg_as(
    views: &[ViewKind],
    settings: &Settings,
    jobs: &Jobs,
    (zoom, size): (&[Zoom], Vec2),
    crosshair: bool,
    look: &Look,
) -> String {
    let mut r = Renderer::new(settings, zoom, size, look);
    style::set_crosshair(&r.ctx, crosshair);
    // Inside legends take two passes more: one to widen a legend too tall
    // for its plot, one to settle the layout after one went above its
    // plot instead.
    let passes = match look.legend {
        style::LegendPlace::Inside(_) => PASSES + 2,
        _ => PASSES,
    };
    for pass in 0..passes {
        r.pass(views, jobs, pass as f64 * 0.1);
    }
    r.svg()
}

/// An animation of one view drawn frame after frame by one off-screen
/// context, `dt` seconds of ui time apart (the block view's clock runs on
/// it): the caller sets what each frame shows (the plane's path up to its
/// time) in the jobs before asking for it.
pub struct FrameRenderer {
    r: Renderer,
    view: ViewKind,
    dt: f64,
    frames: usize,
}

impl FrameRenderer {
    /// A renderer whose first frame shows `jobs` as they are now, after
    /// the passes that settle the layout, all at ui time 0 (so the block's
    /// clock has not moved when the first frame is drawn).
    pub fn new(
        view: ViewKind,
        settings: &Settings,
        jobs: &Jobs,
        (size, look): (Vec2, &Look),
        dt: f64,
    ) -> Self {
        Self::new_with(view, settings, jobs, (size, look), dt, (|_| {}, None))
    }

    /// [`FrameRenderer::new`] with the views' state set by `prepare`
    /// before the passes that settle the layout (a played return map's
    /// held axes: its first frame is then drawn in them), and the legends
    /// and plot bounds gathered or held over a play (`hold`).
    pub fn new_with(
        view: ViewKind,
        settings: &Settings,
        jobs: &Jobs,
        (size, look): (Vec2, &Look),
        dt: f64,
        (prepare, hold): (impl FnOnce(&mut Views), Option<super::hold::Start>),
    ) -> Self {
        let mut r = Renderer::new(settings, &[], size, look);
        prepare(&mut r.state);
        match hold {
            Some(super::hold::Start::Collect) => super::hold::collect(&r.ctx),
            Some(super::hold::Start::Hold(held)) => super::hold::hold(&r.ctx, held),
            None => {}
        }
        for _ in 0..PASSES - 1 {
            r.pass(&[view], jobs, 0.0);
        }
        FrameRenderer {
            r,
            view,
            dt,
            frames: 0,
        }
    }

    /// The next frames are drawn from `settings` (θν played: the cursor
    /// and the labels of each frame's parameters), with the current
    /// parameters' lines if `crosshair`.
    pub fn set_settings(&mut self, settings: &Settings, crosshair: bool) {
        self.r.settings = settings.clone();
        style::set_crosshair(&self.r.ctx, crosshair);
    }

    /// The next frame's SVG, of `jobs` as they are now: frame k at ui
    /// time k·dt.
    pub fn next_frame(&mut self, jobs: &Jobs) -> String {
        self.observe(jobs);
        self.r.svg()
    }

    /// The next frame drawn, not written: what a renderer gathering a
    /// play's legends and bounds needs of it.
    pub fn observe(&mut self, jobs: &Jobs) {
        self.r
            .pass(&[self.view], jobs, self.frames as f64 * self.dt);
        self.frames += 1;
    }

    /// The legends and plot bounds gathered so far (`hold::Start::Collect`).
    pub fn gathered(&self) -> super::hold::Held {
        super::hold::gathered(&self.r.ctx)
    }
}

/// One off-screen context with the views' state, run pass after pass.
struct Renderer {
    ctx: egui::Context,
    state: Views,
    settings: Settings,
    textures: Textures,
    shapes: Vec<egui::epaint::ClippedShape>,
    frames: Vec<(&'static str, Rect)>,
    area: Rect,
    look: Look,
}

impl Renderer {
    fn new(settings: &Settings, zoom: &[Zoom], size: Vec2, look: &Look) -> Renderer {
        let ctx = document_context(settings, look);
        // Only the figure: title, axes, legend; no buttons or switches.
        style::set_figure_only(&ctx, true);
        style::set_legend_place(&ctx, look.legend);
        if !look.window {
            style::set_line_scale(&ctx, figure_scale(look, size));
        }
        let mut state = Views::default();
        state.bifurcation.zoom = zoom.to_vec();
        Renderer {
            ctx,
            state,
            settings: settings.clone(),
            textures: Textures::new(),
            shapes: Vec::new(),
            frames: Vec::new(),
            area: Rect::from_min_size(egui::Pos2::ZERO, size),
            look: look.clone(),
        }
    }

    /// One frame of the views at ui time `time`.
    fn pass(&mut self, views: &[ViewKind], jobs: &Jobs, time: f64) {
        let area = self.area;
        let input = egui::RawInput {
            screen_rect: Some(area),
            time: Some(time),
            ..Default::default()
        };
        let (state, s, look) = (&mut self.state, &mut self.settings, &self.look);
        let mut out = self.ctx.run_ui(input, |ui| {
            axes::clear_frames(ui.ctx());
            legend::clear(ui.ctx());
            let rects = if views.len() == 1 {
                vec![area.shrink(4.0)]
            } else {
                tile_rects(area.shrink(4.0), views.len())
            };
            let mut actions = Vec::new();
            for (v, r) in views.iter().zip(rects) {
                let view = state.get_mut(*v);
                let title = if look.window {
                    Some(view.title().to_string())
                } else {
                    look.title.clone()
                };
                ui.scope_builder(egui::UiBuilder::new().max_rect(r).id_salt(v.key()), |ui| {
                    let frame = if look.window {
                        egui::Frame::group(ui.style())
                    } else {
                        egui::Frame::new()
                    };
                    frame.inner_margin(4.0).show(ui, |ui| {
                        ui.set_min_size(ui.available_size());
                        if let Some(t) = title {
                            ui.label(RichText::new(t).strong());
                        }
                        view.ui(ui, s, jobs, &mut actions);
                    });
                });
            }
        });
        for (id, deltas) in std::mem::take(&mut out.textures_delta.set) {
            for d in deltas {
                apply_delta(&mut self.textures, id, d);
            }
        }
        // The font atlas is not needed: text is written as text.
        self.textures.remove(&egui::TextureId::default());
        self.shapes = std::mem::take(&mut out.shapes);
        self.frames = axes::plot_frames(&self.ctx);
        super::hold::end_pass(&self.ctx);
        if let style::LegendPlace::Inside(corner) = self.look.legend {
            let (frames, shapes) = (&self.frames, &self.shapes);
            legend::place(&self.ctx, corner, frames, shapes, &self.textures);
        }
    }

    /// The last pass as SVG.
    fn svg(&self) -> String {
        let mut w = SvgWriter::new(self.area, &self.frames, &self.textures);
        w.set_marks(super::diagram_marks::registered(&self.ctx));
        w.add(&self.shapes);
        let bg = self.ctx.global_style().visuals.panel_fill;
        let size = self.area.size();
        let mut svg = w.finish(size, if bg.a() == 0 { Color32::WHITE } else { bg });
        if let Some(f) = &self.look.font {
            use super::svg_text::{FONT_FAMILY, family_attribute};
            let named = format!("font-family=\"{FONT_FAMILY}\"");
            let asked = format!("font-family=\"{}\"", family_attribute(f));
            svg = svg.replacen(&named, &asked, 1);
        }
        // Where the legends are, unpainted (as the plots' frames).
        let boxes = legend::svg_boxes(&legend::drawn(&self.ctx));
        let end = svg.rfind("</svg>").unwrap_or(svg.len());
        svg.insert_str(end, &boxes);
        svg
    }
}

/// A page's lines, markers and legend keys relative to the window's: its
/// text's size relative to egui's (a column's 7 points: about half), and
/// smaller still on a figure under 450 × 300 points, down to a third.
fn figure_scale(look: &Look, size: Vec2) -> f32 {
    let body = egui::Style::default()
        .text_styles
        .get(&egui::TextStyle::Body)
        .map_or(12.5, |f| f.size);
    let text = look.font_size.map_or(1.0, |f| f / body);
    let room = (size.x / 450.0).min(size.y / 300.0);
    text.min(room).clamp(0.35, 1.0)
}

/// A context styled as the window is (theme, text size), without hover or
/// animation: a picture for a document. A page's look ([`Look`]) is the
/// light theme on white, every text `look.font_size` if
/// given.
fn document_context(settings: &Settings, look: &Look) -> egui::Context {
    let ctx = egui::Context::default();
    // Text laid out in the font it is set in (--font), where this system
    // has it: labels then take the room their glyphs do.
    #[cfg(not(target_arch = "wasm32"))]
    if let Some(data) = look.font.as_deref().and_then(super::figure::face_data) {
        let mut fonts = egui::FontDefinitions::default();
        let name = "figure-font".to_owned();
        fonts
            .font_data
            .insert(name.clone(), std::sync::Arc::new(data));
        for family in [egui::FontFamily::Proportional, egui::FontFamily::Monospace] {
            fonts
                .families
                .entry(family)
                .or_default()
                .insert(0, name.clone());
        }
        ctx.set_fonts(fonts);
    }
    ctx.set_theme(if settings.dark && look.window {
        egui::Theme::Dark
    } else {
        egui::Theme::Light
    });
    let base = egui::Style::default().text_styles;
    let scale = settings.font_scale.clamp(0.5, 3.0);
    ctx.all_styles_mut(|s| {
        for (ts, font) in s.text_styles.iter_mut() {
            if let Some(b) = base.get(ts) {
                font.size = look.font_size.unwrap_or(b.size * scale);
            }
        }
        s.animation_time = 0.0;
        if !look.window {
            let v = &mut s.visuals;
            v.panel_fill = Color32::WHITE;
            v.extreme_bg_color = Color32::WHITE;
            v.window_fill = Color32::WHITE;
            // A page's text is black, as a journal prints it.
            v.override_text_color = Some(Color32::BLACK);
        }
    });
    ctx
}

/// A texture update of one frame: a whole new image, or a patch of one.
fn apply_delta(textures: &mut Textures, id: egui::TextureId, d: egui::epaint::ImageDelta) {
    let egui::ImageData::Color(img) = d.image;
    match d.pos {
        None => {
            textures.insert(id, (*img).clone());
        }
        Some([x0, y0]) => {
            if let Some(t) = textures.get_mut(&id) {
                let [w, h] = img.size;
                for y in 0..h {
                    for x in 0..w {
                        let (tx, ty) = (x0 + x, y0 + y);
                        if tx < t.size[0] && ty < t.size[1] {
                            t.pixels[ty * t.size[0] + tx] = img.pixels[y * w + x];
                        }
                    }
                }
            }
        }
    }
}

/// The views a picture of the window shows: the tab, or the tiles.
pub fn shown_views(s: &Settings) -> Vec<ViewKind> {
    match s.layout {
        Layout::Tabs => vec![s.tab],
        Layout::Tiles => s.tiled.clone(),
    }
}
