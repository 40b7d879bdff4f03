//! `oneblock orbit`: an orbit of the map. One CSV row per kept slip event,
//! then the detected period and the Lyapunov exponent (on stderr, or as a
//! JSON summary on stdout with `--json`).
//!
//! With `--map interpolant` (or `auto` on long runs) the iterates come from
//! the map's verified interpolant (docs/interpolant.md): a row taken from
//! it cost no integration, so its `rhs_evals` and `steps` are 0, and the
//! summary's evaluation count is that of the construction and of the
//! iterates integrated directly.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;

use super::CliError;
use super::common::{
    ModelArgs, SolverArgs, check_out, check_second_out, check_theta, count_in, describe, emit,
    emit_all, finite, max_seconds, settings_json, total_iterates, warn_validity, with_provenance,
};
use super::run_control::{Limits, Progress, check_stdout, collect_job, job_error};
use super::values::{parse_count, parse_number, short};
use crate::formats::{SLIP_EVENT_COLUMNS, slip_event_row};
use crate::jobs::{IterateOptions, IterateSpec, Update};
use crate::sim::interpolant::{InterpolantSummary, MapUsed};
use crate::sim::period::longest_testable;
use crate::sim::{MapChoice, Orbit, OrbitOptions, Period, Simulator};

/// The most iterates an orbit keeps: each is a slip event held in memory
/// (and a CSV row) until the file is written atomically, ~400 bytes in all.
pub const MAX_KEEP: usize = 1_000_000;

/// An orbit θ0, f(θ0), f(f(θ0)), … of the map.
#[derive(Debug, Clone, Args)]
pub struct OrbitArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    #[command(flatten)]
    pub solver: SolverArgs,
    /// θ of the first slip onset, in radians (on the exit arc) [default: θν,
    /// which always is].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub theta0: Option<f64>,
    /// Iterates dropped before any is kept (transient + keep ≤ 1e12; bound
    /// the time with --max-seconds).
    #[arg(long, default_value_t = 1000, value_parser = parse_count, allow_hyphen_values = true)]
    pub transient: usize,
    /// Iterates kept: one CSV row each (1 to 1e6).
    #[arg(long, default_value_t = 200, value_parser = parse_count, allow_hyphen_values = true)]
    pub keep: usize,
    /// CSV file of the kept events ("-" = stdout) [default: stdout, or none
    /// with --json or --stats].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the summary (period, Lyapunov exponent, …) as one JSON object
    /// on stdout instead of as text on stderr.
    #[arg(long)]
    pub json: bool,
    /// Overwrite an existing --out file.
    #[arg(long)]
    pub force: bool,
    /// Skip the Lyapunov exponent (it costs two extra map evaluations per
    /// kept iterate).
    #[arg(long)]
    pub no_lyapunov: bool,
    /// Tolerance of the period test, in radians [default: 1e4·tol within
    /// [1e-9, 1e-3]; 1e-6 for the fixed-step methods].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub period_tol: Option<f64>,
    /// Stop after this many seconds, in (0, 1e7], writing nothing, exit 1.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub max_seconds: Option<f64>,
    /// How the map is evaluated: direct (every iterate integrated),
    /// interpolant (a verified piecewise Chebyshev interpolant of the map,
    /// built once; docs/interpolant.md) or auto (the interpolant from 20000
    /// iterates on). Where the interpolant cannot be verified the run
    /// integrates and says so.
    #[arg(long, value_enum, default_value_t = MapChoice::Auto)]
    pub map: MapChoice,
    /// CSV file of the kept events' intermittency statistics: the laminar
    /// lengths (runs of creep slips between two stick-slip slips, creep
    /// being where the slip starts: gamma^2 < kappa cos^2 theta + sin^2
    /// theta), the creep channel's passage time computed from f, and the
    /// slip-size distribution in logarithmic bins (docs/cli.md).
    #[arg(long)]
    pub stats: Option<PathBuf>,
    /// With --stats: locate a tangency by continuation (the fold of a
    /// periodic window's cycle within 0.05 of theta-nu) and fit the mean
    /// laminar length against the distance to it; where there is none, the
    /// file says so (seconds to a minute).
    #[arg(long)]
    pub scaling: bool,
}

