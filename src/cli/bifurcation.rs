//! `oneblock bifurcation`: the data of a bifurcation diagram, CSV
//! `theta_nu,theta,lyapunov,lyapunov_stderr` (`kappa,theta,…` with
//! `--param kappa`): the window's sweep job ([`crate::jobs`]) run on every
//! core. Its plan (a coarse pass in chains, then fill-in, each column
//! continued from a named neighbour; [`crate::jobs::sweep_plan`]) is fixed
//! by the flags alone, so the file is the same on any machine, and the
//! same as the window's diagram of the same parameters and range.

use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use clap::Args;

use super::CliError;
use super::common::{
    MAX_ROWS, ModelArgs, SolverArgs, check_out, check_theta, count_in, emit, finite, max_seconds,
    total_iterates, warn_validity, with_provenance,
};
use super::run_control::{Limits, Progress};
use super::values::{count_between, param_error, parse_count, parse_number, short};
use crate::formats::bifurcation_csv;
use crate::jobs::{Axis, JobError, Spec, SweepSpec, Update, run_collect};
use crate::model::Params;
use crate::provenance::model_line_varying;
use crate::sim::Simulator;
use crate::sim::column_lyapunov::ColumnLyapunov;
use crate::sim::continuation::ContParam;
use crate::sim::interpolant::{MapChoice, MapTally, MapUsed};
use crate::sim::seeded::{MAX_OTHERS, MAX_SEEDS};

/// A bifurcation diagram: θ against θν (or against another parameter,
/// `--param`).
#[derive(Debug, Clone, Args)]
pub struct BifurcationArgs {
    /// The model's flags (θν held fixed when --param varies another
    /// parameter; the varied one's own flag is not used).
    #[command(flatten)]
    pub model: ModelArgs,
    #[command(flatten)]
    pub solver: SolverArgs,
    /// The parameter varied along the diagram (theta-nu, kappa, gamma, nu
    /// or omega), the others held fixed; its own flag is not used: --from
    /// and --to give its range [default: theta-nu].
    #[arg(long)]
    pub param: Option<ContParam>,
    /// First value of --param's grid: with theta-nu in [-1000, 1000]
    /// radians, else within that parameter's flag's range.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, conflicts_with_all = ["theta_nu_from", "theta_nu_to"], requires = "to")]
    pub from: Option<f64>,
    /// Last value of --param's grid (may be below --from: the sweep then
    /// runs downwards).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, requires = "from")]
    pub to: Option<f64>,
    /// First θν of the grid, in radians, in [-1000, 1000] (the same as
    /// --from when θν is varied).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = parse_number)]
    pub theta_nu_from: f64,
    /// Last θν of the grid, in radians, in [-1000, 1000] (may be below
    /// --theta-nu-from: the sweep then runs downwards).
    #[arg(long, default_value_t = std::f64::consts::FRAC_PI_2, allow_hyphen_values = true, value_parser = parse_number)]
    pub theta_nu_to: f64,
    /// Number of values, evenly spaced (in log10 of the value for kappa,
    /// nu and omega, which span decades), ends included (1 to 1e6).
    #[arg(long, default_value_t = 200, value_parser = parse_count, allow_hyphen_values = true)]
    pub columns: usize,
    /// Iterates dropped at each θν before any is kept (columns times
    /// transient plus keep ≤ 1e12; bound the time with --max-seconds). Not
    /// held in memory: a column keeps only its kept iterates.
    #[arg(long, default_value_t = 500, value_parser = parse_count, allow_hyphen_values = true)]
    pub transient: usize,
    /// Iterates kept at each θν: one CSV row each (≥ 1; columns × keep ≤ 1e7).
    #[arg(long, default_value_t = 100, value_parser = parse_count, allow_hyphen_values = true)]
    pub keep: usize,
    /// How a column that has not settled after its transient evaluates the
    /// map: direct, interpolant (the map's verified interpolant, built per
    /// column; docs/interpolant.md) or auto (the interpolant from 5000 kept
    /// iterates on). Where it is refused the column integrates.
    #[arg(long, value_enum, default_value_t = MapChoice::Auto)]
    pub map: MapChoice,
    /// θ where each chain of the coarse pass starts [default: its first
    /// column's θν].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub theta0: Option<f64>,
    /// Every attractor at each column besides the followed one, from the
    /// exit arc's cell graph with no orbit budget (0 to 256; 0: off, any
    /// other value: on). Each one's points are written, with an
    /// `attractor` column (0: the followed one; docs/attractors.md).
    #[arg(long, default_value_t = 0, value_parser = parse_count, allow_hyphen_values = true)]
    pub seeds: usize,
    /// CSV file ("-" = stdout).
    #[arg(long, default_value = "-")]
    pub out: PathBuf,
    /// Overwrite an existing --out file.
    #[arg(long)]
    pub force: bool,
    /// Stop after this many seconds, in (0, 1e7], writing nothing, exit 1.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub max_seconds: Option<f64>,
}

