//! The continuation jobs, by the library's `sim::continuation`: a cycle
//! followed in one parameter with its bifurcations, then its cascade or
//! the curves through its bifurcations in two parameters (find
//! bifurcations: the window's button and `oneblock continue`), and the
//! doublings followed in (θν, κ) (boundaries). Each special point, branch
//! and curve is sent as it is found. The library polls the sink once per
//! computed point ([`Sink::cycle`]), so a newer job, a cancel or the
//! command line's limits stop it within one point; a stopped job still
//! sends what it has, which a host may keep ([`super::run_kept`]). The
//! jobs are the library's paced walks ([`PacedJob`]): they pause between
//! two map evaluations when the host wants its thread back (the browser's
//! frame), and resume with the same numbers, bit for bit.

use std::sync::Arc;
use web_time::Instant;

use super::JobError;
use super::paced::{PacedJob, Shared};
use super::protocol::{BoundarySpec, CascadeFrom, ContinuationSpec, CurveFollow, Update};
use crate::integrate::SolverSettings;
use crate::model::Params;
use crate::sim::continuation::{
    Attractor, Branch, Cascade, ContOptions, ContParam, Curve, CurveKind, CurveOf, CurveOptions,
    FirstLevel, Pace, Problem, Reach, SpecialKind, SpecialPoint, attractor_cycle_paced,
    cascade_paced, continue_branch_paced, continue_curves_paced,
};
use crate::sim::{CycleFailure, PERIOD_MAX, SimError};

/// The attractor's cycle at `params`
/// ([`crate::sim::continuation::attractor_cycle`]); `Err` says what the
/// attractor is instead.
async fn attractor_seed(
    pace: &Pace,
    params: Params,
    settings: SolverSettings,
) -> Result<Result<(usize, f64), String>, SimError> {
    Ok(match attractor_cycle_paced(pace, params, settings).await? {
        Attractor::Cycle { period, theta } => Ok((period, theta)),
        a => Err(a.describe()),
    })
}

/// The parameter's letter, as the window writes it.
fn symbol(p: ContParam) -> &'static str {
    p.symbol()
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

/// One continuation job's way to its sink (through the step that polls
/// it: [`Shared`]).
struct Out {
    shared: Arc<Shared>,
}

impl Out {
    fn pace(&self) -> &Pace {
        &self.shared.pace
    }

    fn stale(&self) -> bool {
        self.shared.stale()
    }

    fn send(&self, u: Update) {
        self.shared.send(u);
    }

    fn generation(&self) -> u64 {
        self.shared.generation()
    }

    fn summary(&self, text: String) {
        self.send(Update::Summary {
            generation: self.generation(),
            lane: self.shared.lane(),
            text,
        });
    }

    fn progress(&self, fraction: f64, evals: u64, since: Instant) {
        let secs = since.elapsed().as_secs_f64().max(1e-9);
        self.send(Update::Progress {
            generation: self.generation(),
            lane: self.shared.lane(),
            fraction,
            iterates_per_second: evals as f64 / secs,
        });
    }

    /// A branch, sent.
    fn send_branch(&self, branch: &Branch) {
        self.send(Update::Branch {
            generation: self.generation(),
            branch: branch.clone(),
        });
    }

    /// The spec's branch, then its cascade or its curves.
    async fn find(&self, spec: &ContinuationSpec) -> Result<(), JobError> {
        let started = Instant::now();
        let Some((prob, seed)) = self.start(spec).await? else {
            return Ok(());
        };
        let opts = ContOptions::for_range(&spec.settings, spec.from, spec.to);
        let max_period = spec.max_period.clamp(prob.period, PERIOD_MAX);
        if spec.cascade == CascadeFrom::Levels && spec.curves.is_none() {
            return self
                .levels(&prob, spec, seed, &opts, max_period, started)
                .await;
        }
        let branch = self.branch(&prob, spec, seed, &opts).await?;
        match spec.curves {
            Some(follow) => self.curves(&prob, spec, &branch, follow).await,
            None => {
                self.cascade_after(&prob, spec, branch, &opts, max_period, started)
                    .await
            }
        }
    }

