//! The continuation jobs: a cycle followed in one parameter with its
//! bifurcations (find bifurcations), and the doublings followed in
//! (θν, κ) (boundaries), by the library's `sim::continuation`. Each branch
//! or curve is sent as it ends; the library polls the sink once per
//! computed point, so a newer job or a cancel stops it within one point.
//! Each job is one unit: the library's continuation is not yet steppable
//! point by point.

use std::sync::Mutex;
use web_time::Instant;

use super::protocol::{BoundarySpec, ContinuationSpec, Lane, Update};
use super::{Job, JobError, Sink, Status, lock};
use crate::integrate::SolverSettings;
use crate::model::Params;
use crate::sim::continuation::{
    Attractor, Branch, ContOptions, ContParam, CurveKind, CurveOptions, Problem, SpecialKind,
    SpecialPoint, attractor_cycle, cascade_from, continue_branch, continue_curves,
};
use crate::sim::{CycleFailure, PERIOD_MAX, SimError};

/// The attractor's cycle at `params` ([`attractor_cycle`]); `Err` says
/// what the attractor is instead.
fn attractor_seed(
    params: Params,
    settings: SolverSettings,
    cancel: &dyn Fn() -> bool,
) -> Result<Result<(usize, f64), String>, SimError> {
    Ok(match attractor_cycle(params, settings, cancel)? {
        Attractor::Cycle { period, theta } => Ok((period, theta)),
        a => Err(a.describe()),
    })
}

/// The parameter's letter, as the window writes it.
fn symbol(p: ContParam) -> &'static str {
    match p {
        ContParam::ThetaNu => "θν",
        ContParam::Kappa => "κ",
        ContParam::Gamma => "γ",
        ContParam::Nu => "ν",
        ContParam::Omega => "Ω",
    }
}

/// A start that is not on a cycle: the job ends, saying why.
fn start_failure(e: CycleFailure) -> JobError {
    match e {
        CycleFailure::Sim(SimError::Cancelled) => JobError::Stop,
        CycleFailure::Sim(e) => JobError::Sim(e),
        e => JobError::Failed(format!("no cycle to follow at the start: {e}")),
    }
}

/// "1 PD, 0 fold, 1 border" over `branches`, and the jumps of the
/// multiplier if any (never counted as bifurcations).
fn counts(branches: &[Branch]) -> String {
    let n = |k| branches.iter().map(|b| b.of_kind(k).count()).sum::<usize>();
    let jumps = match n(SpecialKind::Jump) {
        0 => String::new(),
        j => format!(", {j} jump of m (no bifurcation)"),
    };
    format!(
        "{} PD, {} fold, {} border{jumps}",
        n(SpecialKind::PeriodDoubling),
        n(SpecialKind::Fold),
        n(SpecialKind::Border)
    )
}

/// One continuation job's way to its sink.
struct Out<'a> {
    sink: &'a dyn Sink,
    lane: Lane,
}

