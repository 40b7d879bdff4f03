//! Issue 57: `figure --out x.csv` for every view that draws data writes
//! what the figure draws, with the `#` lines the other CSVs have, and a
//! header whose fields every row has; the numerics view's CSV holds the
//! work-precision rows its chart draws.
#![cfg(feature = "gui")]

use crate::common::figure::{figure, small_session};

/// A CSV line's fields (quoted fields may hold commas).
fn fields(line: &str) -> usize {
    let (mut n, mut quoted) = (1, false);
    for c in line.chars() {
        match c {
            '"' => quoted = !quoted,
            ',' if !quoted => n += 1,
            _ => {}
        }
    }
    n
}

#[test]
fn every_view_writes_the_data_it_draws_as_csv() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let session = session.to_str().expect("utf-8 path");
    for (view, first) in [
        ("plane", "t,x,y"),
        ("block", "t,x,y"),
        ("time-series", "t,x,y"),
        ("events", ""),
        ("return-map", "kind,theta,theta_next"),
        ("phase", ""),
        ("bifurcation", ""),
    ] {
        let out = dir.path().join(format!("{view}.csv"));
        let o = figure(&[
            "--view",
            view,
            "--session",
            session,
            "--out",
            out.to_str().expect("utf-8"),
        ]);
        assert!(
            o.status.success(),
            "{view}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let csv = std::fs::read_to_string(&out).expect("csv");
        assert!(csv.starts_with('#'), "{view}: no # lines");
        let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
        let header = lines.next().expect("a header");
        assert!(header.starts_with(first), "{view}: {header}");
        let n = fields(header);
        let rows: Vec<&str> = lines.collect();
        assert!(!rows.is_empty(), "{view}: no rows");
        for r in &rows {
            assert_eq!(fields(r), n, "{view}: '{r}' under '{header}'");
        }
        if view == "return-map" {
            assert!(rows.iter().any(|r| r.starts_with("curve,")), "no curve");
            assert!(rows.iter().any(|r| r.starts_with("orbit,")), "no orbit");
        }
    }
}

#[test]
fn the_numerics_csv_holds_the_rows_its_chart_draws() {
    let dir = tempfile::tempdir().expect("temp dir");
    let session = small_session(dir.path());
    let out = dir.path().join("n.csv");
    let o = figure(&[
        "--view",
        "numerics",
        "--session",
        session.to_str().expect("utf-8 path"),
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(&out).expect("csv");
    assert!(csv.starts_with('#'), "no # lines");
    assert!(csv.contains("view: numerics"), "the # lines name the view");
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let header = lines.next().expect("a header");
    assert!(
        header.starts_with("source,method,kind,setting,points,failed,max_error"),
        "{header}"
    );
    let n = fields(header);
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert!(
        rows.iter().all(|r| r.len() == n),
        "a row without {n} fields"
    );
    // The run measured on the figure's parameters, and the committed chart
    // behind it, with every method the chart draws a curve of.
    for source in ["run", "committed"] {
        let of: Vec<&Vec<&str>> = rows.iter().filter(|r| r[0] == source).collect();
        assert!(!of.is_empty(), "no {source} rows");
        for method in ["dop853", "dp54", "rk4"] {
            assert!(
                of.iter().any(|r| r[1] == method),
                "no {source} row of {method}"
            );
        }
        // A measured row has its error and cost as numbers.
        assert!(of.iter().any(|r| r[6].parse::<f64>().is_ok_and(|e| e > 0.0)
            && r[n - 1].parse::<f64>().is_ok_and(|c| c > 0.0)));
    }
}

/// Issue 55: `phase` with no flags at all is the window's default grid,
/// as `figure --view phase` draws it: the same cells, row for row.
#[test]
fn phase_without_flags_is_the_grid_figure_view_phase_draws() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (a, b) = (dir.path().join("a.csv"), dir.path().join("b.csv"));
    let phase = std::process::Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args(["phase", "--out", a.to_str().expect("utf-8")])
        .output()
        .expect("runs");
    assert!(
        phase.status.success(),
        "{}",
        String::from_utf8_lossy(&phase.stderr)
    );
    let o = figure(&["--view", "phase", "--out", b.to_str().expect("utf-8")]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows = |p: &std::path::Path| -> Vec<String> {
        let text = std::fs::read_to_string(p).expect("csv");
        text.lines()
            .filter(|l| !l.starts_with('#'))
            .map(str::to_string)
            .collect()
    };
    let (a, b) = (rows(&a), rows(&b));
    // A header and the window's 30 × 30 cells.
    assert_eq!(a.len(), 1 + 30 * 30);
    assert_eq!(a, b);
}