    /// The cycle to follow and a point of it at `from`: the given one, or
    /// the attractor's (`None` when the attractor is no cycle, after a
    /// summary saying what it is).
    async fn start(&self, spec: &ContinuationSpec) -> Result<Option<(Problem, f64)>, JobError> {
        let (from, to) = (spec.from, spec.to);
        let name = symbol(spec.param);
        if !(from.is_finite() && to.is_finite()) || from == to {
            return Err(JobError::Failed(format!(
                "the range {name} from {from} to {to} is empty"
            )));
        }
        let base = spec.param.set(&spec.params, from);
        let (period, seed) = match spec.cycle {
            Some(c) => (c.period, c.theta),
            None => match attractor_seed(self.pace(), base, spec.settings).await? {
                Ok(found) => found,
                Err(what) => {
                    self.summary(format!(
                        "stopped: the attractor at {name} = {from:.6} {what}: no cycle to follow"
                    ));
                    return Ok(None);
                }
            },
        };
        let prob = Problem {
            base,
            settings: spec.settings,
            param: spec.param,
            period,
        };
        Ok(Some((prob, seed)))
    }

    /// The branch over the whole range, each special point sent as it is
    /// located and the branch once it ends.
    async fn branch(
        &self,
        prob: &Problem,
        spec: &ContinuationSpec,
        seed: f64,
        opts: &ContOptions,
    ) -> Result<Branch, JobError> {
        let mut on_special = |p: &SpecialPoint| {
            self.send(Update::Special {
                generation: self.generation(),
                point: p.clone(),
            });
        };
        let reach = Reach::new(prob, spec.from, spec.to, opts);
        let walk = continue_branch_paced(self.pace(), reach, seed, &mut on_special);
        let branch = walk.await.map_err(start_failure)?;
        self.send_branch(&branch);
        Ok(branch)
    }

    /// The cascade from `first`, the branch over the whole range, up to
    /// `max_period`: only the levels after it are new.
    async fn cascade_after(
        &self,
        prob: &Problem,
        spec: &ContinuationSpec,
        first: Branch,
        opts: &ContOptions,
        max_period: usize,
        started: Instant,
    ) -> Result<(), JobError> {
        let period = prob.period;
        let levels = (max_period / period).max(1).ilog2() as f64 + 1.0;
        let mut tally = Tally::new(&first, levels, started);
        let doubles = first.doublings().next().is_some();
        let said = format!("P{period} branch: it {}", first.stop_message());
        if !doubles || 2 * period > max_period {
            self.progress(1.0, tally.evals, started);
            let why = if doubles {
                format!("the cascade's period is capped at {max_period}")
            } else {
                "no period doubling".to_string()
            };
            let counted = counts(&tally.all);
            self.summary(format!("{counted} · stopped: {said}; {why}"));
            return Ok(());
        }
        self.progress(1.0 / levels, tally.evals, started);
        self.summary(format!("{} · following the cascade…", counts(&tally.all)));
        let reach = Reach::new(prob, spec.from, spec.to, opts);
        let mut on_level = |b: &Branch| tally.level(self, b);
        let first = FirstLevel::Given(first);
        let walk = cascade_paced(self.pace(), reach, first, max_period, &mut on_level);
        let cascade = walk.await.map_err(start_failure)?;
        self.cascade_done(period, cascade, &tally);
        Ok(())
    }

    /// The cascade from the cycle through `seed`, each level from its
    /// birth to its doubling, up to `max_period`.
    async fn levels(
        &self,
        prob: &Problem,
        spec: &ContinuationSpec,
        seed: f64,
        opts: &ContOptions,
        max_period: usize,
        started: Instant,
    ) -> Result<(), JobError> {
        let period = prob.period;
        let levels = (max_period / period).max(1).ilog2() as f64 + 1.0;
        let mut tally = Tally {
            evals: 0,
            all: Vec::new(),
            levels,
            started,
        };
        let reach = Reach::new(prob, spec.from, spec.to, opts);
        let mut on_level = |b: &Branch| tally.level(self, b);
        let first = FirstLevel::Seed(seed);
        let walk = cascade_paced(self.pace(), reach, first, max_period, &mut on_level);
        let cascade = walk.await.map_err(start_failure)?;
        self.cascade_done(period, cascade, &tally);
        Ok(())
    }

    /// The end of a cascade from the `period`-cycle: full progress, the
    /// cascade, and its summary.
    fn cascade_done(&self, period: usize, cascade: Cascade, tally: &Tally) {
        self.progress(1.0, tally.evals, tally.started);
        let top = cascade.branches.last().map_or(period, |b| b.period);
        let text = format!(
            "{} · cascade P{period}…P{top} · stopped: {}",
            counts(&tally.all),
            cascade.stop
        );
        self.send(Update::Cascade {
            generation: self.generation(),
            cascade,
        });
        self.summary(text);
    }

