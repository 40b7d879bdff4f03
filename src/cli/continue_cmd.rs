//! `oneblock continue`: a period-p cycle followed in one parameter, with
//! its period doublings, folds and borders located (`--cascade`: the
//! doubled cycles followed in turn), or a doubling or fold followed in two
//! parameters (`--curve`). docs/continuation.md describes the method.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use clap::Args;

use super::CliError;
use super::common::{
    ModelArgs, SolverArgs, check_out, check_second_out, check_theta, describe, emit, emit_all,
    finite, max_seconds, warn_validity, with_provenance,
};
use super::continue_out as out;
use super::run_control::{Limits, stderr_is_terminal};
use super::values::{count_between, echo, parse_count, parse_number, short};
use crate::jobs::{
    CascadeFrom, ContinuationSpec, CurveFollow, GivenCycle, JobError, Spec, Update, run_kept,
};
use crate::model::Params;
use crate::sim::continuation::{
    Attractor, Branch, ContParam, CurveKind, Problem, SpecialKind, Stop, attractor_cycle,
};
use crate::sim::{CycleFailure, PERIOD_MAX, SimError, Simulator};

/// The model's flags with the varied parameter's (if left out) set to
/// `from`, where the branch starts.
fn with_varied(model: &ModelArgs, varied: Option<ContParam>, from: f64) -> ModelArgs {
    let mut m = model.clone();
    if let Some(p) = varied {
        m.flag_mut(p).get_or_insert(from);
    }
    m
}

/// Follows a cycle, a cascade, or a bifurcation curve.
#[derive(Debug, Clone, Args)]
pub struct ContinueArgs {
    /// The model's flags: the varied parameter's own may be left out.
    #[command(flatten)]
    pub model: ModelArgs,
    #[command(flatten)]
    pub solver: SolverArgs,
    /// The parameter varied. Its own flag (such as --theta-nu) may be left
    /// out: --from and --to set it.
    #[arg(long, conflicts_with = "params")]
    pub param: Option<ContParam>,
    /// With --curve: the two parameters, "P1,P2" (e.g. theta-nu,kappa); the
    /// start is located along P1 over [--from, --to], the curve is followed
    /// within that range and [--from2, --to2].
    #[arg(long, requires = "curve")]
    pub params: Option<String>,
    /// The branch's first parameter value (where it starts).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub from: f64,
    /// The branch's last parameter value (may be below --from).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub to: f64,
    /// The period p of the cycle followed (1 to 64; 1 is a fixed point).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_count)]
    pub period: usize,
    /// A point θ of the cycle at --from, in radians (a Newton seed)
    /// [default: the attractor there, which must have period p].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub theta: Option<f64>,
    /// Branch CSV ("-" = stdout): one row per computed point (with
    /// --curve: one row per point of the curve).
    #[arg(long)]
    pub out: PathBuf,
    /// Special points CSV: kind,period,parameter,value,theta,multiplier.
    #[arg(long)]
    pub points: Option<PathBuf>,
    /// Print one JSON summary on stdout instead of the text summary on stderr.
    #[arg(long)]
    pub json: bool,
    /// Overwrite existing --out and --points files.
    #[arg(long)]
    pub force: bool,
    /// Follow the period-doubling cascade: at each doubling switch to the
    /// doubled cycle, until the doublings crowd within the location accuracy.
    #[arg(long, conflicts_with = "curve")]
    pub cascade: bool,
    /// Follow a bifurcation curve in two parameters: period doublings or
    /// folds (needs --params, --from2, --to2).
    #[arg(long)]
    pub curve: Option<CurveKind>,
    /// With --curve: one end of the second parameter's range.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, requires = "curve")]
    pub from2: Option<f64>,
    /// With --curve: the other end of the second parameter's range.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, requires = "curve")]
    pub to2: Option<f64>,
    /// Stop after this many seconds, in (0, 1e7], writing what was
    /// computed and where it stopped, exit 1.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub max_seconds: Option<f64>,
}

