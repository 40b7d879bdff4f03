//! `oneblock attractors`: every attractor and basin at one parameter
//! point, from the exit arc as a cell graph (docs/attractors.md): its
//! period (or chaotic), points, multiplier or Lyapunov exponent (and the
//! invariant density), basin fraction and the basins along the arc.

use std::fmt::Write as _;
use std::path::Path;

use clap::Args;

use super::CliError;
use super::common::{ModelArgs, SolverArgs, describe, emit, max_seconds, warn_validity};
use super::run_control::{Limits, Progress, check_stdout, run_job};
use super::values::{count_between, parse_count, parse_number, short};
use crate::jobs::{Axis, BasinsSpec, MapBasinsSpec, Update};
use crate::sim::Simulator;
use crate::sim::attractors::{CellOptions, Found, GRAPH_RTOL, Verdict};
use crate::sim::continuation::ContParam;

mod range;

/// The most cells.
pub const MAX_CELLS: usize = 1 << 22;
/// The finest and coarsest resolution a user may ask for (radians).
pub const RESOLUTION_RANGE: (f64, f64) = (1e-9, 1e-2);

/// Every attractor and basin at the parameters, from the exit arc's cell
/// graph (docs/attractors.md).
#[derive(Debug, Clone, Args)]
pub struct AttractorsArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    #[command(flatten)]
    pub solver: SolverArgs,
    /// The finest cell width subdivision goes to, in radians (1e-9 to
    /// 1e-2): tighten it where the output says the resolution could not
    /// decide [default: 1e-6; 1e-5 in each column of a range].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub resolution: Option<f64>,
    /// The most cells in all (1024 to 4194304) [default: 65536; 8192 in
    /// each column of a range].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_count)]
    pub max_cells: Option<usize>,
    /// The finest grid a chaotic attractor's invariant density is computed
    /// on (4096 to 1048576 cells over its hull): grids are doubled up to it
    /// until λ from the density is steady, and its error is the change
    /// over the last two doublings.
    #[arg(long, default_value = "65536", allow_hyphen_values = true, value_parser = parse_count)]
    pub density_cells: usize,
    /// Print one JSON object instead of the text summary.
    #[arg(long)]
    pub json: bool,
    /// Stop after this many seconds (0 < S ≤ 1e7), printing nothing, exit 1.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub max_seconds: Option<f64>,
    /// Follow every attractor over a range of this parameter (theta-nu,
    /// kappa, gamma, nu or omega; its own flag is not used): --from, --to
    /// and --columns give the range, and the attractors of neighbouring
    /// columns are joined into tracks by their basins' overlap.
    #[arg(long)]
    pub param: Option<ContParam>,
    /// First value of --param's range: with theta-nu in [-1000, 1000]
    /// radians, else within that parameter's flag's range.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, conflicts_with_all = ["theta_nu_from", "theta_nu_to"], requires = "to")]
    pub from: Option<f64>,
    /// Last value of --param's range (may be below --from).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, requires = "from")]
    pub to: Option<f64>,
    /// First θν of a range over θν (the same as --param theta-nu --from).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, requires = "theta_nu_to")]
    pub theta_nu_from: Option<f64>,
    /// Last θν of a range over θν (the same as --param theta-nu --to).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, requires = "theta_nu_from")]
    pub theta_nu_to: Option<f64>,
    /// Columns of a range, ends included (2 to 2000), evenly spaced (in
    /// log10 of the value for kappa, nu and omega) [default: 81].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_count)]
    pub columns: Option<usize>,
    /// With a range: also write one CSV row per column and attractor
    /// (value, track, label, period, basin_fraction, multiplier,
    /// lyapunov) to this file ("-" = stdout, instead of the summary).
    #[arg(long)]
    pub out: Option<std::path::PathBuf>,
    /// Overwrite an existing --out file.
    #[arg(long)]
    pub force: bool,
}

/// What `run` needs, checked before any work.
pub struct Plan {
    pub sim: Simulator,
    pub cells: CellOptions,
    pub max_seconds: Option<f64>,
}

/// Checks the flags (values, bounds, stdout).
pub fn check(args: &AttractorsArgs) -> Result<Plan, CliError> {
    let resolution = resolution(args.resolution.unwrap_or(1e-6))?;
    let max_cells = max_cells(args.max_cells.unwrap_or(1 << 16))?;
    let density_cells = count_between("density-cells", args.density_cells, 4096, 1 << 20)?;
    let params = args.model.params()?;
    let settings = args.solver.settings()?;
    let sim = Simulator::new(params, settings)?;
    let max_seconds = max_seconds(args.max_seconds)?;
    check_stdout()?;
    Ok(Plan {
        sim,
        cells: CellOptions {
            resolution,
            max_cells,
            density_cells,
            ..CellOptions::default()
        },
        max_seconds,
    })
}