    /// The `follow.kind` curves through the branch's points of that kind.
    async fn curves(
        &self,
        prob: &Problem,
        spec: &ContinuationSpec,
        branch: &Branch,
        follow: CurveFollow,
    ) -> Result<(), JobError> {
        let want = match follow.kind {
            CurveKind::PeriodDoubling => SpecialKind::PeriodDoubling,
            CurveKind::Fold => SpecialKind::Fold,
        };
        // Of the branch's own period (not the doubling it was born at).
        let starts: Vec<SpecialPoint> = branch
            .of_kind(want)
            .filter(|s| s.period == prob.period)
            .cloned()
            .collect();
        if starts.is_empty() {
            self.summary(format!(
                "stopped: no {} point on the P{} branch: no curve to follow",
                want.name(),
                prob.period
            ));
            return Ok(());
        }
        let copts = CurveOptions::for_box([[spec.from, spec.to], follow.range]);
        let of = CurveOf {
            base: prob.base,
            settings: spec.settings,
            params: [spec.param, follow.param],
            period: prob.period,
            kind: follow.kind,
        };
        let curves = self.curves_through(&of, &starts, &copts).await;
        self.summary(format!("{} curves · done", curves.len()));
        Ok(())
    }

    /// The `kind` curves of the `period`-cycle through `starts` (a start on
    /// an earlier curve is skipped), each sent; see
    /// [`crate::sim::continuation::continue_curves`].
    async fn curves_through(
        &self,
        of: &CurveOf,
        starts: &[SpecialPoint],
        copts: &CurveOptions,
    ) -> Vec<Curve> {
        let found = continue_curves_paced(self.pace(), of, starts, copts).await;
        for curve in &found {
            self.send(Update::Curve {
                generation: self.generation(),
                curve: curve.clone(),
            });
        }
        found
    }

    /// The doublings of the attractor's cycle at the box's left edge, and
    /// of the cycle it doubles into, each followed as a curve in (θν, κ).
    async fn boundaries(&self, spec: &BoundarySpec) -> Result<(), JobError> {
        let started = Instant::now();
        let (t0, t1) = spec.theta_nu;
        let (k0, k1) = spec.kappa;
        let kappa = spec.params.kappa;
        if !(t0 < t1 && k0 < k1 && (k0..=k1).contains(&kappa)) {
            return Err(JobError::Failed(format!(
                "the box θν in [{t0}, {t1}], κ in [{k0}, {k1}] is empty or does not hold κ = {kappa}"
            )));
        }
        let Some((prob, branch, starts)) = self.doublings(spec).await? else {
            return Ok(());
        };
        let copts = CurveOptions::for_box([[t0, t1], [k0, k1]]);
        let mut curves: Vec<Curve> = Vec::new();
        let mut evals = branch.map_evals;
        let period = prob.period;
        let periods: Vec<usize> = [period, 2 * period]
            .into_iter()
            .filter(|p| starts.iter().any(|s| s.period == *p))
            .collect();
        // The folds of the followed cycle's branch: the fold curves
        // (`continue --curve fold`), where the cycle is born or dies.
        let folds: Vec<SpecialPoint> = branch.of_kind(SpecialKind::Fold).cloned().collect();
        let steps = periods.len() + usize::from(!folds.is_empty());
        // Every curve of the box is in (θν, κ), at the spec's solver.
        let boundary = CurveOf {
            base: prob.base,
            settings: spec.settings,
            params: [ContParam::ThetaNu, ContParam::Kappa],
            period,
            kind: CurveKind::PeriodDoubling,
        };
        for (i, &p) in periods.iter().enumerate() {
            // One curve per boundary: a doubling on a curve already
            // followed is not followed again.
            let of_p: Vec<SpecialPoint> =
                starts.iter().filter(|s| s.period == p).cloned().collect();
            let of = CurveOf {
                period: p,
                ..boundary
            };
            let found = self.curves_through(&of, &of_p, &copts).await;
            evals += found.iter().map(|c| c.map_evals).sum::<u64>();
            curves.extend(found);
            self.progress((i + 1) as f64 / steps as f64, evals, started);
        }
        if !folds.is_empty() {
            let of = CurveOf {
                period,
                kind: CurveKind::Fold,
                ..boundary
            };
            let found = self.curves_through(&of, &folds, &copts).await;
            evals += found.iter().map(|c| c.map_evals).sum::<u64>();
            curves.extend(found);
            self.progress(1.0, evals, started);
        }
        let names: Vec<String> = curves.iter().map(curve_name).collect();
        self.summary(format!(
            "{} curves: {} · done",
            curves.len(),
            names.join(", ")
        ));
        Ok(())
    }

