//! A phase cell's neighbour's cycle (`super::super::capture`): solved
//! before the first iterate, then watched for the orbit converging onto it.

use super::super::capture::{Known, neighbour_options};
use super::{CellRun, CycleSolve, PhaseCell};

impl CellRun {
    /// Begins the solve of the neighbour's `p`-cycle from `seed` (a seed
    /// off the arc: none, the cell goes on alone).
    pub(super) fn begin_known(&mut self, seed: f64, p: usize) {
        let opts = neighbour_options(&self.cycle_opts);
        if let Ok(s) = CycleSolve::start(&self.sim, seed, p, &opts) {
            self.solving = Some((seed, p, s));
        }
    }

    /// The neighbour's cycle, once solved: kept if it is a genuine
    /// p-cycle that attracts.
    pub(super) fn take_known(&mut self) {
        if let Some((_, p, r)) = self.solved.pop() {
            self.known = Known::of(r.ok(), p);
        }
    }

    /// Whether the orbit is captured by the neighbour's cycle (the cell is
    /// then periodic on it): see `super::capture`.
    pub(super) fn captured(&mut self, cell: &mut PhaseCell) -> bool {
        let Some(known) = &self.known else {
            return false;
        };
        let n = 3 * known.period();
        if self.thetas.len() < n {
            return false;
        }
        let mut seq = self.thetas[self.thetas.len() - n..].to_vec();
        seq.push(self.theta);
        let Some(c) = known.captures(&seq, self.noise) else {
            return false;
        };
        cell.theta_last = c.points[0];
        self.periodic(cell, &c.points, c.lyapunov());
        true
    }
}