/// What is asked.
#[derive(Clone, Copy)]
pub enum Mode {
    /// One branch.
    Branch,
    /// The cascade.
    Cascade,
    /// A curve: its kind, the second parameter and its range.
    Curve(CurveKind, ContParam, [f64; 2]),
}

/// The checked inputs.
pub struct Plan {
    pub prob: Problem,
    pub max_seconds: Option<f64>,
    pub from: f64,
    pub to: f64,
    pub theta: Option<f64>,
    pub mode: Mode,
}

fn param_name(flag: &str, name: &str) -> Result<ContParam, CliError> {
    ContParam::parse(name.trim()).ok_or_else(|| {
        CliError::Usage(format!(
            "--{flag}: unknown parameter '{}': expected theta-nu, kappa, gamma, nu or omega",
            echo(name)
        ))
    })
}

/// A range end: finite, and the parameters valid there (the message names
/// the flag). `bifurcation --param` checks its range with it too.
pub(super) fn range_end(
    flag: &str,
    v: f64,
    param: ContParam,
    base: &Params,
) -> Result<f64, CliError> {
    let v = finite(flag, v)?;
    if param == ContParam::ThetaNu && v.abs() > 1000.0 {
        return Err(CliError::Usage(format!(
            "--{flag} = {} is out of range: theta-nu must lie in [-1000, 1000] radians",
            short(v)
        )));
    }
    param.set(base, v).validate().map_err(|e| {
        CliError::Usage(format!(
            "--{flag} = {}: {} is out of range: {}",
            short(v),
            e.name,
            e.range
        ))
    })?;
    Ok(v)
}

fn range(
    flags: [&str; 2],
    a: f64,
    b: f64,
    param: ContParam,
    base: &Params,
) -> Result<(), CliError> {
    let a = range_end(flags[0], a, param, base)?;
    let b = range_end(flags[1], b, param, base)?;
    if a == b {
        return Err(CliError::Usage(format!(
            "--{} = {} equals --{}: the range is empty",
            flags[1],
            short(b),
            flags[0]
        )));
    }
    Ok(())
}

/// Checks the flags and the outputs before any work.
pub fn check(args: &ContinueArgs) -> Result<Plan, CliError> {
    let period = count_between("period", args.period, 1, PERIOD_MAX)?;
    let max_seconds = max_seconds(args.max_seconds)?;
    let base = base_params(args)?;
    let settings = args.solver.settings()?;
    let (param, mode) = match (args.curve, &args.params, args.param) {
        (Some(kind), params, _) => curve_mode(args, kind, params.as_deref(), &base)?,
        (None, _, Some(p)) => (
            p,
            if args.cascade {
                Mode::Cascade
            } else {
                Mode::Branch
            },
        ),
        (None, _, None) => {
            return Err(CliError::Usage(
                "--param: required (theta-nu, kappa, gamma, nu or omega), or --curve with --params"
                    .into(),
            ));
        }
    };
    range(["from", "to"], args.from, args.to, param, &base)?;
    let prob = Problem {
        base: param.set(&base, args.from),
        settings,
        param,
        period,
    };
    let theta = match args.theta {
        Some(th) => Some(check_theta(&prob.sim(args.from)?, "theta", th)?),
        None => None,
    };
    check_outputs(args)?;
    Ok(Plan {
        prob,
        max_seconds,
        from: args.from,
        to: args.to,
        theta,
        mode,
    })
}

/// The model's parameters at --from, the varied one's flag left out or
/// not.
fn base_params(args: &ContinueArgs) -> Result<Params, CliError> {
    // The varied parameter, as far as the flags say it (a wrong name in
    // --params is refused later, with its flag).
    let varied = match (args.curve, &args.params, args.param) {
        (Some(_), Some(ps), _) => ps
            .split(',')
            .next()
            .and_then(|n| ContParam::parse(n.trim())),
        (None, _, p) => p,
        _ => None,
    };
    with_varied(&args.model, varied, args.from)
        .params()
        .map_err(|e| {
            // The varied parameter's own flag left out, its value is --from's:
            // the message names --from, as it does for --to.
            match (varied, args.model.params()) {
                (Some(p), Ok(b)) if args.model.flag(p).is_none() => {
                    range_end("from", args.from, p, &b).err().unwrap_or(e)
                }
                _ => e,
            }
        })
}

