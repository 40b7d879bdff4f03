//! `oneblock bifurcation`: the data of a bifurcation diagram, CSV
//! `theta_nu,theta`, computed on two threads.
//!
//! The θν grid is split into two halves, the lower ⌈C/2⌉ columns and the
//! rest, one per thread, and each half into [`LANES`] segments
//! ([`segments`]); each segment is a continued sweep of its own (each
//! column starts from the last iterate of the previous one; docs/model.md), and
//! a thread steps its segments' slips together ([`sweep_segments`]: one
//! core runs three independent chains of dependent evaluations side by
//! side, ~1.4× the iterates per second of one). The split does not depend
//! on the number of cores, so the output depends only on the flags: it is
//! the same file on any machine and equals [`sweep_columns`] called on each
//! segment in turn.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};

use super::CliError;
use super::common::{
    MAX_ROWS, SolverArgs, check_out, check_theta, count_in, describe_sweep, emit, finite,
    stderr_is_terminal, total_iterates,
};
use crate::model::Params;
use crate::sim::{Column, Simulator, SweepOptions, sweep_segments, theta_nu_grid};
#[cfg(doc)]
use crate::sim::{LANES, segments, sweep_columns};

/// A bifurcation diagram: θ against θν.
#[derive(Debug, Clone, Args)]
pub struct BifurcationArgs {
    /// κ = k_x/k_y, the spring anisotropy (> 0).
    #[arg(long, allow_hyphen_values = true)]
    pub kappa: f64,
    /// γ, the friction weakening (≥ 0).
    #[arg(long, allow_hyphen_values = true)]
    pub gamma: f64,
    /// ν, the pulling speed (> 0).
    #[arg(long, allow_hyphen_values = true)]
    pub nu: f64,
    /// Ω, the memory of the friction direction (> 0).
    #[arg(long, default_value_t = 50.0, allow_hyphen_values = true)]
    pub omega: f64,
    #[command(flatten)]
    pub solver: SolverArgs,
    /// First θν of the grid, in radians.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub theta_nu_from: f64,
    /// Last θν of the grid, in radians (may be below --theta-nu-from: the
    /// sweep then runs downwards).
    #[arg(long, default_value_t = std::f64::consts::FRAC_PI_2, allow_hyphen_values = true)]
    pub theta_nu_to: f64,
    /// Number of θν values, evenly spaced, ends included (1 to 1e6).
    #[arg(long, default_value_t = 200)]
    pub columns: usize,
    /// Iterates dropped at each θν before any is kept.
    #[arg(long, default_value_t = 500)]
    pub transient: usize,
    /// Iterates kept at each θν: one CSV row each (≥ 1; columns × keep ≤ 1e8).
    #[arg(long, default_value_t = 100)]
    pub keep: usize,
    /// θ where each half's first column starts [default: that column's θν].
    #[arg(long, allow_hyphen_values = true)]
    pub theta0: Option<f64>,
    /// CSV file ("-" = stdout).
    #[arg(long, default_value = "-")]
    pub out: PathBuf,
    /// Overwrite an existing --out file.
    #[arg(long)]
    pub force: bool,
}

/// The most θν values a diagram may have (far more than a screen's pixels).
pub const MAX_COLUMNS: usize = 1_000_000;

/// The two halves the grid is split into: the first ⌈n/2⌉ values, then the rest.
pub fn halves(grid: &[f64]) -> (&[f64], &[f64]) {
    grid.split_at(grid.len().div_ceil(2))
}

pub fn run(args: BifurcationArgs) -> Result<(), CliError> {
    let from = finite("theta-nu-from", args.theta_nu_from)?;
    let to = finite("theta-nu-to", args.theta_nu_to)?;
    let params = Params {
        kappa: args.kappa,
        gamma: args.gamma,
        nu: args.nu,
        theta_nu: from,
        omega: args.omega,
    };
    params
        .validate()
        .map_err(|e| CliError::Usage(format!("--{e}")))?;
    let settings = args.solver.settings()?;
    let columns = count_in("columns", args.columns, MAX_COLUMNS)?;
    let keep = count_in("keep", args.keep, MAX_ROWS / columns)?;
    let total = total_iterates(args.transient, ("keep", keep), columns)?;
    if let Some(th) = args.theta0 {
        // On the arc of the first column; later columns project it onto theirs.
        let sim = Simulator::new(params, settings)?;
        check_theta(&sim, "theta0", th)?;
    }
    check_out(&args.out, args.force)?;

    let grid = theta_nu_grid(from, to, columns);
    let (lower, upper) = halves(&grid);
    let opts = SweepOptions {
        transient: args.transient,
        keep,
    };
    let bar = if stderr_is_terminal() {
        let b = ProgressBar::new(total);
        if let Ok(style) = ProgressStyle::with_template(
            "bifurcation {bar:40} {percent:>3}% of {human_len} iterates, eta {eta}",
        ) {
            b.set_style(style);
        }
        b
    } else {
        ProgressBar::hidden()
    };
    let iterates = AtomicU64::new(0);
    let failed = AtomicU64::new(0);
    let count = || {
        iterates.fetch_add(1, Ordering::Relaxed);
        bar.inc(1);
        false
    };
    let report = |col: &Column| {
        if let Some(e) = &col.error {
            failed.fetch_add(1, Ordering::Relaxed);
            bar.suspend(|| {
                eprintln!(
                    "warning: column theta-nu = {} failed after {} of {} kept iterates: {e}",
                    col.theta_nu,
                    col.thetas.len(),
                    keep
                );
            });
        }
    };
    let theta0 = args.theta0;
    let start = Instant::now();
    let (cols_lower, cols_upper) = std::thread::scope(|s| {
        let upper_job =
            s.spawn(|| sweep_segments(params, settings, upper, &opts, theta0, &count, report));
        let lower_cols = sweep_segments(params, settings, lower, &opts, theta0, &count, report);
        (lower_cols, upper_job.join())
    });
    bar.finish_and_clear();
    let cols_upper = cols_upper.map_err(|_| {
        CliError::Failed("the thread computing the upper half of the θν range failed".into())
    })?;
    let seconds = start.elapsed().as_secs_f64();

    let cols: Vec<&Column> = cols_lower.iter().chain(&cols_upper).collect();
    let rows: usize = cols.iter().map(|c| c.thetas.len()).sum();
    let mut csv = String::with_capacity(48 * (rows + 1));
    csv.push_str("theta_nu,theta\n");
    for c in &cols {
        for th in &c.thetas {
            writeln!(csv, "{},{}", c.theta_nu, th).ok();
        }
    }
    emit(&args.out, csv.as_bytes(), args.force)?;

    let n = iterates.load(Ordering::Relaxed);
    let evals: u64 = cols.iter().map(|c| c.rhs_evals).sum();
    let failed = failed.load(Ordering::Relaxed);
    eprintln!(
        "bifurcation: {}\n  {columns} columns in theta-nu [{from}, {to}] x ({} transient + {keep} kept), {rows} rows; {seconds:.2} s on 2 threads; {n} of {} iterates integrated ({:.0}/s; columns settled onto a cycle repeat it), {:.0} rhs evaluations per integrated iterate{}",
        describe_sweep(&params, &settings),
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
    if failed == columns as u64 {
        return Err(CliError::Failed(format!(
            "every one of the {columns} columns failed"
        )));
    }
    Ok(())
}
