//! Issue 57 item 3: `figure --font FAMILY` names the family in the SVG
//! (quoted, the sans-serif faces after it; a generic family as it is),
//! with no per-glyph stretching (`textLength`); the PNG is drawn in it or,
//! where the system lacks it, in the built-in sans-serif with one note on
//! stderr; a family that would break the SVG's quoting, or a format with
//! no text, is refused with one line naming --font (exit 2).
#![cfg(feature = "gui")]

use crate::common::figure::{figure, small_session};

/// The root element's font-family.
fn root_family(svg: &str) -> String {
    let at = svg.find("<svg ").expect("an svg element");
    let tag = &svg[at..at + svg[at..].find('>').expect("a tag")];
    let v = tag.split("font-family=\"").nth(1).expect("a font-family");
    v[..v.find('"').expect("quoted")].to_owned()
}

#[test]
fn the_svg_names_the_font_asked_for() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let session = session.to_str().expect("utf-8 path");
    for (font, family) in [
        (
            "DejaVu Serif",
            "'DejaVu Serif', DejaVu Sans, Helvetica, Arial, sans-serif",
        ),
        ("serif", "serif"),
        ("monospace", "monospace"),
    ] {
        let out = dir.path().join(format!("{font}.svg"));
        let o = figure(&[
            "--view",
            "return-map",
            "--session",
            session,
            "--font",
            font,
            "--out",
            out.to_str().expect("utf-8"),
        ]);
        assert!(
            o.status.success(),
            "{font}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let svg = std::fs::read_to_string(&out).expect("svg");
        assert_eq!(root_family(&svg), family, "{font}");
        assert!(!svg.contains("textLength"), "{font}: stretched glyphs");
    }
}

#[test]
fn a_png_in_a_missing_font_says_so_once() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let out = dir.path().join("x.png");
    let o = figure(&[
        "--view",
        "return-map",
        "--session",
        session.to_str().expect("utf-8 path"),
        "--font",
        "No Such Font 57",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let notes: Vec<&str> = err
        .lines()
        .filter(|l| l.contains("No Such Font 57"))
        .collect();
    assert_eq!(notes.len(), 1, "{err}");
    assert!(notes[0].starts_with("note: --font"), "{err}");
    assert_eq!(&std::fs::read(&out).expect("png")[1..4], b"PNG");
}

#[test]
fn a_font_that_would_break_the_svg_is_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let svg = dir.path().join("x.svg");
    let gif = dir.path().join("x.gif");
    let (svg, gif) = (svg.to_str().expect("utf-8"), gif.to_str().expect("utf-8"));
    for (font, out) in [
        ("Times\" onload=\"x", svg),
        ("Times'", svg),
        ("a<b", svg),
        ("", svg),
        (" Times", svg),
        ("Times; color: red", svg),
        ("serif", gif),
    ] {
        let mut args = vec!["--view", "return-map", "--font", font, "--out", out];
        if out == gif {
            args.extend(["--play", "--frames", "2"]);
        }
        let o = figure(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{font:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{font:?}: {err}");
        assert!(err.contains("--font"), "{font:?}: {err}");
    }
    assert!(!std::path::Path::new(svg).exists());
}
