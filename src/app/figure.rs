//! `oneblock figure`: one view drawn headless, with no display, GPU or
//! window. The view's data is computed by the job model's single-threaded
//! worker ([`LocalWorker`], pumped until the view's jobs are done, the
//! others dropped unrun, through the window's same [`Jobs`]), then the view
//! is drawn by
//! [`svg_render::render_svg`], the window's own SVG export: a fresh egui
//! context runs the same view code, figure only (no buttons, no sliders),
//! and its shapes are written as SVG. A PNG is that SVG rasterised by
//! resvg, with the fonts egui laid the text out with, so both files come
//! from one drawing path.

use std::sync::Arc;

use eframe::egui;

use super::bifurcation::{Zoom, auto_theta_range};
use super::session::Session;
use super::settings::{Settings, ViewKind};
use super::svg_render::{self, Look};

mod compute;
pub mod given;

pub use compute::compute;
pub(super) use compute::{ComputeRun, view_settings};

/// One figure to draw: a view over `size` points, from `settings`, the
/// bifurcation diagram at `zoom` (innermost last, as a session holds it)
/// and then, if given, over `theta_nu` × `theta` (θ by default the range
/// of the computed columns).
#[derive(Clone, Debug)]
pub struct Figure {
    pub view: ViewKind,
    pub settings: Settings,
    pub zoom: Vec<Zoom>,
    pub theta_nu: Option<(f64, f64)>,
    pub theta: Option<(f64, f64)>,
    pub size: egui::Vec2,
    /// Whether the current parameters' lines are drawn (θν; κ on the phase
    /// diagram): a figure leaves them out unless asked for.
    pub crosshair: bool,
    /// How it looks: a page's by default (white, no frame, no view name).
    pub look: Look,
    /// What is drawn over the view, computed as the window's buttons do.
    pub overlays: Overlays,
    /// The session the figure starts from: the results it kept are drawn
    /// as they are (an overlay asked for is then not computed), unless
    /// the figure's parameters differ from the session's.
    pub session: Option<Session>,
}

/// What a figure draws over its view that the window computes only on
/// request: "Find bifurcations"' branches and special points over the
/// bifurcation diagram, "Boundaries"' curves over the phase diagram.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Overlays {
    pub branches: bool,
    pub boundaries: bool,
}

impl Figure {
    /// What the window's Record makes of `view`: the window's settings, no
    /// zoom or range of its own, 640×480 points, figure only.
    pub fn record(view: ViewKind, settings: Settings) -> Figure {
        Figure {
            view,
            settings,
            zoom: Vec::new(),
            theta_nu: None,
            theta: None,
            size: egui::vec2(640.0, 480.0),
            crosshair: false,
            look: Look::window(),
            overlays: Overlays::default(),
            session: None,
        }
    }

    /// The diagram's θν range the sweep computes, if not the whole one.
    pub(super) fn sweep_zoom(&self) -> Option<(f64, f64)> {
        match (self.theta_nu, self.theta) {
            (Some(tn), _) => Some(tn),
            (None, Some(_)) => Some(self.settings.sweep_range()),
            (None, None) => self.zoom.last().map(|z| z.theta_nu),
        }
    }
}

/// The figure as SVG: its data computed here, then drawn by the window's
/// view code, figure only.
pub fn svg(fig: &Figure) -> Result<String, String> {
    let jobs = compute(fig)?;
    Ok(svg_of(fig, &jobs))
}

/// The figure as SVG from data already computed (`jobs`, as [`compute`]
/// gives them, or [`given::phase_jobs`] a `phase` run's grid), drawn by
/// the window's view code, figure only.
pub fn svg_of(fig: &Figure, jobs: &super::jobs::Jobs) -> String {
    let s = view_settings(fig);
    let mut zoom = fig.zoom.clone();
    if fig.theta_nu.is_some() || fig.theta.is_some() {
        zoom.push(Zoom {
            theta_nu: fig.sweep_zoom().unwrap_or_else(|| s.sweep_range()),
            theta: fig
                .theta
                .unwrap_or_else(|| auto_theta_range(&jobs.sweep.data)),
        });
    }
    svg_render::render_svg_as(
        &[fig.view],
        &s,
        jobs,
        (&zoom, fig.size),
        fig.crosshair,
        &fig.look,
    )
}

