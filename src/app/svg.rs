//! egui's shapes as SVG: the vector picture of a view.
//!
//! A view is drawn once more into an off-screen egui context (see
//! [`super::svg_render`]) and the shapes of that pass, before
//! tessellation, are written out one by one: lines and plot series as
//! `<path>`, markers as `<circle>`, bars and frames as `<rect>`, every
//! text (tick labels, axis titles, legends) as `<text>` with the galley's
//! string, a texture (the bifurcation and phase diagrams' density images)
//! as an embedded PNG `<image>`. Walking the shapes rather than describing
//! each plot again keeps one drawing code: the SVG has exactly the ticks,
//! labels, legend and series the window draws.
//!
//! Each shape drawn inside a plot's frame that is a series (a polyline,
//! markers, bars or an image, not a grid line) carries
//! `class="series" data-series="<plot>:<colour>"`, so a reader (and the
//! tests) can count a plot's series.

use base64::Engine as _;
use std::collections::HashMap;
use std::fmt::Write as _;

use eframe::egui;
use egui::epaint::{ClippedShape, Mesh, Shape};
use egui::{Color32, ColorImage, Pos2, Rect, TextureId};

use super::svg_text::text;
pub use super::svg_text::{FONT_FAMILY, escape};

/// One plot's frame, by name (see `axes::plot_frames`).
pub type PlotFrame = (&'static str, Rect);

/// The textures a mesh may show, by id (the font atlas is not needed:
/// text is written as text).
pub type Textures = HashMap<TextureId, ColorImage>;

/// `#rrggbb` and the opacity of a colour.
fn colour(c: Color32) -> (String, f32) {
    let [r, g, b, a] = c.to_srgba_unmultiplied();
    (format!("#{r:02x}{g:02x}{b:02x}"), f32::from(a) / 255.0)
}

pub(super) fn paint(attr: &str, c: Color32) -> String {
    if c.a() == 0 {
        return format!(" {attr}=\"none\"");
    }
    let (hex, a) = colour(c);
    if a >= 1.0 {
        format!(" {attr}=\"{hex}\"")
    } else {
        format!(" {attr}=\"{hex}\" {attr}-opacity=\"{a:.3}\"")
    }
}

fn stroke_attrs(s: egui::Stroke) -> String {
    if s.width <= 0.0 || s.color.a() == 0 {
        return " stroke=\"none\"".into();
    }
    format!(
        "{} stroke-width=\"{:.2}\"",
        paint("stroke", s.color),
        s.width
    )
}

/// A path stroke's colour (a gradient's colour at its start).
fn solid(s: &egui::epaint::PathStroke) -> Color32 {
    match &s.color {
        egui::epaint::ColorMode::Solid(c) => *c,
        egui::epaint::ColorMode::UV(f) => f(Rect::ZERO, Pos2::ZERO),
    }
}

fn points_d(points: &[Pos2], closed: bool) -> String {
    let mut d = String::with_capacity(points.len() * 16);
    for (i, p) in points.iter().enumerate() {
        write!(
            d,
            "{}{:.2},{:.2}",
            if i == 0 { "M" } else { " L" },
            p.x,
            p.y
        )
        .ok();
    }
    if closed {
        d.push_str(" Z");
    }
    d
}

/// The SVG writer: shapes in, one document out.
pub struct SvgWriter<'a> {
    frames: &'a [PlotFrame],
    screen: Rect,
    textures: &'a Textures,
    body: String,
    defs: String,
    clips: Vec<Rect>,
    /// Images drawn as vector dots instead (the diagram's points).
    marks: super::diagram_marks::MarksOf,
}

/// Whether two rectangles are the same to within half a point.
fn same_rect(a: Rect, b: Rect) -> bool {
    (a.min - b.min).length() < 0.5 && (a.max - b.max).length() < 0.5
}

impl<'a> SvgWriter<'a> {
    /// A writer for shapes drawn over `screen` whose plots have these
    /// frames, showing these textures. A clip rectangle smaller than the
    /// screen that is no recorded frame is taken for an unnamed plot's
    /// (egui_plot clips its items to its frame; the rest of a view is
    /// clipped to the screen).
    pub fn new(screen: Rect, frames: &'a [PlotFrame], textures: &'a Textures) -> Self {
        SvgWriter {
            frames,
            screen,
            textures,
            body: String::new(),
            defs: String::new(),
            clips: Vec::new(),
            marks: Default::default(),
        }
    }

    /// Draws the images these marks are registered for as the marks.
    pub fn set_marks(&mut self, marks: super::diagram_marks::MarksOf) {
        self.marks = marks;
    }

