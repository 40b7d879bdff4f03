//! A neighbour's cycle, solved first: a cell whose finished neighbour was
//! periodic solves that cycle at its own (θν, κ) by Newton's method before
//! it iterates (a few map evaluations: the cycle moves little from one cell
//! to the next). The cell's orbit still starts where a cell computed alone
//! starts (θ = θν), so that its class is the attractor that orbit reaches,
//! not the branch the neighbour was on (two attractors coexist in the
//! hysteresis ranges): the solved cycle only lets the cell stop as soon as
//! its orbit is seen converging onto it ([`Known::captures`]), instead of
//! waiting for the period test's window. Where the solve fails, finds a
//! shorter cycle, or a cycle that does not attract, the cell is classified
//! by its orbit alone, as if it had no neighbour.

use crate::model::wrap_angle;
use crate::sim::cycles::{Cycle, CycleOptions, approaches};

/// The Newton budget of a neighbour's cycle: from so near a start a
/// solve that converges does so in two or three steps, and one that does
/// not should cost little.
pub(super) fn neighbour_options(classifier: &CycleOptions) -> CycleOptions {
    CycleOptions {
        max_iter: 5,
        max_halvings: 4,
        ..*classifier
    }
}

/// The farthest the newest onset may be from the known cycle for the
/// cell to be captured by it, in radians: well inside the basin of any
/// cycle the paper's grids show, and still within the linear range of
/// the map about it (the approach is checked too).
pub(super) const CAPTURE_DISTANCE: f64 = 1e-2;

/// The neighbour's cycle solved at this cell: a genuine p-cycle that
/// attracts.
pub(super) struct Known {
    cycle: Cycle,
}

impl Known {
    /// The cycle's period.
    pub(super) fn period(&self) -> usize {
        self.cycle.period()
    }

    /// The solve's result when it is a cycle of the neighbour's period
    /// `p` (not a shorter one) that attracts.
    pub(super) fn of(solved: Option<Cycle>, p: usize) -> Option<Self> {
        solved
            .filter(|c| c.minimal_period == p && c.stable)
            .map(|cycle| Known { cycle })
    }

    /// The cycle, its point 0 in the phase of `seq`'s newest value, when
    /// `seq` (the orbit's recent onsets, the next onset last) is captured
    /// by it: the newest value within [`CAPTURE_DISTANCE`] of a point of
    /// the cycle and the orbit approaching it ([`approaches`], as a solved
    /// contraction is confirmed). `noise`: the map's own error.
    pub(super) fn captures(&self, seq: &[f64], noise: f64) -> Option<Cycle> {
        let newest = *seq.last()?;
        let pts = &self.cycle.points;
        let (j, d) = pts
            .iter()
            .map(|&x| wrap_angle(newest - x).abs())
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(&b.1))?;
        if d > CAPTURE_DISTANCE {
            return None;
        }
        let mut rotated = self.cycle.clone();
        rotated.points.rotate_left(j);
        approaches(&rotated, seq, noise).then_some(rotated)
    }
}