/// The most pixels rasterised at once: a larger PNG is drawn in strips of
/// rows, each streamed to the encoder, so the largest figure (`--size
/// 10000x10000`, 20000 × 20000 pixels: 1.6 GB as one picture, twice that
/// while encoding, which aborted) takes two strips' 64 MB at a time.
pub const STRIP_PIXELS: usize = 1 << 24;

/// Rasterises `svg` (drawn over `size` points) to a PNG of `scale` pixels
/// per point, in strips of at most [`STRIP_PIXELS`]. Text is set in the
/// fonts egui measured it with (its built-in fonts, the only ones in
/// resvg's font database: no system font), so the PNG's labels take the
/// room the layout gave them on any machine.
pub fn png_of_svg(svg: &str, size: egui::Vec2, scale: f32) -> Result<Vec<u8>, String> {
    png_of_svg_with(svg, size, scale, &font_db())
}

/// `tree` as a PNG of `w` × `h` pixels at `scale` pixels per point,
/// rasterised `rows` rows at a time and streamed to the encoder.
fn encode_in_strips(
    tree: &resvg::usvg::Tree,
    (w, h): (u32, u32),
    scale: f32,
    rows: u32,
) -> Result<Vec<u8>, String> {
    use resvg::tiny_skia;
    // Each strip is drawn with MARGIN rows more above and below, kept out
    // of the picture: anti-aliasing at a pixmap's edge differs from the
    // whole picture's, which made faint seams.
    const MARGIN: u32 = 8;
    let mut strip = tiny_skia::Pixmap::new(w, rows + 2 * MARGIN)
        .ok_or_else(|| format!("cannot make a {w}x{h} picture"))?;
    let failed = |e: png::EncodingError| format!("PNG encoding failed: {e}");
    let mut data = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut data, w, h);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().map_err(failed)?;
        let mut out = writer.stream_writer().map_err(failed)?;
        let mut bytes = Vec::with_capacity(strip.data().len());
        let mut top = 0;
        while top < h {
            let n = rows.min(h - top);
            strip.fill(tiny_skia::Color::TRANSPARENT);
            let at = tiny_skia::Transform::from_scale(scale, scale)
                .post_translate(0.0, MARGIN as f32 - top as f32);
            resvg::render(tree, at, &mut strip.as_mut());
            // PNG holds straight alpha; the pixmap premultiplied.
            bytes.clear();
            let rows_kept = (w * MARGIN) as usize..(w * (MARGIN + n)) as usize;
            for px in &strip.pixels()[rows_kept] {
                let c = px.demultiply();
                bytes.extend_from_slice(&[c.red(), c.green(), c.blue(), c.alpha()]);
            }
            std::io::Write::write_all(&mut out, &bytes)
                .map_err(|e| format!("PNG encoding failed: {e}"))?;
            top += n;
        }
        out.finish().map_err(failed)?;
    }
    Ok(data)
}

/// A picture's size in pixels: `size` points at `scale` pixels a point.
fn pixel_size(size: egui::Vec2, scale: f32) -> (u32, u32) {
    (
        (size.x * scale).round() as u32,
        (size.y * scale).round() as u32,
    )
}

/// `svg` parsed with the fonts of `db`.
fn parse_svg(
    svg: &str,
    db: &Arc<resvg::usvg::fontdb::Database>,
) -> Result<resvg::usvg::Tree, String> {
    let opt = resvg::usvg::Options {
        fontdb: db.clone(),
        ..Default::default()
    };
    resvg::usvg::Tree::from_str(svg, &opt).map_err(|e| format!("the SVG did not parse: {e}"))
}