/// `--curve`'s mode: the two parameters of --params, and the second's range
/// (which must hold the model's value: the curve starts there).
fn curve_mode(
    args: &ContinueArgs,
    kind: CurveKind,
    params: Option<&str>,
    base: &Params,
) -> Result<(ContParam, Mode), CliError> {
    let Some(params) = params else {
        return Err(CliError::Usage(
            "--params: required with --curve (e.g. --params theta-nu,kappa)".into(),
        ));
    };
    let names: Vec<&str> = params.split(',').collect();
    let [a, b] = names[..] else {
        return Err(CliError::Usage(format!(
            "--params: '{}' is not two names: expected P1,P2, e.g. theta-nu,kappa",
            echo(params)
        )));
    };
    let (p1, p2) = (param_name("params", a)?, param_name("params", b)?);
    if p1 == p2 {
        return Err(CliError::Usage(format!(
            "--params: the two parameters must differ, not {} twice",
            p1.name()
        )));
    }
    let (Some(a2), Some(b2)) = (args.from2, args.to2) else {
        return Err(CliError::Usage(
            "--from2 and --to2: required with --curve (the second parameter's range)".into(),
        ));
    };
    range(["from2", "to2"], a2, b2, p2, base)?;
    let at = p2.get(base);
    if !(at >= a2.min(b2) && at <= a2.max(b2)) {
        return Err(CliError::Usage(format!(
            "--from2, --to2: the model's {} = {} is outside [{}, {}]: the curve starts there",
            p2.name(),
            short(at),
            short(a2.min(b2)),
            short(a2.max(b2))
        )));
    }
    Ok((p1, Mode::Curve(kind, p2, [a2, b2])))
}

/// The outputs: free to write (or --force), and the summary's place.
fn check_outputs(args: &ContinueArgs) -> Result<(), CliError> {
    if args.json && args.out.as_os_str() == "-" {
        return Err(CliError::Usage(
            "--out: with --json the summary is on stdout: give --out a file".into(),
        ));
    }
    check_out(&args.out, args.force)?;
    if let Some(p) = &args.points {
        check_second_out("points", p, &args.out, args.force)?;
    }
    Ok(())
}

/// The seed: `--theta`, or a point of the attractor at --from when it has
/// period p (a search that stops with `limits`: Ctrl+C, --max-seconds).
fn seed(plan: &Plan, limits: &Limits) -> Result<f64, CliError> {
    if let Some(th) = plan.theta {
        return Ok(th);
    }
    let sim = plan.prob.sim(plan.from)?;
    let attractor = match attractor_cycle(*sim.params(), *sim.settings(), &|| limits.stop()) {
        Err(_) if limits.stop() => return Err(limits.stopped("continue")),
        r => r?,
    };
    let found = match attractor {
        Attractor::Cycle { period, theta } if period == plan.prob.period => return Ok(theta),
        Attractor::Cycle { period, .. } | Attractor::Unsolved(period) => {
            format!("has period {period}")
        }
        a => a.describe(),
    };
    Err(CliError::Usage(format!(
        "--theta: not given, and the attractor at {} = {} {found}, not {}: give --theta, a point of a {}-cycle there",
        plan.prob.param.name(),
        short(plan.from),
        plan.prob.period,
        plan.prob.period
    )))
}

/// A start that is not on a cycle is the user's input (exit 2).
fn start_error(plan: &Plan, seed: f64, e: CycleFailure) -> CliError {
    match e {
        CycleFailure::Sim(SimError::Cancelled) => CliError::Failed("cancelled".into()),
        CycleFailure::Sim(e) if !matches!(e, SimError::OffExitArc { .. }) => CliError::from(e),
        e => CliError::Usage(format!(
            "--theta = {}: no {}-cycle through it at {} = {}: {e}",
            short(seed),
            plan.prob.period,
            plan.prob.param.name(),
            short(plan.from)
        )),
    }
}

