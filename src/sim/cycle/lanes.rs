//! Cycles in lanes, up to three at a time: while several slips are in
//! flight, the stages of their steps are computed together, stage by
//! stage, so that one slip's chain of dependent right-hand-side evaluations
//! fills the cycles the others leave idle. One slip's step waits on a chain
//! of ~120 cycles per evaluation (sqrt, e^x − 1, sin/cos); the CPU has the
//! units to run two or three such chains side by side (docs/performance.md,
//! "Slips in lanes").
//!
//! For work made of independent cycles: f'(θ)'s central difference, the
//! return map's graph, the sample's reference cycles, a bifurcation sweep's
//! columns (`sim::sweep::run_columns`). Every cycle's result is bitwise what
//! [`Simulator::cycle`] gives for it.

use super::slip::{Counted, Next, SlipRun};
use super::{SimError, Simulator, SlipEvent};
use crate::integrate::{LaneAttempt, Method, Solver, State};
use crate::model::point_from_theta;

/// One cycle to compute: the simulator (parameters and solver settings),
/// the onset θ and the onset time.
pub type Task<'s> = (&'s Simulator, f64, f64);

/// A cycle in flight on one of the lanes.
struct InFlight<'s> {
    sim: &'s Simulator,
    theta: f64,
    onset: [f64; 2],
    onset_time: f64,
    run: SlipRun<'s>,
}

/// Computes cycles on [`LANES`] lanes until all run dry. `feed(lane,
/// result)` is called with `None` once per lane to get its first task, then
/// with each finished cycle's result on that lane, and returns the lane's
/// next task (the next iterate of an orbit, say) or `None` to retire the
/// lane. Lanes whose partners have retired go on together, or alone.
pub fn run_lanes<'s>(
    mut feed: impl FnMut(usize, Option<Result<SlipEvent, SimError>>) -> Option<Task<'s>>,
) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked just above).
        return unsafe { run_lanes_avx2(&mut feed) };
    }
    run_lanes_impl(&mut feed)
}

/// The same code compiled with AVX2, as single slips are
/// (`Simulator::slip`); no FMA, so the results are the same.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn run_lanes_avx2<'s>(
    feed: &mut impl FnMut(usize, Option<Result<SlipEvent, SimError>>) -> Option<Task<'s>>,
) {
    run_lanes_impl(feed)
}

/// How many slips are stepped together. Three: on the 200 committed points
/// of each chaotic attractor three lanes took 11–13 % less time per iterate
/// than two, and four 4–9 % more than three (more live registers than the
/// CPU has); on an older host three measured the same as two
/// (docs/performance.md).
pub const LANES: usize = 3;

#[inline(always)]
fn run_lanes_impl<'s>(
    feed: &mut impl FnMut(usize, Option<Result<SlipEvent, SimError>>) -> Option<Task<'s>>,
) {
    let mut lanes: [Option<InFlight<'s>>; LANES] = std::array::from_fn(|_| None);
    for (i, lane) in lanes.iter_mut().enumerate() {
        *lane = launch(i, None, feed);
    }
    // The attempt each lane asks for this round.
    let mut h: [Option<f64>; LANES] = [None; LANES];
    while lanes.iter().any(Option::is_some) {
        for i in 0..LANES {
            h[i] = None;
            // A lane whose cycle ends here takes its next task at once.
            while let Some(c) = &mut lanes[i] {
                match c.run.prepare(None) {
                    Ok(Next::Attempt(hi)) => {
                        h[i] = Some(hi);
                        break;
                    }
                    Ok(Next::Done(end)) => {
                        let ev = c.sim.complete(c.theta, c.onset, c.onset_time, &end, None);
                        lanes[i] = launch(i, Some(Ok(ev)), feed);
                    }
                    Err(e) => lanes[i] = launch(i, Some(Err(e)), feed),
                }
            }
        }
        let y_new = lanes_stages(&mut lanes, &h);
        for i in 0..LANES {
            let (Some(c), Some(hi), Some(y)) = (&mut lanes[i], h[i], &y_new[i]) else {
                continue;
            };
            match c.run.finish(y, hi, None) {
                Ok(None) => {}
                Ok(Some(end)) => {
                    let ev = c.sim.complete(c.theta, c.onset, c.onset_time, &end, None);
                    lanes[i] = launch(i, Some(Ok(ev)), feed);
                }
                Err(e) => lanes[i] = launch(i, Some(Err(e)), feed),
            }
        }
    }
}

/// The stages of each lane's attempt: computed together for the lanes that
/// have one and run the same adaptive method (all of them, or any two),
/// alone otherwise.
#[inline(always)]
fn lanes_stages(
    lanes: &mut [Option<InFlight<'_>>; LANES],
    h: &[Option<f64>; LANES],
) -> [Option<State>; LANES] {
    let mut out = [None; LANES];
    for method in [Method::Dop853, Method::Dp54] {
        let mut ready = [0; LANES];
        let mut n = 0;
        for i in 0..LANES {
            if let (Some(c), Some(_)) = (&lanes[i], h[i])
                && c.sim.settings().method == method
            {
                ready[n] = i;
                n += 1;
            }
        }
        if n == LANES {
            let mut i = 0;
            let attempts = lanes.each_mut().map(|c| {
                let a = attempt(c, h[i]);
                i += 1;
                a.expect("every lane is in flight")
            });
            return Solver::stages_lanes(attempts).map(Some);
        }
        if n >= 2 {
            let (i, j) = (ready[0], ready[1]);
            if let Ok([a, b]) = lanes.get_disjoint_mut([i, j])
                && let (Some(a), Some(b)) = (attempt(a, h[i]), attempt(b, h[j]))
            {
                let [ya, yb] = Solver::stages_lanes([a, b]);
                (out[i], out[j]) = (Some(ya), Some(yb));
            }
        }
    }
    for i in 0..LANES {
        if out[i].is_none()
            && let (Some(c), Some(hi)) = (&mut lanes[i], h[i])
        {
            out[i] = Some(c.run.stages(hi));
        }
    }
    out
}

/// A lane's attempt (only lanes in flight with an attempt are asked).
#[inline(always)]
fn attempt<'a>(
    c: &'a mut Option<InFlight<'_>>,
    h: Option<f64>,
) -> Option<LaneAttempt<'a, Counted<'a>>> {
    let h = h.unwrap_or_default();
    c.as_mut().map(|c| c.run.attempt(h))
}

/// Hands `result` to the feed and starts the lane's next cycle; a task the
/// model rejects at once (an onset off the exit arc, a step too large) is
/// answered at once too.
fn launch<'s>(
    lane: usize,
    mut result: Option<Result<SlipEvent, SimError>>,
    feed: &mut impl FnMut(usize, Option<Result<SlipEvent, SimError>>) -> Option<Task<'s>>,
) -> Option<InFlight<'s>> {
    loop {
        let (sim, theta, onset_time) = feed(lane, result.take())?;
        let started = sim.check_onset(theta).and_then(|()| {
            let onset = point_from_theta(sim.params().kappa, theta);
            SlipRun::start(sim, theta, onset, onset_time, None).map(|run| (onset, run))
        });
        match started {
            Ok((onset, run)) => {
                return Some(InFlight {
                    sim,
                    theta,
                    onset,
                    onset_time,
                    run,
                });
            }
            Err(e) => result = Some(Err(e)),
        }
    }
}