    /// The attractor's cycle at the box's left edge, its branch along θν,
    /// and the doublings the curves start from: every doubling of that
    /// branch (the fixed point's boundary is crossed twice at some κ) and
    /// the first of the cycle it doubles into. `None` (after a summary)
    /// when there is none, and no fold either.
    #[allow(clippy::type_complexity)]
    async fn doublings(
        &self,
        spec: &BoundarySpec,
    ) -> Result<Option<(Problem, Branch, Vec<SpecialPoint>)>, JobError> {
        let (t0, t1) = spec.theta_nu;
        let kappa = spec.params.kappa;
        let base = ContParam::ThetaNu.set(&spec.params, t0);
        let (period, seed) = match attractor_seed(self.pace(), base, spec.settings).await? {
            Ok(found) => found,
            Err(what) => {
                self.summary(format!(
                    "stopped: the attractor at θν = {t0:.6}, κ = {kappa:.6} {what}: no cycle to follow"
                ));
                return Ok(None);
            }
        };
        let prob = Problem {
            base,
            settings: spec.settings,
            param: ContParam::ThetaNu,
            period,
        };
        let opts = ContOptions::for_range(&spec.settings, t0, t1);
        let quiet = &mut |_: &SpecialPoint| {};
        let reach = Reach::new(&prob, t0, t1, &opts);
        let walk = continue_branch_paced(self.pace(), reach, seed, quiet);
        let branch = walk.await.map_err(start_failure)?;
        let mut starts: Vec<SpecialPoint> = branch.doublings().cloned().collect();
        if !starts.is_empty() && 2 * period <= PERIOD_MAX {
            let first = FirstLevel::Given(branch.clone());
            let quiet = &mut |_: &Branch| {};
            let walk = cascade_paced(self.pace(), reach, first, 2 * period, quiet);
            let c = walk.await.map_err(start_failure)?;
            starts.extend(c.doublings.into_iter().filter(|d| d.period == 2 * period));
        }
        if self.stale() {
            return Err(JobError::Stop);
        }
        if starts.is_empty() && branch.of_kind(SpecialKind::Fold).next().is_none() {
            self.summary(format!(
                "stopped: the P{period} cycle does not double or fold along θν in [{t0:.4}, {t1:.4}] at κ = {kappa:.4}: pick a κ where it does"
            ));
            return Ok(None);
        }
        Ok(Some((prob, branch, starts)))
    }
}

/// A cascade's levels so far, for its progress and summary.
struct Tally {
    evals: u64,
    all: Vec<Branch>,
    /// The levels expected.
    levels: f64,
    started: Instant,
}

impl Tally {
    /// The tally after the first level, `first`.
    fn new(first: &Branch, levels: f64, started: Instant) -> Self {
        Tally {
            evals: first.map_evals,
            all: vec![first.clone()],
            levels,
            started,
        }
    }

    /// A level has ended: it is sent, and counted in the progress.
    fn level(&mut self, out: &Out, b: &Branch) {
        out.send_branch(b);
        self.evals += b.map_evals;
        self.all.push(b.clone());
        let done = self.all.len() as f64;
        out.progress((done / self.levels).min(1.0), self.evals, self.started);
    }
}

/// "P1 to P2 (40 points, 1 generalised flip)".
fn curve_name(c: &Curve) -> String {
    // Where the doubling turns subcritical along the curve.
    let flips = match c.generalised_flips.len() {
        0 => String::new(),
        1 => ", 1 generalised flip".into(),
        n => format!(", {n} generalised flips"),
    };
    match c.kind {
        CurveKind::PeriodDoubling => format!(
            "P{} to P{} ({} points{flips})",
            c.period,
            2 * c.period,
            c.points.len()
        ),
        CurveKind::Fold => format!("P{} fold ({} points)", c.period, c.points.len()),
    }
}

/// Find bifurcations: the spec's branch and its cascade or curves.
pub(crate) fn find_job(spec: ContinuationSpec) -> PacedJob {
    PacedJob::new(move |shared| async move {
        let out = Out { shared };
        out.find(&spec).await
    })
}

/// Boundaries: the doubling curves in (θν, κ).
pub(crate) fn boundaries_job(spec: BoundarySpec) -> PacedJob {
    PacedJob::new(move |shared| async move {
        let out = Out { shared };
        out.boundaries(&spec).await
    })
}
