//! Issue 57 items 1–3: figures a referee accepts, checked in the SVG
//! `figure` writes for every view, at 900×600 and at a column's 250×200
//! with `--font-size 7`: the lowest and highest tick labels of each axis
//! within 15 % of the axis's length of its ends; no two texts' boxes
//! (approximated from the font size and the number of characters)
//! overlapping; no `textLength` (no stretched glyphs); every text black;
//! and with `--legend none` no legend entry. Item 4: `--dpi` sets a PNG's
//! pixels per inch, and `--size` goes down to a column's 100 points.
#![cfg(feature = "gui")]

use std::collections::HashMap;
use std::path::Path;

use crate::common::figure::{figure, small_session};

/// Every view `figure` draws.
pub(crate) const VIEWS: [&str; 9] = [
    "plane",
    "block",
    "bifurcation",
    "return-map",
    "events",
    "phase",
    "numerics",
    "time-series",
    "basins",
];

/// The sizes checked: a page's figure, and a column's with small text.
pub(crate) const SIZES: [(&str, Option<&str>); 2] = [("900x600", None), ("250x200", Some("7"))];

/// How far from its axis's end the outer tick label may be, as a share of
/// the axis's length.
const REACH: f64 = 0.15;

/// A `<text>`: its string, size, fill, and its box's corners (x0, y0, x1,
/// y1) as drawn (turned with its group's rotation).
#[derive(Debug)]
pub(crate) struct Text {
    pub(crate) text: String,
    pub(crate) size: f64,
    fill: String,
    pub(crate) rotated: bool,
    pub(crate) mid: [f64; 2],
    pub(crate) bx: [f64; 4],
}

/// A plot's frame (x0, y0, x1, y1).
pub(crate) type Frame = [f64; 4];

fn attrs(e: &quick_xml::events::BytesStart) -> HashMap<String, String> {
    e.attributes()
        .flatten()
        .map(|a| {
            (
                String::from_utf8_lossy(a.key.as_ref()).into_owned(),
                String::from_utf8_lossy(&a.value).into_owned(),
            )
        })
        .collect()
}

fn num(a: &HashMap<String, String>, k: &str) -> f64 {
    a.get(k).and_then(|v| v.parse().ok()).unwrap_or(f64::NAN)
}

/// A character's width in ems, roughly, in a sans-serif font: narrow
/// (i, l, punctuation, space), wide (m, w), digits, the rest.
fn em(c: char) -> f64 {
    match c {
        'i' | 'l' | 'j' | 'I' | '|' | '.' | ',' | ':' | ';' | '\'' | ' ' | '(' | ')' | '['
        | ']' | 'f' | 't' | 'r' => 0.3,
        'm' | 'w' | 'M' | 'W' => 0.8,
        '0'..='9' => 0.55,
        _ => 0.5,
    }
}

/// The box of `text` in `size` points centred on `x` at baseline `y`
/// (its width from its characters' widths in ems, [`em`]), from 0.75 em
/// above the baseline to 0.2 em below; turned by `rot` (degrees about a
/// point).
fn text_box(x: f64, y: f64, size: f64, text: &str, rot: Option<[f64; 3]>) -> [f64; 4] {
    let w = size * text.chars().map(em).sum::<f64>();
    let corners = [
        [x - w / 2.0, y - 0.75 * size],
        [x + w / 2.0, y + 0.2 * size],
    ];
    match rot {
        None => [corners[0][0], corners[0][1], corners[1][0], corners[1][1]],
        Some([deg, cx, cy]) => {
            let (s, c) = deg.to_radians().sin_cos();
            let turn = |[px, py]: [f64; 2]| {
                let (dx, dy) = (px - cx, py - cy);
                [cx + dx * c - dy * s, cy + dx * s + dy * c]
            };
            let (a, b) = (turn(corners[0]), turn(corners[1]));
            [
                a[0].min(b[0]),
                a[1].min(b[1]),
                a[0].max(b[0]),
                a[1].max(b[1]),
            ]
        }
    }
}

