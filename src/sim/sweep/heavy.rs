//! A column's heavy pieces: the cycle solves it has due (a slow
//! contraction to confirm, a neighbour's slow cycle to continue), run one
//! map evaluation at a time, and its turn to the interpolant (the build,
//! then the rest of its points), in the build's pieces, so that a host on a
//! slice of time can pause them.

use super::{ColumnRun, SOLVE_COOLDOWN, Yield};
use crate::integrate::SolverSettings;
use crate::sim::cycles::{Cycle, CycleOptions, CycleSolve, approaches};
use crate::sim::interpolant::{InterpolantOptions, MapUsed, Stepper, StepperBuild};
use crate::sim::period::Contraction;
use crate::sim::{SimError, Simulator};

/// The settings slow cycles are solved with (see the module notes).
fn solve_settings(settings: &SolverSettings) -> SolverSettings {
    if settings.method.is_adaptive() && settings.rtol > 1e-10 {
        SolverSettings {
            rtol: 1e-10,
            atol: 1e-10,
            ..*settings
        }
    } else {
        *settings
    }
}

/// A cycle solve a column has due: milliseconds of work in one piece, which
/// a host that wants its thread back soon may put off to its next step
/// ([`Yield::defer_heavy`]).
#[derive(Clone, Copy, Debug)]
pub(super) enum Heavy {
    /// The neighbour's slow cycle, of this period, from the first onset.
    Handover(usize),
    /// The slow contraction just seen, to be solved and confirmed.
    Contraction(Contraction),
}

impl Heavy {
    /// The period solved for.
    fn period(self) -> usize {
        match self {
            Heavy::Handover(p) => p,
            Heavy::Contraction(c) => c.period,
        }
    }
}

/// A column's cycle solve under way: at the solve settings (see the module
/// notes), with [`CycleOptions::for_classifier`]'s budget.
pub(super) struct Solving {
    heavy: Heavy,
    accurate: Simulator,
    solve: CycleSolve,
}

impl Solving {
    /// `None` where no solve can start (the accurate simulator or the seed
    /// refused): no genuine cycle, at no cost.
    fn start(sim: &Simulator, heavy: Heavy, seed: f64, p: usize) -> Option<Self> {
        let settings = solve_settings(sim.settings());
        let accurate = Simulator::new(*sim.params(), settings).ok()?;
        let opts = CycleOptions::for_classifier(&settings);
        let solve = CycleSolve::start(&accurate, seed, p, &opts).ok()?;
        Some(Solving {
            heavy,
            accurate,
            solve,
        })
    }
}

/// A column's turn to the interpolant under way.
pub(super) enum Tabled {
    /// Its interpolant being built.
    Building(StepperBuild),
    /// The rest of its points from it.
    Iterating(Stepper),
}

/// Iterates on the interpolant between two questions to the host (an
/// extension's piece, or an integrated iterate, asks at once).
const TABLED_ITERATES: usize = 64;

impl ColumnRun {
    /// Runs the heavy work due or in flight (a cycle solve, then the turn
    /// to the interpolant) until it ends (true) or `yielding` asks for the
    /// thread back (false: the work keeps its state and goes on at the next
    /// call, with the same iterates). `cancel` is polled as the iterates on
    /// the interpolant go, once every 4096.
    pub(super) fn heavy_step(
        &mut self,
        sim: &Simulator,
        yielding: &dyn Yield,
        cancel: &dyn Fn() -> bool,
    ) -> bool {
        self.solve_step(sim, yielding) && self.tabled_step(sim, yielding, cancel)
    }

    /// Runs the cycle solve that is due or in flight, one map evaluation
    /// at a time, until it ends (true) or `yielding` asks for the thread
    /// back (false). At least one evaluation is made.
    fn solve_step(&mut self, sim: &Simulator, yielding: &dyn Yield) -> bool {
        if self.solving.is_none() {
            let Some(heavy) = self.heavy.take() else {
                return true;
            };
            let (seed, p) = match heavy {
                Heavy::Handover(p) => (self.onsets[0], p),
                Heavy::Contraction(c) => (c.limit, c.period),
            };
            match Solving::start(sim, heavy, seed, p) {
                Some(s) => self.solving = Some(Box::new(s)),
                None => {
                    self.solved(heavy, None);
                    return true;
                }
            }
        }
        loop {
            let Some(s) = self.solving.as_mut() else {
                return true;
            };
            if let Some(r) = s.solve.advance(&s.accurate) {
                let heavy = s.heavy;
                self.col.rhs_evals += s.solve.spent().1;
                self.solving = None;
                self.solved(heavy, r.ok().filter(|c| c.minimal_period == heavy.period()));
                return true;
            }
            if yielding.pause() {
                return false;
            }
        }
    }

