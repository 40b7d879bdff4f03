//! `oneblock phase`: the phase diagram in (θν, κ) (the paper's Fig. 4), CSV
//! `theta_nu,kappa,period,lyapunov,regime,iterates,class,lyapunov_stderr`
//! and optionally a picture, drawn by `figure`'s code (`phase_picture`).
//! Rows (one per κ) run in parallel; each row is a continued sweep along
//! θν, so the file depends only on the flags, not on the number of
//! threads. Ctrl+C stops the run and writes nothing.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;

use super::CliError;
use super::bifurcation::theta_nu_end;
use super::common::{
    SolverArgs, check_out, check_second_out, count_in, describe_sweep, emit, finite, max_seconds,
    warn_validity, with_provenance,
};
use super::run_control::{Limits, Progress};
use super::values::{given_or_preset, param_error, parse_count, parse_number, preset_params};
use crate::formats::{PHASE_LEGEND, legend_class, phase_header, phase_row};
use crate::jobs::{Axis, JobError, PhaseSpec, PhaseTuning, Spec, Update, run_collect};
use crate::model::{Params, Preset};
use crate::sim::interpolant::{MapChoice, MapTally};
use crate::sim::phase::{PhaseCell, PhaseOptions};
use crate::sim::theta_nu_grid;

/// The κ range without `--kappa-from`/`--kappa-to`: the paper's Fig. 4,
/// as the window's Phase view.
pub const DEFAULT_KAPPA: (f64, f64) = (1.0, 42.0);
/// Rows and columns without `--kappa-steps`/`--theta-nu-steps`: the
/// window's Phase view's.
pub const DEFAULT_STEPS: usize = 30;

