//! `oneblock work-precision`: the map error against the cost per iterate for
//! every method and setting, on a fixed sample of attractor points (CSV, and
//! optionally the log-log chart as SVG).

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use clap::Args;

use super::CliError;
use super::common::{
    ModelArgs, check_out, check_second_out, check_theta, count_in, emit_all, finite, max_seconds,
    warn_validity, with_provenance,
};
use super::run_control::{Limits, Progress, collect_job, job_error};
use super::values::{parse_count, parse_number};
use crate::jobs::{Timing, Update, WorkPrecisionSpec};
use crate::numerics::sample::{Attractor, default_attractors};
use crate::numerics::work_precision::{CSV_HEADER, Row, default_subjects};
use crate::numerics::{Subject, chart};

/// The work-precision chart: error against cost for every method.
#[derive(Debug, Clone, Args)]
pub struct WorkPrecisionArgs {
    /// A single attractor to measure on [default: the four-attractor
    /// sample]: its parameters, from a preset or given one by one.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Where that attractor's orbit starts, on its exit arc [default: θν];
    /// only with --preset or the model's flags.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub theta0: Option<f64>,
    /// Orbit points per attractor (1 to 10000). The default attractors'
    /// first 64 (200 for the two chaotic ones) are committed, so the
    /// default sample does not move when the integrator changes; more are
    /// taken from a fresh orbit.
    #[arg(long, default_value_t = 16, value_parser = parse_count, allow_hyphen_values = true)]
    pub points: usize,
    /// Each point is timed over repeated runs lasting at least this many
    /// milliseconds, in [0, 10000].
    #[arg(long, default_value_t = 2.0, allow_hyphen_values = true, value_parser = parse_number)]
    pub min_time_ms: f64,
    /// Only the methods whose name contains this: dp54, dop853, rk4, euler,
    /// or a peer's (ode_solvers).
    #[arg(long)]
    pub only: Option<String>,
    /// CSV file ("-" = stdout).
    #[arg(long)]
    pub out: PathBuf,
    /// Also draw the chart (log-log, error against time per iterate) as SVG.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Overwrite existing output files.
    #[arg(long)]
    pub force: bool,
    /// Stop after this many seconds, in (0, 1e7], writing nothing, exit 1.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub max_seconds: Option<f64>,
}

/// The machine's 1-minute load average, read from /proc/loadavg.
pub fn load_average() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// The checked inputs of `work-precision`.
pub struct Plan {
    attractors: Vec<Attractor>,
    points: usize,
    min_ms: f64,
    subjects: Vec<Subject>,
    max_seconds: Option<f64>,
}

/// Checks the flags and the outputs before any work.
pub fn check(args: &WorkPrecisionArgs) -> Result<Plan, CliError> {
    let attractors = if !args.model.any() {
        if let Some(t) = args.theta0 {
            // The default sample's attractors each start where their
            // committed points do: a θ₀ would be ignored, so it is refused.
            return Err(CliError::Usage(format!(
                "--theta0 = {} needs an attractor to start on: give --preset or the model's flags (the default sample's four attractors start at their own onsets)",
                super::values::short(t)
            )));
        }
        default_attractors()
    } else {
        let params = args.model.params()?;
        let theta0 = match args.theta0 {
            Some(t) => {
                // On the exit arc, said with the flag and a short number
                // (the sample's own error would print all 309 digits of 1e308).
                let sim = crate::sim::Simulator::new(
                    params,
                    crate::integrate::SolverSettings::adaptive(
                        crate::integrate::Method::Dop853,
                        1e-10,
                    ),
                )
                .map_err(CliError::from)?;
                check_theta(&sim, "theta0", finite("theta0", t)?)?
            }
            None => params.theta_nu,
        };
        vec![Attractor {
            name: "given",
            params,
            theta0,
            transient: 300,
            extra: None,
            fixed: None,
        }]
    };
    let points = count_in("points", args.points, 10_000)?;
    let min_ms = finite("min-time-ms", args.min_time_ms)?;
    if !(0.0..=10_000.0).contains(&min_ms) {
        return Err(CliError::Usage(format!(
            "--min-time-ms = {} is out of range: must lie in [0, 10000]",
            super::values::short(min_ms)
        )));
    }
    let all = default_subjects();
    let subjects: Vec<Subject> = all
        .iter()
        .filter(|s| {
            args.only
                .as_deref()
                .is_none_or(|o| s.method_name().contains(o))
        })
        .cloned()
        .collect();
    if subjects.is_empty() {
        let mut names: Vec<&str> = all.iter().map(Subject::method_name).collect();
        names.dedup();
        return Err(CliError::Usage(format!(
            "--only = '{}' matches no method: expected a part of {}",
            super::values::echo(args.only.as_deref().unwrap_or("")),
            names.join(", ")
        )));
    }
    check_out(&args.out, args.force)?;
    if let Some(svg) = &args.svg {
        check_second_out("svg", svg, &args.out, args.force)?;
    }
    let max_seconds = max_seconds(args.max_seconds)?;
    Ok(Plan {
        attractors,
        points,
        min_ms,
        subjects,
        max_seconds,
    })
}

