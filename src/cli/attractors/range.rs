//! `oneblock attractors --param P --from A --to B --columns N`: every
//! attractor of each column of a parameter range, from the exit arc's cell
//! graph (the Basins job, one column a unit, on every core), joined into
//! tracks by their basins' overlap ([`crate::sim::attractors::tracks`]),
//! each start, end and period change located with its cause
//! ([`crate::sim::attractors::events`], the job's last update).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::{AttractorsArgs, max_cells, resolution};
use crate::cli::CliError;
use crate::cli::bifurcation::{checked_range, model_params, theta_nu_end};
use crate::cli::common::{check_out, emit, max_seconds, warn_validity, with_provenance};
use crate::cli::run_control::{Limits, Progress, check_stdout, run_job};
use crate::cli::values::{count_between, param_error, short};
use crate::integrate::SolverSettings;
use crate::jobs::{Axis, BasinColumn, BasinsSpec, Spec, Update};
use crate::model::Params;
use crate::provenance::model_line_varying;
use crate::sim::attractors::CellOptions;
use crate::sim::attractors::events::{Bound, Cause, Event, Events, Span, to_error};
use crate::sim::attractors::tracks::{Track, kind_name};
use crate::sim::continuation::ContParam;

/// The fewest and most columns of a range.
pub const COLUMNS_RANGE: (usize, usize) = (2, 2000);
/// Columns when `--columns` is not given.
pub const DEFAULT_COLUMNS: usize = 81;

/// What the user wrote to vary a parameter: any of these asks for a range.
pub(super) fn wanted(a: &AttractorsArgs) -> bool {
    a.param.is_some()
        || a.from.is_some()
        || a.to.is_some()
        || a.theta_nu_from.is_some()
        || a.theta_nu_to.is_some()
        || a.columns.is_some()
        || a.out.is_some()
}

/// The checked inputs of a range.
pub(super) struct RangePlan {
    params: Params,
    settings: SolverSettings,
    param: ContParam,
    from: f64,
    to: f64,
    columns: usize,
    cells: CellOptions,
    max_seconds: Option<f64>,
}

/// The varied parameter and its ends, each checked against the model's
/// range of it as `bifurcation --param` checks them.
fn varied(args: &AttractorsArgs) -> Result<(ContParam, f64, f64), CliError> {
    let param = args.param.unwrap_or(ContParam::ThetaNu);
    let given = (args.from, args.to, args.theta_nu_from, args.theta_nu_to);
    let (flags, from, to) = match given {
        (Some(a), Some(b), ..) => {
            checked_range(&args.model, param, a, b)?;
            (["from", "to"], a, b)
        }
        (None, None, Some(a), Some(b)) if param == ContParam::ThetaNu => {
            let a = theta_nu_end("theta-nu-from", a)?;
            let b = theta_nu_end("theta-nu-to", b)?;
            (["theta-nu-from", "theta-nu-to"], a, b)
        }
        (None, None, Some(_), Some(_)) => {
            return Err(CliError::Usage(format!(
                "--theta-nu-from and --theta-nu-to give a range of theta-nu: with --param {} give --from and --to",
                param.name()
            )));
        }
        _ => {
            let flag = if args.param.is_some() {
                "param"
            } else if args.columns.is_some() {
                "columns"
            } else {
                "out"
            };
            return Err(CliError::Usage(format!(
                "--{flag}: a range needs --param P with --from A and --to B (or --theta-nu-from and --theta-nu-to)"
            )));
        }
    };
    if from == to {
        return Err(CliError::Usage(format!(
            "--{} = {} and --{} = {}: the range is empty: give two different ends",
            flags[0],
            short(from),
            flags[1],
            short(to)
        )));
    }
    Ok((param, from, to))
}

/// Checks the flags and the outputs before any work.
pub(super) fn check(args: &AttractorsArgs) -> Result<RangePlan, CliError> {
    let (param, from, to) = varied(args)?;
    let (lo, hi) = COLUMNS_RANGE;
    let columns = count_between("columns", args.columns.unwrap_or(DEFAULT_COLUMNS), lo, hi)?;
    let params = model_params(&args.model, param, from)?;
    params.validate().map_err(param_error)?;
    let settings = args.solver.settings()?;
    let cells = CellOptions {
        resolution: resolution(args.resolution.unwrap_or(CellOptions::column().resolution))?,
        max_cells: max_cells(args.max_cells.unwrap_or(CellOptions::column().max_cells))?,
        ..CellOptions::column()
    };
    let max_seconds = max_seconds(args.max_seconds)?;
    if let Some(out) = &args.out {
        if out.as_os_str() == "-" && args.json {
            return Err(CliError::Usage(
                "--out -: the CSV and --json would both go to stdout: give --out a file".into(),
            ));
        }
        check_out(out, args.force)?;
    }
    check_stdout()?;
    Ok(RangePlan {
        params,
        settings,
        param,
        from,
        to,
        columns,
        cells,
        max_seconds,
    })
}