/// The checked inputs of `orbit`.
pub struct Plan {
    sim: Simulator,
    theta0: f64,
    opts: OrbitOptions,
    total: u64,
    csv_out: Option<PathBuf>,
    max_seconds: Option<f64>,
    choice: MapChoice,
}

/// Checks the flags and the output before any work.
pub fn check(args: &OrbitArgs) -> Result<Plan, CliError> {
    let params = args.model.params()?;
    let settings = args.solver.settings()?;
    let keep = count_in("keep", args.keep, MAX_KEEP)?;
    let choice = args.map;
    let total = total_iterates(args.transient, ("keep", keep), 1)?;
    let period_tol = match args.period_tol {
        Some(t) => {
            let t = finite("period-tol", t)?;
            if t <= 0.0 {
                return Err(CliError::Usage(format!(
                    "--period-tol = {} is out of range: must be a finite number > 0",
                    short(t)
                )));
            }
            t
        }
        None => OrbitOptions::period_tol_of(&settings),
    };
    let csv_out: Option<PathBuf> = match (&args.out, args.json) {
        (Some(p), true) if p.as_os_str() == "-" => {
            return Err(CliError::Usage(
                "--out - and --json would both write to stdout: give --out a file name".into(),
            ));
        }
        (Some(p), _) => Some(p.clone()),
        (None, true) => None,
        (None, false) if args.stats.is_some() => None,
        (None, false) => Some(PathBuf::from("-")),
    };
    if let Some(p) = &csv_out {
        check_out(p, args.force)?;
    }
    if args.scaling && args.stats.is_none() {
        return Err(CliError::Usage(
            "--scaling: give --stats FILE too (the scan's numbers are written there)".into(),
        ));
    }
    if let Some(st) = &args.stats {
        if st.as_os_str() == "-" {
            return Err(CliError::Usage(
                "--stats: give a file name (the statistics are not written to stdout)".into(),
            ));
        }
        let other = csv_out.as_deref().unwrap_or(Path::new("-"));
        check_second_out("stats", st, other, args.force)?;
    }
    if args.json {
        check_stdout()?;
    }
    let max_seconds = max_seconds(args.max_seconds)?;
    let sim = Simulator::new(params, settings)?;
    let theta0 = check_theta(&sim, "theta0", args.theta0.unwrap_or(params.theta_nu))?;
    let opts = OrbitOptions {
        transient: args.transient,
        keep,
        lyapunov: !args.no_lyapunov,
        period_tol,
    };
    Ok(Plan {
        sim,
        theta0,
        opts,
        total,
        csv_out,
        max_seconds,
        choice,
    })
}