    /// The plot whose frame is the clip rectangle `clip` (number `id`),
    /// if any.
    fn plot_of(&self, clip: Rect, id: usize) -> Option<String> {
        self.frames
            .iter()
            .find(|(_, f)| same_rect(*f, clip) || f.contains_rect(clip) && clip.area() > 0.0)
            .map(|(n, _)| n.to_string())
            .or_else(|| (!same_rect(clip, self.screen)).then(|| format!("plot{id}")))
    }

    fn clip_id(&mut self, clip: Rect) -> usize {
        if let Some(i) = self.clips.iter().position(|c| same_rect(*c, clip)) {
            return i;
        }
        let i = self.clips.len();
        writeln!(
            self.defs,
            "<clipPath id=\"c{i}\"><rect x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\"/></clipPath>",
            clip.min.x,
            clip.min.y,
            clip.width(),
            clip.height()
        )
        .ok();
        self.clips.push(clip);
        i
    }

    /// Adds the shapes of a pass, in painting order. A shape that lies
    /// within its clip rectangle is written unclipped, and a run of shapes
    /// cut by one clip rectangle shares one group: a renderer masks each
    /// clipped group over the whole picture (resvg does), which made the
    /// clipping most of a GIF frame's cost when every shape had its own.
    pub fn add(&mut self, shapes: &[ClippedShape]) {
        let mut open: Option<usize> = None;
        for cs in shapes {
            let clip = cs.clip_rect;
            if !clip.is_positive() {
                continue;
            }
            let id = self.clip_id(clip);
            let plot = self.plot_of(clip, id);
            let mut out = String::new();
            self.shape(&cs.shape, plot.as_deref(), &mut out);
            if out.is_empty() {
                continue;
            }
            // Half a point of slack: egui's rounding of a line's ends.
            let inside = clip
                .expand(0.5)
                .contains_rect(cs.shape.visual_bounding_rect())
                || clip.contains_rect(self.screen);
            let want = (!inside).then_some(id);
            if want != open {
                if open.is_some() {
                    self.body.push_str("</g>\n");
                }
                if let Some(id) = want {
                    writeln!(self.body, "<g clip-path=\"url(#c{id})\">").ok();
                }
                open = want;
            }
            self.body.push_str(&out);
            self.body.push('\n');
        }
        if open.is_some() {
            self.body.push_str("</g>\n");
        }
    }

    /// The series attributes of a shape of colour `c` in `plot`. The
    /// colour is rounded to 3 bits per channel: one series drawn with
    /// slightly different alphas (markers over a line) stays one series.
    fn series(plot: Option<&str>, c: Color32) -> String {
        match plot {
            Some(p) => {
                let [r, g, b, _] = c.to_srgba_unmultiplied();
                format!(
                    " class=\"series\" data-series=\"{}:{:x}{:x}{:x}\"",
                    escape(p),
                    r >> 5,
                    g >> 5,
                    b >> 5
                )
            }
            None => String::new(),
        }
    }

    /// A path: a series when it has more than two points.
    fn path(p: &egui::epaint::PathShape, plot: Option<&str>, out: &mut String) {
        if p.points.len() < 2 {
            return;
        }
        let stroke = solid(&p.stroke);
        let c = if p.fill.a() > 0 { p.fill } else { stroke };
        let tag = if p.points.len() > 2 {
            Self::series(plot, c)
        } else {
            String::new()
        };
        let width = p.stroke.width;
        let s = if width > 0.0 && stroke.a() > 0 {
            format!(
                "{} stroke-width=\"{width:.2}\" stroke-linejoin=\"round\"",
                paint("stroke", stroke)
            )
        } else {
            " stroke=\"none\"".into()
        };
        write!(
            out,
            "<path d=\"{}\"{}{s}{tag}/>",
            points_d(&p.points, p.closed),
            if p.closed {
                paint("fill", p.fill)
            } else {
                " fill=\"none\"".into()
            }
        )
        .ok();
    }

    /// A rectangle: a filled one in a plot is a bar (or a cell), a series.
    fn rect(r: &egui::epaint::RectShape, plot: Option<&str>, out: &mut String) {
        // A filled rectangle in a plot is a bar (or a cell).
        let tag = if r.fill.a() > 0 {
            Self::series(plot, r.fill)
        } else {
            String::new()
        };
        let rad = r.corner_radius.average();
        write!(
            out,
            "<rect x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\" rx=\"{rad:.1}\"{}{}{tag}/>",
            r.rect.min.x,
            r.rect.min.y,
            r.rect.width(),
            r.rect.height(),
            paint("fill", r.fill),
            stroke_attrs(r.stroke)
        )
        .ok();
    }

