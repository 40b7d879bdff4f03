//! Locating on a cycle's branch: a track's end by the first fold, flip
//! or border its continuation meets, a chaotic set's by bisection on the
//! cell graph, and two tracks that are one cycle continued.

use super::super::tracks::Identities;
use super::super::{Attractor, Found, Verdict};
use super::plan::spans;
use super::{Cause, Event, LOCATE_TOL, Locator, Role, unresolved};
use crate::sim::Simulator;
use crate::sim::continuation::{
    Branch, ContOptions, Problem, SpecialKind, SpecialPoint, Stop, continue_branch,
};

impl Locator {
    /// Joins a track that ends at a stable cycle to one that starts in
    /// the next computed column with a cycle of the same period, where
    /// the first cycle's continuation reaches the second with no fold,
    /// flip or border between (the graph did not pair them: one lay on
    /// the other's basin boundary at its resolution).
    pub(super) fn join_continued(
        &self,
        values: &[f64],
        found: &[Option<&Found>],
        ids: &mut Identities,
        cancel: &dyn Fn() -> bool,
    ) {
        let index = |ids: &Identities, c: usize, t: usize| {
            ids.of[c]
                .as_ref()
                .and_then(|v| v.iter().position(|&x| x == t))
        };
        let mut t = 0;
        while t < ids.tracks.len() {
            let sp = spans(found, ids);
            let (_, last, _, after) = sp[t];
            let joined = after.and_then(|j| {
                let a = &found[last]?.attractors[index(ids, last, t)?];
                let p = a.period?;
                let u = (0..ids.tracks.len()).find(|&u| {
                    sp[u].0 == j
                        && index(ids, j, u).is_some_and(|b| {
                            found[j].is_some_and(|f| f.attractors[b].period == Some(p))
                        })
                })?;
                let b = &found[j]?.attractors[index(ids, j, u)?];
                self.continues(a, p, values[last], values[j], b, cancel)
                    .then_some(u)
            });
            match joined {
                Some(u) => ids.join(t, u),
                None => t += 1,
            }
        }
    }

    /// Whether the p-cycle `a` at `from`, continued to `to`, is `b` there
    /// (every point within 1e-6 rad of one of `b`'s) with no special point
    /// between.
    fn continues(
        &self,
        a: &Attractor,
        p: usize,
        from: f64,
        to: f64,
        b: &Attractor,
        cancel: &dyn Fn() -> bool,
    ) -> bool {
        let prob = Problem {
            base: self.base,
            settings: self.settings,
            param: self.param,
            period: p,
        };
        let opts = ContOptions::for_range(&self.settings, from, to);
        let seed = a.points.first().copied().unwrap_or(0.0);
        let Ok(branch) = continue_branch(&prob, from, to, seed, &opts, cancel) else {
            return false;
        };
        let clean = branch.stop == Stop::Reached
            && branch.special.iter().all(|s| s.kind == SpecialKind::End);
        let close = |x: f64| {
            b.points
                .iter()
                .any(|&y| crate::model::wrap_angle(x - y).abs() < 1e-6)
        };
        clean
            && branch
                .points
                .last()
                .is_some_and(|q| q.points.iter().all(|&x| close(x)))
    }

    /// The first fold, flip or border on the p-cycle through `at`'s first
    /// point, followed from `from` towards `to`.
    pub(super) fn cycle_end(
        &self,
        at: &Attractor,
        p: usize,
        from: f64,
        to: f64,
        role: Role,
        cancel: &dyn Fn() -> bool,
    ) -> Event {
        let prob = Problem {
            base: self.base,
            settings: self.settings,
            param: self.param,
            period: p,
        };
        let mid = 0.5 * (from + to);
        let width = (to - from).abs();
        let opts = ContOptions::for_range(&self.settings, from, to);
        let seed = at.points.first().copied().unwrap_or(0.0);
        let branch = match continue_branch(&prob, from, to, seed, &opts, cancel) {
            Ok(b) => b,
            Err(e) => {
                return unresolved(
                    mid,
                    width,
                    format!("the P{p} cycle could not be continued: {e}"),
                );
            }
        };
        let first = branch.special.iter().find(|s| {
            s.kind != SpecialKind::End
                && (s.kind != SpecialKind::PeriodDoubling
                    || s.period == p
                    || branch.stop == Stop::Merged && 2 * s.period == p)
        });
        match first {
            Some(s) => special_event(&prob, &branch, s, opts.locate_tol, role),
            None => {
                let m = branch.points.last().map_or(f64::NAN, |q| q.multiplier);
                let why = match &branch.stop {
                    Stop::Reached => format!(
                        "the P{p} cycle goes on to the next column (m = {m:.4}) with no fold, flip or border, though the cell graph pairs it with nothing there"
                    ),
                    _ => format!("the P{p} cycle's branch {}", branch.stop_message()),
                };
                unresolved(mid, width, why)
            }
        }
    }