/// The most θν values a diagram may have (far more than a screen's pixels).
pub const MAX_COLUMNS: usize = 1_000_000;

/// The largest |θν| a range may have, in radians: hundreds of turns, and
/// still 1e-13 rad of precision.
pub const MAX_ABS_THETA_NU: f64 = 1000.0;

/// Checks an end of a θν range.
pub fn theta_nu_end(flag: &str, v: f64) -> Result<f64, CliError> {
    let v = finite(flag, v)?;
    if v.abs() <= MAX_ABS_THETA_NU {
        Ok(v)
    } else {
        Err(CliError::Usage(format!(
            "--{flag} = {} is out of range: must lie in [-1000, 1000] radians",
            short(v)
        )))
    }
}

/// The checked inputs of `bifurcation`.
pub struct Plan {
    params: Params,
    settings: crate::SolverSettings,
    param: ContParam,
    from: f64,
    to: f64,
    columns: usize,
    keep: usize,
    total: u64,
    max_seconds: Option<f64>,
    map: crate::sim::MapChoice,
    seeds: usize,
}

/// The model's parameters with the varied one at `from`: each of the
/// others from its flag, else the preset's (θν's too when it is fixed).
pub(super) fn model_params(
    model: &ModelArgs,
    param: ContParam,
    from: f64,
) -> Result<Params, CliError> {
    let mut model = model.clone();
    *model.flag_mut(param) = Some(from);
    model.given()
}

/// The varied parameter and its range: --from and --to, checked against
/// the model's range of --param (the other parameters `params`), or
/// --theta-nu-from and --theta-nu-to for θν.
fn varied_range(args: &BifurcationArgs) -> Result<(ContParam, f64, f64), CliError> {
    let param = args.param.unwrap_or(ContParam::ThetaNu);
    let (Some(from), Some(to)) = (args.from, args.to) else {
        if param != ContParam::ThetaNu {
            return Err(CliError::Usage(format!(
                "--from and --to: required with --param {} (the range of {} the diagram spans)",
                param.name(),
                param.name()
            )));
        }
        let from = theta_nu_end("theta-nu-from", args.theta_nu_from)?;
        let to = theta_nu_end("theta-nu-to", args.theta_nu_to)?;
        return Ok((param, from, to));
    };
    checked_range(&args.model, param, from, to)?;
    Ok((param, from, to))
}

/// Checks --from and --to as a range of `param` (the others from `model`'s
/// flags): each end within the model's range of it, positive where its
/// axis is logarithmic; the message names the flag.
pub(super) fn checked_range(
    model: &ModelArgs,
    param: ContParam,
    from: f64,
    to: f64,
) -> Result<(), CliError> {
    // The other parameters checked first, so that a range end is judged
    // with valid neighbours (its message then names --from or --to).
    let params = model_params(model, param, from.max(to))?;
    for (flag, v) in [("from", from), ("to", to)] {
        if param.spans_decades() && v.is_finite() && v <= 0.0 {
            return Err(CliError::Usage(format!(
                "--{flag} = {} is out of range: {} must be positive (its axis is logarithmic)",
                short(v),
                param.name()
            )));
        }
        super::continue_cmd::range_end(flag, v, param, &params)?;
    }
    Ok(())
}