/// Follows what the flags ask (the window's "Find bifurcations" job, with
/// the cycle checked and seeded here) and writes it.
pub fn run(args: ContinueArgs) -> Result<(), CliError> {
    let plan = check(&args)?;
    warn_validity(&plan.prob.base);
    // The clock of --max-seconds starts no later than the limit's own, so
    // a run the limit stopped has always passed it here (Ctrl+C has not).
    // Both start before the attractor search, which Ctrl+C also stops.
    let started = Instant::now();
    let limits = Limits::start_polled(plan.max_seconds);
    let seed = start(&plan, &limits)?;
    let sim = Simulator::new(plan.prob.base, plan.prob.settings)?;
    let described = describe(sim.params(), sim.settings());
    let ran = follow(&plan, seed, &limits)?;
    curve_starts_found(&plan, &ran.branches)?;
    let timed_out = plan
        .max_seconds
        .is_some_and(|m| started.elapsed().as_secs_f64() >= m);
    if limits.stop() && !timed_out {
        return Err(limits.stopped("continue"));
    }
    let seconds = started.elapsed().as_secs_f64();
    let data = match &ran.extra {
        out::Extra::Curves(params, c) => out::curve_csv(*params, c),
        _ => out::branches_csv(&ran.branches),
    };
    let data = with_provenance(&described, &data);
    let points = args
        .points
        .as_ref()
        .map(|_| with_provenance(&described, &out::points_csv(&ran.branches)));
    let mut outputs = vec![("out", args.out.as_path(), data.as_bytes())];
    if let (Some(p), Some(text)) = (&args.points, &points) {
        outputs.push(("points", p.as_path(), text.as_bytes()));
    }
    emit_all(&outputs, args.force)?;
    let summary = out::Summary {
        described: &described,
        branches: &ran.branches,
        extra: &ran.extra,
        seconds,
    };
    if args.json {
        emit(Path::new("-"), summary.json().as_bytes(), false)?;
    } else {
        eprint!("{}", summary.text());
    }
    ended(&plan, &ran, seconds, timed_out)
}

/// The seed, checked to lie on a cycle of period p exactly: a seed on a
/// shorter cycle (a fixed point is also a 3-cycle) would follow that cycle
/// under another name.
fn start(plan: &Plan, limits: &Limits) -> Result<f64, CliError> {
    let seed = seed(plan, limits)?;
    let solved = crate::sim::solve_cycle(
        &plan.prob.sim(plan.from)?,
        seed,
        plan.prob.period,
        &crate::sim::CycleOptions::for_settings(&plan.prob.settings),
    )
    .map_err(|e| start_error(plan, seed, e))?;
    if solved.minimal_period < plan.prob.period {
        return Err(CliError::Usage(format!(
            "--theta = {}: the cycle through it at {} = {} has period {}, not {}",
            short(seed),
            plan.prob.param.name(),
            short(plan.from),
            solved.minimal_period,
            plan.prob.period
        )));
    }
    Ok(seed)
}

/// The job the flags ask for: the p-cycle through `seed` followed over the
/// range, with the cascade (each level to its doubling) or the curves.
fn spec(plan: &Plan, seed: f64) -> ContinuationSpec {
    let period = plan.prob.period;
    let (max_period, cascade, curves) = match plan.mode {
        Mode::Branch => (period, CascadeFrom::Branch, None),
        Mode::Cascade => (PERIOD_MAX, CascadeFrom::Levels, None),
        Mode::Curve(kind, param, range) => {
            let follow = CurveFollow { kind, param, range };
            (period, CascadeFrom::Branch, Some(follow))
        }
    };
    ContinuationSpec {
        params: plan.prob.base,
        settings: plan.prob.settings,
        param: plan.prob.param,
        from: plan.from,
        to: plan.to,
        max_period,
        cycle: Some(GivenCycle {
            period,
            theta: seed,
        }),
        cascade,
        curves,
    }
}

/// What a run computed.
struct Ran {
    branches: Vec<Branch>,
    extra: out::Extra,
}