pub fn run(args: OrbitArgs) -> Result<(), CliError> {
    let Plan {
        sim,
        theta0,
        opts,
        total,
        csv_out,
        max_seconds,
        choice,
    } = check(&args)?;
    let (params, settings) = (*sim.params(), *sim.settings());
    let period_tol = opts.period_tol;
    warn_validity(&params);
    let progress = Progress::new("orbit", "iterates", total);
    let limits = Limits::start(max_seconds);
    let start = Instant::now();
    let spec = IterateSpec {
        params,
        settings,
        theta0: Some(theta0),
        transient: opts.transient,
        keep: opts.keep,
        graph_powers: 0,
        options: IterateOptions {
            map: choice,
            period_tol: Some(period_tol),
            lyapunov: opts.lyapunov,
            report: true,
            // Without a CSV or statistics, the summary only: memory that
            // does not grow with --keep.
            events: csv_out.is_some() || args.stats.is_some(),
        },
    };
    // Only the whole orbit is kept (its streamed batches are the window's).
    let whole = |u: &Update| matches!(u, Update::Orbit { .. });
    let updates = collect_job(spec.into(), 1, &progress, &limits, &|_| {}, whole)
        .map_err(|e| job_error("orbit", &limits, e))?;
    let Some((orbit, used)) = updates.into_iter().find_map(|u| match u {
        Update::Orbit { orbit, map, .. } => Some((*orbit, map)),
        _ => None,
    }) else {
        return Err(CliError::Failed(
            "orbit: the job ended without its orbit".into(),
        ));
    };
    let seconds = start.elapsed().as_secs_f64();
    warn_anomalies(&orbit);

    // Both files made before either is written: all or nothing.
    let model = describe(sim.params(), sim.settings());
    let csv = csv_out.as_ref().map(|_| {
        let mut csv = with_provenance(&model, &SLIP_EVENT_COLUMNS.join(","));
        csv.push('\n');
        for e in &orbit.events {
            csv.push_str(&slip_event_row(e));
            csv.push('\n');
        }
        csv
    });
    let mut stats = None;
    if args.stats.is_some() {
        let source = match &used {
            MapUsed::Interpolant(i) => format!(
                "; slip sizes from the interpolant's tables (map error {:.1e} rad)",
                i.max_map_error
            ),
            MapUsed::Refused(_) => "; slip sizes integrated (the interpolant was refused)".into(),
            MapUsed::Direct => "; slip sizes integrated".into(),
        };
        let text = super::orbit_stats::stats_text(&sim, &orbit, &source, args.scaling, &limits)?;
        stats = Some(with_provenance(&model, &text));
    }
    let mut outputs = Vec::new();
    if let (Some(p), Some(text)) = (&csv_out, &csv) {
        outputs.push(("out", p.as_path(), text.as_bytes()));
    }
    if let (Some(p), Some(text)) = (&args.stats, &stats) {
        outputs.push(("stats", p.as_path(), text.as_bytes()));
    }
    emit_all(&outputs, args.force)?;
    let summary = Summary {
        args: &args,
        theta0,
        period_tol,
        orbit: &orbit,
        seconds,
        used: &used,
    };
    if args.json {
        let mut obj = summary.json();
        if let Some(m) = obj.as_object_mut() {
            m.insert(
                "params".into(),
                serde_json::to_value(params).unwrap_or_default(),
            );
            m.insert("solver".into(), settings_json(&settings));
        }
        emit(Path::new("-"), format!("{obj}\n").as_bytes(), false)?;
    } else {
        eprint!(
            "orbit: {}\n{}",
            describe(&params, &settings),
            summary.text()
        );
    }
    Ok(())
}

/// Warns of the kept events outside the model: the first in full, then
/// how many there are.
fn warn_anomalies(orbit: &Orbit) {
    if let Some(first) = &orbit.first_anomaly {
        eprintln!("warning: {first}");
        eprintln!(
            "warning: {} of {} kept events are outside the model (negative energy released, or theta' = theta - pi)",
            orbit.anomalies, orbit.kept
        );
    }
}

struct Summary<'a> {
    args: &'a OrbitArgs,
    theta0: f64,
    period_tol: f64,
    orbit: &'a Orbit,
    seconds: f64,
    used: &'a MapUsed,
}