/// The texts and plot frames of `svg` (which must parse).
pub(crate) fn read(svg: &str) -> (Vec<Text>, Vec<Frame>) {
    use quick_xml::events::Event;
    let mut r = quick_xml::Reader::from_str(svg);
    let (mut texts, mut frames) = (Vec::new(), Vec::new());
    let mut turns: Vec<Option<[f64; 3]>> = Vec::new();
    let mut open: Option<HashMap<String, String>> = None;
    loop {
        match r.read_event().expect("the SVG parses") {
            Event::Start(e) => {
                let a = attrs(&e);
                match e.name().as_ref() {
                    b"text" => open = Some(a),
                    b"g" => turns.push(a.get("transform").and_then(|t| {
                        let v: Vec<f64> = t
                            .strip_prefix("rotate(")?
                            .strip_suffix(')')?
                            .split_whitespace()
                            .filter_map(|n| n.parse().ok())
                            .collect();
                        (v.len() == 3).then(|| [v[0], v[1], v[2]])
                    })),
                    _ => {}
                }
            }
            Event::Empty(e) if e.name().as_ref() == b"rect" => {
                let a = attrs(&e);
                if a.get("class").is_some_and(|c| c == "plot-frame") {
                    let (x, y) = (num(&a, "x"), num(&a, "y"));
                    frames.push([x, y, x + num(&a, "width"), y + num(&a, "height")]);
                }
            }
            Event::Text(t) => {
                if let Some(a) = open.take() {
                    let text = t.decode().expect("utf-8").into_owned();
                    let (x, y, size) = (num(&a, "x"), num(&a, "y"), num(&a, "font-size"));
                    let rot = turns.iter().flatten().next_back().copied();
                    texts.push(Text {
                        bx: text_box(x, y, size, &text, rot),
                        mid: [x, y - 0.3 * size],
                        fill: a.get("fill").cloned().unwrap_or_default(),
                        rotated: rot.is_some(),
                        text,
                        size,
                    });
                }
            }
            Event::End(e) => match e.name().as_ref() {
                b"text" => open = None,
                b"g" => {
                    turns.pop();
                }
                _ => {}
            },
            Event::Eof => break,
            _ => {}
        }
    }
    (texts, frames)
}

/// Whether `t` is a tick label: a number, an angle or a multiple of π.
pub(crate) fn is_tick(t: &Text) -> bool {
    !t.rotated
        && t.text.chars().any(|c| c.is_ascii_digit() || c == 'π')
        && t.text.chars().all(|c| "0123456789.-−e°π/".contains(c))
}

/// The x tick labels under `f` and the y tick labels left of it.
fn ticks_of<'a>(texts: &'a [Text], f: &Frame) -> (Vec<&'a Text>, Vec<&'a Text>) {
    let below = |t: &&Text| {
        t.bx[1] >= f[3] - 0.3 * t.size
            && t.bx[1] <= f[3] + 0.6 * t.size
            && (f[0] - t.size..=f[2] + t.size).contains(&t.mid[0])
    };
    let left = |t: &&Text| {
        t.mid[0] < f[0]
            && t.bx[2] > f[0] - 2.5 * t.size
            && (f[1] - t.size..=f[3] + t.size).contains(&t.mid[1])
    };
    let ticks = texts.iter().filter(|t| is_tick(t));
    (
        ticks.clone().filter(below).collect(),
        ticks.filter(left).collect(),
    )
}