impl Out<'_> {
    fn stale(&self) -> bool {
        self.sink.stale()
    }

    fn send(&self, u: Update) -> Result<(), JobError> {
        Ok(self.sink.send(u)?)
    }

    fn summary(&self, text: String) -> Result<(), JobError> {
        self.send(Update::Summary {
            generation: self.sink.generation(),
            lane: self.lane,
            text,
        })
    }

    fn progress(&self, fraction: f64, evals: u64, since: Instant) -> Result<(), JobError> {
        let secs = since.elapsed().as_secs_f64().max(1e-9);
        self.send(Update::Progress {
            generation: self.sink.generation(),
            lane: self.lane,
            fraction,
            iterates_per_second: evals as f64 / secs,
        })
    }

    /// The attractor at `from` followed over the range, then its cascade.
    fn find(&self, spec: &ContinuationSpec) -> Result<(), JobError> {
        let started = Instant::now();
        let cancel = || self.stale();
        let (from, to) = (spec.from, spec.to);
        let name = symbol(spec.param);
        if !(from.is_finite() && to.is_finite()) || from == to {
            return Err(JobError::Failed(format!(
                "the range {name} from {from} to {to} is empty"
            )));
        }
        let base = spec.param.set(&spec.params, from);
        let (period, seed) = match attractor_seed(base, spec.settings, &cancel)? {
            Ok(found) => found,
            Err(what) => {
                let text = format!(
                    "stopped: the attractor at {name} = {from:.6} {what}: no cycle to follow"
                );
                self.summary(text)?;
                return Ok(());
            }
        };
        let prob = Problem {
            base,
            settings: spec.settings,
            param: spec.param,
            period,
        };
        let opts = ContOptions::for_range(&spec.settings, from, to);
        let branch =
            continue_branch(&prob, from, to, seed, &opts, &cancel).map_err(start_failure)?;
        if self.stale() {
            return Err(JobError::Stop);
        }
        let max_period = spec.max_period.clamp(period, PERIOD_MAX);
        let levels = (max_period / period).max(1).ilog2() as f64 + 1.0;
        let mut evals = branch.map_evals;
        let doubles = branch.of_kind(SpecialKind::PeriodDoubling).next().is_some();
        let first = format!("P{period} branch: it {}", branch.stop_message());
        let mut all = vec![branch.clone()];
        self.send(Update::Branch {
            generation: self.sink.generation(),
            branch,
        })?;
        if !doubles || 2 * period > max_period {
            self.progress(1.0, evals, started)?;
            let why = if doubles {
                format!("the cascade's period is capped at {max_period}")
            } else {
                "no period doubling".to_string()
            };
            self.summary(format!("{} · stopped: {first}; {why}", counts(&all)))?;
            return Ok(());
        }
        self.progress(1.0 / levels, evals, started)?;
        self.summary(format!("{} · following the cascade…", counts(&all)))?;
        // The cascade goes on from the branch above: only the doubled
        // levels are new.
        let first = all[0].clone();
        let mut sent: Result<(), JobError> = Ok(());
        let mut done = 1.0;
        let mut on_level = |b: &Branch| {
            if sent.is_err() {
                return;
            }
            evals += b.map_evals;
            done += 1.0;
            all.push(b.clone());
            sent = self
                .send(Update::Branch {
                    generation: self.sink.generation(),
                    branch: b.clone(),
                })
                .and_then(|()| self.progress((done / levels).min(1.0), evals, started));
        };
        let cascade = cascade_from(
            &prob,
            from,
            to,
            first,
            max_period,
            &opts,
            &cancel,
            &mut on_level,
        )
        .map_err(start_failure)?;
        sent?;
        if self.stale() {
            return Err(JobError::Stop);
        }
        self.progress(1.0, evals, started)?;
        let top = cascade.branches.last().map_or(period, |b| b.period);
        self.summary(format!(
            "{} · cascade P{period}…P{top} · stopped: {}",
            counts(&all),
            cascade.stop
        ))
    }

    /// The doublings of the attractor's cycle at the box's left edge, and
    /// of the cycle it doubles into, each followed as a curve in (θν, κ).
    fn boundaries(&self, spec: &BoundarySpec) -> Result<(), JobError> {
        let started = Instant::now();
        let cancel = || self.stale();
        let (t0, t1) = spec.theta_nu;
        let (k0, k1) = spec.kappa;
        let kappa = spec.params.kappa;
        if !(t0 < t1 && k0 < k1 && (k0..=k1).contains(&kappa)) {
            return Err(JobError::Failed(format!(
                "the box θν in [{t0}, {t1}], κ in [{k0}, {k1}] is empty or does not hold κ = {kappa}"
            )));
        }
        let base = ContParam::ThetaNu.set(&spec.params, t0);
        let (period, seed) = match attractor_seed(base, spec.settings, &cancel)? {
            Ok(found) => found,
            Err(what) => {
                self.summary(format!(
                    "stopped: the attractor at θν = {t0:.6}, κ = {kappa:.6} {what}: no cycle to follow"
                ))?;
                return Ok(());
            }
        };
        let prob = Problem {
            base,
            settings: spec.settings,
            param: ContParam::ThetaNu,
            period,
        };
        let opts = ContOptions::for_range(&spec.settings, t0, t1);
        // Every doubling of the attractor's cycle along θν (the fixed
        // point's boundary is crossed twice at most κ), and the first of
        // the cycle it doubles into.
        let branch = continue_branch(&prob, t0, t1, seed, &opts, &cancel).map_err(start_failure)?;
        let mut starts: Vec<SpecialPoint> = branch
            .of_kind(SpecialKind::PeriodDoubling)
            .cloned()
            .collect();
        if !starts.is_empty() && 2 * period <= PERIOD_MAX {
            let c = cascade_from(
                &prob,
                t0,
                t1,
                branch.clone(),
                2 * period,
                &opts,
                &cancel,
                &mut |_| {},
            )
            .map_err(start_failure)?;
            starts.extend(c.doublings.into_iter().filter(|d| d.period == 2 * period));
        }
        if self.stale() {
            return Err(JobError::Stop);
        }
        if starts.is_empty() {
            self.summary(format!(
                "stopped: the P{period} cycle does not double along θν in [{t0:.4}, {t1:.4}] at κ = {kappa:.4}: pick a κ where it does"
            ))?;
            return Ok(());
        }
        let copts = CurveOptions::for_box([[t0, t1], [k0, k1]]);
        let mut curves: Vec<crate::sim::continuation::Curve> = Vec::new();
        let mut evals = branch.map_evals;
        let periods: Vec<usize> = [period, 2 * period]
            .into_iter()
            .filter(|p| starts.iter().any(|s| s.period == *p))
            .collect();
        for (i, &p) in periods.iter().enumerate() {
            // One curve per boundary: a doubling on a curve already
            // followed is not followed again.
            let of_p: Vec<SpecialPoint> =
                starts.iter().filter(|s| s.period == p).cloned().collect();
            let found = continue_curves(
                &base,
                &spec.settings,
                [ContParam::ThetaNu, ContParam::Kappa],
                p,
                CurveKind::PeriodDoubling,
                &of_p,
                &copts,
                &cancel,
            );
            if self.stale() {
                return Err(JobError::Stop);
            }
            for curve in found {
                evals += curve.map_evals;
                curves.push(curve.clone());
                self.send(Update::Curve {
                    generation: self.sink.generation(),
                    curve,
                })?;
            }
            self.progress((i + 1) as f64 / periods.len() as f64, evals, started)?;
        }
        let names: Vec<String> = curves
            .iter()
            .map(|c| {
                format!(
                    "P{} to P{} ({} points)",
                    c.period,
                    2 * c.period,
                    c.points.len()
                )
            })
            .collect();
        self.summary(format!(
            "{} curves: {} · done",
            curves.len(),
            names.join(", ")
        ))
    }
}