pub fn run(args: WorkPrecisionArgs) -> Result<(), CliError> {
    let Plan {
        attractors,
        points,
        min_ms,
        subjects,
        max_seconds,
    } = check(&args)?;
    if let [a] = attractors.as_slice() {
        warn_validity(&a.params);
    }
    let limits = Limits::start(max_seconds);
    let load_before = load_average();
    let start = Instant::now();
    let spec = WorkPrecisionSpec {
        attractors: attractors.clone(),
        points,
        timing: Timing::PerPoint(Duration::from_secs_f64(min_ms * 1e-3)),
        subjects,
    };
    // One line per setting, on a terminal or not: a run takes minutes.
    let each = |u: &Update| {
        if let Update::WorkPrecisionRow {
            index, total, row, ..
        } = u
        {
            eprintln!("[{}/{}] {}", index + 1, total, row.csv());
        }
    };
    let total = spec.subjects.len() as u64;
    let progress = Progress::new("work-precision", "settings", total).quiet();
    let updates = collect_job(spec.into(), 1, &progress, &limits, &each, |_| true)
        .map_err(|e| job_error("work-precision", &limits, e))?;
    let (mut sample_len, mut spread) = (0, 0.0);
    let mut rows: Vec<Row> = Vec::new();
    for u in updates {
        match u {
            Update::WorkPrecisionSample {
                points,
                reference_spread,
                ..
            } => (sample_len, spread) = (points, reference_spread),
            Update::WorkPrecisionRow { row, .. } => rows.push(row),
            _ => {}
        }
    }
    let load_after = load_average();
    let loads = [load_before, load_after];
    let csv = with_provenance(
        "each attractor's own, on the line below",
        &csv_text(&attractors, sample_len, spread, loads, &rows),
    );
    let chart = match &args.svg {
        Some(_) => Some(
            chart::svg(
                &rows,
                &format!("{sample_len} points, reference spread {spread:.1e}"),
            )
            .map_err(|e| CliError::Failed(format!("--svg: cannot draw the chart: {e}")))?,
        ),
        None => None,
    };
    let mut outputs = vec![("out", args.out.as_path(), csv.as_bytes())];
    if let (Some(p), Some(text)) = (&args.svg, &chart) {
        outputs.push(("svg", p.as_path(), text.as_bytes()));
    }
    emit_all(&outputs, args.force)?;
    report(&rows, sample_len, spread, start, loads);
    Ok(())
}

/// A load average as the CSV and the summary show it.
fn fmt_load(l: Option<f64>) -> String {
    l.map_or("?".into(), |l| format!("{l:.2}"))
}

/// The CSV: a comment line saying what was measured on what (and the
/// load average before and after), the header, a row per setting.
fn csv_text(
    attractors: &[Attractor],
    points: usize,
    spread: f64,
    loads: [Option<f64>; 2],
    rows: &[Row],
) -> String {
    let mut csv = String::new();
    writeln!(
        csv,
        "# oneblock work-precision: {} points on {} attractor(s) ({}); reference DOP853 tol 1e-14, max |theta'_ref - theta'_dp54(1e-13)| = {spread:.2e}; load average {} before, {} after",
        points,
        attractors.len(),
        attractors
            .iter()
            .map(|a| format!(
                "{}: kappa {} gamma {} nu {} theta-nu {}",
                a.name, a.params.kappa, a.params.gamma, a.params.nu, a.params.theta_nu
            ))
            .collect::<Vec<_>>()
            .join("; "),
        fmt_load(loads[0]),
        fmt_load(loads[1])
    )
    .ok();
    csv.push_str(CSV_HEADER);
    csv.push('\n');
    for r in rows {
        csv.push_str(&r.csv());
        csv.push('\n');
    }
    csv
}

/// A note per setting that failed on some points, and the summary line.
fn report(rows: &[Row], points: usize, spread: f64, start: Instant, loads: [Option<f64>; 2]) {
    for r in rows.iter().filter(|r| r.failed > 0) {
        eprintln!(
            "note: {} {} {:e}: {} of {} points failed, first: {}",
            r.method,
            r.kind,
            r.setting,
            r.failed,
            r.points,
            super::values::escape_controls(r.failure.as_deref().unwrap_or("?"))
        );
    }
    let failed = rows.iter().filter(|r| r.all_failed()).count();
    let failed = if failed > 0 {
        format!(" ({failed} failed on every point: no measurement, empty columns)")
    } else {
        String::new()
    };
    eprintln!(
        "work-precision: {} settings{failed} on {points} points in {:.1} s; reference spread (DOP853 1e-14 vs DP5(4) 1e-13) {spread:.2e}; load average {} → {}",
        rows.len(),
        start.elapsed().as_secs_f64(),
        fmt_load(loads[0]),
        fmt_load(loads[1])
    );
}