    /// The end of a set with no cycle (attractor `a` of `f`, at `from`):
    /// bisection on the cell graph towards `to` for where it stops having
    /// a partner.
    pub(super) fn set_end(
        &self,
        f: &Found,
        a: usize,
        from: f64,
        to: f64,
        role: Role,
        cancel: &dyn Fn() -> bool,
    ) -> Event {
        let mut lo = (from, f.clone(), a);
        let mut hi = to;
        let tol = LOCATE_TOL * from.abs().max(1.0);
        let chaotic = f.attractors[a].verdict == Verdict::Chaotic;
        while (hi - lo.0).abs() > tol {
            if cancel() {
                return unresolved(
                    0.5 * (from + to),
                    0.5 * (to - from).abs(),
                    "not located: cancelled".into(),
                );
            }
            let mid = 0.5 * (lo.0 + hi);
            let sim = match Simulator::new(self.param.set(&self.base, mid), self.settings) {
                Ok(s) => s,
                Err(e) => {
                    return unresolved(
                        mid,
                        (hi - lo.0).abs(),
                        format!("the bisection failed: {e}"),
                    );
                }
            };
            let here = match super::super::attractors(&sim, &self.cells, cancel) {
                Ok(h) => h,
                Err(e) => {
                    return unresolved(
                        mid,
                        (hi - lo.0).abs(),
                        format!("the cell graph failed in the bisection: {e}"),
                    );
                }
            };
            let ids = super::super::tracks::identify(&[Some(&lo.1), Some(&here)]);
            let track = ids.of[0].as_ref().and_then(|t| t.get(lo.2)).copied();
            let partner = ids.of[1]
                .as_ref()
                .and_then(|t| t.iter().position(|&x| Some(x) == track));
            match partner {
                Some(b) => lo = (mid, here, b),
                None => hi = mid,
            }
        }
        let (value, error) = (0.5 * (lo.0 + hi), 0.5 * (hi - lo.0).abs());
        let what = if role == Role::Start {
            "appears"
        } else {
            "vanishes"
        };
        let detail = format!(
            "the {} set {what} (located by bisection on the cell graph; the unstable cycle it meets is not named)",
            if chaotic {
                "chaotic"
            } else {
                "aperiodic (not proved chaotic)"
            },
        );
        if chaotic {
            Event {
                cause: Cause::Crisis,
                ..unresolved(value, error, detail)
            }
        } else {
            unresolved(value, error, detail)
        }
    }
}

/// The event a special point of a branch is, in words for `role`.
fn special_event(prob: &Problem, branch: &Branch, s: &SpecialPoint, tol: f64, role: Role) -> Event {
    let p = s.period;
    let mut e = Event {
        theta: Some(s.theta),
        period: Some(p),
        ..unresolved(s.lambda, tol, String::new())
    };
    let (born, gains) = match role {
        Role::Start => ("is born", "gains"),
        _ => ("vanishes", "loses"),
    };
    match s.kind {
        SpecialKind::Fold => {
            e.cause = Cause::Fold;
            e.detail = format!("the P{p} cycle {born} with an unstable one in a fold (m = +1)");
        }
        SpecialKind::PeriodDoubling => {
            let crit = match s.criticality_name() {
                "" => "undecided",
                c => c,
            };
            e.cause = Cause::Flip;
            e.criticality = Some(crit);
            e.detail = if 2 * p == branch.period {
                let born = if role == Role::Start {
                    "is born"
                } else {
                    "ends"
                };
                format!(
                    "the P{} {born} in the flip of the P{p} cycle, which the columns do not see as an attractor ({crit} flip)",
                    branch.period
                )
            } else if role == Role::Change {
                format!(
                    "the P{p} cycle's multiplier passes −1 and the P{} born in the flip is the track's ({crit} flip)",
                    2 * p
                )
            } else {
                format!(
                    "the P{p} cycle {gains} its stability as its multiplier passes −1 ({crit} flip)"
                )
            };
        }
        SpecialKind::Jump | SpecialKind::Border => border(prob, branch, s, role, &mut e),
        SpecialKind::End => {}
    }
    e
}

