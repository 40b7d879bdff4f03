//! `oneblock attractors --param P --from A --to B --columns N`: every
//! attractor of each column of a parameter range, from the exit arc's cell
//! graph (the Basins job, one column a unit, on every core), joined into
//! tracks by their basins' overlap ([`crate::sim::attractors::tracks`]).
//! A track's start or end inside the range is given between the two
//! columns it lies between; its cause (fold, flip, border collision,
//! crisis) is not located yet.

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
use crate::sim::attractors::tracks::{Identities, Track, identify, kind_name};
use crate::sim::attractors::{CellOptions, Found};
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
    for u in updates {
        if let Update::Basins { column, .. } = u
            && let Some(slot) = cols.get_mut(column.index)
        {
            *slot = Some(*column);
        }
    }
    let Some(cols) = cols.into_iter().collect::<Option<Vec<_>>>() else {
        return Err(CliError::Failed(
            "attractors: the job ended without every column".into(),
        ));
    };
    let report = Report::new(plan.param, &cols);
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

/// Where a track starts or ends: at an end of the range, or between two
/// computed columns (the cause not located yet).
#[derive(Clone, Copy, Debug)]
struct End {
    /// At the range's end (`true`), else between `between`.
    at_range: bool,
    value: f64,
    between: (f64, f64),
}

impl End {
    fn cause(&self, start: bool) -> &'static str {
        match (self.at_range, start) {
            (true, true) => "range start",
            (true, false) => "range end",
            (false, _) => "unresolved",
        }
    }

    fn json(&self, start: bool) -> serde_json::Value {
        serde_json::json!({"cause": self.cause(start), "value": self.value})
    }

    fn text(&self, start: bool) -> String {
        if self.at_range {
            self.cause(start).to_string()
        } else {
            format!(
                "unresolved (between {} and {})",
                val(self.between.0),
                val(self.between.1)
            )
        }
    }
}

/// A track's span over the columns.
struct Span {
    first: usize,
    last: usize,
    start: End,
    end: End,
}

/// The columns, their tracks and where each track starts and ends.
struct Report<'a> {
    param: ContParam,
    cols: &'a [BasinColumn],
    ids: Identities,
    spans: Vec<Span>,
}

impl<'a> Report<'a> {
    fn new(param: ContParam, cols: &'a [BasinColumn]) -> Self {
        let found: Vec<Option<&Found>> = cols.iter().map(|c| c.found.as_ref().ok()).collect();
        let ids = identify(&found);
        let computed: Vec<bool> = found.iter().map(Option::is_some).collect();
        let n = cols.len();
        let mut reach: Vec<Option<(usize, usize)>> = vec![None; ids.tracks.len()];
        for (c, of) in ids.of.iter().enumerate() {
            for &t in of.iter().flatten() {
                let r = reach[t].get_or_insert((c, c));
                r.1 = c;
            }
        }
        let at = |i: usize| cols[i].value;
        let end = |inside: usize, beyond: Option<usize>| match beyond {
            None => End {
                at_range: true,
                value: at(inside),
                between: (at(inside), at(inside)),
            },
            Some(b) => End {
                at_range: false,
                value: 0.5 * (at(inside) + at(b)),
                between: (at(inside.min(b)), at(inside.max(b))),
            },
        };
        let spans = reach
            .into_iter()
            .map(|r| {
                let (first, last) = r.unwrap_or((0, 0));
                // The computed column next to the track's first (last),
                // outside it; a failed one beside it if none was computed.
                let before = (first > 0)
                    .then(|| (0..first).rev().find(|&i| computed[i]).unwrap_or(first - 1));
                let after = (last + 1 < n)
                    .then(|| (last + 1..n).find(|&i| computed[i]).unwrap_or(last + 1));
                Span {
                    first,
                    last,
                    start: end(first, before),
                    end: end(last, after),
                }
            })
            .collect();
        Report {
            param,
            cols,
            ids,
            spans,
        }
    }

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

    fn text(&self, model: &str) -> String {
        let name = self.param.name();
        let mut s = format!("attractors: {model}\n");
        writeln!(
            s,
            "{} track(s) over {} columns, matched by their basins' overlap:",
            self.ids.tracks.len(),
            self.cols.len()
        )
        .ok();
        for (t, sp) in self.ids.tracks.iter().zip(&self.spans) {
            writeln!(
                s,
                "  #{} {}: {}, periods {}, {name} {} to {}; start: {}; end: {}",
                t.id,
                t.label,
                Self::kind(t),
                Self::periods(t),
                val(self.cols[sp.first].value),
                val(self.cols[sp.last].value),
                sp.start.text(true),
                sp.end.text(false)
            )
            .ok();
        }
        if self
            .spans
            .iter()
            .any(|sp| !sp.start.at_range || !sp.end.at_range)
        {
            writeln!(
                s,
                "starts and ends inside the range are not located yet: each lies between the two columns named (its cause, a fold, flip, border collision or crisis, is a later step)"
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
            .ids
            .tracks
            .iter()
            .zip(&self.spans)
            .map(|(t, sp)| {
                serde_json::json!({
                    "id": t.id,
                    "kind": Self::kind(t),
                    "periods": t.periods,
                    "label": t.label,
                    "from": self.cols[sp.first].value,
                    "to": self.cols[sp.last].value,
                    "start": sp.start.json(true),
                    "end": sp.end.json(false),
                })
            })
            .collect();
        let mut events = Vec::new();
        for (t, sp) in self.ids.tracks.iter().zip(&self.spans) {
            for (e, start) in [(sp.start, true), (sp.end, false)] {
                if e.at_range {
                    continue;
                }
                let what = if start { "starts" } else { "ends" };
                events.push(serde_json::json!({
                    "cause": "unresolved",
                    "value": e.value,
                    "between": [e.between.0, e.between.1],
                    "tracks": [t.id],
                    "detail": format!(
                        "track {} ({}) {what} between these columns; its cause is not located yet",
                        t.id, t.label
                    ),
                }));
            }
        }
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
                serde_json::json!({
                    "track": self.ids.track(i, a).map(|t| t.id),
                    "basin_fraction": at.basin_fraction,
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
            "{},track,label,period,basin_fraction,multiplier,lyapunov\n",
            self.param.column()
        );
        for (i, c) in self.cols.iter().enumerate() {
            let v = c.value;
            let Ok(found) = &c.found else {
                writeln!(out, "{v},,failed,,,,").ok();
                continue;
            };
            for (a, at) in found.attractors.iter().enumerate() {
                let id = self
                    .ids
                    .track(i, a)
                    .map_or(String::new(), |t| t.id.to_string());
                let period = at.period.map_or(String::new(), |p| p.to_string());
                writeln!(
                    out,
                    "{v},{id},{},{period},{},{},{}",
                    kind_name(at.period, &at.verdict),
                    at.basin_fraction,
                    num(at.multiplier),
                    num(at.lyapunov)
                )
                .ok();
            }
            writeln!(out, "{v},,boundary,,{},,", found.boundary_fraction).ok();
        }
        out
    }
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
