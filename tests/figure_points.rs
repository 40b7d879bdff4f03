//! Issue 57: the bifurcation diagram's points as vector marks in a
//! figure's SVG (no raster image of them), one dot per distinct point of
//! each column, in a path per colour; a 400-column Fig. 3b diagram has at
//! least one mark per column and as many as its CSV's distinct points on
//! the diagram's grid, in a file of reasonable size.
#![cfg(feature = "gui")]

use std::collections::HashSet;

use crate::common::figure::{figure, session_of, small_settings};

#[test]
fn a_400_column_diagram_draws_its_points_as_vector_marks() {
    let dir = tempfile::tempdir().expect("temp dir");
    let settings = oneblock::app::Settings {
        columns: 400,
        ..small_settings()
    };
    let session = session_of(dir.path(), settings);
    let session = session.to_str().expect("utf-8 path");
    let svg_path = dir.path().join("d.svg");
    let o = figure(&[
        "--view",
        "bifurcation",
        "--session",
        session,
        "--out",
        svg_path.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let svg = std::fs::read_to_string(&svg_path).expect("svg");
    assert!(
        !svg.contains("data-series=\"bifurcation:image\""),
        "the points are a raster image"
    );
    // Each dot is one subpath "Mx y" of a points path.
    let mut marks = 0;
    let mut columns = HashSet::new();
    for el in svg
        .split('<')
        .filter(|e| e.contains("data-series=\"bifurcation:points\""))
    {
        let d = el
            .split("d=\"")
            .nth(1)
            .and_then(|s| s.split('"').next())
            .expect("a d");
        for sub in d.split('M').skip(1) {
            marks += 1;
            let x: f64 = sub
                .split(' ')
                .next()
                .and_then(|v| v.parse().ok())
                .expect("x");
            columns.insert((x * 10.0).round() as i64);
        }
    }
    assert!(marks >= 400, "{marks} vector marks");
    assert!(
        columns.len() >= 380,
        "{} columns with a mark",
        columns.len()
    );
    // As many as the CSV's points, merged where they coincide on a grid
    // of 1680 rows (not more: no point drawn twice).
    let csv_path = dir.path().join("d.csv");
    let o = figure(&[
        "--view",
        "bifurcation",
        "--session",
        session,
        "--out",
        csv_path.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(&csv_path).expect("csv");
    let rows: Vec<&str> = csv
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .collect();
    assert!(
        rows.len() >= marks,
        "{} CSV rows, {marks} marks",
        rows.len()
    );
    // A file a journal takes: well under a megabyte.
    assert!(svg.len() < 1_000_000, "{} bytes", svg.len());
}
