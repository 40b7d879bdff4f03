//! The walk along a branch: predict along the tangent, correct, and
//! locate the special points between the last two points (see
//! [`super::branch`] for the method).

use super::branch::{
    Branch, BranchPoint, ContOptions, Ctx, Fail, JUMP, Pt, SpecialKind, SpecialPoint, Stop,
};
use super::{EvalError, Pace, Problem, drive};
use crate::sim::cycles::{CycleFailure, CycleOptions};

/// Where a walk along branches goes: the cycle of `prob` from λ = `from`
/// towards λ = `to`, stepped as `opts` says. What a branch's walk and a
/// cascade's share, as one value rather than four arguments each.
#[derive(Clone, Copy, Debug)]
pub struct Reach<'a> {
    /// The cycle followed (its parameters, solver, varied parameter and
    /// period).
    pub prob: &'a Problem,
    /// Where the walk starts.
    pub from: f64,
    /// Where it is headed.
    pub to: f64,
    /// How it steps and locates.
    pub opts: &'a ContOptions,
}

impl<'a> Reach<'a> {
    /// `prob`'s cycle from `from` towards `to`, stepped as `opts` says.
    pub fn new(prob: &'a Problem, from: f64, to: f64, opts: &'a ContOptions) -> Self {
        Reach {
            prob,
            from,
            to,
            opts,
        }
    }
}

/// Follows the p-cycle through `seed` at λ = `from` towards λ = `to`
/// (see the module notes). Fails only when no cycle is found at the start;
/// a branch that fails later ends with [`Stop::Failed`] and keeps what it
/// has. `cancel` is polled once per point.
pub fn continue_branch(
    prob: &Problem,
    from: f64,
    to: f64,
    seed: f64,
    opts: &ContOptions,
    cancel: &dyn Fn() -> bool,
) -> Result<Branch, CycleFailure> {
    let reach = Reach::new(prob, from, to, opts);
    continue_branch_reporting(reach, seed, cancel, &mut |_| {})
}

/// A branch being followed: where it is, and what it has found.
struct Walk<'a, 'b, R: FnMut(&SpecialPoint) + ?Sized> {
    ctx: Ctx<'a>,
    from: f64,
    to: f64,
    /// +1 when `to` ≥ `from`.
    dir: f64,
    /// The last corrected point and the unit tangent there.
    cur: Pt,
    t: [f64; 2],
    /// Points closer than this are one (for the minimal period).
    tol: f64,
    points: Vec<BranchPoint>,
    special: Vec<SpecialPoint>,
    on_special: &'b mut R,
    /// How often a step has met the tip of the pitchfork the branch was
    /// born in (each halves the step, to end close to it).
    tip_tries: u32,
    /// The branch's end where it met its birth: the half-period cycle's
    /// doubling.
    tip: Option<SpecialPoint>,
    /// Small jumps of f^p stepped over ([`Walk::leap`]).
    leaps: u32,
}

/// How many steps that meet the tip of the branch's pitchfork are
/// retried at half the length before the branch ends there.
const TIP_TRIES: u32 = 6;

/// The most small jumps of f^p a branch steps over.
const MAX_LEAPS: u32 = 8;

/// The error of a multiplier at the solver's tolerance `tol`, as a
/// multiple of it: at tol 1e-10 m is off by up to ~6e-7 at κ = 19,
/// γ = 10 (issue 52 item 5), so 1e5·tol leaves a margin of 15.
const M_ERR_PER_TOL: f64 = 1e5;

/// A special point located on a step: its kind, the point, a note, and
/// (λ, m) at the branch points its location corrected.
type Found = (SpecialKind, Pt, String, Vec<(f64, f64)>);

/// What one step of the walk came to.
enum Step {
    /// A point was added: go on (with a longer step if `grow`).
    Next,
    /// The step failed and was halved: try again.
    Retry,
    /// The branch ends.
    Stop(Stop),
}

/// [`continue_branch`] over `reach`, calling `on_special` with each PD,
/// fold, border and jump as it is located (for progress lines): the walk
/// of [`continue_branch_paced`] driven to its end.
pub fn continue_branch_reporting(
    reach: Reach<'_>,
    seed: f64,
    cancel: &dyn Fn() -> bool,
    on_special: &mut dyn FnMut(&SpecialPoint),
) -> Result<Branch, CycleFailure> {
    let pace = Pace::new();
    let walk = continue_branch_paced(&pace, reach, seed, on_special);
    drive(&pace, walk, cancel)
}