/// Runs the job until it ends or the limits stop it (it then ends with
/// what it has), with a line per located point, level and curve on
/// stderr where no bar or terminal shows progress (levels: always).
fn follow(plan: &Plan, seed: f64, limits: &Limits) -> Result<Ran, CliError> {
    let lines = !stderr_is_terminal();
    let curves = AtomicUsize::new(0);
    let name = plan.prob.param.name();
    let on_update = |u: &Update| match u {
        Update::Special { point: p, .. } if lines => eprintln!(
            "continue: {} of the P{} branch at {name} = {}",
            p.kind.name(),
            p.period,
            out::located(p.lambda)
        ),
        Update::Branch { branch: b, .. } if matches!(plan.mode, Mode::Cascade) => eprintln!(
            "continue: P{} branch, {} points: it {}",
            b.period,
            b.points.len(),
            b.stop_message()
        ),
        Update::Curve { curve, .. } if lines => {
            let i = curves.fetch_add(1, Ordering::Relaxed);
            eprintln!("continue: {}", out::curve_line(i, curve));
        }
        _ => {}
    };
    let spec = Spec::Branches(spec(plan, seed));
    let (updates, ended) = run_kept(spec, 1, on_update, || limits.stop());
    match ended {
        Ok(()) | Err(JobError::Stop) => {}
        Err(JobError::Sim(e)) => return Err(start_error(plan, seed, CycleFailure::Sim(e))),
        Err(JobError::Failed(m)) => {
            return Err(CliError::Usage(format!("--theta = {}: {m}", short(seed))));
        }
    }
    let (mut branches, mut cascade, mut curves) = (Vec::new(), None, Vec::new());
    for u in updates {
        match u {
            Update::Branch { branch, .. } => branches.push(branch),
            Update::Cascade { cascade: c, .. } => cascade = Some(c),
            Update::Curve { curve, .. } => curves.push(curve),
            _ => {}
        }
    }
    let extra = match (plan.mode, cascade) {
        (Mode::Cascade, Some(c)) => {
            branches.clone_from(&c.branches);
            out::Extra::Cascade(c)
        }
        (Mode::Curve(_, p2, _), _) => out::Extra::Curves([plan.prob.param, p2], curves),
        _ => out::Extra::None,
    };
    Ok(Ran { branches, extra })
}

/// With --curve, a branch that ended with no point of the curve's kind has
/// nothing to start from (one stopped early may simply not have reached
/// one).
fn curve_starts_found(plan: &Plan, branches: &[Branch]) -> Result<(), CliError> {
    let (Mode::Curve(kind, ..), Some(b)) = (plan.mode, branches.first()) else {
        return Ok(());
    };
    let want = match kind {
        CurveKind::PeriodDoubling => SpecialKind::PeriodDoubling,
        CurveKind::Fold => SpecialKind::Fold,
    };
    if b.of_kind(want).any(|s| s.period == b.period) || b.stop == Stop::Cancelled {
        return Ok(());
    }
    Err(CliError::Failed(format!(
        "no {} point on the P{} branch in {} from {} to {} to start the curve from (the branch {})",
        want.name(),
        plan.prob.period,
        plan.prob.param.name(),
        short(plan.from),
        short(plan.to),
        b.stop_message()
    )))
}

/// How the run ended once its results are written: stopped by
/// --max-seconds, a branch that failed mid-way, or well.
fn ended(plan: &Plan, ran: &Ran, seconds: f64, timed_out: bool) -> Result<(), CliError> {
    if timed_out {
        return Err(CliError::Failed(format!(
            "continue: stopped by --max-seconds = {} after {seconds:.1} s: what was computed is written; {}",
            short(plan.max_seconds.unwrap_or(0.0)),
            out::where_stopped(&ran.branches, &ran.extra)
        )));
    }
    // A branch that failed mid-way has written what it has; the run failed.
    let failed = ran.branches.first().and_then(|b| match &b.stop {
        Stop::Failed(_) => Some(format!("the P{} branch {}", b.period, b.stop_message())),
        _ => None,
    });
    match failed {
        Some(m) => Err(CliError::Failed(format!(
            "{m} (the points computed before are written)"
        ))),
        None => Ok(()),
    }
}