impl Summary<'_> {
    /// The longest period the kept iterates can reveal (a period is seen
    /// only when it repeats twice).
    fn longest_testable(&self) -> usize {
        longest_testable(self.orbit.kept)
    }

    fn iterates(&self) -> usize {
        self.args.transient + self.orbit.kept
    }

    fn text(&self) -> String {
        let o = self.orbit;
        let mut s = String::new();
        writeln!(
            s,
            "  from theta0 = {}: {} transient + {} kept iterates, {} restart(s), {:.3} s, {:.0} rhs evaluations per iterate{}",
            self.theta0,
            self.args.transient,
            o.kept,
            o.restarts,
            self.seconds,
            o.rhs_evals as f64 / self.iterates().max(1) as f64,
            if o.lyapunov.is_some() {
                " (derivatives included)"
            } else {
                ""
            }
        )
        .ok();
        s.push_str(&self.map_text());
        let p = self.longest_testable();
        match o.period {
            _ if p == 0 => writeln!(s, "  period: not determined (needs --keep >= 2)"),
            Period::Periodic(n) => match &o.cycle {
                Some(c) => writeln!(
                    s,
                    "  period: {n} (cycle solved by Newton: multiplier {}, residual {:e}; period tolerance {:e})",
                    c.multiplier, c.residual, self.period_tol
                ),
                None => writeln!(s, "  period: {n} (tolerance {:e})", self.period_tol),
            },
            Period::Aperiodic => writeln!(
                s,
                "  period: aperiodic (no period <= {p} within {:e})",
                self.period_tol
            ),
        }
        .ok();
        match (o.lyapunov, o.lyapunov_stderr) {
            (Some(l), _) if o.cycle.is_some() => writeln!(
                s,
                "  lyapunov exponent: {l:.6} (ln|multiplier|/p of the solved cycle: exact)"
            ),
            (Some(l), Some(e)) => writeln!(
                s,
                "  lyapunov exponent: {l:.6} ± {e:.1e} (standard error; ln|f'| averaged over the kept iterates)"
            ),
            (Some(l), None) => writeln!(
                s,
                "  lyapunov exponent: {l:.6} (under 16 kept iterates: no error estimate)"
            ),
            _ => writeln!(s, "  lyapunov exponent: not computed (--no-lyapunov)"),
        }
        .ok();
        s
    }

    fn map_text(&self) -> String {
        match self.used {
            MapUsed::Direct => "  map: direct integration of every iterate\n".into(),
            MapUsed::Refused(why) => format!(
                "  map: direct integration of every iterate (the interpolant was refused: {why})\n"
            ),
            MapUsed::Interpolant(InterpolantSummary {
                pieces,
                degree,
                interval,
                evaluations,
                points,
                max_map_error: max_error,
                max_event_error,
                direct_iterates,
                refused_extension,
            }) => {
                let mut s = format!(
                    "  map: interpolant, {pieces} piece(s) of degree <= {degree} over theta in [{:.6}, {:.6}], built from {evaluations} map evaluations; measured max error {max_error:.1e} rad in theta' (event quantities {max_event_error:.1e} relative) at {points} independent points; {direct_iterates} iterate(s) integrated directly\n",
                    interval.0, interval.1
                );
                if let Some(why) = refused_extension {
                    writeln!(s, "  map: an extension was refused ({why}); the iterates beyond were integrated").ok();
                }
                s
            }
        }
    }

    fn map_json(&self) -> serde_json::Value {
        match self.used {
            MapUsed::Direct => serde_json::json!({ "method": "direct" }),
            MapUsed::Refused(why) => {
                serde_json::json!({ "method": "direct", "interpolant_refused": why })
            }
            MapUsed::Interpolant(InterpolantSummary {
                pieces,
                degree,
                interval,
                evaluations,
                points,
                max_map_error: max_error,
                max_event_error,
                direct_iterates,
                refused_extension,
            }) => serde_json::json!({
                "method": "interpolant",
                "pieces": pieces,
                "max_degree": degree,
                "interval": [interval.0, interval.1],
                "build_evaluations": evaluations,
                "check_points": points,
                "max_map_error": max_error,
                "max_event_error": max_event_error,
                "direct_iterates": direct_iterates,
                "extension_refused": refused_extension,
            }),
        }
    }

    fn json(&self) -> serde_json::Value {
        let o = self.orbit;
        let period = match o.period {
            _ if self.longest_testable() == 0 => serde_json::Value::Null,
            Period::Periodic(n) => n.into(),
            Period::Aperiodic => "aperiodic".into(),
        };
        serde_json::json!({
            "theta0": self.theta0,
            "transient": self.args.transient,
            "keep": o.kept,
            "period": period,
            "period_tol": self.period_tol,
            "period_max_tested": self.longest_testable(),
            "lyapunov": o.lyapunov,
            "lyapunov_stderr": o.lyapunov_stderr,
            "cycle": o.cycle.as_ref().map(|c| serde_json::json!({
                "points": c.points,
                "multiplier": c.multiplier,
                "residual": c.residual,
                "iterations": c.iterations,
            })),
            "restarts": o.restarts,
            "rhs_evals": o.rhs_evals,
            "theta_last": o.theta_last,
            "seconds": self.seconds,
            "map": self.map_json(),
        })
    }
}