/// The walk along a branch, a piece after each map evaluation and a
/// cancel asked once per point: [`continue_branch_reporting`] drives it to
/// its end at once, a job ([`crate::jobs`]) piece by piece.
pub async fn continue_branch_paced<R: FnMut(&SpecialPoint) + ?Sized>(
    pace: &Pace,
    reach: Reach<'_>,
    seed: f64,
    on_special: &mut R,
) -> Result<Branch, CycleFailure> {
    let opts = reach.opts;
    let mut walk = Walk::start(pace, reach, seed, on_special).await?;
    let mut h = opts.h0;
    let mut grow = true;
    let stop = loop {
        if pace.cancelled().await {
            break Stop::Cancelled;
        }
        if walk.points.len() >= opts.max_points {
            break Stop::MaxPoints;
        }
        match walk.step(h).await {
            Step::Next => {
                if grow {
                    h = (1.5 * h).min(opts.h_max);
                }
                grow = true;
            }
            Step::Retry => {
                h *= 0.5;
                grow = false;
                if h < opts.h_min {
                    match walk.leap().await {
                        Some(over) => h = over,
                        None => break walk.fail(),
                    }
                }
            }
            Step::Stop(stop) => break stop,
        }
    };
    Ok(walk.finish(stop))
}

impl<'a, 'b, R: FnMut(&SpecialPoint) + ?Sized> Walk<'a, 'b, R> {
    /// The cycle through `seed`, solved and corrected at λ = `from`
    /// exactly.
    async fn start(
        pace: &'a Pace,
        reach: Reach<'a>,
        seed: f64,
        on_special: &'b mut R,
    ) -> Result<Self, CycleFailure> {
        let (prob, from, to, opts) = (reach.prob, reach.from, reach.to, reach.opts);
        let sim = prob.sim(from)?;
        let mut cyc_opts = CycleOptions::for_settings(&prob.settings);
        cyc_opts.tol = cyc_opts.tol.min(opts.newton_tol);
        let mut spent = (0, 0);
        let cycle =
            super::pace::solve_cycle(pace, &sim, seed, prob.period, &cyc_opts, &mut spent).await?;
        let mut ctx = Ctx {
            pace,
            prob,
            opts,
            evals: cycle.map_evals,
            last_fail: None,
        };
        let scale = opts.scale;
        let dir = if to >= from { 1.0 } else { -1.0 };
        let cur = ctx
            .correct([cycle.points[0], from / scale], [0.0, 1.0])
            .await
            .map_err(|f| start_failure(f, seed, opts))?;
        let t = cur.tangent(scale, [0.0, dir]);
        // Points closer than 100× the solver's tolerance are one point (as
        // `solve_cycle` decides the minimal period).
        let tol = CycleOptions::for_settings(&prob.settings).tol;
        let mut first = ctx.point(&cur, tol);
        // Exactly the λ asked for, not μ·scale rounded.
        first.lambda = from;
        Ok(Walk {
            ctx,
            from,
            to,
            dir,
            cur,
            t,
            tol,
            points: vec![first],
            special: Vec::new(),
            on_special,
            tip_tries: 0,
            tip: None,
            leaps: 0,
        })
    }

    fn scale(&self) -> f64 {
        self.ctx.opts.scale
    }