/// Checks `--resolution`.
fn resolution(v: f64) -> Result<f64, CliError> {
    let (lo, hi) = RESOLUTION_RANGE;
    if v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(CliError::Usage(format!(
            "--resolution = {} is out of range: must lie in [{lo:e}, {hi:e}] radians",
            short(v)
        )))
    }
}

/// Checks `--max-cells`.
fn max_cells(v: usize) -> Result<usize, CliError> {
    count_between("max-cells", v, 1024, MAX_CELLS)
}

/// Checks the flags of either form (one point, or a range with --param).
pub fn check_any(args: &AttractorsArgs) -> Result<(), CliError> {
    if range::wanted(args) {
        range::check(args).map(drop)
    } else {
        check(args).map(drop)
    }
}

pub fn run(args: AttractorsArgs) -> Result<(), CliError> {
    if range::wanted(&args) {
        return range::run(&args);
    }
    let Plan {
        sim,
        cells,
        max_seconds,
    } = check(&args)?;
    let (params, settings) = (*sim.params(), *sim.settings());
    warn_validity(&params);
    // Bounded like every long command: a line of life on a terminal, and
    // --max-seconds or Ctrl+C end it with one line, printing nothing. The
    // job is the return map's basin band (one point, with densities).
    let limits = Limits::start(max_seconds);
    let progress = Progress::new("attractors", "point", 1);
    let spec = MapBasinsSpec(BasinsSpec {
        params,
        settings,
        param: ContParam::ThetaNu,
        axis: Axis::new(params.theta_nu, params.theta_nu, 1),
        cells,
    });
    let updates = run_job("attractors", spec.into(), 1, &progress, &limits)?;
    let Some(found) = updates.into_iter().find_map(|u| match u {
        Update::Basins { column, .. } => Some(column.found),
        _ => None,
    }) else {
        return Err(CliError::Failed(
            "attractors: the job ended without its answer".into(),
        ));
    };
    let found = found.map_err(CliError::Failed)?;
    if found.attractors.is_empty() {
        return Err(CliError::Failed(
            "attractors: no closed set of cells was found: the map could not be enclosed over the exit arc".into(),
        ));
    }
    let text = if args.json {
        json(&found, &params, &settings)
    } else {
        let mut described = describe(&params, &settings);
        if settings.method.is_adaptive() && settings.rtol > GRAPH_RTOL {
            described.push_str(&format!(
                "; the cell graph integrates at tol {GRAPH_RTOL:e}: its enclosures need it"
            ));
        }
        text(&found, &described)
    };
    emit(Path::new("-"), text.as_bytes(), false)
}

/// The verdict as one word, and its reason where undecided.
fn verdict(v: &Verdict) -> (&'static str, Option<&str>) {
    match v {
        Verdict::Proved => ("proved", None),
        Verdict::CycleInSet => ("cycle-in-set", None),
        Verdict::Chaotic => ("chaotic", None),
        Verdict::Undecided(why) => ("undecided", Some(why.as_str())),
    }
}

/// `{"params", "solver", "attractors": [{"id", "period", "points", "multiplier", "lyapunov",
/// "lyapunov_stderr", "lyapunov_from_density", "lyapunov_density_error",
/// "density", "basin_fraction", "min_kick", "min_kick_width",
/// "verdict", "reason"}, …], "basins": [{"from", "to", "attractor"}, …]
/// (`attractor` an attractor's `id`, numbered from 1 as the text's `#1`),
/// "boundary_fraction", "unenclosed_fraction", "resolution":
/// {"cell_width", "widest_cell", "epsilon", "cells", "budget_hit",
/// "nodes_capped"}}`.
fn json(found: &Found, params: &crate::model::Params, settings: &crate::SolverSettings) -> String {
    let list: Vec<_> = found
        .attractors
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let (word, why) = verdict(&a.verdict);
            let kick = found.min_kick(i);
            serde_json::json!({
                "id": i + 1,
                "period": a.period,
                "points": a.points,
                "multiplier": a.multiplier,
                "lyapunov": a.lyapunov,
                "lyapunov_stderr": a.lyapunov_stderr,
                "lyapunov_from_density": a.lyapunov_from_density,
                "lyapunov_density_error": a.lyapunov_density_error,
                "density": a.density.as_ref().map(|d| serde_json::json!({
                    "from": d.from, "to": d.to, "values": d.values,
                })),
                "basin_fraction": a.basin_fraction,
                "min_kick": kick.map(|k| k.0),
                "min_kick_width": kick.map(|k| k.1),
                "verdict": word,
                "reason": why,
            })
        })
        .collect();
    let basins: Vec<_> = found
        .basins
        .iter()
        .map(|b| serde_json::json!({"from": b.from, "to": b.to, "attractor": b.attractor.map(|k| k + 1)}))
        .collect();
    let r = &found.resolution;
    format!(
        "{}\n",
        serde_json::json!({
            "params": params,
            "solver": super::common::settings_json(settings),
            "attractors": list,
            "basins": basins,
            "boundary_fraction": found.boundary_fraction,
            "unenclosed_fraction": found.unenclosed_fraction,
            "resolution": {
                "cell_width": r.finest,
                "widest_cell": r.widest,
                "epsilon": r.eps,
                "cells": r.cells,
                "budget_hit": r.budget_hit,
                "nodes_capped": r.nodes_capped,
            },
        })
    )
}