/// A phase diagram: the attractor's class over a (θν, κ) grid.
#[derive(Debug, Clone, Args)]
pub struct PhaseArgs {
    /// Take γ, ν and Ω from a named parameter set (fig3a, fig3b, fig4,
    /// creep, chaos, intermittent, hysteresis); the flags below override them.
    #[arg(long)]
    pub preset: Option<Preset>,
    /// γ, the friction weakening, in [0.1, 1e4] (outside, slips turn into
    /// steady sliding or never stop, which the map cannot represent)
    /// [default: 6.5, or the preset's].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub gamma: Option<f64>,
    /// ν, the pulling speed, in [1e-12, 0.1] (beyond, slips turn into steady
    /// sliding, which the map cannot represent; the model assumes ν ≤ 1e-2)
    /// [default: 1e-3, or the preset's].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub nu: Option<f64>,
    /// Ω, the memory of the friction direction, in (0, 1e8] (the model
    /// assumes [1, 1e4]) [default: 50,
    /// or the preset's].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub omega: Option<f64>,
    /// First κ (the bottom row), in [1e-6, 1e3] [default: 1, the paper's
    /// Fig. 4, as the window's Phase view].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub kappa_from: Option<f64>,
    /// Last κ (the top row), in [1e-6, 1e3] [default: 42].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub kappa_to: Option<f64>,
    /// Number of κ rows, evenly spaced, ends included (1 to 10000)
    /// [default: 30, as the window's Phase view].
    #[arg(long, value_parser = parse_count, allow_hyphen_values = true)]
    pub kappa_steps: Option<usize>,
    /// First θν, in radians, in [-1000, 1000].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = parse_number)]
    pub theta_nu_from: f64,
    /// Last θν, in radians, in [-1000, 1000].
    #[arg(long, default_value_t = std::f64::consts::FRAC_PI_2, allow_hyphen_values = true, value_parser = parse_number)]
    pub theta_nu_to: f64,
    /// Number of θν columns, evenly spaced, ends included (1 to 10000;
    /// rows × columns ≤ 4e6) [default: 30, as the window's Phase view].
    #[arg(long, value_parser = parse_count, allow_hyphen_values = true)]
    pub theta_nu_steps: Option<usize>,
    /// The most iterates a cell spends looking for a period (0 to 1e6).
    #[arg(long, default_value_t = 400, value_parser = parse_count, allow_hyphen_values = true)]
    pub transient: usize,
    /// The most iterates with f'(θ) for the Lyapunov exponent when no period
    /// was found (16 to 1e6).
    #[arg(long, default_value_t = 128, value_parser = parse_count, allow_hyphen_values = true)]
    pub keep: usize,
    #[command(flatten)]
    pub solver: SolverArgs,
    /// Tolerance of the period test, in radians, in (0, 1] [default: 1e4·tol
    /// within [1e-9, 1e-3]; 1e-6 for the fixed-step methods].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub period_tol: Option<f64>,
    /// No early exit: every cell runs the whole transient and keeps every
    /// iterate with f'(θ) (the reference the fast path is compared with).
    #[arg(long)]
    pub brute_force: bool,
    /// How a cell evaluates the map after its first 400 iterates: direct,
    /// interpolant (docs/interpolant.md) or auto (the interpolant when at
    /// least 20000 iterates are left). Where refused, the cell integrates.
    #[arg(long, value_enum, default_value_t = MapChoice::Auto)]
    pub map: MapChoice,
    /// Count each cell's attractors from the exit arc's cell graph (0 to
    /// 256; 0: not counted, any other value: counted), into an
    /// `attractors` column; cells with more than one are multistable
    /// (docs/attractors.md).
    #[arg(long, default_value_t = 0, value_parser = parse_count, allow_hyphen_values = true)]
    pub seeds: usize,
    /// Compute only part K of N of the grid, K/N with 1 ≤ K ≤ N ≤ the
    /// grid's blocks of 32 × 32 cells: a run of whole blocks, each cell as
    /// the whole grid computes it; `--merge` joins the parts
    /// (docs/phase.md).
    #[arg(long, value_name = "K/N", allow_hyphen_values = true)]
    pub shard: Option<String>,
    /// Join the CSVs of a sharded grid's parts (every part once, all of one
    /// grid) into the CSV the whole grid writes, to --out (and --png); no
    /// grid flags then.
    #[arg(long, num_args = 1.., value_name = "PART")]
    pub merge: Vec<PathBuf>,
    /// Worker threads, 1 to 1024 [default: the number of cores]. The output
    /// does not depend on it.
    #[arg(long, value_parser = parse_count, allow_hyphen_values = true)]
    pub threads: Option<usize>,
    /// CSV file ("-" = stdout) [default: stdout, or none with --png].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Also (or only) draw the diagram, as `oneblock figure --view phase`
    /// draws it (the same picture over the same grid): a PNG, or an SVG or
    /// PDF when FILE ends in .svg or .pdf. Needs the default build (the
    /// window's drawing code).
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Draw these curves over the picture, as the window's Boundaries
    /// does (each kind and doubling level in its own style and legend
    /// entry): a CSV with theta_nu, kappa, kind and period columns, as
    /// `oneblock continue --curve ... --params theta-nu,kappa` writes
    /// (needs --png).
    #[arg(long, requires = "png")]
    pub boundaries: Option<PathBuf>,
    /// The figure's size in points, WIDTHxHEIGHT, each in [100, 10000], as
    /// `figure --size` (needs --png) [default: 900x600].
    #[arg(long, requires = "png", allow_hyphen_values = true, value_parser = super::figure_flags::parse_figure_size)]
    pub size: Option<[f32; 2]>,
    /// The PNG's resolution in pixels per inch (72 points), in [72, 600]
    /// and at most 20000 pixels along the longer side, as `figure --dpi`
    /// (needs --png) [default: 144, two pixels a point].
    #[arg(long, requires = "png", allow_hyphen_values = true, value_parser = parse_number)]
    pub dpi: Option<f64>,
    /// Overwrite existing --out / --png files.
    #[arg(long)]
    pub force: bool,
    /// Stop after this many seconds, in (0, 1e7], writing nothing, exit 1.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub max_seconds: Option<f64>,
}

/// The most rows or columns of a grid.
pub const MAX_STEPS: usize = 10_000;
/// The most cells of a grid.
pub const MAX_CELLS: usize = 4_000_000;