/// Checks the flags and the output before any work.
pub fn check(args: &BifurcationArgs) -> Result<Plan, CliError> {
    let (param, from, to) = varied_range(args)?;
    let params = model_params(&args.model, param, from)?;
    params.validate().map_err(param_error)?;
    let settings = args.solver.settings()?;
    let columns = count_in("columns", args.columns, MAX_COLUMNS)?;
    let keep = count_in("keep", args.keep, MAX_ROWS / columns)?;
    let total = total_iterates(args.transient, ("keep", keep), columns)?;
    let map = args.map;
    let seeds = count_between("seeds", args.seeds, 0, MAX_SEEDS)?;
    // Further attractors' points are rows too (each at most `keep`).
    let drawn = if seeds > 0 { MAX_OTHERS as u64 + 1 } else { 1 };
    if (columns as u64) * drawn * keep as u64 > MAX_ROWS as u64 {
        return Err(CliError::Usage(format!(
            "--seeds = {seeds} is out of range: with seeds, columns x {} x keep must be at most {}",
            MAX_OTHERS + 1,
            super::values::short_count(MAX_ROWS)
        )));
    }
    if let Some(th) = args.theta0 {
        // On the arc of the first column; later columns project it onto theirs.
        let sim = Simulator::new(params, settings)?;
        check_theta(&sim, "theta0", th)?;
    }
    check_out(&args.out, args.force)?;
    let max_seconds = max_seconds(args.max_seconds)?;
    Ok(Plan {
        params,
        settings,
        param,
        from,
        to,
        columns,
        keep,
        // The cell graph's evaluations are not iterates of the sweep.
        total,
        max_seconds,
        map,
        seeds,
    })
}

pub fn run(args: BifurcationArgs) -> Result<(), CliError> {
    let Plan {
        params,
        settings,
        param,
        from,
        to,
        columns,
        keep,
        total,
        max_seconds,
        map,
        seeds,
    } = check(&args)?;
    warn_validity(&params);
    let spec = SweepSpec {
        params,
        settings,
        param,
        axis: Axis::new(from, to, columns),
        transient: args.transient,
        keep,
        map,
        theta0: args.theta0,
        seeds,
    };
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let progress = Progress::new("bifurcation", "iterates", total);
    let limits = Limits::start(max_seconds);
    let (failed, uncounted) = (AtomicU64::new(0), AtomicU64::new(0));
    let report = |u: &Update| match u {
        Update::Error { message, .. } => {
            failed.fetch_add(1, Ordering::Relaxed);
            progress.println(&format!("warning: {message}"));
        }
        Update::Column {
            index,
            value,
            uncounted: Some(why),
            ..
        } => {
            uncounted.fetch_add(1, Ordering::Relaxed);
            progress.println(&format!(
                "warning: column {index} at {} = {value}: its other attractors not counted: {why}",
                param.name()
            ));
        }
        _ => {}
    };
    // Polled before every slip cycle: the progress bar counts them.
    let stop = || {
        progress.inc(1);
        limits.stop()
    };
    let start = Instant::now();
    let run = run_collect(Spec::Sweep(spec), threads, report, stop);
    progress.finish();
    let updates = match run {
        Ok(u) => u,
        Err(JobError::Stop) => return Err(limits.stopped("bifurcation")),
        Err(JobError::Sim(e)) => return Err(e.into()),
        Err(JobError::Failed(m)) => return Err(CliError::Failed(m)),
    };
    let seconds = start.elapsed().as_secs_f64();

    let cols = in_grid_order(updates, columns);
    let csv = bifurcation_csv(
        param,
        cols.iter()
            .map(|c| (c.0, c.1.as_slice(), c.4, c.5.as_slice())),
        seeds > 0,
    );
    let described = model_line_varying(&params, &settings, param);
    let csv = with_provenance(&described, &csv);
    emit(&args.out, csv.as_bytes(), args.force)?;
    let plan_summary = Summary {
        described,
        param,
        from,
        to,
        columns,
        keep,
    };

    let run = Ran {
        columns: &cols,
        integrated: progress.done(),
        failed: failed.load(Ordering::Relaxed),
        uncounted: uncounted.load(Ordering::Relaxed),
        seconds,
        threads,
    };
    summarise(&args, &plan_summary, &run)
}

/// A finished column: the varied parameter's value, its points, its cost, the map it used, its λ
/// and its points' attractor labels (empty without seeds).
type Done = (f64, Vec<f64>, u64, MapUsed, Option<ColumnLyapunov>, Vec<u8>);

/// The sweep's columns in grid order.
fn in_grid_order(updates: Vec<Update>, columns: usize) -> Vec<Done> {
    let mut cols: Vec<Option<Done>> = vec![None; columns];
    for u in updates {
        if let Update::Column {
            index,
            value,
            thetas,
            rhs_evals,
            map,
            lyapunov,
            attractor,
            ..
        } = u
        {
            cols[index] = Some((value, thetas, rhs_evals, map, lyapunov, attractor));
        }
    }
    cols.into_iter().flatten().collect()
}