    /// Predicts a step h along the tangent, corrects it, clips it to the
    /// range, detects the special points crossed, and records them.
    async fn step(&mut self, h: f64) -> Step {
        let Some((n, tn)) = self.predict_correct(h).await else {
            return Step::Retry;
        };
        // Before any fold test: a step that reaches the tip of the
        // pitchfork the branch was born in, onto the half-period cycle or
        // round to the same cycle with its halves swapped, is never taken.
        if super::tip::meets_birth(&self.cur, &n, self.tol) {
            if self.tip_tries < TIP_TRIES && h > 64.0 * self.ctx.opts.h_min {
                self.tip_tries += 1;
                return Step::Retry;
            }
            return Step::Stop(self.end_at_tip(&n).await);
        }
        // A step that lands on a cycle of smaller minimal period (not at
        // the tip of the branch's pitchfork) jumped to another branch:
        // at κ = 1.22, γ = 6.5 a P5 past a jump of f⁵ corrected onto the
        // fixed point. Shorter steps, and a border where none works.
        let q = self.ctx.point(&n, self.tol).minimal_period;
        if q < self.ctx.point(&self.cur, self.tol).minimal_period {
            self.ctx.last_fail = Some(Fail::OtherCycle(q));
            return Step::Retry;
        }
        let (n, last) = match self.clip(n).await {
            Ok(v) => v,
            Err(()) => return Step::Retry,
        };
        let found = self.detect(&n).await;
        // A fold on an even-period branch within m's error of the tip of
        // the pitchfork it was born in is that tip, seen through m's error
        // (κ = 7, γ = 4: the P4 reached m = +1 1.3e-8 before the P2's
        // doubling where it merges, and was reported as a fold there).
        if let Some(fold) = found.iter().find(|f| f.0 == SpecialKind::Fold)
            && let Some(tip) = self.fold_at_tip(&n, &fold.1).await
        {
            self.record_tip(tip);
            return Step::Stop(Stop::Merged);
        }
        let mut pd = false;
        for (kind, p, note, samples) in &found {
            let mut sp = self.ctx.special(*kind, p, note.clone());
            if *kind == SpecialKind::PeriodDoubling {
                sp.flip = self.ctx.flip(p, samples).await;
            }
            (self.on_special)(&sp);
            self.special.push(sp);
            self.points.push(self.ctx.point(p, self.tol));
            pd |= *kind == SpecialKind::PeriodDoubling;
        }
        let mut np = self.ctx.point(&n, self.tol);
        if let Some(target) = last {
            np.lambda = target;
        }
        self.points.push(np);
        // λ turned without a fold: an even-period branch passes the tip of
        // the pitchfork where it is born from the half-period cycle, and
        // would come back as the same cycle with its halves swapped.
        let turned =
            self.t[1] * tn[1] < 0.0 && found.is_empty() && self.ctx.prob.period.is_multiple_of(2);
        self.cur = n;
        self.t = tn;
        if let Some(target) = last {
            return Step::Stop(if target == self.to {
                Stop::Reached
            } else {
                Stop::Returned
            });
        }
        if turned {
            return Step::Stop(Stop::Merged);
        }
        if pd && self.ctx.opts.stop_at_pd {
            return Step::Stop(Stop::PeriodDoubling);
        }
        Step::Next
    }

    /// The corrected point a step h along the tangent, and its tangent;
    /// The branch's end at the tip of its pitchfork, met on the step to
    /// `n`: the half-period cycle's doubling located there and recorded
    /// (see [`super::tip`]).
    async fn end_at_tip(&mut self, n: &Pt) -> Stop {
        let prev = self.prev_point();
        let cur = self.cur.clone();
        if let Some(pd) = super::tip::locate_tip(&mut self.ctx, &cur, prev.as_ref(), n).await {
            self.record_tip(pd);
        }
        Stop::Merged
    }

    /// The point before the current one, if any.
    fn prev_point(&self) -> Option<BranchPoint> {
        self.points
            .len()
            .checked_sub(2)
            .map(|i| self.points[i].clone())
    }

    /// Records `pd`, the half-period cycle's doubling at the tip of the
    /// branch's pitchfork, and the branch's end there.
    fn record_tip(&mut self, pd: SpecialPoint) {
        (self.on_special)(&pd);
        let end = SpecialPoint {
            kind: SpecialKind::End,
            period: self.ctx.prob.period,
            multiplier: pd.multiplier * pd.multiplier,
            note: format!(
                "{}{} cycle it is born from, at its doubling",
                super::branch::MERGED_NOTE,
                pd.period
            ),
            flip: None,
            ..pd.clone()
        };
        self.special.push(pd);
        self.tip = Some(end);
    }

    /// For a fold located at `fold` on the step to `n` of an even-period
    /// branch: the half-period cycle's doubling at the tip of the branch's
    /// pitchfork, when there is one within m's error of the fold. Near the
    /// tip m → +1 like (b − λ)·|dm/dλ|, so an error δm in m moves m = +1
    /// by δm/|dm/dλ| off the tip; a fold no further than that from the
    /// doubling is the tip. `None` for odd periods, where no doubling is
    /// found, or where it is further (a fold of the cycle's own).
    async fn fold_at_tip(&mut self, n: &Pt, fold: &Pt) -> Option<SpecialPoint> {
        if !self.ctx.prob.period.is_multiple_of(2) {
            return None;
        }
        let scale = self.scale();
        let cur = self.cur.clone();
        let dl = n.lambda(scale) - cur.lambda(scale);
        let slope = ((n.e.multiplier - cur.e.multiplier) / dl).abs();
        let near = M_ERR_PER_TOL * self.tol / slope;
        if !near.is_finite() {
            return None;
        }
        let prev = self.prev_point();
        let pd = super::tip::locate_tip(&mut self.ctx, &cur, prev.as_ref(), n).await?;
        ((pd.lambda - fold.lambda(scale)).abs() <= near).then_some(pd)
    }

