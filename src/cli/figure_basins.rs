//! `oneblock figure --view basins --out x.csv`: the Basins view's columns
//! as a table instead of a picture, computed by the same job as the
//! window's view (and the same attractor identities its colours follow):
//! one row per attractor of each column, then the column's basin
//! boundary.

use crate::sim::attractors::tracks::kind_name;
use std::fmt::Write as _;

use super::common::{describe_sweep, with_provenance};
use crate::app::basins::{BOUNDARY, hex, track_color};
use crate::app::figure::{Figure, compute};
use crate::app::jobs::basins::BasinsData;
use crate::app::jobs::basins::BasinsKey;
use crate::sim::attractors::Verdict;

/// `fig`'s data as CSV: the Basins view's columns, or the bifurcation
/// diagram's onsets and λ as `oneblock bifurcation --out` writes them (the
/// same job, so the same numbers at the same settings).
pub fn data_csv(fig: &Figure) -> Result<String, String> {
    match fig.view {
        crate::app::ViewKind::Bifurcation => {
            let jobs = compute(fig)?;
            let s = &fig.settings;
            let kind = crate::app::jobs::JobKind::Sweep;
            let solver = kind.solver(s).unwrap_or_else(|| s.custom_solver());
            let model = crate::provenance::model_line_varying(&s.params, &solver, s.diagram.param);
            let body = crate::app::export::bifurcation_csv(&jobs.sweep.data);
            Ok(with_provenance(&model, &body))
        }
        _ => csv(fig),
    }
}

/// The CSV's column names.
pub const HEADER: &str =
    "theta_nu,attractor,label,period,basin_fraction,multiplier,lyapunov,verdict,colour";

/// Computes `fig`'s Basins columns and writes them as CSV: `#` lines
/// naming the program, its version, the command line and the parameters
/// first ([`crate::provenance`]).
pub fn csv(fig: &Figure) -> Result<String, String> {
    let jobs = compute(fig)?;
    let key = BasinsKey::of(&fig.settings, None);
    let model = format!(
        "{}; theta-nu {} to {}, {} columns",
        describe_sweep(&key.params, &key.solver),
        key.range.0,
        key.range.1,
        key.columns,
    );
    let mut out = with_provenance(&model, &format!("{HEADER}\n"));
    rows(&jobs.basins.data, &mut out);
    Ok(out)
}

/// A field without commas or quotes (a verdict's words may hold them).
fn field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// One row per attractor (its track's number and its kind here), then the
/// boundary's (`attractor` empty, label `boundary`); a failed column is
/// one row saying why.
fn rows(d: &BasinsData, out: &mut String) {
    let num = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x}"));
    for (i, col) in d.columns.iter().enumerate() {
        let Some(col) = col else { continue };
        let tn = col.theta_nu;
        let found = match &col.found {
            Ok(f) => f,
            Err(e) => {
                writeln!(out, "{tn},,failed,,,,,{},", field(e)).ok();
                continue;
            }
        };
        for (a, at) in found.attractors.iter().enumerate() {
            let track = d.ids.track(i, a);
            let id = track.map_or(String::new(), |t| t.id.to_string());
            let colour = track.map_or(String::new(), |t| hex(track_color(t.id)));
            let label = kind_name(at.period, &at.verdict);
            let verdict = match &at.verdict {
                Verdict::Proved => "proved".to_string(),
                Verdict::CycleInSet => "cycle in set".to_string(),
                Verdict::Chaotic => "chaotic".to_string(),
                Verdict::Undecided(w) => format!("undecided: {w}"),
            };
            let period = at.period.map_or(String::new(), |p| p.to_string());
            writeln!(
                out,
                "{tn},{id},{},{period},{},{},{},{},{colour}",
                field(&label),
                at.basin_fraction,
                num(at.multiplier),
                num(at.lyapunov),
                field(&verdict)
            )
            .ok();
        }
        let grey = hex(BOUNDARY);
        writeln!(out, "{tn},,boundary,,{},,,,{grey}", found.boundary_fraction).ok();
    }
}