/// The checked inputs of `phase`.
pub struct Plan {
    params: Params,
    settings: crate::SolverSettings,
    kappas: Vec<f64>,
    theta_nus: Vec<f64>,
    opts: PhaseOptions,
    threads: usize,
    out: Option<PathBuf>,
    max_seconds: Option<f64>,
    /// Part K of N (--shard).
    shard: Option<Shard>,
    /// The picture of --png, drawn by `figure`'s code.
    picture: Option<super::phase_picture::Picture>,
}

/// Part K of N of a grid (--shard).
type Shard = (usize, usize);

/// Checks the flags and the outputs before any work.
pub fn check(args: &PhaseArgs) -> Result<Plan, CliError> {
    let t_from = theta_nu_end("theta-nu-from", args.theta_nu_from)?;
    let t_to = theta_nu_end("theta-nu-to", args.theta_nu_to)?;
    // Without a preset, the window's defaults (Fig. 4's γ and ν), as
    // `figure --view phase`.
    let base = Some(preset_params(args.preset).unwrap_or_default());
    let params = Params {
        kappa: 1.0,
        gamma: given_or_preset("gamma", args.gamma, base.map(|b| b.gamma))?,
        nu: given_or_preset("nu", args.nu, base.map(|b| b.nu))?,
        theta_nu: t_from,
        omega: args.omega.or(base.map(|b| b.omega)).unwrap_or(50.0),
    };
    params.validate().map_err(param_error)?;
    // Each end of the κ range is a κ of the grid, checked as one, under
    // its own flag's name.
    let (k_from, k_to) = (
        finite("kappa-from", args.kappa_from.unwrap_or(DEFAULT_KAPPA.0))?,
        finite("kappa-to", args.kappa_to.unwrap_or(DEFAULT_KAPPA.1))?,
    );
    for (name, k) in [("kappa-from", k_from), ("kappa-to", k_to)] {
        Params { kappa: k, ..params }.validate().map_err(|mut e| {
            e.name = name;
            param_error(e)
        })?;
    }
    let settings = args.solver.settings()?;
    let (rows, cols, shard) = grid_steps(args)?;
    if rows * cols > MAX_CELLS {
        return Err(CliError::Usage(format!(
            "--kappa-steps = {rows} with --theta-nu-steps = {cols} is out of range: at most {MAX_CELLS} cells"
        )));
    }
    let opts = phase_options(args, &settings)?;
    let threads = match args.threads {
        Some(n) => count_in("threads", n, 1024)?,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    let out = check_outputs(args)?;
    let max_seconds = max_seconds(args.max_seconds)?;
    let picture = super::phase_picture::check(args)?;
    Ok(Plan {
        params: Params {
            kappa: k_from,
            ..params
        },
        settings,
        kappas: theta_nu_grid(k_from, k_to, rows),
        theta_nus: theta_nu_grid(t_from, t_to, cols),
        opts,
        threads,
        out,
        max_seconds,
        shard,
        picture,
    })
}

/// [`check`], or the merge's checks with `--merge`.
pub fn check_any(args: &PhaseArgs) -> Result<(), CliError> {
    if args.merge.is_empty() {
        check(args).map(drop)
    } else {
        super::phase_merge::check(args).map(drop)
    }
}

/// The grid's rows and columns, and the part of it asked for (--shard).
fn grid_steps(args: &PhaseArgs) -> Result<(usize, usize, Option<Shard>), CliError> {
    let steps =
        |name: &str, v: Option<usize>| count_in(name, v.unwrap_or(DEFAULT_STEPS), MAX_STEPS);
    let rows = steps("kappa-steps", args.kappa_steps)?;
    let cols = steps("theta-nu-steps", args.theta_nu_steps)?;
    let shard = args
        .shard
        .as_deref()
        .map(|s| super::phase_merge::parse_shard(s, rows, cols, args.png.is_some()))
        .transpose()?;
    Ok((rows, cols, shard))
}

/// The options of every cell: the transient, the iterates kept and the
/// period's tolerance, checked.
fn phase_options(
    args: &PhaseArgs,
    settings: &crate::SolverSettings,
) -> Result<PhaseOptions, CliError> {
    if args.transient > 1_000_000 {
        return Err(CliError::Usage(format!(
            "--transient = {} is out of range: must lie in [0, 1e6]",
            args.transient
        )));
    }
    let keep = if (16..=1_000_000).contains(&args.keep) {
        args.keep
    } else {
        return Err(CliError::Usage(format!(
            "--keep = {} is out of range: must lie in [16, 1e6] (the Lyapunov exponent's error needs 8 batches of 2)",
            args.keep
        )));
    };
    let mut opts = PhaseOptions::for_settings(settings);
    opts.transient = args.transient;
    opts.keep = keep;
    opts.early_exit = !args.brute_force;
    opts.map = args.map;
    opts.seeds =
        super::values::count_between("seeds", args.seeds, 0, crate::sim::seeded::MAX_SEEDS)?;
    if let Some(t) = args.period_tol {
        if !(t.is_finite() && t > 0.0 && t <= 1.0) {
            return Err(CliError::Usage(format!(
                "--period-tol = {} is out of range: must lie in (0, 1] radians",
                super::values::short(t)
            )));
        }
        opts.period_tol = t;
    }
    Ok(opts)
}

/// The CSV's place (none with --png alone) and the picture's, both free
/// to write (or --force).
pub(super) fn check_outputs(args: &PhaseArgs) -> Result<Option<PathBuf>, CliError> {
    // Without --png the CSV goes to stdout unless --out names a file; with
    // --png alone only the picture is written.
    let out = match (&args.out, &args.png) {
        (Some(o), _) => Some(o.clone()),
        (None, None) => Some(PathBuf::from("-")),
        (None, Some(_)) => None,
    };
    if let Some(o) = &out {
        check_out(o, args.force)?;
    }
    if let Some(png) = &args.png {
        if png.as_os_str() == "-" {
            return Err(CliError::Usage(
                "--png: give a file name (the image is not written to stdout)".into(),
            ));
        }
        check_second_out(
            "png",
            png,
            out.as_deref().unwrap_or(Path::new("-")),
            args.force,
        )?;
    }
    Ok(out)
}

pub fn run(args: PhaseArgs) -> Result<(), CliError> {
    if !args.merge.is_empty() {
        return super::phase_merge::run(&args);
    }
    let plan = check(&args)?;
    warn_validity(&plan.params);
    let start = Instant::now();
    let grid = compute(&plan)?;
    let seconds = start.elapsed().as_secs_f64();
    let cells: Vec<&PhaseCell> = grid.iter().flatten().collect();
    let mut csv = String::with_capacity(80 * (cells.len() + 1));
    if let Some((k, n)) = plan.shard {
        // What the merge checks the parts by.
        csv.push_str(&super::phase_merge::shard_line(k, n, &grid_key(&plan)));
    }
    let attractors = plan.opts.seeds > 0;
    csv.push_str(&phase_header(attractors));
    csv.push('\n');
    for c in &cells {
        writeln!(csv, "{}", phase_row(c, attractors)).ok();
    }
    // The picture first: if it cannot be written, neither is the CSV.
    if let Some(p) = &plan.picture {
        let (rows, cols) = (plan.kappas.len(), plan.theta_nus.len());
        let grid = super::phase_picture::Grid {
            cells: &grid,
            theta_nu: (plan.theta_nus[0], plan.theta_nus[cols - 1]),
            kappa: (plan.kappas[0], plan.kappas[rows - 1]),
            params: plan.params,
            transient: plan.opts.transient,
            keep: plan.opts.keep,
            seeds: plan.opts.seeds,
        };
        super::phase_picture::write(p, &grid, args.force)?;
    }
    if let Some(o) = &plan.out {
        let model = format!(
            "{}; kappa and theta-nu vary over the grid",
            describe_sweep(&plan.params, &plan.settings)
        );
        let csv = with_provenance(&model, &csv);
        emit(o, csv.as_bytes(), args.force)?;
    }
    report(&plan, &cells, seconds)
}

/// The grid of `plan`, computed by the window's phase job on the plan's
/// threads, rows of increasing κ.
fn compute(plan: &Plan) -> Result<Vec<Vec<PhaseCell>>, CliError> {
    let (rows, cols) = (plan.kappas.len(), plan.theta_nus.len());
    let opts = &plan.opts;
    let planned = match plan.shard {
        Some((k, n)) => super::phase_merge::shard_cells(rows, cols, k, n).len(),
        None => rows * cols,
    };
    let progress = Progress::with_extra("phase", "cells", planned as u64, "iterates");
    let limits = Limits::start(plan.max_seconds);
    let stop = || limits.stop();
    let spec = PhaseSpec {
        params: plan.params,
        settings: plan.settings,
        theta_nu: Axis::new(plan.theta_nus[0], plan.theta_nus[cols - 1], cols),
        kappa: Axis::new(plan.kappas[0], plan.kappas[rows - 1], rows),
        transient: opts.transient,
        keep: opts.keep,
        tuning: PhaseTuning {
            early_exit: opts.early_exit,
            map: opts.map,
            period_tol: Some(opts.period_tol),
            seeds: opts.seeds,
            list_attractors: false,
            shard: plan.shard,
        },
    };
    let on_update = |u: &Update| {
        if let Update::PhaseCells { cells, .. } = u {
            for c in cells {
                // The shown count only grows: both counts are read under
                // one lock.
                progress.add_extra(c.cell.iterates);
                progress.inc(1);
            }
        }
    };
    let run = run_collect(Spec::Phase(spec), plan.threads, on_update, stop);
    progress.finish();
    let updates = match run {
        Ok(u) => u,
        Err(JobError::Stop) => return Err(limits.stopped("phase")),
        Err(JobError::Sim(e)) => return Err(e.into()),
        Err(JobError::Failed(m)) => return Err(CliError::Failed(m)),
    };
    let mut grid: Vec<Vec<Option<PhaseCell>>> = vec![vec![None; cols]; rows];
    for u in updates {
        if let Update::PhaseCells { cells, .. } = u {
            for c in cells {
                grid[c.row][c.column] = Some(c.cell);
            }
        }
    }
    Ok(grid
        .into_iter()
        .map(|row| row.into_iter().flatten().collect())
        .collect())
}

/// Everything that decides a grid's cells but not which part of it is
/// computed: the parts of a sharded grid must agree on it.
fn grid_key(plan: &Plan) -> String {
    let (rows, cols) = (plan.kappas.len(), plan.theta_nus.len());
    format!(
        "{rows} x {cols} cells, kappa {:?} to {:?}, theta-nu {:?} to {:?}, {:?}, {:?}, {:?}",
        plan.kappas[0],
        plan.kappas[rows - 1],
        plan.theta_nus[0],
        plan.theta_nus[cols - 1],
        plan.params,
        plan.settings,
        plan.opts
    )
}

/// The grid's size and ranges as the summary says them, with the part
/// computed (`n` cells) when sharded.
fn grid_text(plan: &Plan, n: usize) -> String {
    let (rows, cols) = (plan.kappas.len(), plan.theta_nus.len());
    let (k_from, k_to) = (plan.kappas[0], plan.kappas[rows - 1]);
    let (t_from, t_to) = (plan.theta_nus[0], plan.theta_nus[cols - 1]);
    let part = plan
        .shard
        .map(|(k, n_parts)| format!("part {k}/{n_parts} ({n} cells) of "))
        .unwrap_or_default();
    format!("{part}{rows} x {cols} cells (kappa [{k_from}, {k_to}], theta-nu [{t_from}, {t_to}])")
}

/// The summary on stderr (the first failed cells, the classes' counts, the
/// cost); an error if every cell failed.
fn report(plan: &Plan, cells: &[&PhaseCell], seconds: f64) -> Result<(), CliError> {
    let size = grid_text(plan, cells.len());
    let (opts, threads) = (&plan.opts, plan.threads);
    let iterates: u64 = cells.iter().map(|c| c.iterates).sum();
    let evals: u64 = cells.iter().map(|c| c.rhs_evals).sum();
    let mut counts: Vec<(String, usize)> = Vec::new();
    for c in cells {
        let label = legend_class(c.class).to_string();
        match counts.iter_mut().find(|(l, _)| *l == label) {
            Some((_, n)) => *n += 1,
            None => counts.push((label, 1)),
        }
    }
    counts.sort_by_key(|(l, _)| PHASE_LEGEND.iter().position(|(n, _)| n == l));
    let failed: Vec<&&PhaseCell> = cells.iter().filter(|c| c.error.is_some()).collect();
    for c in failed.iter().take(5) {
        if let Some(e) = &c.error {
            eprintln!(
                "warning: cell kappa = {}, theta-nu = {} failed: {e}",
                c.kappa, c.theta_nu
            );
        }
    }
    let uncounted: Vec<&&PhaseCell> = cells.iter().filter(|c| c.uncounted.is_some()).collect();
    for c in uncounted.iter().take(5) {
        if let Some(why) = &c.uncounted {
            eprintln!(
                "warning: cell kappa = {}, theta-nu = {}: its attractors not counted: {why}",
                c.kappa, c.theta_nu
            );
        }
    }
    eprintln!(
        "phase: {}\n  {size}, at most {} transient + {} kept iterates{}, period tol {:e}\n  {}\n  {iterates} iterates ({:.1} per cell), {:.0} rhs evaluations per iterate; {seconds:.2} s on {threads} thread(s)",
        describe_sweep(&plan.params, &plan.settings),
        opts.transient,
        opts.keep,
        if opts.early_exit {
            ", early exit"
        } else {
            ", brute force"
        },
        opts.period_tol,
        counts
            .iter()
            .map(|(l, n)| format!("{l} {n}"))
            .collect::<Vec<_>>()
            .join(", "),
        iterates as f64 / cells.len().max(1) as f64,
        evals as f64 / iterates.max(1) as f64,
    );
    if let Some(line) = map_line(cells) {
        eprintln!("{line}");
    }
    if opts.seeds > 0 {
        // A failed or uncounted cell is neither multistable nor not: the
        // line says how many were counted, and why the others were not.
        let multi = cells.iter().filter(|c| c.attractors > Some(1)).count();
        let counted = cells.iter().filter(|c| c.attractors.is_some()).count();
        let uncounted = match (failed.len(), uncounted.len()) {
            (0, 0) => String::new(),
            (f, 0) => format!("; {f} failed"),
            (0, u) => format!("; {u} not counted (see the warnings)"),
            (f, u) => format!("; {f} failed, {u} not counted (see the warnings)"),
        };
        eprintln!(
            "  seeds: {} per cell; {multi} of {counted} cell(s) multistable (more than one attractor){uncounted}",
            opts.seeds,
        );
    }
    if !failed.is_empty() && failed.len() == cells.len() {
        return Err(CliError::Failed(format!(
            "every one of the {} cells failed",
            cells.len()
        )));
    }
    Ok(())
}

/// Reads back a phase CSV's class column per cell (for tests and tools).
pub fn read_classes(path: &Path) -> std::io::Result<Vec<(f64, f64, String)>> {
    let mut reader = csv::ReaderBuilder::new().flexible(true).from_path(path)?;
    Ok(reader
        .records()
        .filter_map(|r| {
            let f = r.ok()?;
            Some((
                f.get(0)?.parse().ok()?,
                f.get(1)?.parse().ok()?,
                f.get(6)?.to_string(),
            ))
        })
        .collect())
}

/// The summary's line on the interpolant, when any cell asked for it: how
/// many cells iterated it (with the largest error measured and the map
/// evaluations their constructions took) and how many it was refused.
fn map_line(cells: &[&PhaseCell]) -> Option<String> {
    MapTally::of(cells.iter().map(|c| &c.map)).map(|t| {
        format!(
            "  map: {} cell(s) continued on the interpolant (built from {} map evaluations, measured max error {:.1e} rad), {} refused it and integrated",
            t.used, t.evaluations, t.max_error, t.refused
        )
    })
}
