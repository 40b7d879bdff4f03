//! Pictures for files, drawn as SVG and rasterised to PNG by resvg, their
//! text set in the font committed under `assets/fonts` (DejaVu Sans) so that
//! a picture reads the same on every machine and needs no system font. The
//! phase diagram of `oneblock phase --png` is the first; the window's
//! screenshots are egui's own and do not come here.
//!
//! Nothing here depends on the `gui` feature.

pub mod phase;

use std::fmt::Write as _;
use std::sync::{Arc, LazyLock};

use resvg::tiny_skia;
use resvg::usvg;

/// The font every picture's text is set in (the family name SVG text names).
pub const FONT_FAMILY: &str = "DejaVu Sans";

/// DejaVu Sans (assets/fonts/README.md: its origin and licence); also the
/// window's fallback for glyphs egui's own fonts lack (→ in "P2 → P1").
pub const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// The font database: only the committed font, loaded once.
static FONTS: LazyLock<Arc<usvg::fontdb::Database>> = LazyLock::new(|| {
    let mut db = usvg::fontdb::Database::new();
    db.load_font_data(FONT.to_vec());
    db.set_sans_serif_family(FONT_FAMILY);
    Arc::new(db)
});

/// Whether `path` names an SVG file (by its extension, any case): the
/// picture is then written as SVG rather than rasterised.
pub fn is_svg(path: &std::path::Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"))
}

/// Rasterises `svg` at its own size (one pixel per SVG unit) to PNG bytes.
/// An error (an SVG that does not parse, a size of zero or too large, a
/// failed encoding) is a message, never an empty image.
pub fn svg_to_png(svg: &str) -> Result<Vec<u8>, String> {
    let opt = usvg::Options {
        font_family: FONT_FAMILY.to_string(),
        fontdb: FONTS.clone(),
        ..usvg::Options::default()
    };
    let tree = usvg::Tree::from_str(svg, &opt).map_err(|e| format!("the picture's SVG: {e}"))?;
    let size = tree.size().to_int_size();
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height()).ok_or_else(|| {
        format!(
            "the picture's size {} x {} cannot be rendered",
            size.width(),
            size.height()
        )
    })?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    pixmap
        .encode_png()
        .map_err(|e| format!("cannot encode the PNG: {e}"))
}

/// Text for an SVG attribute or element: `&`, `<`, `>` and `"` escaped.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

/// An SVG document being written: a white page of `width` × `height`
/// units, text in [`FONT_FAMILY`].
pub struct Svg {
    body: String,
    width: f64,
    height: f64,
}

impl Svg {
    /// An empty page.
    pub fn new(width: f64, height: f64) -> Self {
        Svg {
            body: String::new(),
            width,
            height,
        }
    }

    /// A filled rectangle (crisp edges: cells meet without seams).
    pub fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, fill: [u8; 3]) {
        writeln!(
            self.body,
            r#"<rect x="{x:.2}" y="{y:.2}" width="{w:.2}" height="{h:.2}" fill="{}" shape-rendering="crispEdges"/>"#,
            hex(fill)
        )
        .ok();
    }

    /// An unfilled rectangle outline.
    pub fn frame(&mut self, x: f64, y: f64, w: f64, h: f64, width: f64) {
        writeln!(
            self.body,
            r#"<rect x="{x:.2}" y="{y:.2}" width="{w:.2}" height="{h:.2}" fill="none" stroke="black" stroke-width="{width}"/>"#
        )
        .ok();
    }

    /// A straight black line.
    pub fn line(&mut self, a: [f64; 2], b: [f64; 2], width: f64) {
        writeln!(
            self.body,
            r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="black" stroke-width="{width}"/>"#,
            a[0], a[1], b[0], b[1]
        )
        .ok();
    }

    /// A black polyline on a white halo 3 units wider, clipped to the
    /// rectangle `clip` (x, y, w, h), not anti-aliased: drawn over the
    /// cells it adds black and white pixels only, so it shows over every
    /// class's colour (black chaos cells as much as pale ones).
    pub fn polyline(&mut self, points: &[[f64; 2]], width: f64, clip: [f64; 4]) {
        if points.len() < 2 {
            return;
        }
        let d: Vec<String> = points
            .iter()
            .map(|p| format!("{:.2},{:.2}", p[0], p[1]))
            .collect();
        writeln!(
            self.body,
            r#"<svg x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" viewBox="{:.2} {:.2} {:.2} {:.2}" overflow="hidden"><polyline points="{d}" fill="none" stroke="white" stroke-width="{halo}" stroke-linejoin="round" shape-rendering="crispEdges"/><polyline points="{d}" fill="none" stroke="black" stroke-width="{width}" stroke-linejoin="round" shape-rendering="crispEdges"/></svg>"#,
            clip[0],
            clip[1],
            clip[2],
            clip[3],
            clip[0],
            clip[1],
            clip[2],
            clip[3],
            d = d.join(" "),
            halo = width + 3.0,
        )
        .ok();
    }

    /// Text at (x, y) (its baseline), anchored `start`, `middle` or `end`,
    /// turned by `rotate` degrees about that point.
    pub fn text(&mut self, x: f64, y: f64, size: f64, anchor: &str, rotate: f64, t: &str) {
        let turn = if rotate == 0.0 {
            String::new()
        } else {
            format!(r#" transform="rotate({rotate} {x:.2} {y:.2})""#)
        };
        writeln!(
            self.body,
            r#"<text x="{x:.2}" y="{y:.2}" font-size="{size}" text-anchor="{anchor}"{turn}>{}</text>"#,
            escape(t)
        )
        .ok();
    }

    /// The document.
    pub fn finish(self) -> String {
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" font-family=\"{FONT_FAMILY}\">\n<rect width=\"{w}\" height=\"{h}\" fill=\"white\"/>\n{}</svg>\n",
            self.body,
            w = self.width,
            h = self.height
        )
    }
}

/// `#rrggbb`.
fn hex(c: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The committed font sets Greek text: a label "κ" rasterises to dark
    /// pixels (the font database has no other font to fall back on).
    #[test]
    fn greek_text_is_drawn_from_the_committed_font() {
        let mut svg = Svg::new(60.0, 40.0);
        svg.text(30.0, 30.0, 28.0, "middle", 0.0, "κθν");
        let png = svg_to_png(&svg.finish()).expect("renders");
        let img = image::load_from_memory(&png).expect("a PNG").to_rgb8();
        assert_eq!(img.dimensions(), (60, 40));
        let dark = img.pixels().filter(|p| p.0[0] < 100).count();
        assert!(dark > 50, "{dark} dark pixels: the glyphs are missing");
        // An empty page has none.
        let png = svg_to_png(&Svg::new(60.0, 40.0).finish()).expect("renders");
        let img = image::load_from_memory(&png).expect("a PNG").to_rgb8();
        assert_eq!(img.pixels().filter(|p| p.0[0] < 100).count(), 0);
    }

    #[test]
    fn a_bad_picture_is_an_error_not_an_empty_file() {
        assert!(svg_to_png("<svg").is_err());
        assert!(svg_to_png(&Svg::new(0.0, 10.0).finish()).is_err());
    }
}