/// Find bifurcations, as a job of one unit.
pub(crate) struct FindJob {
    spec: ContinuationSpec,
    done: Mutex<bool>,
}

impl FindJob {
    pub fn new(spec: ContinuationSpec) -> Self {
        FindJob {
            spec,
            done: Mutex::new(false),
        }
    }
}

impl Job for FindJob {
    fn lane(&self) -> Lane {
        Lane::Continuation
    }

    fn step(&self, _width: usize, sink: &dyn Sink) -> Result<Status, JobError> {
        let mut done = lock(&self.done);
        if !*done {
            *done = true;
            let out = Out {
                sink,
                lane: Lane::Continuation,
            };
            out.find(&self.spec)?;
        }
        Ok(Status::Done)
    }
}

/// Boundaries, as a job of one unit.
pub(crate) struct BoundariesJob {
    spec: BoundarySpec,
    done: Mutex<bool>,
}

impl BoundariesJob {
    pub fn new(spec: BoundarySpec) -> Self {
        BoundariesJob {
            spec,
            done: Mutex::new(false),
        }
    }
}

impl Job for BoundariesJob {
    fn lane(&self) -> Lane {
        Lane::Curves
    }

    fn step(&self, _width: usize, sink: &dyn Sink) -> Result<Status, JobError> {
        let mut done = lock(&self.done);
        if !*done {
            *done = true;
            let out = Out {
                sink,
                lane: Lane::Curves,
            };
            out.boundaries(&self.spec)?;
        }
        Ok(Status::Done)
    }
}