fn text(found: &Found, described: &str) -> String {
    let r = &found.resolution;
    let mut s = format!("attractors: {described}\n");
    writeln!(
        s,
        "the exit arc as a cell graph: {} cells, {:.1e} to {:.1e} rad wide, images widened by eps = {:.1e}: {} attractor(s)",
        r.cells,
        r.finest,
        r.widest,
        r.eps,
        found.attractors.len()
    )
    .ok();
    for i in 0..found.attractors.len() {
        attractor_lines(&mut s, found, i);
    }
    if found.boundary_fraction > 0.0 {
        writeln!(
            s,
            "basin boundary at this resolution: {} of the arc reaches more than one attractor",
            if found.boundary_fraction >= 1e-3 {
                format!("{:.4}", found.boundary_fraction)
            } else {
                format!("{:.1e}", found.boundary_fraction)
            }
        )
        .ok();
    }
    if found.unenclosed_fraction > 0.0 {
        writeln!(
            s,
            "of which {:.1e} lies where f could not be enclosed (nodes that fail the enclosure test, docs/attractors.md): boundary at any resolution",
            found.unenclosed_fraction
        )
        .ok();
    }
    if r.nodes_capped {
        writeln!(
            s,
            "the budget of nodes where no series resolves f ({} evaluations) stopped a refinement: the boundary there is wider than the resolution",
            crate::sim::attractors::arc::NODE_EVALUATIONS
        )
        .ok();
    }
    if r.budget_hit {
        writeln!(
            s,
            "the cell budget stopped subdivision before the resolution asked for: raise --max-cells"
        )
        .ok();
    }
    writeln!(s, "basins along the arc (theta from, to: attractor):").ok();
    for b in &found.basins {
        let who = b
            .attractor
            .map_or("boundary".to_string(), |k| format!("#{}", k + 1));
        writeln!(s, "  {:.6} {:.6}: {who}", b.from, b.to).ok();
    }
    s
}

/// "smallest kick out of its basin: 0.0862 rad (the edge within 3.1e-6
/// beyond)": the distance from the attractor to the nearest onset not in
/// its basin, to the decimals the cells resolve.
fn kick_words(found: &Found, i: usize) -> String {
    match found.kick_text(i) {
        None => "no kick of the onset leaves its basin (no other basin on the arc)".into(),
        Some(k) => format!("smallest kick out of its basin: {k}, at this resolution"),
    }
}

/// One attractor's lines of the text output.
fn attractor_lines(s: &mut String, found: &Found, i: usize) {
    let a = &found.attractors[i];
    let what = match a.period {
        Some(p) => format!("P{p}"),
        None if a.verdict == Verdict::Chaotic => "chaotic".into(),
        None => "set".into(),
    };
    let pts = a
        .points
        .iter()
        .map(|p| format!("{p:.9}"))
        .collect::<Vec<_>>()
        .join(", ");
    let how = a.stability();
    let points = if a.period.is_some() {
        format!("points {pts}")
    } else {
        format!("theta in [{pts}]")
    };
    let (word, why) = verdict(&a.verdict);
    writeln!(
        s,
        "  {what:<8} basin {:.4}  {how}  {points}  ({word})",
        a.basin_fraction
    )
    .ok();
    if let Some(why) = why {
        writeln!(s, "    undecided: {why}").ok();
    }
    if found.attractors.len() > 1 {
        writeln!(s, "    {}", kick_words(found, i)).ok();
    }
    if a.verdict == Verdict::CycleInSet {
        writeln!(
            s,
            "    a stable cycle in a closed set the cells did not shrink onto it: another attractor may hide in the set; tighten with --resolution or --max-cells"
        )
        .ok();
    }
}