    /// `None` when the corrector fails, lands more than half a step from
    /// the prediction, or the tangent turns by more than ~18°.
    async fn predict_correct(&mut self, h: f64) -> Option<(Pt, [f64; 2])> {
        let (cur, t, scale) = (&self.cur, self.t, self.scale());
        let pred = [cur.x[0] + h * t[0], cur.x[1] + h * t[1]];
        match self.ctx.correct(pred, t).await {
            Ok(n) => {
                let tn = n.tangent(scale, t);
                let far = (n.x[0] - pred[0]).hypot(n.x[1] - pred[1]) > 0.5 * h + 1e-12;
                if far || tn[0] * t[0] + tn[1] * t[1] < 0.95 {
                    self.ctx.last_fail = Some(Fail::NoConvergence(n.e.g.abs()));
                    None
                } else {
                    Some((n, tn))
                }
            }
            Err(f) => {
                self.ctx.last_fail = Some(f);
                None
            }
        }
    }

    /// `n`, or the point at the range's end (or its start, after a fold)
    /// when `n` is past it, corrected at exactly that λ, with that λ.
    async fn clip(&mut self, n: Pt) -> Result<(Pt, Option<f64>), ()> {
        let scale = self.scale();
        let at = n.lambda(scale);
        let past_end = self.dir * (at - self.to) >= 0.0;
        let behind = self.dir * (at - self.from) < 0.0;
        if !(past_end || behind) {
            return Ok((n, None));
        }
        let target = if past_end { self.to } else { self.from };
        let l0 = self.cur.lambda(scale);
        let w = (target - l0) / (at - l0);
        let th = self.cur.x[0] + w * (n.x[0] - self.cur.x[0]);
        match self.ctx.correct([th, target / scale], [0.0, 1.0]).await {
            Ok(c) => Ok((c, Some(target))),
            Err(_) => {
                self.ctx.last_fail = Some(Fail::NoConvergence(f64::NAN));
                Err(())
            }
        }
    }

    /// The PD and fold crossings between the current point and `n`,
    /// located and in order along the step; a crossing that is no zero of
    /// m ± 1 is a [`SpecialKind::Jump`].
    async fn detect(&mut self, n: &Pt) -> Vec<Found> {
        let (cur, t) = (self.cur.clone(), self.t);
        let (m0, m1) = (cur.e.multiplier, n.e.multiplier);
        let along = |p: &Pt| (p.x[0] - cur.x[0]) * t[0] + (p.x[1] - cur.x[1]) * t[1];
        let dist = along(n);
        let mut found: Vec<Found> = Vec::new();
        let tests: [(SpecialKind, f64); 2] = [
            (SpecialKind::PeriodDoubling, -1.0),
            (SpecialKind::Fold, 1.0),
        ];
        for (kind, at) in tests {
            if (m0 - at) * (m1 - at) >= 0.0 {
                continue;
            }
            let test = move |m: f64| m - at;
            let mut l = self.ctx.locate(&cur, n, t, dist, test).await;
            if l.real {
                l = self.ctx.refine(l, t, test).await;
                found.push((kind, l.pt, String::new(), l.samples));
            } else {
                let note = format!(
                    "m goes from {m0:.6} to {m1:.6} across the step but stays |m {} 1| >= {:.2e} away to the location accuracy: a jump or pole of m, not a {}",
                    if at < 0.0 { '+' } else { '-' },
                    l.off,
                    kind.name()
                );
                found.push((SpecialKind::Jump, l.pt, note, l.samples));
            }
        }
        found.sort_by(|a, b| along(&a.1).total_cmp(&along(&b.1)));
        found
    }