/// Runs the columns through the Basins job, joins them into tracks and
/// writes the summary (or JSON) and the CSV.
pub(super) fn run(args: &AttractorsArgs) -> Result<(), CliError> {
    let plan = check(args)?;
    warn_validity(&plan.params);
    let limits = Limits::start(plan.max_seconds);
    let progress = Progress::new("attractors", "columns", plan.columns as u64);
    let spec = BasinsSpec {
        params: plan.params,
        settings: plan.settings,
        param: plan.param,
        axis: Axis::new(plan.from, plan.to, plan.columns),
        cells: plan.cells,
    };
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let updates = run_job(
        "attractors",
        Spec::Basins(spec),
        threads,
        &progress,
        &limits,
    )?;
    let mut cols: Vec<Option<BasinColumn>> = vec![None; plan.columns];
    let mut located = None;
    for u in updates {
        match u {
            Update::Basins { column, .. } => {
                if let Some(slot) = cols.get_mut(column.index) {
                    *slot = Some(*column);
                }
            }
            Update::BasinEvents { events, .. } => located = Some(*events),
            _ => {}
        }
    }
    let (Some(cols), Some(located)) = (cols.into_iter().collect::<Option<Vec<_>>>(), located)
    else {
        return Err(CliError::Failed(
            "attractors: the job ended without every column and its events".into(),
        ));
    };
    let report = Report {
        param: plan.param,
        cols: &cols,
        located,
    };
    let model = format!(
        "{}; {} {} to {}, {} columns",
        model_line_varying(&plan.params, &plan.settings, plan.param),
        plan.param.name(),
        plan.from,
        plan.to,
        plan.columns
    );
    let to_stdout = args.out.as_deref() != Some(Path::new("-"));
    let summary = if args.json {
        report.json()
    } else {
        report.text(&model)
    };
    let csv = with_provenance(&model, &report.csv());
    // The file first: a summary printed and then a failed write would
    // read as success.
    if let Some(out) = &args.out {
        emit(out, csv.as_bytes(), args.force)?;
    }
    if to_stdout {
        emit(&PathBuf::from("-"), summary.as_bytes(), false)?;
    }
    Ok(())
}

/// The columns, their tracks, and the located events.
struct Report<'a> {
    param: ContParam,
    cols: &'a [BasinColumn],
    located: Events,
}

