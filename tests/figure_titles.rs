//! Issue 57: every view's axes titled on both axes, with units where the
//! quantity has one (docs/gui.md: lengths in F₀/k_y, angles in rad or °);
//! the time series' x(t), y(t), |v_r|(t) and E(t) in the model's units
//! (docs/model.md: lengths F₀/k_y, time √(m/k_y), speeds F₀/√(m k_y),
//! energies F₀²/k_y), checked in the SVG `figure` writes.
#![cfg(feature = "gui")]

use crate::common::figure::small_session;
use crate::figure_referee::{SIZES, VIEWS, is_tick, read, svg_of};

#[test]
fn every_view_titles_both_axes() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let session = session.to_str().expect("utf-8 path");
    let mut bad = Vec::new();
    for view in VIEWS.iter().filter(|v| **v != "block") {
        for size in SIZES {
            let what = format!("{view} at {}", size.0);
            let svg = svg_of(dir.path(), session, view, size, &[]);
            let (texts, frames) = read(&svg);
            if !texts.iter().any(|t| t.rotated) {
                bad.push(format!("{what}: no y-axis title"));
            }
            // An x title: under a frame, below its tick labels, no number.
            let x_title = texts.iter().any(|t| {
                !t.rotated
                    && !is_tick(t)
                    && frames.iter().any(|f| {
                        t.bx[1] >= f[3]
                            && t.bx[1] <= f[3] + 3.0 * t.size
                            && (f[0]..=f[2]).contains(&t.mid[0])
                    })
            });
            if !x_title {
                bad.push(format!("{what}: no x-axis title"));
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn the_time_series_axes_name_their_units() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let session = session.to_str().expect("utf-8 path");
    let svg = svg_of(dir.path(), session, "time-series", ("900x600", None), &[]);
    let (texts, _) = read(&svg);
    let titles: Vec<&str> = texts
        .iter()
        .filter(|t| t.rotated)
        .map(|t| t.text.as_str())
        .collect();
    // In full where it fits along its plot, else symbol and unit.
    for (symbol, unit) in [
        ("x", "(F₀/k_y)"),
        ("y", "(F₀/k_y)"),
        ("|v_r|", "(F₀/√(m k_y))"),
        ("E", "(F₀²/k_y)"),
    ] {
        assert!(
            titles
                .iter()
                .any(|t| t.starts_with(symbol) && t.ends_with(unit)),
            "no '{symbol} … {unit}' in {titles:?}"
        );
    }
    assert!(
        texts.iter().any(|t| t.text == "t, time (√(m/k_y))"),
        "no time title with its unit"
    );
    // At a column's size each keeps at least its symbol, with its unit
    // where that fits.
    let svg = svg_of(
        dir.path(),
        session,
        "time-series",
        ("250x200", Some("7")),
        &[],
    );
    let (texts, _) = read(&svg);
    let rotated = texts.iter().filter(|t| t.rotated).count();
    assert_eq!(rotated, 4, "{rotated} y titles");
    assert!(
        texts
            .iter()
            .any(|t| t.text.starts_with("t") && t.text.contains("√(m/k_y)"))
    );
}