/// The font database resvg sets a figure's text with: egui's own fonts,
/// which laid the text out (no system font).
pub(super) fn font_db() -> Arc<resvg::usvg::fontdb::Database> {
    let mut db = resvg::usvg::fontdb::Database::new();
    for data in egui::FontDefinitions::default().font_data.values() {
        db.load_font_data(data.font.as_ref().as_ref().to_vec());
    }
    db.set_sans_serif_family("Ubuntu");
    Arc::new(db)
}

/// The fonts for a figure whose text asks for `family` (`figure --font`):
/// egui's own ([`font_db`]), and for a family other than sans-serif the
/// system's fonts, with the family the SVG names found among them (Hack,
/// egui's own, for monospace; the first serif face installed for serif);
/// where the system has none, egui's alone and a note saying so.
#[cfg(not(target_arch = "wasm32"))]
pub fn fonts_for(family: Option<&str>) -> (Arc<resvg::usvg::fontdb::Database>, Option<String>) {
    let Some(f) = family.filter(|f| *f != "sans-serif") else {
        return (font_db(), None);
    };
    let mut db = (*font_db()).clone();
    if f == "monospace" {
        db.set_monospace_family("Hack");
        return (Arc::new(db), None);
    }
    db.load_system_fonts();
    let has = |name: &str| {
        db.faces().any(|face| {
            face.families
                .iter()
                .any(|(n, _)| n.eq_ignore_ascii_case(name))
        })
    };
    let found = if f == "serif" {
        [
            "DejaVu Serif",
            "Liberation Serif",
            "Noto Serif",
            "Times New Roman",
            "FreeSerif",
        ]
        .into_iter()
        .find(|n| has(n))
        .map(str::to_owned)
    } else {
        has(f).then(|| f.to_owned())
    };
    match found {
        Some(name) => {
            if f == "serif" {
                db.set_serif_family(name);
            }
            (Arc::new(db), None)
        }
        None => (
            font_db(),
            Some(format!(
                "--font: this system has no '{f}' font: the text is set in the built-in \
                 sans-serif (the SVG still names '{f}')"
            )),
        ),
    }
}

/// The regular face of `family` (`figure --font`) for egui to lay the
/// figure's text out in, from [`fonts_for`]'s fonts; `None` for
/// sans-serif (egui's own) and a family this system lacks.
#[cfg(not(target_arch = "wasm32"))]
pub(super) fn face_data(family: &str) -> Option<egui::FontData> {
    use resvg::usvg::fontdb::{Family, Query};
    let (db, note) = fonts_for(Some(family));
    if note.is_some() || family == "sans-serif" {
        return None;
    }
    let asked = match family {
        "serif" => Family::Serif,
        "monospace" => Family::Monospace,
        name => Family::Name(name),
    };
    let id = db.query(&Query {
        families: &[asked],
        ..Query::default()
    })?;
    db.with_face_data(id, |data, index| {
        let mut f = egui::FontData::from_owned(data.to_vec());
        f.index = index;
        f
    })
}

/// [`png_of_svg`] with the fonts of `db` ([`fonts_for`]).
pub fn png_of_svg_with(
    svg: &str,
    size: egui::Vec2,
    scale: f32,
    db: &Arc<resvg::usvg::fontdb::Database>,
) -> Result<Vec<u8>, String> {
    let tree = parse_svg(svg, db)?;
    let (w, h) = pixel_size(size, scale);
    let rows = (STRIP_PIXELS / (w.max(1) as usize)).clamp(1, h.max(1) as usize) as u32;
    encode_in_strips(&tree, (w, h), scale, rows)
}

/// `svg` rasterised at `scale` pixels per point with the fonts of `db`
/// (loaded once for all of an animation's frames).
pub(super) fn pixmap_with_fonts(
    svg: &str,
    size: egui::Vec2,
    scale: f32,
    db: &Arc<resvg::usvg::fontdb::Database>,
) -> Result<resvg::tiny_skia::Pixmap, String> {
    use resvg::tiny_skia;
    let tree = parse_svg(svg, db)?;
    let (w, h) = pixel_size(size, scale);
    let mut pixmap =
        tiny_skia::Pixmap::new(w, h).ok_or_else(|| format!("cannot make a {w}x{h} picture"))?;
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(scale, scale),
        &mut pixmap.as_mut(),
    );
    Ok(pixmap)
}

