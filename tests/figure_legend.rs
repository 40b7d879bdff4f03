//! Issue 57's legend where you want it: `figure --legend inside` (the
//! corner over the least data) and `inside-top-right` … `inside-bottom-left`
//! put every legend box inside its plot's frame, boxes apart and no two
//! texts overlapping; `outside` (the default) keeps them out of the frames;
//! at a column's 250 × 200 points with `--font-size 7` the legends take
//! little of the figure, the return map's lines and basin band are thin,
//! and the diagram keeps its λ strip (or says on stderr it left it out).
//! Read from the invisible `<rect class="legend">` and
//! `<rect class="plot-frame">` the SVG carries.
#![cfg(feature = "gui")]

use std::collections::HashMap;

use crate::common::figure::{figure, small_session};
use crate::figure_referee::{Frame, SIZES, VIEWS, overlaps, read, svg_of};

/// The legend boxes of `svg`: (x0, y0, x1, y1) and whether inside.
fn legends(svg: &str) -> Vec<([f64; 4], bool)> {
    use quick_xml::events::Event;
    let mut r = quick_xml::Reader::from_str(svg);
    let mut out = Vec::new();
    loop {
        match r.read_event().expect("the SVG parses") {
            Event::Empty(e) if e.name().as_ref() == b"rect" => {
                let a: HashMap<String, String> = e
                    .attributes()
                    .flatten()
                    .map(|a| {
                        (
                            String::from_utf8_lossy(a.key.as_ref()).into_owned(),
                            String::from_utf8_lossy(&a.value).into_owned(),
                        )
                    })
                    .collect();
                if a.get("class").is_some_and(|c| c == "legend") {
                    let n = |k: &str| a[k].parse::<f64>().expect("a number");
                    let (x, y) = (n("x"), n("y"));
                    let b = [x, y, x + n("width"), y + n("height")];
                    out.push((b, a["data-place"] == "inside"));
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    out
}

/// The overlap of two boxes' areas.
fn overlap(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    let dx = a[2].min(b[2]) - a[0].max(b[0]);
    let dy = a[3].min(b[3]) - a[1].max(b[1]);
    if dx > 0.0 && dy > 0.0 { dx * dy } else { 0.0 }
}

fn within(b: &[f64; 4], f: &Frame) -> bool {
    b[0] >= f[0] - 0.5 && b[1] >= f[1] - 0.5 && b[2] <= f[2] + 0.5 && b[3] <= f[3] + 0.5
}

#[test]
fn inside_legends_lie_in_their_plots_apart_and_outside_ones_out_of_them() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let session = session.to_str().expect("utf-8 path");
    let (mut bad, mut inside_seen, mut outside_seen) = (Vec::new(), 0, 0);
    for view in VIEWS.iter().filter(|v| **v != "block") {
        for size in SIZES {
            let what = format!("{view} at {}", size.0);
            let svg = svg_of(dir.path(), session, view, size, &["--legend", "inside"]);
            let (texts, frames) = read(&svg);
            let boxes = legends(&svg);
            for (i, (b, inside)) in boxes.iter().enumerate() {
                if *inside {
                    inside_seen += 1;
                    if !frames.iter().any(|f| within(b, f)) {
                        bad.push(format!("{what}: legend {b:?} in no frame of {frames:?}"));
                    }
                }
                for (c, _) in &boxes[i + 1..] {
                    if overlap(b, c) > 0.5 {
                        bad.push(format!("{what}: legends {b:?} and {c:?} overlap"));
                    }
                }
            }
            bad.extend(overlaps(&format!("{what} inside"), &texts));
            let svg = svg_of(dir.path(), session, view, size, &[]);
            let (_, frames) = read(&svg);
            for (b, inside) in legends(&svg) {
                outside_seen += 1;
                if inside || frames.iter().any(|f| overlap(&b, f) > 0.5) {
                    bad.push(format!("{what}: outside legend {b:?} over a frame"));
                }
            }
        }
    }
    assert!(inside_seen >= 12, "{inside_seen} inside legends drawn");
    assert!(outside_seen >= 12, "{outside_seen} outside legends drawn");
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn a_named_corner_is_the_corner_the_legend_takes() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let session = session.to_str().expect("utf-8 path");
    for (corner, left, top) in [
        ("inside-top-right", false, true),
        ("inside-top-left", true, true),
        ("inside-bottom-right", false, false),
        ("inside-bottom-left", true, false),
    ] {
        let svg = svg_of(
            dir.path(),
            session,
            "plane",
            ("900x600", None),
            &["--legend", corner],
        );
        let (_, frames) = read(&svg);
        let boxes = legends(&svg);
        assert_eq!(boxes.len(), 1, "{corner}: {boxes:?}");
        let (b, f) = (boxes[0].0, frames[0]);
        let near = |a: f64, b: f64| (a - b).abs() < 12.0;
        let x_ok = if left {
            near(b[0], f[0])
        } else {
            near(b[2], f[2])
        };
        let y_ok = if top {
            near(b[1], f[1])
        } else {
            near(b[3], f[3])
        };
        assert!(x_ok && y_ok && within(&b, &f), "{corner}: {b:?} in {f:?}");
    }
    // A corner nobody spells is refused with one line naming the flag.
    let out = dir.path().join("x.svg");
    let o = figure(&[
        "--legend",
        "inside-middle",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--legend"));
}

/// The widest `stroke-width` of the SVG's paths.
fn widest_stroke(svg: &str) -> f64 {
    svg.split("stroke-width=\"")
        .skip(1)
        .filter_map(|s| s.split('"').next()?.parse::<f64>().ok())
        .fold(0.0, f64::max)
}

#[test]
fn a_columns_figure_keeps_its_legend_small_its_lines_thin_and_its_lambda_strip() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let session = session.to_str().expect("utf-8 path");
    let small = ("250x200", Some("7"));
    for legend in ["inside", "outside"] {
        for view in ["return-map", "bifurcation", "plane", "time-series"] {
            let svg = svg_of(dir.path(), session, view, small, &["--legend", legend]);
            let area: f64 = legends(&svg)
                .iter()
                .map(|(b, _)| (b[2] - b[0]) * (b[3] - b[1]))
                .sum();
            assert!(
                area < 0.3 * 250.0 * 200.0,
                "{view} --legend {legend}: legends take {area:.0} of 50000 pt²"
            );
            // Lines, markers' outlines and the basin band scaled down
            // with the text (the band was 6 points thick).
            let w = widest_stroke(&svg);
            assert!(w <= 4.0, "{view} --legend {legend}: a stroke {w} wide");
        }
    }
    // The λ strip is drawn under the diagram at that size, or stderr says
    // it was left out.
    let out = dir.path().join("strip.svg");
    let o = figure(&[
        "--view",
        "bifurcation",
        "--session",
        session,
        "--size",
        "250x200",
        "--font-size",
        "7",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success());
    let (_, frames) = read(&std::fs::read_to_string(&out).expect("svg"));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        frames.len() == 2 || err.contains("λ strip"),
        "{frames:?} {err}"
    );
}
