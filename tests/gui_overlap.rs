//! Projector mode (text ×1.5) leaves no text on top of another, read off
//! the drawn shapes: every view is drawn by the window's code into an SVG
//! (the figure path, in-process) at a window's and a tile's size, and the
//! boxes of its `<text>` elements (each at the width egui laid it out at,
//! turned as drawn, cut by its clip rectangle) are checked against each
//! other, against the picture's edge, and, for an axis title turned on its side (the events view's
//! count label), against the plot it names: it stays beside that plot's
//! frame instead of running past it into the line or plot above or below.
//! And the whole window on a projector, 1024 × 768 at text 1.5 in tabs and
//! in tiles (egui_kittest, the text the frame painted): no text on top of
//! another (a view's title under its buttons, the status bar's words),
//! at least four labelled ticks on each axis of every plot, and a status
//! bar of one line.
#![cfg(feature = "gui")]

use crate::window;

use std::collections::HashMap;

use eframe::egui;
use oneblock::app::figure::{Figure, svg};
use oneblock::app::{Layout, Recorder, Settings, ViewKind};
use window::{painted_texts, tick_labels, window_with_slips};

/// A text's box on the picture, in points, and its string.
#[derive(Clone, Debug)]
struct TextBox {
    min: [f64; 2],
    max: [f64; 2],
    text: String,
    rotated: bool,
    /// Its box before its clip rectangle cut it.
    whole: [f64; 4],
}

/// A rectangle `[x0, y0, x1, y1]`.
type Frame = [f64; 4];

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
    a.get(k).and_then(|v| v.parse().ok()).unwrap_or(0.0)
}

/// The `rotate(deg cx cy)` of a `transform`.
fn rotation(t: &str) -> Option<[f64; 3]> {
    let inner = t.strip_prefix("rotate(")?.strip_suffix(')')?;
    let v: Vec<f64> = inner
        .split([' ', ','])
        .filter_map(|x| x.parse().ok())
        .collect();
    (v.len() == 3).then(|| [v[0], v[1], v[2]])
}

/// The SVG's text boxes (from the baseline: ascent 0.75 and, for text with
/// a descending glyph, descent 0.2 of the font size; egui's laid-out width) and its clip rectangles, which
/// are the plots' frames and the picture.
fn boxes(svg: &str) -> (Vec<TextBox>, Vec<Frame>) {
    use quick_xml::events::Event;
    let mut r = quick_xml::Reader::from_str(svg);
    let (mut out, mut clips) = (Vec::new(), Vec::new());
    let mut turn: Vec<Option<[f64; 3]>> = Vec::new();
    // Each open group's clip rectangle (by its clipPath's number), if any.
    let mut clipped: Vec<Option<usize>> = Vec::new();
    let mut open: Option<HashMap<String, String>> = None;
    let mut in_clip = false;
    loop {
        match r.read_event().expect("the SVG parses") {
            Event::Start(e) => {
                match e.name().as_ref() {
                    b"text" => open = Some(attrs(&e)),
                    b"g" => {
                        let a = attrs(&e);
                        turn.push(a.get("transform").and_then(|t| rotation(t)));
                        clipped.push(a.get("clip-path").and_then(|c| {
                            c.strip_prefix("url(#c")?.strip_suffix(')')?.parse().ok()
                        }));
                    }
                    b"clipPath" => in_clip = true,
                    _ => {}
                }
            }
            Event::Empty(e) if in_clip && e.name().as_ref() == b"rect" => {
                let a = attrs(&e);
                let (x, y) = (num(&a, "x"), num(&a, "y"));
                clips.push([x, y, x + num(&a, "width"), y + num(&a, "height")]);
            }
            Event::Text(t) => {
                if let Some(a) = &open {
                    // x is the middle of the row egui laid out, data-width its width.
                    let w = num(a, "data-width");
                    let (x, y, size) = (num(a, "x") - 0.5 * w, num(a, "y"), num(a, "font-size"));
                    let text = t.decode().map(|s| s.into_owned()).unwrap_or_default();
                    // Below the baseline only where a glyph descends (a
                    // number has none).
                    let descent = if text.contains(|c| "gjpqyQ,;()[]{}|_/µ".contains(c)) {
                        0.2 * size
                    } else {
                        0.0
                    };
                    let corners = [
                        [x, y - 0.75 * size],
                        [x + w, y - 0.75 * size],
                        [x, y + descent],
                        [x + w, y + descent],
                    ];
                    let rot = turn.iter().flatten().next_back().copied();
                    let turned: Vec<[f64; 2]> = corners
                        .iter()
                        .map(|&[px, py]| match rot {
                            Some([deg, cx, cy]) => {
                                let (s, c) = deg.to_radians().sin_cos();
                                let (dx, dy) = (px - cx, py - cy);
                                [cx + dx * c - dy * s, cy + dx * s + dy * c]
                            }
                            None => [px, py],
                        })
                        .collect();
                    let fold = |f: fn(f64, f64) -> f64, k: usize, init: f64| {
                        turned.iter().map(|p| p[k]).fold(init, f)
                    };
                    let mut b = TextBox {
                        min: [fold(f64::min, 0, f64::MAX), fold(f64::min, 1, f64::MAX)],
                        max: [fold(f64::max, 0, f64::MIN), fold(f64::max, 1, f64::MIN)],
                        text,
                        rotated: rot.is_some(),
                        whole: [0.0; 4],
                    };
                    b.whole = [b.min[0], b.min[1], b.max[0], b.max[1]];
                    // What its clip rectangle lets show; nothing, if it lies
                    // wholly outside (egui_plot's labels past an axis's end).
                    let clip = clipped
                        .iter()
                        .flatten()
                        .next_back()
                        .and_then(|&i| clips.get(i));
                    if let Some(&[x0, y0, x1, y1]) = clip {
                        b.min = [b.min[0].max(x0), b.min[1].max(y0)];
                        b.max = [b.max[0].min(x1), b.max[1].min(y1)];
                    }
                    if b.min[0] < b.max[0] && b.min[1] < b.max[1] {
                        out.push(b);
                    }
                }
            }
            Event::End(e) => match e.name().as_ref() {
                b"text" => open = None,
                b"g" => {
                    turn.pop();
                    clipped.pop();
                }
                b"clipPath" => in_clip = false,
                _ => {}
            },
            Event::Eof => break,
            _ => {}
        }
    }
    (out, clips)
}

