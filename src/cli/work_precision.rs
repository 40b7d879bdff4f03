//! `oneblock work-precision`: the map error against the cost per iterate for
//! every method and setting, on a fixed sample of attractor points (CSV, and
//! optionally the log-log chart as SVG).

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use clap::Args;

use super::CliError;
use super::common::{
    check_out, check_second_out, check_theta, count_in, emit, emit_as, finite, max_seconds,
    warn_validity,
};
use super::run_control::Limits;
use super::values::{given_or_preset, param_error, parse_count, parse_number, preset_params};
use crate::model::{Params, Preset};
use crate::numerics::sample::{Attractor, build_sample, default_attractors};
use crate::numerics::work_precision::{CSV_HEADER, Row, default_subjects, measure};
use crate::numerics::{Subject, chart};

/// The work-precision chart: error against cost for every method.
#[derive(Debug, Clone, Args)]
pub struct WorkPrecisionArgs {
    /// Measure on a single attractor from a named parameter set (fig3a,
    /// fig3b, fig4, creep, chaos, intermittent); the flags below override it.
    #[arg(long)]
    pub preset: Option<Preset>,
    /// κ of a single attractor to measure on [default: the four-attractor
    /// sample], in [1e-6, 1e3] (beyond, slips turn into steady sliding).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub kappa: Option<f64>,
    /// γ of that attractor, in [0.1, 1e4] (outside, slips never stop).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub gamma: Option<f64>,
    /// ν of that attractor, in [1e-12, 0.1] (beyond, slips turn into steady
    /// sliding).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub nu: Option<f64>,
    /// θν of that attractor, in radians.
    #[arg(long = "theta-nu", allow_hyphen_values = true, value_parser = parse_number)]
    pub theta_nu: Option<f64>,
    /// Ω of that attractor, in (0, 1e8] (the model assumes [1, 1e4])
    /// [default: 50, or the preset's].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub omega: Option<f64>,
    /// Where that attractor's orbit starts [default: θν].
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
    let single = args.preset.is_some()
        || args.kappa.is_some()
        || args.gamma.is_some()
        || args.nu.is_some()
        || args.theta_nu.is_some();
    let attractors = if !single {
        default_attractors()
    } else {
        let base = preset_params(args.preset);
        let params = Params {
            kappa: given_or_preset("kappa", args.kappa, base.map(|b| b.kappa))?,
            gamma: given_or_preset("gamma", args.gamma, base.map(|b| b.gamma))?,
            nu: given_or_preset("nu", args.nu, base.map(|b| b.nu))?,
            theta_nu: given_or_preset("theta-nu", args.theta_nu, base.map(|b| b.theta_nu))?,
            omega: args.omega.or(base.map(|b| b.omega)).unwrap_or(50.0),
        };
        params.validate().map_err(param_error)?;
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
    let sample = build_sample(&attractors, points)?;
    let spread = sample
        .iter()
        .map(|s| s.reference_spread())
        .fold(0.0, f64::max);
    let min_time = Duration::from_secs_f64(min_ms * 1e-3);
    let mut rows: Vec<Row> = Vec::with_capacity(subjects.len());
    for (i, s) in subjects.iter().enumerate() {
        if limits.stop() {
            return Err(limits.stopped("work-precision"));
        }
        let row = measure(&sample, s, min_time);
        // One line per setting, on a terminal or not: a run takes minutes.
        eprintln!("[{}/{}] {}", i + 1, subjects.len(), row.csv());
        rows.push(row);
    }
    let load_after = load_average();
    let fmt_load = |l: Option<f64>| l.map_or("?".into(), |l| format!("{l:.2}"));

    let mut csv = String::new();
    writeln!(
        csv,
        "# oneblock work-precision: {} points on {} attractor(s) ({}); reference DOP853 tol 1e-14, max |theta'_ref - theta'_dp54(1e-13)| = {spread:.2e}; load average {} before, {} after",
        sample.len(),
        attractors.len(),
        attractors
            .iter()
            .map(|a| format!(
                "{}: kappa {} gamma {} nu {} theta-nu {}",
                a.name, a.params.kappa, a.params.gamma, a.params.nu, a.params.theta_nu
            ))
            .collect::<Vec<_>>()
            .join("; "),
        fmt_load(load_before),
        fmt_load(load_after)
    )
    .ok();
    csv.push_str(CSV_HEADER);
    csv.push('\n');
    for r in &rows {
        csv.push_str(&r.csv());
        csv.push('\n');
    }
    emit(&args.out, csv.as_bytes(), args.force)?;
    if let Some(svg) = &args.svg {
        let text = chart::svg(
            &rows,
            &format!("{} points, reference spread {spread:.1e}", sample.len()),
        )
        .map_err(|e| CliError::Failed(format!("--svg: cannot draw the chart: {e}")))?;
        emit_as("svg", svg, text.as_bytes(), args.force)?;
    }
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
        "work-precision: {} settings{failed} on {} points in {:.1} s; reference spread (DOP853 1e-14 vs DP5(4) 1e-13) {spread:.2e}; load average {} → {}",
        rows.len(),
        sample.len(),
        start.elapsed().as_secs_f64(),
        fmt_load(load_before),
        fmt_load(load_after)
    );
    Ok(())
}