    fn shape(&self, shape: &Shape, plot: Option<&str>, out: &mut String) {
        match shape {
            Shape::Noop | Shape::Callback(_) => {}
            Shape::Vec(v) => {
                for s in v {
                    self.shape(s, plot, out);
                }
            }
            Shape::Circle(c) => {
                let tag = Self::series(
                    plot,
                    if c.fill.a() > 0 {
                        c.fill
                    } else {
                        c.stroke.color
                    },
                );
                write!(
                    out,
                    "<circle cx=\"{:.2}\" cy=\"{:.2}\" r=\"{:.2}\"{}{}{tag}/>",
                    c.center.x,
                    c.center.y,
                    c.radius,
                    paint("fill", c.fill),
                    stroke_attrs(c.stroke)
                )
                .ok();
            }
            Shape::Ellipse(e) => {
                write!(
                    out,
                    "<ellipse cx=\"{:.2}\" cy=\"{:.2}\" rx=\"{:.2}\" ry=\"{:.2}\"{}{}/>",
                    e.center.x,
                    e.center.y,
                    e.radius.x,
                    e.radius.y,
                    paint("fill", e.fill),
                    stroke_attrs(e.stroke)
                )
                .ok();
            }
            // Grid lines, axis ticks, reference lines: never a series.
            Shape::LineSegment { points, stroke } => {
                write!(
                    out,
                    "<path d=\"{}\" fill=\"none\"{}/>",
                    points_d(points, false),
                    stroke_attrs(*stroke)
                )
                .ok();
            }
            Shape::Path(p) => Self::path(p, plot, out),
            Shape::Band(b) => {
                if b.points.is_empty() {
                    return;
                }
                let mut pts: Vec<Pos2> = b.points.iter().map(|p| Pos2::new(p.x, p.y.min)).collect();
                pts.extend(b.points.iter().rev().map(|p| Pos2::new(p.x, p.y.max)));
                write!(
                    out,
                    "<path d=\"{}\"{}{}/>",
                    points_d(&pts, true),
                    paint("fill", b.fill),
                    stroke_attrs(b.stroke)
                )
                .ok();
            }
            Shape::Rect(r) => Self::rect(r, plot, out),
            Shape::Text(t) => text(t, out),
            Shape::Mesh(m) => self.mesh(m, plot, out),
            Shape::QuadraticBezier(q) => {
                let stroke = egui::Stroke::new(q.stroke.width, solid(&q.stroke));
                bezier(out, 'Q', &q.points, q.closed, q.fill, stroke);
            }
            Shape::CubicBezier(q) => {
                let stroke = egui::Stroke::new(q.stroke.width, solid(&q.stroke));
                bezier(out, 'C', &q.points, q.closed, q.fill, stroke);
            }
        }
    }

    /// A textured mesh (a plot image) as an embedded PNG over the mesh's
    /// bounds; an untextured one as its triangles.
    fn mesh(&self, m: &Mesh, plot: Option<&str>, out: &mut String) {
        if m.vertices.is_empty() {
            return;
        }
        let bounds = m.calc_bounds();
        if let Some(marks) = self.marks.get(&m.texture_id) {
            out.push_str(&super::diagram_marks::svg(marks, bounds, plot));
            return;
        }
        if let Some(img) = self.textures.get(&m.texture_id) {
            let img = blocky(img, bounds);
            let Ok(png) = super::files::encode_png(&img, None, 1.0) else {
                return;
            };
            let tag = plot.map_or(String::new(), |p| {
                format!(" class=\"series\" data-series=\"{}:image\"", escape(p))
            });
            write!(
                out,
                "<image x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\" preserveAspectRatio=\"none\" image-rendering=\"optimizeSpeed\"{tag} href=\"data:image/png;base64,{}\"/>",
                bounds.min.x,
                bounds.min.y,
                bounds.width(),
                bounds.height(),
                base64::engine::general_purpose::STANDARD.encode(&png)
            )
            .ok();
            return;
        }
        if m.texture_id != TextureId::default() {
            return;
        }
        for tri in m.indices.chunks_exact(3) {
            let v: Vec<&egui::epaint::Vertex> = tri
                .iter()
                .filter_map(|&i| m.vertices.get(i as usize))
                .collect();
            if v.len() < 3 || v[0].color.a() == 0 {
                continue;
            }
            write!(
                out,
                "<path d=\"M{:.2},{:.2} L{:.2},{:.2} L{:.2},{:.2} Z\"{}/>",
                v[0].pos.x,
                v[0].pos.y,
                v[1].pos.x,
                v[1].pos.y,
                v[2].pos.x,
                v[2].pos.y,
                paint("fill", v[0].color)
            )
            .ok();
        }
    }