/// Whether two boxes overlap by more than `slack` points each way.
fn overlap(a: &TextBox, b: &TextBox, slack: f64) -> bool {
    a.min[0] + slack < b.max[0]
        && b.min[0] + slack < a.max[0]
        && a.min[1] + slack < b.max[1]
        && b.min[1] + slack < a.max[1]
}

/// Small jobs (every view quick), projector mode as its switch sets it.
fn projector_settings() -> Settings {
    let mut s = Settings {
        columns: 60,
        sweep_transient: 60,
        sweep_keep: 40,
        trajectory_cycles: 40,
        projector: true,
        font_scale: 1.5,
        dark: false,
        ..Settings::default()
    };
    s.phase.theta_nu_steps = 6;
    s.phase.kappa_steps = 6;
    s
}

/// Every overlap in `view` drawn over `w`×`h` points, as messages.
fn overlaps(view: ViewKind, settings: &Settings, (w, h): (f32, f32)) -> Vec<String> {
    let fig = Figure {
        view,
        settings: settings.clone(),
        zoom: Vec::new(),
        theta_nu: None,
        theta: None,
        size: egui::vec2(w, h),
        // With the current parameters' lines and legend entry: the most
        // a figure draws.
        crosshair: true,
        look: Default::default(),
        overlays: Default::default(),
        session: None,
    };
    let svg = svg(&fig).expect("the figure is drawn");
    let (texts, frames) = boxes(&svg);
    assert!(!texts.is_empty(), "{view:?}: no text drawn");
    let at = |m: &str| format!("{view:?} at {w}x{h}: {m}");
    let mut bad = Vec::new();
    // The x axis's title, under the plot, is in the picture: the plots
    // above did not push it out of the tile.
    let bottom = match view {
        ViewKind::Plane => Some("position (F₀/k_y)"),
        ViewKind::Bifurcation => Some("θν, pull direction"),
        ViewKind::ReturnMap => Some("θ, this onset"),
        ViewKind::TimeSeries => Some("t, time"),
        ViewKind::Numerics => Some("max map error"),
        _ => None,
    };
    if let Some(title) = bottom
        && !texts.iter().any(|t| t.text.contains(title))
    {
        bad.push(at(&format!(
            "the x axis's title '{title}' is not in the picture"
        )));
    }
    for (i, a) in texts.iter().enumerate() {
        let [x0, y0, x1, y1] = a.whole;
        let outside = x0 < -0.5 || y0 < -0.5 || x1 > f64::from(w) + 0.5 || y1 > f64::from(h) + 0.5;
        if outside {
            bad.push(at(&format!("'{}' leaves the picture {a:?}", a.text)));
        }
        for b in &texts[i + 1..] {
            if overlap(a, b, 0.5) {
                bad.push(at(&format!("'{}' overlaps '{}'", a.text, b.text)));
            }
        }
        if a.rotated {
            // The plot it names: the frame just right of it at its height.
            let mid = (a.min[1] + a.max[1]) / 2.0;
            let plot = frames
                .iter()
                .filter(|f| f[0] >= a.max[0] - 0.5 && f[1] <= mid && mid <= f[3])
                .min_by(|f, g| f[0].total_cmp(&g[0]));
            if let Some(f) = plot
                && (a.min[1] < f[1] - 2.0 || a.max[1] > f[3] + 2.0)
            {
                bad.push(at(&format!(
                    "the turned title '{}' ({:.0}..{:.0}) runs past its plot ({:.0}..{:.0})",
                    a.text, a.min[1], a.max[1], f[1], f[3]
                )));
            }
        }
    }
    bad
}

