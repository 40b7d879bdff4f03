//! `oneblock figure --out x.csv`: the data a view's figure draws, as a
//! table a reader can replot (issue 57), each with the `#` lines of
//! [`crate::provenance`]: the bifurcation diagram's onsets and λ per
//! column and the Basins view's columns ([`super::figure_basins`]); the
//! phase diagram's cells as `oneblock phase --out`; the trajectory the
//! plane, block and time series draw (`t,x,y,u,w,phase`, as `oneblock
//! trajectory`); the events view's slips (as `oneblock orbit --events`);
//! the return map's curve and orbit (`kind,theta,theta_next`: `curve`
//! rows are the map's graph θ ↦ f(θ), `orbit` rows each onset and the
//! next); the numerics view's work-precision rows (`source` then
//! `oneblock work-precision`'s columns: `run` rows measured on the
//! figure's parameters, `committed` rows the chart drawn faint behind).

use std::fmt::Write as _;

use crate::app::ViewKind;
use crate::app::data::IterateData;
use crate::app::export;
use crate::app::figure::{Figure, compute};
use crate::app::jobs::JobKind;

/// `fig`'s data as CSV.
pub fn data_csv(fig: &Figure) -> Result<String, String> {
    if matches!(fig.view, ViewKind::Basins | ViewKind::Bifurcation) {
        return super::figure_basins::data_csv(fig);
    }
    let jobs = compute(fig)?;
    let (kind, body) = match fig.view {
        ViewKind::Phase => (JobKind::Phase, export::phase_csv(&jobs.phase.data)),
        ViewKind::Events => (
            JobKind::Trajectory,
            export::events_csv(&jobs.trajectory.data.events),
        ),
        ViewKind::ReturnMap => (JobKind::Iterate, return_map_csv(&jobs.iterate.data)),
        ViewKind::Numerics => (JobKind::Numerics, numerics_csv(&jobs.numerics.data)),
        _ => (
            JobKind::Trajectory,
            export::trajectory_csv(&jobs.trajectory.data.samples),
        ),
    };
    let header = export::header(fig.view.key(), &fig.settings, kind);
    Ok(crate::provenance::with_header(&header, &body))
}

/// The return map's curve (θ, f(θ)) and its orbit's onsets (θₙ, θₙ₊₁).
pub fn return_map_csv(d: &IterateData) -> String {
    let mut s = String::from("kind,theta,theta_next\n");
    for [t, f] in &d.graph {
        writeln!(s, "curve,{t},{f}").ok();
    }
    for w in d.thetas.windows(2) {
        writeln!(s, "orbit,{},{}", w[0], w[1]).ok();
    }
    s
}

/// The work-precision rows the numerics figure draws: the run's (on the
/// figure's parameters) and the committed chart's behind them, or the
/// committed chart alone when the run measured nothing; one row per
/// setting, as `oneblock work-precision` writes it, after its source.
pub fn numerics_csv(d: &crate::app::data::WorkPrecisionData) -> String {
    use crate::numerics::committed::default_rows;
    use crate::numerics::work_precision::CSV_HEADER;
    let mut s = format!("source,{CSV_HEADER}\n");
    for r in &d.rows {
        writeln!(s, "run,{}", r.csv()).ok();
    }
    for r in default_rows() {
        writeln!(s, "committed,{}", r.csv()).ok();
    }
    s
}