/// A border event `e` at the jump or border `s` of a branch, in words
/// for `role`: where λ turns (a non-smooth fold), where the cycle goes
/// on across a kink of f, or where it ends.
fn border(prob: &Problem, branch: &Branch, s: &SpecialPoint, role: Role, e: &mut Event) {
    let p = s.period;
    let (born, gains) = match role {
        Role::Start => ("is born", "gains"),
        _ => ("vanishes", "loses"),
    };
    e.cause = Cause::Border;
    let m = |v: Option<f64>| v.map_or("none".to_string(), |m| format!("{m:.4}"));
    if let Some(turn) = turn_at(branch, s) {
        // λ turns where m jumps over +1: the stable cycle meets
        // the unstable one at a kink of f (a non-smooth fold).
        e.multipliers = Some(turn.map(Some));
        e.border_type = Some("fold");
        e.detail = format!(
            "the P{p} cycle {born} with an unstable one where a point of them meets a kink of f (a non-smooth fold: m jumps from {} to {} without passing +1)",
            m(Some(turn[0])),
            m(Some(turn[1]))
        );
    } else if s.kind == SpecialKind::Jump {
        let sides = one_sided(prob, branch, s);
        e.multipliers = Some(sides);
        e.border_type = Some("persists");
        e.detail = format!(
            "a point of the P{p} cycle crosses a kink of f: the cycle goes on and {gains} its stability, multiplier {} below and {} above",
            m(sides[0]),
            m(sides[1])
        );
    } else {
        e.multipliers = Some(one_sided(prob, branch, s));
        e.border_type = Some("ends");
        let ends = if role == Role::Start {
            "begins"
        } else {
            "ends"
        };
        e.detail = format!(
            "the P{p} cycle {ends} where a point of it meets a border of f ({})",
            s.note
        );
    }
}

/// Where the branch turns in λ at the special point `s` (a jump of m):
/// the multipliers at the computed points next to it on its two sides,
/// first the side the branch came from. `None` where λ goes on.
fn turn_at(branch: &Branch, s: &SpecialPoint) -> Option<[f64; 2]> {
    let i = branch.points.iter().position(|q| q.lambda == s.lambda)?;
    let before = branch.points[..i]
        .iter()
        .rev()
        .find(|q| q.lambda != s.lambda)?;
    let after = branch.points[i..].iter().find(|q| q.lambda != s.lambda)?;
    let turns = (s.lambda - before.lambda) * (after.lambda - s.lambda) < 0.0;
    turns.then_some([before.multiplier, after.multiplier])
}

/// The multiplier of the cycle a hair (1e-8 relative) below and above a
/// border: Newton in θ at fixed λ on each side, from the branch's
/// nearest computed point on that side (on the smooth piece there).
fn one_sided(prob: &Problem, branch: &Branch, s: &SpecialPoint) -> [Option<f64>; 2] {
    let delta = 1e-8 * s.lambda.abs().max(1.0);
    [-1.0, 1.0].map(|side| {
        let lambda = s.lambda + side * delta;
        let nearest = branch
            .points
            .iter()
            .filter(|q| side * (q.lambda - s.lambda) > 0.5 * delta)
            .min_by(|a, b| {
                (a.lambda - s.lambda)
                    .abs()
                    .total_cmp(&(b.lambda - s.lambda).abs())
            })?;
        let mut theta = nearest.points.first().copied()?;
        let mut evals = 0;
        let tol = 10.0 * crate::sim::cycles::CycleOptions::for_settings(&prob.settings).tol;
        for _ in 0..20 {
            let e = prob.eval(theta, lambda, &mut evals).ok()?;
            let step = e.g / (e.multiplier - 1.0);
            if !step.is_finite() {
                return None;
            }
            theta -= step;
            if step.abs() < tol {
                return prob
                    .eval(theta, lambda, &mut evals)
                    .ok()
                    .map(|e| e.multiplier);
            }
        }
        None
    })
}