    /// A step over a small jump of f^p, when no step down to the shortest
    /// works but the corrector's residual stays small (below [`JUMP`]):
    /// then f^p jumps by about that residual next to the cycle, whose
    /// zero of G on the far side is displaced by residual/|1 − m|, and the
    /// cycle may go on there (at κ = 15, γ = 4, ν = 1e-3 the P8 born at
    /// θν = 1.1778800 meets a jump of G of 2e-6 at 1.1779297, 5e-5 past
    /// its birth, and goes on 6e-5 away in θ to its own doubling). Steps
    /// of h0/16, h0/4, h0 and 4·h0 are tried; the first that corrects to
    /// a cycle with a multiplier close to the last one's is the step the
    /// walk goes on with (taken again, with its tests), and a `jump` is
    /// recorded at the last point. `None` where none does.
    async fn leap(&mut self) -> Option<f64> {
        let r = match self.ctx.last_fail {
            Some(Fail::NoConvergence(r)) if r <= JUMP => r,
            _ => return None,
        };
        if self.leaps >= MAX_LEAPS {
            return None;
        }
        let (h0, m0) = (self.ctx.opts.h0, self.cur.e.multiplier);
        // The failure the branch ends with if no leap works: the short
        // steps', not the long leaps'.
        let stalled = self.ctx.last_fail.take();
        for h in [h0 / 16.0, h0 / 4.0, h0, 4.0 * h0] {
            let Some((n, _)) = self.predict_correct(h).await else {
                continue;
            };
            if (n.e.multiplier - m0).abs() > 0.1 * (1.0 + m0.abs()) {
                continue;
            }
            let moved = (n.x[0] - self.cur.x[0]).abs();
            let note = format!(
                "f^p jumps next to the cycle: Newton's residual stays {r:.1e} at every step down to the shortest; the cycle goes on past it (theta {moved:.1e} further on, m from {m0:.6} to {:.6}): no bifurcation",
                n.e.multiplier
            );
            let sp = self.ctx.special(SpecialKind::Jump, &self.cur, note);
            (self.on_special)(&sp);
            self.special.push(sp);
            self.leaps += 1;
            self.ctx.last_fail = None;
            return Some(h);
        }
        self.ctx.last_fail = stalled;
        None
    }

    /// The end when no step down to the shortest works: a border where a
    /// cycle point meets the map's edge or f^p jumps, else a failure.
    fn fail(&mut self) -> Stop {
        let here = self.ctx.special(SpecialKind::End, &self.cur, String::new());
        let note = match self.ctx.last_fail.take() {
            Some(Fail::Eval(e)) if e.is_border() => {
                format!("a cycle point reaches the map's edge {e}")
            }
            // G cannot change by this much over a step shorter than the
            // location accuracy unless f^p jumps there.
            Some(Fail::NoConvergence(r)) if r > JUMP => format!(
                "f^p jumps or its slope diverges: |G| = {r:.1e} a step below the location accuracy away"
            ),
            Some(Fail::OtherCycle(q)) => format!(
                "f^p jumps here: past it every step, down to the shortest, lands on a P{q} cycle, not this one"
            ),
            Some(Fail::NoConvergence(r)) if r.is_nan() => {
                return Stop::Failed("the cycle at the range's end did not converge".into());
            }
            Some(f) => return Stop::Failed(f.describe()),
            None => return Stop::Failed("no step succeeded".into()),
        };
        let border = SpecialPoint {
            kind: SpecialKind::Border,
            note,
            ..here
        };
        (self.on_special)(&border);
        self.special.push(border);
        Stop::Border
    }

    /// The branch, its end point added.
    fn finish(mut self, stop: Stop) -> Branch {
        let note = match &stop {
            Stop::Reached => "the end of the range".to_string(),
            Stop::Returned => "back at the start of the range".to_string(),
            Stop::Merged => "merged with the half-period cycle".to_string(),
            Stop::PeriodDoubling => "its first period doubling".to_string(),
            Stop::Border => "a border".to_string(),
            Stop::Failed(why) => why.clone(),
            Stop::MaxPoints => "the most points".to_string(),
            Stop::Cancelled => "cancelled".to_string(),
        };
        let mut last_point = self.ctx.special(SpecialKind::End, &self.cur, note);
        if let Some(p) = self.points.last() {
            last_point.lambda = p.lambda;
        }
        if let Some(tip) = self.tip.take() {
            last_point = tip;
        }
        self.special.push(last_point);
        Branch {
            param: self.ctx.prob.param,
            period: self.ctx.prob.period,
            points: self.points,
            special: self.special,
            stop,
            map_evals: self.ctx.evals,
        }
    }
}

/// A start that Newton could not correct, as the cycle solver's failure.
fn start_failure(f: Fail, seed: f64, opts: &ContOptions) -> CycleFailure {
    match f {
        Fail::Eval(EvalError::Sim(e)) => CycleFailure::Sim(e),
        Fail::Eval(e) => CycleFailure::Discontinuity {
            theta: match e {
                EvalError::NotDifferentiable { theta, .. } | EvalError::OffArc { theta } => theta,
                _ => seed,
            },
        },
        Fail::NoConvergence(r) => CycleFailure::NoConvergence {
            iterations: opts.max_newton,
            residual: r,
        },
        // Only a step sets it, never the start's correction.
        Fail::OtherCycle(_) => CycleFailure::Discontinuity { theta: seed },
    }
}