/// Two cycles computed together.
pub fn cycle_pair<'s>(tasks: [Task<'s>; 2]) -> [Result<SlipEvent, SimError>; 2] {
    let mut out = [None, None];
    run_in_order(&tasks, &mut out);
    out.map(|r| r.expect("run_lanes answers every task it is given"))
}

/// The cycle of each task, computed in lanes; the results in the tasks'
/// order.
pub fn cycles_in_lanes<'s>(tasks: &[Task<'s>]) -> Vec<Result<SlipEvent, SimError>> {
    let mut out: Vec<_> = (0..tasks.len()).map(|_| None).collect();
    run_in_order(tasks, &mut out);
    out.into_iter()
        .map(|r| r.expect("run_lanes answers every task it is given"))
        .collect()
}

/// Runs `tasks` on the lanes, each result into `out` at its task's index.
fn run_in_order<'s>(tasks: &[Task<'s>], out: &mut [Option<Result<SlipEvent, SimError>>]) {
    let mut next = 0;
    let mut working = [usize::MAX; LANES];
    run_lanes(|lane, result| {
        if let Some(r) = result {
            out[working[lane]] = Some(r);
        }
        let task = tasks.get(next)?;
        working[lane] = next;
        next += 1;
        Some(*task)
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::SolverSettings;
    use crate::model::Params;
    use crate::numerics::fixed_sample;

    /// In lanes or alone, every cycle comes out bitwise the same: over the
    /// committed chaotic and intermittent points, with lanes on different
    /// parameters and methods (DOP853 and DP5(4) lanes step with their own
    /// kind; RK4 runs alone), and
    /// with tasks the model rejects (off the exit arc) in between.
    #[test]
    fn cycles_in_lanes_are_bitwise_the_cycles_alone() {
        let p = |kappa, nu, theta_nu| Params {
            kappa,
            gamma: 6.5,
            nu,
            theta_nu,
            omega: 50.0,
        };
        let dop = SolverSettings::adaptive(Method::Dop853, 1e-9);
        let dp54 = SolverSettings::adaptive(Method::Dp54, 1e-8);
        let sims = [
            Simulator::new(p(18.95, 1e-3, 1.25), dop).expect("valid"),
            Simulator::new(p(50.0, 1e-4, 1.4), dop).expect("valid"),
            Simulator::new(p(18.95, 1e-3, 1.25), dp54).expect("valid"),
            Simulator::new(p(50.0, 1e-4, 1.4), dp54).expect("valid"),
            Simulator::new(
                p(18.95, 1e-3, 1.25),
                SolverSettings::fixed(Method::Rk4, 0.01),
            )
            .expect("valid"),
        ];
        let mut tasks: Vec<Task> = Vec::new();
        for i in 0..60 {
            tasks.push((&sims[0], fixed_sample::CHAOS[i], i as f64));
            tasks.push((&sims[1], fixed_sample::INTERMITTENT[i], 0.0));
            // Runs of DP5(4) tasks, so that its lanes step together too.
            if i % 3 != 0 {
                tasks.push((&sims[3], fixed_sample::INTERMITTENT[i], 0.0));
                tasks.push((&sims[2], fixed_sample::CHAOS[i], 0.0));
            }
            if i % 11 == 0 {
                tasks.push((&sims[4], fixed_sample::CHAOS[i], 0.0));
            }
            if i % 7 == 0 {
                tasks.push((&sims[2], fixed_sample::CHAOS[i], 0.0));
                // Off the exit arc: an error at once.
                tasks.push((&sims[0], fixed_sample::CHAOS[i] + std::f64::consts::PI, 0.0));
            }
        }
        let in_lanes = cycles_in_lanes(&tasks);
        assert_eq!(in_lanes.len(), tasks.len());
        let mut errors = 0;
        for (&(sim, theta, t0), got) in tasks.iter().zip(&in_lanes) {
            let alone = sim.cycle(theta, t0, None);
            assert_eq!(format!("{got:?}"), format!("{alone:?}"), "θ = {theta}");
            errors += usize::from(alone.is_err());
        }
        assert_eq!(errors, 9, "the off-arc tasks, and only they, fail");
    }
}