/// What a finished run reports on: its columns in grid order, the cycles
/// the progress bar counted, the columns that failed, its time and threads.
struct Ran<'a> {
    columns: &'a [Done],
    integrated: u64,
    failed: u64,
    /// Seeded columns whose other attractors the cell graph could not count.
    uncounted: u64,
    seconds: f64,
    threads: usize,
}

/// The summary on stderr; an error if every column failed.
fn summarise(args: &BifurcationArgs, plan: &Summary, run: &Ran) -> Result<(), CliError> {
    let Summary {
        ref described,
        param,
        from,
        to,
        columns,
        keep,
    } = *plan;
    let cols = run.columns;
    let rows: usize = cols.iter().map(|c| c.1.len()).sum();
    // A column on the interpolant integrated its construction's samples and
    // the iterates outside its series, not the cycles counted by the bar.
    let n = run.integrated
        + cols
            .iter()
            .map(|c| match &c.3 {
                MapUsed::Interpolant(s) => (s.evaluations + s.direct_iterates) as u64,
                _ => 0,
            })
            .sum::<u64>();
    let evals: u64 = cols.iter().map(|c| c.2).sum();
    let (failed, seconds, threads) = (run.failed, run.seconds, run.threads);
    eprintln!(
        "bifurcation: {described}\n  {columns} columns in {} [{}, {}] x ({} transient + {keep} kept), {rows} rows; {seconds:.2} s on {threads} thread(s); {n} of {} iterates integrated ({:.0}/s; columns settled onto a cycle repeat it), {:.0} rhs evaluations per integrated iterate{}",
        param.name(),
        crate::text::short(from),
        crate::text::short(to),
        args.transient,
        columns as u64 * (args.transient + keep) as u64,
        n as f64 / seconds.max(1e-9),
        evals as f64 / n.max(1) as f64,
        if failed > 0 {
            format!("; {failed} column(s) failed (see above)")
        } else {
            String::new()
        }
    );
    if let Some(line) = map_line(cols.iter().map(|c| &c.3)) {
        eprintln!("{line}");
    }
    if args.seeds > 0 {
        eprintln!(
            "{}",
            multistable_line(param, cols, run.failed, run.uncounted)
        );
    }
    if failed == columns as u64 {
        return Err(CliError::Failed(format!(
            "every one of the {columns} columns failed"
        )));
    }
    Ok(())
}

/// What the summary names of the checked flags.
struct Summary {
    /// The model's line ([`model_line_varying`]).
    described: String,
    param: ContParam,
    from: f64,
    to: f64,
    columns: usize,
    keep: usize,
}

/// The summary's line on every attractor (the cell graph): how many
/// columns have more than one, and where the first and last of them are.
/// Failed columns and those the graph could not count (`uncounted`) are
/// neither: the line counts them apart.
fn multistable_line(param: ContParam, cols: &[Done], failed: u64, uncounted: u64) -> String {
    let multi: Vec<f64> = cols
        .iter()
        .filter(|c| c.5.iter().any(|&a| a > 0))
        .map(|c| c.0)
        .collect();
    let counted = (cols.len() as u64).saturating_sub(failed + uncounted);
    let apart = match (failed, uncounted) {
        (0, 0) => String::new(),
        (f, 0) => format!("; {f} failed"),
        (0, u) => format!("; {u} not counted (see the warnings)"),
        (f, u) => format!("; {f} failed, {u} not counted (see the warnings)"),
    };
    match (multi.first(), multi.last()) {
        (Some(a), Some(b)) => format!(
            "  every attractor (the cell graph): {} of {counted} counted column(s) have more than one, at {} {a} to {b}{apart}",
            multi.len(),
            param.name()
        ),
        _ if counted == 0 => {
            format!("  every attractor (the cell graph): no column counted{apart}")
        }
        _ if apart.is_empty() => {
            "  every attractor (the cell graph): every column has one attractor".into()
        }
        _ => format!(
            "  every attractor (the cell graph): each of the {counted} counted column(s) has one attractor{apart}"
        ),
    }
}

/// The summary's line on the interpolant, when any column asked for it.
fn map_line<'a>(maps: impl Iterator<Item = &'a MapUsed>) -> Option<String> {
    MapTally::of(maps).map(|t| {
        format!(
            "  map: {} column(s) kept their points from the interpolant (built from {} map evaluations, measured max error {:.1e} rad), {} refused it and integrated",
            t.used, t.evaluations, t.max_error, t.refused
        )
    })
}