impl<'a> Report<'a> {
    /// "cycle" (every period known), "chaotic" (every part proved
    /// chaotic), "undecided" (no cycle, not every part chaotic) or
    /// "mixed".
    fn kind(t: &Track) -> &'static str {
        let cycles = t.periods.iter().filter(|p| p.is_some()).count();
        if cycles == t.periods.len() {
            "cycle"
        } else if cycles > 0 {
            "mixed"
        } else if t.kinds.iter().all(|k| k == "chaotic") {
            "chaotic"
        } else {
            "undecided"
        }
    }

    fn periods(t: &Track) -> String {
        t.periods
            .iter()
            .map(|p| p.map_or("aperiodic".to_string(), |p| p.to_string()))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// A start or end in words: "range start", "fold at theta-nu = 1.4202315".
    fn bound_text(&self, b: Bound, start: bool) -> String {
        match b {
            Bound::Edge if start => "range start".into(),
            Bound::Edge => "range end".into(),
            Bound::Event(k) => {
                let e = &self.located.events[k];
                match e.cause {
                    Cause::Unresolved => format!(
                        "unresolved (between {} and {})",
                        val(e.between.0),
                        val(e.between.1)
                    ),
                    c => format!(
                        "{} at {} = {}",
                        c.name(),
                        self.param.name(),
                        to_error(e.value, e.error)
                    ),
                }
            }
        }
    }

    fn bound_json(&self, b: Bound, sp: &Span, start: bool) -> serde_json::Value {
        match b {
            Bound::Edge => {
                let c = if start { sp.first } else { sp.last };
                serde_json::json!({"cause": "edge", "value": self.cols[c].value})
            }
            Bound::Event(k) => {
                let e = &self.located.events[k];
                serde_json::json!({"cause": e.cause.name(), "value": e.value, "event": k})
            }
        }
    }

    fn text(&self, model: &str) -> String {
        let name = self.param.name();
        let mut s = format!("attractors: {model}\n");
        writeln!(
            s,
            "{} track(s) over {} columns, matched by their basins' overlap:",
            self.located.ids.tracks.len(),
            self.cols.len()
        )
        .ok();
        for (t, sp) in self.located.ids.tracks.iter().zip(&self.located.spans) {
            writeln!(
                s,
                "  #{} {}: {}, periods {}, {name} {} to {}; start: {}; end: {}",
                t.id,
                t.label,
                Self::kind(t),
                Self::periods(t),
                val(self.cols[sp.first].value),
                val(self.cols[sp.last].value),
                self.bound_text(sp.start, true),
                self.bound_text(sp.end, false)
            )
            .ok();
        }
        if !self.located.events.is_empty() {
            writeln!(s, "{} event(s):", self.located.events.len()).ok();
        }
        for e in &self.located.events {
            let tracks: Vec<String> = e.tracks.iter().map(|t| format!("#{t}")).collect();
            let at = if e.cause == Cause::Unresolved {
                format!("between {} and {}", val(e.between.0), val(e.between.1))
            } else {
                format!("{name} = {} ± {:.0e}", to_error(e.value, e.error), e.error)
            };
            writeln!(
                s,
                "  {:<10} {at}  tracks {}: {}",
                e.cause.name(),
                tracks.join(", "),
                e.detail
            )
            .ok();
        }
        for c in self.cols {
            match &c.found {
                Err(e) => {
                    writeln!(s, "column at {name} = {}: failed: {e}", val(c.value)).ok();
                }
                Ok(f) if f.attractors.is_empty() => {
                    writeln!(
                        s,
                        "column at {name} = {}: no attractor the cell graph can prove (the map could not be enclosed over the exit arc)",
                        val(c.value)
                    )
                    .ok();
                }
                Ok(_) => {}
            }
        }
        s
    }

    /// `{"tracks": [...], "events": [...], "columns": [...]}`.
    fn json(&self) -> String {
        let tracks: Vec<_> = self
            .located
            .ids
            .tracks
            .iter()
            .zip(&self.located.spans)
            .map(|(t, sp)| {
                serde_json::json!({
                    "id": t.id,
                    "kind": Self::kind(t),
                    "periods": t.periods,
                    "label": t.label,
                    "from": self.cols[sp.first].value,
                    "to": self.cols[sp.last].value,
                    "start": self.bound_json(sp.start, sp, true),
                    "end": self.bound_json(sp.end, sp, false),
                })
            })
            .collect();
        let events: Vec<_> = self.located.events.iter().map(event_json).collect();
        let columns: Vec<_> = self
            .cols
            .iter()
            .enumerate()
            .map(|(i, c)| self.column_json(i, c))
            .collect();
        format!(
            "{}\n",
            serde_json::json!({"tracks": tracks, "events": events, "columns": columns})
        )
    }

    fn column_json(&self, i: usize, c: &BasinColumn) -> serde_json::Value {
        let found = match &c.found {
            Ok(f) => f,
            Err(e) => return serde_json::json!({"value": c.value, "attractors": [], "error": e}),
        };
        let list: Vec<_> = found
            .attractors
            .iter()
            .enumerate()
            .map(|(a, at)| {
                let kick = found.min_kick(a);
                serde_json::json!({
                    "track": self.located.ids.track(i, a).map(|t| t.id),
                    "basin_fraction": at.basin_fraction,
                    "min_kick": kick.map(|k| k.0),
                    "min_kick_width": kick.map(|k| k.1),
                    "period": at.period,
                    "points": at.points,
                })
            })
            .collect();
        serde_json::json!({
            "value": c.value,
            "attractors": list,
            "boundary_fraction": found.boundary_fraction,
        })
    }

    /// One row per column and attractor, then the column's boundary; a
    /// failed column is one row saying so.
    fn csv(&self) -> String {
        let num = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x}"));
        let mut out = format!(
            "{},track,label,period,basin_fraction,min_kick,multiplier,lyapunov\n",
            self.param.column()
        );
        for (i, c) in self.cols.iter().enumerate() {
            let v = c.value;
            let Ok(found) = &c.found else {
                writeln!(out, "{v},,failed,,,,,").ok();
                continue;
            };
            for (a, at) in found.attractors.iter().enumerate() {
                let id = self
                    .located
                    .ids
                    .track(i, a)
                    .map_or(String::new(), |t| t.id.to_string());
                let period = at.period.map_or(String::new(), |p| p.to_string());
                writeln!(
                    out,
                    "{v},{id},{},{period},{},{},{},{}",
                    kind_name(at.period, &at.verdict),
                    at.basin_fraction,
                    num(found.min_kick(a).map(|k| k.0)),
                    num(at.multiplier),
                    num(at.lyapunov)
                )
                .ok();
            }
            writeln!(out, "{v},,boundary,,{},,,", found.boundary_fraction).ok();
        }
        out
    }
}

/// One event as the JSON gives it.
fn event_json(e: &Event) -> serde_json::Value {
    let mut j = serde_json::json!({
        "cause": e.cause.name(),
        "value": e.value,
        "error": e.error,
        "between": [e.between.0, e.between.1],
        "theta": e.theta,
        "period": e.period,
        "criticality": e.criticality,
        "tracks": e.tracks,
        "detail": e.detail,
    });
    if let Some(m) = e.multipliers {
        j["multipliers"] = serde_json::json!(m);
        j["type"] = serde_json::json!(e.border_type);
    }
    j
}

/// A value as the summary writes it: eight significant digits, trailing
/// zeros dropped.
fn val(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let digits = (7 - v.abs().log10().floor() as i32).clamp(0, 17) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}