/// Where the outer labels of each axis with two or more fall short of the
/// axis's ends by more than [`REACH`].
fn tick_reach(what: &str, texts: &[Text], frames: &[Frame]) -> Vec<String> {
    let mut bad = Vec::new();
    for f in frames {
        let (xs, ys) = ticks_of(texts, f);
        let (w, h) = (f[2] - f[0], f[3] - f[1]);
        if xs.len() >= 2 {
            let lo = xs.iter().map(|t| t.mid[0]).fold(f64::INFINITY, f64::min);
            let hi = xs
                .iter()
                .map(|t| t.mid[0])
                .fold(f64::NEG_INFINITY, f64::max);
            if lo - f[0] > REACH * w || f[2] - hi > REACH * w {
                let l: Vec<&str> = xs.iter().map(|t| t.text.as_str()).collect();
                bad.push(format!("{what}: x labels {l:?} {lo:.0}..{hi:.0} on {f:?}"));
            }
        }
        if ys.len() >= 2 {
            let top = ys.iter().map(|t| t.mid[1]).fold(f64::INFINITY, f64::min);
            let bottom = ys
                .iter()
                .map(|t| t.mid[1])
                .fold(f64::NEG_INFINITY, f64::max);
            if top - f[1] > REACH * h || f[3] - bottom > REACH * h {
                let l: Vec<&str> = ys.iter().map(|t| t.text.as_str()).collect();
                bad.push(format!(
                    "{what}: y labels {l:?} {top:.0}..{bottom:.0} on {f:?}"
                ));
            }
        }
    }
    bad
}

/// The pairs of texts whose boxes overlap by more than half a point.
pub(crate) fn overlaps(what: &str, texts: &[Text]) -> Vec<String> {
    let mut bad = Vec::new();
    for (i, a) in texts.iter().enumerate() {
        for b in &texts[i + 1..] {
            let dx = a.bx[2].min(b.bx[2]) - a.bx[0].max(b.bx[0]);
            let dy = a.bx[3].min(b.bx[3]) - a.bx[1].max(b.bx[1]);
            if dx > 0.5 && dy > 0.5 {
                bad.push(format!("{what}: '{}' overlaps '{}'", a.text, b.text));
            }
        }
    }
    bad
}

/// Whether `t` is an axis title: turned (a y axis's), or centred under a
/// frame below its tick labels (an x axis's).
fn is_title(t: &Text, frames: &[Frame]) -> bool {
    t.rotated
        || frames.iter().any(|f| {
            t.bx[1] >= f[3] - 0.3 * t.size
                && t.bx[1] <= f[3] + 2.5 * t.size
                && (f[0]..=f[2]).contains(&t.mid[0])
        })
}