    /// The document, `size` points wide and high, on `background`.
    pub fn finish(self, size: egui::Vec2, background: Color32) -> String {
        let mut s = String::with_capacity(self.body.len() + self.defs.len() + 400);
        writeln!(
            s,
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" \
             width=\"{w:.0}\" height=\"{h:.0}\" viewBox=\"0 0 {w:.2} {h:.2}\" \
             font-family=\"{FONT_FAMILY}\">",
            w = size.x,
            h = size.y
        )
        .ok();
        writeln!(s, "<defs>\n{}</defs>", self.defs).ok();
        // Where each plot's frame is, unpainted: for a reader (and the
        // tests) to find a plot's axes.
        for (name, f) in self.frames {
            writeln!(
                s,
                "<rect class=\"plot-frame\" data-plot=\"{}\" x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"none\" stroke=\"none\"/>",
                escape(name),
                f.min.x,
                f.min.y,
                f.width(),
                f.height()
            )
            .ok();
        }
        writeln!(
            s,
            "<rect width=\"100%\" height=\"100%\"{}/>",
            paint("fill", background)
        )
        .ok();
        s.push_str(&self.body);
        s.push_str("</svg>\n");
        s
    }
}

/// A Bézier curve as a path: `M` to the first point, then `command` (`Q`
/// quadratic, `C` cubic) through the others.
fn bezier(
    out: &mut String,
    command: char,
    points: &[egui::Pos2],
    closed: bool,
    fill: egui::Color32,
    stroke: egui::Stroke,
) {
    let Some((first, rest)) = points.split_first() else {
        return;
    };
    let mut d = format!("M{:.2},{:.2} {command}", first.x, first.y);
    for (k, p) in rest.iter().enumerate() {
        let sep = if k == 0 { "" } else { " " };
        write!(d, "{sep}{:.2},{:.2}", p.x, p.y).ok();
    }
    if closed {
        d.push_str(" Z");
    }
    write!(
        out,
        "<path d=\"{d}\"{}{}/>",
        paint("fill", fill),
        stroke_attrs(stroke)
    )
    .ok();
}

/// A plot image (the phase grid's cells, a density) enlarged by whole
/// pixels to about the size it is shown at, each texel a block: so its
/// cells stay sharp-edged in every renderer, also one that smooths images
/// whatever `image-rendering` says. At most 16× and 4 million pixels.
fn blocky(img: &egui::ColorImage, bounds: Rect) -> egui::ColorImage {
    let [w, h] = img.size;
    if w == 0 || h == 0 {
        return img.clone();
    }
    let fit = (bounds.width() / w as f32).min(bounds.height() / h as f32);
    let room = (4_000_000.0 / (w * h) as f32).sqrt();
    let k = fit.min(room).clamp(1.0, 16.0) as usize;
    if k == 1 {
        return img.clone();
    }
    let mut pixels = Vec::with_capacity(w * h * k * k);
    for row in img.pixels.chunks_exact(w) {
        let wide: Vec<egui::Color32> = row
            .iter()
            .flat_map(|&c| std::iter::repeat_n(c, k))
            .collect();
        for _ in 0..k {
            pixels.extend_from_slice(&wide);
        }
    }
    egui::ColorImage::new([w * k, h * k], pixels)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_escaped() {
        assert_eq!(escape("a<b & \"c\">"), "a&lt;b &amp; &quot;c&quot;&gt;");
    }

    #[test]
    fn a_grid_image_is_enlarged_in_whole_blocks() {
        let (a, b) = (Color32::RED, Color32::BLUE);
        let img = ColorImage::new([2, 1], vec![a, b]);
        // Shown 21 × 10 points: 10 pixels a cell fit across and down.
        let shown = Rect::from_min_size(Pos2::ZERO, egui::vec2(21.0, 10.0));
        let big = blocky(&img, shown);
        assert_eq!(big.size, [20, 10]);
        for (i, c) in big.pixels.iter().enumerate() {
            assert_eq!(*c, if i % 20 < 10 { a } else { b }, "pixel {i}");
        }
        // Never more than 16× across.
        let shown = Rect::from_min_size(Pos2::ZERO, egui::vec2(400.0, 200.0));
        assert_eq!(blocky(&img, shown).size, [32, 16]);
        // Shown smaller than its texels: left as it is.
        let small = blocky(&img, Rect::from_min_size(Pos2::ZERO, egui::vec2(1.0, 1.0)));
        assert_eq!(small.size, [2, 1]);
    }
}
