//! Every row of a phase CSV has as many fields as its header (issue 56):
//! with `--seeds`, a cell whose attractors were not counted (the exit
//! arc's graph could not be built) or that failed had a row one field
//! short, its `attractors` left out instead of left empty. The window's
//! export of the grid is held to the same.

#![allow(clippy::unwrap_used)]

use crate::cli_support::*;

/// `oneblock phase` with `flags` to stdout: its header and rows, each
/// row checked to have the header's number of fields.
fn phase_csv(flags: &[&str]) -> (Vec<String>, Vec<Vec<String>>) {
    let o = oneblock(&[&["phase", "--out", "-"], flags].concat());
    assert_ok(&o);
    let (header, rows) = parse_csv(&stdout(&o));
    assert!(!rows.is_empty(), "{flags:?}");
    for row in &rows {
        assert_eq!(
            row.len(),
            header.len(),
            "{flags:?}: {row:?} under {header:?}"
        );
    }
    (header, rows)
}

/// The field of `row` under column `name`.
fn field<'a>(header: &[String], row: &'a [String], name: &str) -> &'a str {
    let i = header.iter().position(|h| h == name).unwrap();
    &row[i]
}

#[test]
fn failed_and_uncounted_cells_have_an_empty_attractors_field() {
    // The grid: pure creep, the θν = π/2 cell fails.
    let creep = [
        "--preset",
        "creep",
        "--kappa-from",
        "4.142088816959393",
        "--kappa-to",
        "0.14975971782844966",
        "--kappa-steps",
        "1",
        "--theta-nu-steps",
        "4",
        "--transient",
        "28",
        "--keep",
        "42",
        "--seeds",
        "3",
    ];
    // RK4 at a step too long for the exit arc's graph (every cell that
    // runs is uncounted) and for the larger κ (those fail).
    let coarse = [
        "--method",
        "rk4",
        "--step",
        "0.18",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--kappa-from",
        "10",
        "--kappa-to",
        "40",
        "--kappa-steps",
        "4",
        "--theta-nu-from",
        "0.5",
        "--theta-nu-to",
        "1.4",
        "--theta-nu-steps",
        "3",
        "--seeds",
        "1",
    ];
    let (mut failed, mut uncounted, mut counted) = (0, 0, 0);
    for flags in [&creep[..], &coarse[..]] {
        let (header, rows) = phase_csv(flags);
        assert_eq!(header.last().unwrap(), "attractors");
        for row in &rows {
            let n = field(&header, row, "attractors");
            match (field(&header, row, "class"), n) {
                ("failed", "") => failed += 1,
                ("failed", n) => panic!("a failed cell with {n} attractors"),
                (_, "") => uncounted += 1,
                (_, n) => {
                    assert!(n.parse::<usize>().unwrap() >= 1);
                    counted += 1;
                }
            }
        }
    }
    assert!(
        failed >= 2 && uncounted >= 1 && counted >= 1,
        "{failed} {uncounted} {counted}"
    );
}

#[test]
fn counted_cells_and_grids_without_seeds_keep_their_shape() {
    // κ = 10's hysteresis: one cell with two attractors.
    let flags = [
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--kappa-from",
        "10",
        "--kappa-to",
        "10",
        "--kappa-steps",
        "1",
        "--theta-nu-from",
        "1.35",
        "--theta-nu-to",
        "1.43",
        "--theta-nu-steps",
        "3",
    ];
    let (header, rows) = phase_csv(&[&flags[..], &["--seeds", "8"]].concat());
    let counts: Vec<&str> = rows
        .iter()
        .map(|r| field(&header, r, "attractors"))
        .collect();
    assert_eq!(counts, ["1", "2", "1"]);
    let (plain, rows) = phase_csv(&flags);
    assert_eq!(plain.len() + 1, header.len());
    assert!(!plain.iter().any(|h| h == "attractors"));
    assert_eq!(rows.len(), 3);
}

/// The window's export: the column is there when any cell's attractors
/// were asked for, and every row fills it.
#[cfg(feature = "gui")]
#[test]
fn the_windows_export_has_the_same_shape() {
    use oneblock::app::export::phase_csv;
    use oneblock::app::phase_data::PhaseData;
    use oneblock::sim::phase::PhaseCell;
    let mut data = PhaseData::new((0.0, 1.0), (1.0, 2.0), 3, 1);
    let counted = PhaseCell {
        attractors: Some(2),
        ..PhaseCell::failed(0.5, 1.0, 0.5)
    };
    let uncounted = PhaseCell {
        uncounted: Some("the graph could not be built".into()),
        ..PhaseCell::failed(1.0, 1.0, 1.0)
    };
    data.cells = vec![
        Some(PhaseCell::failed(0.0, 1.0, 0.0)),
        Some(counted),
        Some(uncounted),
    ];
    data.filled = 3;
    let (header, rows) = parse_csv(&phase_csv(&data));
    assert_eq!(header.last().unwrap(), "attractors");
    let counts: Vec<&str> = rows
        .iter()
        .map(|r| field(&header, r, "attractors"))
        .collect();
    assert_eq!(counts, ["", "2", ""]);
    data.cells = vec![Some(PhaseCell::failed(0.0, 1.0, 0.0)); 3];
    let (header, rows) = parse_csv(&phase_csv(&data));
    assert!(rows.iter().all(|r| r.len() == header.len()));
    assert_eq!(header.last().unwrap(), "lyapunov_stderr");
}
