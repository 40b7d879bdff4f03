//! A column's heavy pieces: the cycle solves it has due (a slow
//! contraction to confirm, a neighbour's slow cycle to continue), run one
//! map evaluation at a time so that a host on a slice of time can pause
//! them.

use super::{ColumnRun, SOLVE_COOLDOWN, Yield};
use crate::integrate::SolverSettings;
use crate::sim::Simulator;
use crate::sim::cycles::{Cycle, CycleOptions, CycleSolve, approaches};
use crate::sim::period::Contraction;

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

impl ColumnRun {
    /// Runs the cycle solve that is due or in flight, one map evaluation
    /// at a time, until it ends (true) or `yielding` asks for the thread
    /// back (false: the solve keeps its state and goes on at the next
    /// call, with the same iterates). At least one evaluation is made.
    pub(super) fn heavy_step(&mut self, sim: &Simulator, yielding: &dyn Yield) -> bool {
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
