//! `oneblock attractors`: every attractor at one parameter point, from
//! seeds spread over the exit arc, with its period (or chaotic), points,
//! multiplier or Lyapunov exponent, and basin fraction (docs/attractors.md).

use std::fmt::Write as _;
use std::path::Path;

use clap::Args;

use super::CliError;
use super::common::{ModelArgs, SolverArgs, describe, emit, max_seconds, warn_validity};
use super::run_control::{Limits, check_stdout, run_bounded};
use super::values::{count_between, parse_count, parse_number};
use crate::sim::attractors::{Attractor, KEEP, TRANSIENT, attractors};
use crate::sim::{SimError, Simulator};

/// The most seeds.
pub const MAX_SEEDS: usize = 4096;

/// Every attractor at the parameters, from `--seeds` seeds.
#[derive(Debug, Clone, Args)]
pub struct AttractorsArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    #[command(flatten)]
    pub solver: SolverArgs,
    /// Seeds spread over the exit arc (1 to 4096).
    #[arg(long, default_value = "64", allow_hyphen_values = true, value_parser = parse_count)]
    pub seeds: usize,
    /// Print one JSON object instead of the text summary.
    #[arg(long)]
    pub json: bool,
    /// Stop after this many seconds (0 < S ≤ 1e7), printing nothing, exit 1.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub max_seconds: Option<f64>,
}

/// What `run` needs, checked before any work.
pub struct Plan {
    pub sim: Simulator,
    pub seeds: usize,
    pub max_seconds: Option<f64>,
}

/// Checks the flags (values, bounds, stdout).
pub fn check(args: &AttractorsArgs) -> Result<Plan, CliError> {
    let seeds = count_between("seeds", args.seeds, 1, MAX_SEEDS)?;
    let params = args.model.params()?;
    let settings = args.solver.settings()?;
    let sim = Simulator::new(params, settings)?;
    let max_seconds = max_seconds(args.max_seconds)?;
    check_stdout()?;
    Ok(Plan {
        sim,
        seeds,
        max_seconds,
    })
}

pub fn run(args: AttractorsArgs) -> Result<(), CliError> {
    let Plan {
        sim,
        seeds,
        max_seconds,
    } = check(&args)?;
    let (params, settings) = (*sim.params(), *sim.settings());
    warn_validity(&params);
    // Bounded like every long command: a line of life on a terminal, and
    // --max-seconds or Ctrl+C end it with one line, printing nothing.
    let limits = Limits::start(max_seconds);
    let found = run_bounded("attractors", &limits, move || {
        attractors(params, settings, seeds, None, &|| false)
    })?
    .map_err(|e| match e {
        SimError::Cancelled => CliError::Failed("cancelled".into()),
        e => CliError::from(e),
    })?;
    let text = if args.json {
        json(&found)
    } else {
        text(&found, &describe(&params, &settings), seeds)
    };
    emit(Path::new("-"), text.as_bytes(), false)
}

/// `{"attractors": [{"period", "points", "multiplier", "lyapunov",
/// "lyapunov_stderr", "basin_fraction"}, …]}`.
fn json(found: &[Attractor]) -> String {
    let list: Vec<_> = found
        .iter()
        .map(|a| {
            serde_json::json!({
                "period": a.period,
                "points": a.points,
                "multiplier": a.multiplier,
                "lyapunov": a.lyapunov,
                "lyapunov_stderr": a.lyapunov_stderr,
                "basin_fraction": a.basin_fraction,
            })
        })
        .collect();
    format!("{}\n", serde_json::json!({ "attractors": list }))
}

fn text(found: &[Attractor], described: &str, seeds: usize) -> String {
    let mut s = format!("attractors: {described}\n");
    writeln!(
        s,
        "{seeds} seeds spread over the exit arc, {TRANSIENT} transient + {KEEP} kept iterates each: {} attractor(s)",
        found.len()
    )
    .ok();
    for a in found {
        let what = match a.period {
            Some(p) => format!("P{p}"),
            None => "chaotic".into(),
        };
        let pts = a
            .points
            .iter()
            .map(|p| format!("{p:.9}"))
            .collect::<Vec<_>>()
            .join(", ");
        let how = match (a.period, a.multiplier, a.lyapunov, a.lyapunov_stderr) {
            (Some(_), Some(m), _, _) => format!("multiplier {m:.6}"),
            (_, _, Some(l), Some(e)) => format!("lyapunov {l:.4} +- {e:.4}"),
            (_, _, Some(l), None) => format!("lyapunov {l:.4}"),
            _ => "no exponent".into(),
        };
        let points = if a.period.is_some() {
            format!("points {pts}")
        } else {
            format!("theta in [{pts}]")
        };
        writeln!(
            s,
            "  {what:<8} basin {:.3}  {how}  {points}",
            a.basin_fraction
        )
        .ok();
    }
    s
}
