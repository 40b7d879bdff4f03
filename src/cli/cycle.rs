//! `oneblock cycle`: a period-p cycle of the map solved by Newton's method
//! from a seed, with its points, multiplier and stability, as text or as
//! one JSON object.

use std::fmt::Write as _;
use std::path::Path;

use clap::Args;

use super::CliError;
use super::common::{
    ModelArgs, SolverArgs, check_theta, describe, emit, max_seconds, settings_json, warn_validity,
};
use super::run_control::{Limits, check_stdout, run_bounded};
use super::values::{count_between, parse_count, parse_number};
use crate::model::{OnsetCharacter, onset_character};
use crate::sim::{Cycle, CycleFailure, CycleOptions, PERIOD_MAX, Simulator, solve_cycle};

/// Solves f^p(θ) = θ from the seed `--theta`.
#[derive(Debug, Clone, Args)]
pub struct CycleArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    #[command(flatten)]
    pub solver: SolverArgs,
    /// The period p to solve for (1 to 64; 1 is a fixed point).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_count)]
    pub period: usize,
    /// The seed θ, in radians (on the exit arc).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub theta: f64,
    /// Print one JSON object instead of the text summary.
    #[arg(long)]
    pub json: bool,
    /// Give up after this many seconds, in (0, 1e7], printing nothing (a
    /// long period at a small ν can take minutes); Ctrl+C also stops it.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub max_seconds: Option<f64>,
}

/// What `run` needs, checked before any work.
pub struct Plan {
    pub sim: Simulator,
    pub period: usize,
    pub seed: f64,
    pub max_seconds: Option<f64>,
}

/// Checks the flags (values, bounds, the seed on the exit arc, stdout).
pub fn check(args: &CycleArgs) -> Result<Plan, CliError> {
    let period = count_between("period", args.period, 1, PERIOD_MAX)?;
    let params = args.model.params()?;
    let settings = args.solver.settings()?;
    let sim = Simulator::new(params, settings)?;
    let seed = check_theta(&sim, "theta", args.theta)?;
    let max_seconds = max_seconds(args.max_seconds)?;
    check_stdout()?;
    Ok(Plan {
        sim,
        period,
        seed,
        max_seconds,
    })
}

pub fn run(args: CycleArgs) -> Result<(), CliError> {
    let Plan {
        sim,
        period,
        seed,
        max_seconds,
    } = check(&args)?;
    let (params, settings) = (*sim.params(), *sim.settings());
    warn_validity(&params);
    let opts = CycleOptions::for_settings(&settings);
    let limits = Limits::start(max_seconds);
    let solved = run_bounded("cycle", &limits, move || {
        solve_cycle(&sim, seed, period, &opts)
    })?;
    let cycle = solved.map_err(|e| match e {
        CycleFailure::Sim(e) => CliError::from(e),
        e => CliError::Failed(format!("no {period}-cycle from theta = {seed}: {e}")),
    })?;
    let text = if args.json {
        let mut obj = serde_json::json!({
            "period": period,
            "minimal_period": cycle.minimal_period,
            "seed": seed,
            "points": cycle.points,
            "multiplier": cycle.multiplier,
            "stable": cycle.stable,
            "lyapunov": cycle.lyapunov(),
            "residual": cycle.residual,
            "iterations": cycle.iterations,
            "newton_step": cycle.step,
            "tol": opts.tol,
            "residual_floor": opts.floor,
            "map_evals": cycle.map_evals,
            "rhs_evals": cycle.rhs_evals,
        });
        if let Some(m) = obj.as_object_mut() {
            m.insert(
                "params".into(),
                serde_json::to_value(params).unwrap_or_default(),
            );
            m.insert("solver".into(), settings_json(&settings));
        }
        format!("{obj}\n")
    } else {
        summary(&cycle, seed, &opts, &describe(&params, &settings), |th| {
            onset_character(params.kappa, params.gamma, th)
        })
    };
    emit(Path::new("-"), text.as_bytes(), false)
}

fn summary(
    c: &Cycle,
    seed: f64,
    opts: &CycleOptions,
    described: &str,
    character: impl Fn(f64) -> OnsetCharacter,
) -> String {
    let p = c.period();
    let mut s = format!("cycle: {described}\n");
    writeln!(
        s,
        "period           {p}{}",
        if c.minimal_period < p {
            format!(
                " (the points repeat after {}: a {}-cycle traversed {} times)",
                c.minimal_period,
                c.minimal_period,
                p / c.minimal_period
            )
        } else {
            String::new()
        }
    )
    .ok();
    for (i, th) in c.points.iter().enumerate() {
        let kind = match character(*th) {
            OnsetCharacter::Creep => "creep",
            OnsetCharacter::StickSlip => "stick-slip",
        };
        writeln!(s, "theta_{i:<10} {th}  ({kind} onset)").ok();
    }
    writeln!(
        s,
        "multiplier       {}  ({})",
        c.multiplier,
        if c.stable {
            "stable: |m| < 1, the cycle attracts"
        } else {
            "unstable: |m| >= 1"
        }
    )
    .ok();
    writeln!(s, "lyapunov         {}  (ln|m|/p)", c.lyapunov()).ok();
    writeln!(
        s,
        "newton           {} step(s) from theta = {seed}, residual {:e}, step |residual/(1 - m)| {:e} (converged: step <= {:e}, or no step shrinks a residual <= {:e}), {} map evaluations",
        c.iterations, c.residual, c.step, opts.tol, opts.floor, c.map_evals
    )
    .ok();
    s
}
