//! `oneblock bench-worker --pieces`: every kind of job once on the
//! single-threaded host, in the page's compute slices (12 ms per frame),
//! and per kind the pieces (steps) it took and the longest of them: how
//! long the browser's page can be held by one piece of work. Wall-clock
//! figures of this machine, so they live in docs, never in tests.

use crate::bench::diagram::PAGE_SLICE;
use crate::bench::pieces::{Pieces, every_kind, on_interpolant};
use crate::cli::CliError;

/// The report: a table, or with `--json` one object
/// `{"kinds": [{"kind", "pieces", "longest_ms"}]}`; `quick`: the small
/// specs.
pub(super) fn report(quick: bool, json: bool) -> Result<String, CliError> {
    let rows = every_kind(quick).map_err(CliError::Failed)?;
    if json {
        let kinds: Vec<serde_json::Value> = rows
            .iter()
            .map(|r| {
                serde_json::json!({
                    "kind": format!("{:?}", r.kind),
                    "pieces": r.pieces,
                    "longest_ms": r.longest_ms,
                })
            })
            .collect();
        return Ok(serde_json::json!({ "kinds": kinds }).to_string() + "\n");
    }
    let rarer = on_interpolant(quick).map_err(CliError::Failed)?;
    Ok(table(&rows, quick) + &rarer_table(&rarer))
}

/// The rarer paths on the interpolant, in the same columns (not in the
/// JSON, which lists the kinds).
fn rarer_table(rows: &[(&str, Pieces)]) -> String {
    let mut out = String::from("on the map's interpolant, at Fig. 3b's θν = 1.25:\n");
    for (label, r) in rows {
        out += &format!("{}  ({label})\n", row(r));
    }
    out
}

/// One kind's figures in the table's columns.
fn row(r: &Pieces) -> String {
    format!(
        "{:<11} {:>8} {:>11.1} {:>18} {:>16.1}",
        format!("{:?}", r.kind),
        r.pieces,
        r.longest_ms,
        r.longest_cycles,
        r.longest_unit_ms
    )
}

fn table(rows: &[Pieces], quick: bool) -> String {
    let mut out = format!(
        "every job kind on the single-threaded host in {} ms slices (the page's){}:\n",
        PAGE_SLICE.as_millis(),
        if quick { ", quick specs" } else { "" }
    );
    out += &format!(
        "{:<11} {:>8} {:>11} {:>18} {:>16}\n",
        "kind", "pieces", "longest ms", "cycles in longest", "longest unit ms"
    );
    for r in rows {
        out += &row(r);
        out.push('\n');
    }
    for r in rows {
        if let Some(text) = &r.summary {
            out += &format!("{:?}: {text}\n", r.kind);
        }
    }
    out
}