/// `svg` (drawn over its own size in points) as a one-page vector PDF of
/// that size: paths stay paths, text stays text (searchable, copyable),
/// set in the fonts the PNG is rasterised with ([`font_db`]), subset and
/// embedded; the diagrams' density images stay images.
#[cfg(not(target_arch = "wasm32"))]
pub fn pdf_of_svg(svg: &str) -> Result<Vec<u8>, String> {
    pdf_of_svg_with(svg, &font_db())
}

/// [`pdf_of_svg`] with the fonts of `db` ([`fonts_for`]).
#[cfg(not(target_arch = "wasm32"))]
pub fn pdf_of_svg_with(
    svg: &str,
    db: &Arc<resvg::usvg::fontdb::Database>,
) -> Result<Vec<u8>, String> {
    let opt = svg2pdf::usvg::Options {
        fontdb: db.clone(),
        ..Default::default()
    };
    let tree = svg2pdf::usvg::Tree::from_str(svg, &opt)
        .map_err(|e| format!("the SVG did not parse: {e}"))?;
    // 72 dpi: one SVG unit (a point of the figure) is one PDF point.
    svg2pdf::to_pdf(
        &tree,
        svg2pdf::ConversionOptions::default(),
        svg2pdf::PageOptions { dpi: 72.0 },
    )
    .map_err(|e| format!("the PDF could not be made: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pixels of a PNG.
    fn decoded(png: &[u8]) -> image::RgbaImage {
        image::load_from_memory(png).expect("a PNG").to_rgba8()
    }

    #[test]
    fn a_picture_drawn_in_strips_is_the_picture_drawn_whole() {
        // Lines across every strip boundary, a translucent fill, text.
        let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="120" height="90" viewBox="0 0 120 90">
            <rect x="5" y="5" width="110" height="80" fill="#3070c0" fill-opacity="0.4"/>
            <path d="M0,0 L120,90 M0,90 L120,0" stroke="#000" stroke-width="1.3"/>
            <circle cx="60" cy="45" r="30" fill="none" stroke="#c03020" stroke-width="2"/>
            <text x="10" y="50" font-family="sans-serif" font-size="14">θν strips</text>
        </svg>"##;
        let size = egui::vec2(120.0, 90.0);
        let tree = parse_svg(svg, &font_db()).expect("svg");
        let (w, h) = pixel_size(size, 2.0);
        let whole = decoded(&encode_in_strips(&tree, (w, h), 2.0, h).expect("whole"));
        let strips = decoded(&encode_in_strips(&tree, (w, h), 2.0, 7).expect("strips"));
        assert_eq!(whole.dimensions(), (240, 180));
        assert_eq!(strips.dimensions(), (240, 180));
        // Not blank, and the same picture: a strip is drawn shifted by
        // whole pixels, which moves tiny-skia's anti-aliasing of a curve's
        // edge pixels (measured: 268 of 43,200 pixels, on the circle's
        // edge, by at most 59 of 255 in a channel), nothing else.
        let distinct: std::collections::HashSet<_> = whole.pixels().map(|p| p.0).collect();
        assert!(distinct.len() > 20, "{} colours", distinct.len());
        let diffs: Vec<u8> = whole
            .pixels()
            .zip(strips.pixels())
            .map(|(a, b)| {
                a.0.iter()
                    .zip(b.0)
                    .map(|(x, y)| x.abs_diff(y))
                    .max()
                    .unwrap_or(0)
            })
            .collect();
        let off = diffs.iter().filter(|&&d| d > 2).count();
        let worst = diffs.iter().copied().max().unwrap_or(0);
        assert!(
            off * 100 < diffs.len(),
            "{off} of {} pixels differ",
            diffs.len()
        );
        assert!(worst <= 64, "a channel differs by {worst}");
        // And png_of_svg itself draws that picture.
        let direct = decoded(&png_of_svg(svg, size, 2.0).expect("png"));
        assert_eq!(direct.as_raw(), whole.as_raw());
    }
}
