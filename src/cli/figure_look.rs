//! `oneblock figure`'s look flags checked: `--title`, `--font-size` and
//! `--font` (issue 57 item 3: black text in any font), each refusal one
//! line naming the flag and what it takes (exit 2).

use super::CliError;
use super::figure_flags::{FONT_SIZES, FigureArgs, Format};
use super::values::{echo, short};

/// The generic font families `--font` takes besides a family's name.
pub const GENERIC_FONTS: [&str; 3] = ["serif", "sans-serif", "monospace"];

/// The longest family name `--font` takes, in characters.
const MAX_FONT_NAME: usize = 100;

/// --title, --font-size and --font: a title with some text, a size in
/// [`FONT_SIZES`], a family for a picture with text ([`check_font`]);
/// none with the window's look, which has its own.
pub(super) fn check_look(a: &FigureArgs, format: Format) -> Result<(), CliError> {
    let usage = |m: String| Err(CliError::Usage(m));
    if let Some(t) = &a.title
        && t.trim().is_empty()
    {
        return usage("--title: give the title's text (or leave --title out)".into());
    }
    if let Some(c) = a
        .title
        .as_deref()
        .and_then(|t| t.chars().find(|&c| !xml_char(c)))
    {
        return usage(format!(
            "--title: U+{:04X} is not a character an SVG may hold: leave it out",
            c as u32
        ));
    }
    if let Some(v) = a.font_size
        && !(FONT_SIZES.0..=FONT_SIZES.1).contains(&v)
    {
        return usage(format!(
            "--font-size = {} is out of range: must lie in [{}, {}] (points)",
            short(v),
            FONT_SIZES.0,
            FONT_SIZES.1
        ));
    }
    if let Some(f) = &a.font {
        check_font(f, format)?;
    }
    if a.window_look && (a.title.is_some() || a.font_size.is_some() || a.font.is_some()) {
        return usage(
            "--window-look draws the window's title, text sizes and font: leave out --title, \
             --font-size and --font"
                .into(),
        );
    }
    Ok(())
}

/// --font: a generic family, or a name of letters, digits, spaces, '-',
/// '_' and '.' (nothing that would end the SVG's quoted attribute or the
/// CSS name in it), for a format with text set in a font.
fn check_font(f: &str, format: Format) -> Result<(), CliError> {
    let usage = |m: String| Err(CliError::Usage(m));
    if matches!(format, Format::Gif | Format::Csv) {
        return usage(
            "--font: only a .svg, .pdf or .png sets its text in a chosen font: leave --font out"
                .into(),
        );
    }
    let allowed = |c: char| c.is_alphanumeric() || matches!(c, ' ' | '-' | '_' | '.');
    let name = f.trim();
    if name.is_empty()
        || name.chars().count() > MAX_FONT_NAME
        || !name.chars().all(allowed)
        || name != f
    {
        return usage(format!(
            "--font '{}': give a font family of letters, digits, spaces, '-', '_' and '.' \
             (at most {MAX_FONT_NAME}, no leading or trailing space), or one of {}",
            echo(f),
            GENERIC_FONTS.join(", ")
        ));
    }
    Ok(())
}

/// Whether XML 1.0 allows `c` in a document (tab, newline, carriage
/// return, and the rest from U+0020 but U+FFFE and U+FFFF).
pub fn xml_char(c: char) -> bool {
    matches!(c, '\t' | '\n' | '\r') || (c >= ' ' && c != '\u{FFFE}' && c != '\u{FFFF}')
}