/// `figure --view VIEW` at `size` (and `--font-size`), with `more` flags,
/// from `session`, written to `dir`; its SVG.
pub(crate) fn svg_of(
    dir: &Path,
    session: &str,
    view: &str,
    (size, font): (&str, Option<&str>),
    more: &[&str],
) -> String {
    let out = dir.join(format!("{view}-{size}-{}.svg", more.join("")));
    let mut args = vec!["--view", view, "--session", session, "--size", size];
    if let Some(f) = font {
        args.extend(["--font-size", f]);
    }
    args.extend(more);
    args.extend(["--out", out.to_str().expect("utf-8")]);
    let o = figure(&args);
    assert!(
        o.status.success(),
        "{view} {size}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    std::fs::read_to_string(&out).expect("svg written")
}

#[test]
fn every_view_has_labels_at_its_axes_ends_black_unstretched_text_and_no_overlap() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let session = session.to_str().expect("utf-8 path");
    let mut bad = Vec::new();
    for view in VIEWS {
        for size in SIZES {
            let what = format!("{view} at {}", size.0);
            let svg = svg_of(dir.path(), session, view, size, &[]);
            assert!(!svg.contains("textLength"), "{what}: textLength");
            assert!(!svg.contains("lengthAdjust"), "{what}: lengthAdjust");
            let (texts, frames) = read(&svg);
            if view != "block" {
                assert!(!frames.is_empty(), "{what}: no plot frame");
            }
            // The block is a drawing: its forces' labels take their
            // arrows' colours.
            for t in texts.iter().filter(|_| view != "block") {
                if t.fill != "#000000" {
                    bad.push(format!("{what}: '{}' is {}, not black", t.text, t.fill));
                }
            }
            bad.extend(tick_reach(&what, &texts, &frames));
            bad.extend(overlaps(&what, &texts));
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// Legend entries of the views (their labels, as the views write them).
const ENTRIES: [&str; 16] = [
    "stick",
    "slip, accelerating",
    "slip, decelerating",
    "slip onset",
    "critical ellipse",
    "pull θν",
    "stick phase",
    "slip phase",
    "cobweb",
    "θ' = θ",
    "λ = 0",
    "creep",
    "stick-slip",
    "basin boundary",
    "θ = θν",
    "±θc",
];

#[test]
fn legend_none_draws_no_legend() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let session = session.to_str().expect("utf-8 path");
    let mut bad = Vec::new();
    let mut seen = 0;
    // The block is a drawing, its labels part of it, not a legend.
    for view in VIEWS.iter().filter(|v| **v != "block") {
        for size in SIZES {
            let entries = |svg: &str| -> Vec<String> {
                let (texts, frames) = read(svg);
                texts
                    .into_iter()
                    .filter(|t| !is_tick(t) && !is_title(t, &frames))
                    .filter(|t| ENTRIES.contains(&t.text.as_str()))
                    .map(|t| t.text)
                    .collect()
            };
            seen += entries(&svg_of(dir.path(), session, view, size, &[])).len();
            let none = entries(&svg_of(
                dir.path(),
                session,
                view,
                size,
                &["--legend", "none"],
            ));
            bad.extend(none.iter().map(|t| format!("{view} at {}: '{t}'", size.0)));
        }
    }
    // The check bites: the legends are there without --legend none.
    assert!(seen >= 10, "{seen} legend entries drawn by default");
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn the_kappa_diagram_is_labelled_near_5_and_40() {
    let dir = tempfile::tempdir().expect("temp dir");
    for size in SIZES {
        let out = dir.path().join(format!("k{}.svg", size.0));
        let mut args = vec![
            "--view",
            "bifurcation",
            "--preset",
            "fig3b",
            "--param",
            "kappa",
            "--from",
            "5",
            "--to",
            "40",
            "--size",
            size.0,
        ];
        if let Some(f) = size.1 {
            args.extend(["--font-size", f]);
        }
        args.extend(["--out", out.to_str().expect("utf-8")]);
        let o = figure(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let (texts, frames) = read(&std::fs::read_to_string(&out).expect("svg"));
        let bad = tick_reach(size.0, &texts, &frames);
        assert!(bad.is_empty(), "{}", bad.join("\n"));
        // No θ = θν: θν = 1.1 lies far above the diagram's θ.
        assert!(!texts.iter().any(|t| t.text == "θ = θν"), "{}", size.0);
    }
}

#[test]
fn dpi_sets_a_pngs_pixels_and_sizes_go_down_to_100_points() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let session = session.to_str().expect("utf-8 path");
    let out = dir.path().join("d.png");
    let o = figure(&[
        "--view",
        "bifurcation",
        "--session",
        session,
        "--size",
        "250x200",
        "--dpi",
        "288",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out).expect("a PNG");
    assert_eq!((img.width(), img.height()), (1000, 800));
    // Refused with one line naming the flag: too low, too many pixels, not a PNG.
    for (dpi, name, size) in [
        ("10", "e.png", "900x600"),
        ("600", "f.png", "10000x200"),
        ("300", "g.svg", "900x600"),
    ] {
        let out = dir.path().join(name);
        let o = figure(&[
            "--view",
            "bifurcation",
            "--size",
            size,
            "--dpi",
            dpi,
            "--out",
            out.to_str().expect("utf-8"),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "--dpi {dpi}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains("--dpi"), "{err}");
        assert!(!out.exists());
    }
    // A column's figure, 100 points a side, of every view; 99 refused.
    for view in VIEWS {
        let svg = svg_of(dir.path(), session, view, ("100x100", Some("5")), &[]);
        assert!(svg.contains("width=\"100\""), "{view}");
    }
    let out = dir.path().join("small.svg");
    let o = figure(&[
        "--view",
        "plane",
        "--size",
        "99x100",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--size"));
}
