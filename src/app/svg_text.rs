//! A figure's text as SVG: XML escaping, the font family asked for, and
//! a text shape written as `<text>` rows (see [`super::svg`]).

use std::fmt::Write as _;

use eframe::egui::Color32;
use eframe::egui::epaint::TextShape;

use super::svg::paint;

/// The fonts a figure's text asks for: common sans-serif faces, then the
/// generic family (the PNG and PDF set it in egui's own font, which laid
/// it out; see `figure::font_db`).
pub const FONT_FAMILY: &str = "DejaVu Sans, Helvetica, Arial, sans-serif";

/// The SVG's font-family for `--font family`: a generic family as it is
/// (sans-serif as [`FONT_FAMILY`], which ends with it), a name quoted and
/// followed by [`FONT_FAMILY`]'s faces for a reader without it. `family`
/// was checked to hold no quote or markup.
pub fn family_attribute(family: &str) -> String {
    match family {
        "sans-serif" => FONT_FAMILY.to_owned(),
        "serif" | "monospace" => family.to_owned(),
        name => format!("'{name}', {FONT_FAMILY}"),
    }
}

/// XML text escaping.
pub fn escape(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            // What XML 1.0 does not allow (C0 controls, U+FFFE, U+FFFF)
            // left out, so that the file stays well-formed.
            c if (c as u32) < 0x20 && c != '\t' => {}
            '\u{FFFE}' | '\u{FFFF}' => {}
            c => o.push(c),
        }
    }
    o
}

/// A text shape: one `<text>` per row of its galley, at the row's
/// baseline, in the first section's size and colour (rotated as drawn).
pub(super) fn text(t: &TextShape, out: &mut String) {
    let g = &t.galley;
    let Some(section) = g.job.sections.first() else {
        return;
    };
    let c = t
        .override_text_color
        .unwrap_or(if section.format.color == Color32::PLACEHOLDER {
            t.fallback_color
        } else {
            section.format.color
        });
    let size = section.format.font_id.size;
    let rot = t.angle.to_degrees();
    if rot.abs() > 0.01 {
        write!(
            out,
            "<g transform=\"rotate({rot:.2} {:.2} {:.2})\">",
            t.pos.x, t.pos.y
        )
        .ok();
    }
    for row in &g.rows {
        let Some(first) = row.row.glyphs.first() else {
            continue;
        };
        let s: String = row.row.glyphs.iter().map(|gl| gl.chr).collect();
        let s = s.trim_end();
        if s.trim().is_empty() {
            continue;
        }
        let x = t.pos.x + row.pos.x + first.pos.x;
        let y = t.pos.y + row.pos.y + first.pos.y;
        // Anchored at the middle of the width egui laid the row out at:
        // set in another font than egui's (the document's), a row grows
        // or shrinks about its middle, its glyphs unstretched, so centred
        // titles stay centred and labels stay by their ticks.
        let width = row
            .row
            .glyphs
            .iter()
            .rev()
            .find(|gl| !gl.chr.is_whitespace())
            .map_or(0.0, |gl| gl.pos.x + gl.advance_width - first.pos.x);
        write!(
            out,
            "<text x=\"{:.2}\" y=\"{y:.2}\" font-size=\"{size:.1}\"{} text-anchor=\"middle\" \
             data-width=\"{width:.2}\" xml:space=\"preserve\">{}</text>",
            x + 0.5 * width,
            paint("fill", c),
            escape(s)
        )
        .ok();
    }
    if rot.abs() > 0.01 {
        out.push_str("</g>");
    }
}