#[test]
fn projector_text_overlaps_no_other_text_in_any_view() {
    let s = projector_settings();
    let mut bad = Vec::new();
    for view in ViewKind::ALL {
        // A window's view, and a tile of a 2×2 layout on a 1280×800 screen.
        for size in [(900.0, 600.0), (620.0, 380.0)] {
            bad.extend(overlaps(view, &s, size));
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn the_box_reader_sees_an_overlap_when_there_is_one() {
    // The check itself: two labels drawn at one place overlap, a turned
    // title's box is tall and narrow.
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg"><defs><clipPath id="c0"><rect x="0" y="0" width="100" height="100"/></clipPath></defs>
<text x="30" y="20" font-size="10" data-width="40">left</text>
<text x="50" y="22" font-size="10" data-width="40">right</text>
<g transform="rotate(-90.00 5 80)"><text x="30" y="80" font-size="10" data-width="50">count (log)</text></g></svg>"#;
    let (t, frames) = boxes(svg);
    assert_eq!(frames, vec![[0.0, 0.0, 100.0, 100.0]]);
    assert!(overlap(&t[0], &t[1], 0.5));
    assert!(!overlap(&t[0], &t[2], 0.5));
    let turned = &t[2];
    assert!(turned.rotated);
    assert!(
        (turned.max[1] - turned.min[1] - 50.0).abs() < 1e-9,
        "{turned:?}"
    );
    assert!(
        (turned.max[0] - turned.min[0] - 9.5).abs() < 1e-9,
        "{turned:?}"
    );
}

/// Every pair of painted texts that overlap (by more than a point each
/// way), each text cut to the clip rectangle it was painted in.
fn painted_overlaps(h: &egui_kittest::Harness<'static, oneblock::app::Explorer>) -> Vec<String> {
    let texts: Vec<(String, egui::Rect)> = painted_texts(h)
        .into_iter()
        .filter(|(t, r)| !t.trim().is_empty() && r.width() > 0.5 && r.height() > 0.5)
        .collect();
    let mut bad = Vec::new();
    for (i, (a, ra)) in texts.iter().enumerate() {
        for (b, rb) in &texts[i + 1..] {
            let o = ra.intersect(*rb);
            if o.width() > 1.0 && o.height() > 1.0 {
                bad.push(format!("'{a}' {ra:?} overlaps '{b}' {rb:?}"));
            }
        }
    }
    bad
}

/// A projector's window: 1024 × 768, text 1.5, the side panel shown.
fn projector_window(
    layout: Layout,
    tab: ViewKind,
    rec: &Recorder,
) -> egui_kittest::Harness<'static, oneblock::app::Explorer> {
    let s = Settings {
        layout,
        tab,
        ..projector_settings()
    };
    window_with_slips(s, rec, (1024.0, 768.0))
}

#[test]
fn at_1024x768_and_text_1_5_no_text_overprints_every_axis_has_four_ticks_and_the_status_bar_is_one_line()
 {
    let mut bad = Vec::new();
    let cases = ViewKind::ALL
        .iter()
        .map(|v| (Layout::Tabs, *v))
        .chain([(Layout::Tiles, ViewKind::Plane)]);
    for (layout, tab) in cases {
        let rec = Recorder::new();
        let h = projector_window(layout, tab, &rec);
        let what = match layout {
            Layout::Tabs => format!("{} tab", tab.key()),
            Layout::Tiles => "tiles".into(),
        };
        bad.extend(
            painted_overlaps(&h)
                .into_iter()
                .map(|m| format!("{what}: {m}")),
        );
        for (plot, xs, ys) in tick_labels(&h) {
            // The time series' upper plots share the energy plot's t axis.
            let shared_x = matches!(plot, "time-series-x" | "time-series-y" | "time-series-vr");
            if xs.len() < 4 && !(shared_x && xs.is_empty()) {
                bad.push(format!("{what}, {plot}: x tick labels {xs:?}"));
            }
            if ys.len() < 4 {
                bad.push(format!("{what}, {plot}: y tick labels {ys:?}"));
            }
        }
        let row = h.ctx.global_style().text_styles[&egui::TextStyle::Body].size;
        let status = h.state().status_rect;
        if status.height() > 2.2 * row {
            bad.push(format!(
                "{what}: the status bar is {:.0} points tall (a line is {row:.0})",
                status.height()
            ));
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