    /// What the solved cycle (`None`: not a genuine cycle of the period)
    /// does to the column: it follows a stable handed-over cycle, or a
    /// confirmed contraction; an unconfirmed contraction waits a while.
    fn solved(&mut self, heavy: Heavy, cycle: Option<Cycle>) {
        match heavy {
            Heavy::Handover(_) => {
                if let Some(cycle) = cycle
                    && cycle.stable
                {
                    self.follow(&cycle);
                }
            }
            Heavy::Contraction(_) => {
                let confirmed =
                    cycle.filter(|cy| cy.stable && approaches(cy, &self.onsets, self.rep_tol));
                match confirmed {
                    Some(cycle) => self.follow(&cycle),
                    None => {
                        self.solves_left -= 1;
                        self.next_solve = self.len() + SOLVE_COOLDOWN;
                    }
                }
                self.end_cycle();
            }
        }
    }
}

impl ColumnRun {
    /// The column's turn to the interpolant, when due: the interpolant
    /// built over the range of its recent onsets, one piece of the build
    /// at a time, then the rest of the column from it. On a refusal
    /// nothing changes but the column's `map`, and it goes on integrating.
    /// True once there is nothing (more) to do; false when `yielding`
    /// asked for the thread back.
    fn tabled_step(
        &mut self,
        sim: &Simulator,
        yielding: &dyn Yield,
        cancel: &dyn Fn() -> bool,
    ) -> bool {
        if self.tabled.is_none() {
            if !std::mem::take(&mut self.switch_due) || self.done {
                return true;
            }
            let recent = &self.onsets[self.onsets.len().saturating_sub(300)..];
            // A refusal may cost up to twice what the kept points would have.
            let iopts = InterpolantOptions {
                max_evaluations: self.total.saturating_sub(self.transient).saturating_mul(2),
                ..InterpolantOptions::for_settings(sim.settings())
            };
            match StepperBuild::over(sim, recent, iopts) {
                Ok(build) => self.tabled = Some(Box::new(Tabled::Building(build))),
                Err(e) => {
                    self.col.map = MapUsed::Refused(e.to_string());
                    return true;
                }
            }
        }
        loop {
            let Some(tabled) = self.tabled.take() else {
                return true;
            };
            let more = match *tabled {
                Tabled::Building(build) => self.build_piece(build),
                Tabled::Iterating(st) => self.iterate_piece(st, cancel),
            };
            if !more {
                return true;
            }
            if yielding.pause() {
                return false;
            }
        }
    }

    /// One piece of the interpolant's build; whether there is more to do.
    fn build_piece(&mut self, mut build: StepperBuild) -> bool {
        match build.advance() {
            Ok(done) => {
                let next = if done {
                    self.col.rhs_evals += build.spent().1;
                    Tabled::Iterating(build.finish())
                } else {
                    Tabled::Building(build)
                };
                self.tabled = Some(Box::new(next));
                true
            }
            Err(e) => {
                self.col.rhs_evals += build.spent().1;
                self.col.map = MapUsed::Refused(e.to_string());
                false
            }
        }
    }

    /// Up to [`TABLED_ITERATES`] of the column's points from the
    /// interpolant (fewer when a piece of an extension was made); whether
    /// there is more to do. `cancel` is polled before every 4096th point,
    /// once even across a pause.
    fn iterate_piece(&mut self, mut st: Stepper, cancel: &dyn Fn() -> bool) -> bool {
        for _ in 0..TABLED_ITERATES {
            if self.len() > self.total {
                return self.tabled_end(st);
            }
            if self.len().is_multiple_of(4096) && self.polled != self.len() {
                self.polled = self.len();
                if cancel() {
                    self.col.error = Some(SimError::Cancelled);
                    return self.tabled_end(st);
                }
            }
            let theta = self.onsets[self.onsets.len() - 1];
            match st.next_piece(theta) {
                Ok(Some(next)) => self.onsets.push(next),
                // A piece of an extension: the host is asked at once.
                Ok(None) => break,
                Err(e) => {
                    let i = self.len() - 1;
                    self.col.error = Some(e);
                    self.col.thetas = self.span(self.transient.min(i), i).to_vec();
                    return self.tabled_end(st);
                }
            }
        }
        self.tabled = Some(Box::new(Tabled::Iterating(st)));
        true
    }

    /// The column complete on the interpolant (or stopped on it): its cost
    /// and how it used the interpolant.
    fn tabled_end(&mut self, mut st: Stepper) -> bool {
        self.col.rhs_evals += st.take_cost().1;
        self.col.map = MapUsed::Interpolant(st.summary());
        self.done = true;
        false
    }
}
