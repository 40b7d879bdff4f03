//! The sweeps' grids as the window remembers them: the phase diagram's
//! (θν, κ) grid with its zoom levels, and the Basins view's θν columns.

use serde::{Deserialize, Serialize};

use std::f64::consts::{FRAC_PI_2, PI};

use super::{MAX_SWEEP_SEEDS, MAX_ZOOM_LEVELS, Settings, is_usable_range};
use crate::model::KAPPA_RANGE;

/// The grid resolution the view offers, per axis.
pub const MIN_STEPS: usize = 2;
pub const MAX_STEPS: usize = 512;
/// The most iterates per cell the view offers (transient, keep).
pub const MAX_BUDGET: usize = 5000;

/// A (θν, κ) rectangle: the grid's ends, included.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PhaseRange {
    pub theta_nu: (f64, f64),
    pub kappa: (f64, f64),
}

impl PhaseRange {
    /// The paper's Fig. 4: θν ∈ [0, π/2], κ ∈ [1, 42].
    pub const PAPER: PhaseRange = PhaseRange {
        theta_nu: (0.0, FRAC_PI_2),
        kappa: (1.0, 42.0),
    };

    /// Finite, increasing ends ([`is_usable_range`]: not narrower than
    /// 1e-12 of their size), θν within [−π, π] and κ within the model's
    /// [`KAPPA_RANGE`].
    pub fn is_valid(&self) -> bool {
        let (t0, t1) = self.theta_nu;
        let (k0, k1) = self.kappa;
        is_usable_range(self.theta_nu)
            && -PI <= t0
            && t1 <= PI
            && is_usable_range(self.kappa)
            && KAPPA_RANGE.contains(&k0)
            && KAPPA_RANGE.contains(&k1)
    }
}

/// What the phase view remembers between runs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct PhaseSettings {
    /// θν columns and κ rows of the grid (each 2 … 512).
    pub theta_nu_steps: usize,
    pub kappa_steps: usize,
    /// The cell's budget: the most iterates looking for a period, then the
    /// most with f'(θ) for λ (`oneblock phase --transient/--keep`).
    pub transient: usize,
    pub keep: usize,
    /// The whole (unzoomed) range.
    pub range: PhaseRange,
    /// Zoom levels, innermost last; each is recomputed at full resolution.
    pub zoom: Vec<PhaseRange>,
    /// θ₀ spread over each cell's exit arc whose attractors are counted
    /// (`oneblock phase --seeds`, at most [`MAX_SWEEP_SEEDS`]; 0: none).
    pub seeds: usize,
}

impl Default for PhaseSettings {
    fn default() -> Self {
        PhaseSettings {
            theta_nu_steps: 30,
            kappa_steps: 30,
            transient: 400,
            keep: 128,
            range: PhaseRange::PAPER,
            zoom: Vec::new(),
            seeds: 0,
        }
    }
}

impl PhaseSettings {
    /// The range the grid covers now: the innermost zoom, or the whole.
    pub fn current(&self) -> PhaseRange {
        self.zoom.last().copied().unwrap_or(self.range)
    }

    /// The same settings brought into the ranges the view offers (a saved
    /// file may hold anything).
    pub fn sanitised(mut self) -> Self {
        let d = PhaseSettings::default();
        self.theta_nu_steps = self.theta_nu_steps.clamp(MIN_STEPS, MAX_STEPS);
        self.kappa_steps = self.kappa_steps.clamp(MIN_STEPS, MAX_STEPS);
        self.transient = self.transient.min(MAX_BUDGET);
        self.keep = self.keep.clamp(16, MAX_BUDGET);
        self.seeds = self.seeds.min(MAX_SWEEP_SEEDS);
        if !self.range.is_valid() {
            self.range = d.range;
            self.zoom.clear();
        }
        self.zoom.retain(PhaseRange::is_valid);
        self.zoom.truncate(MAX_ZOOM_LEVELS);
        self
    }
}

/// The fewest and most columns the view offers.
pub const MIN_COLUMNS: usize = 2;
pub const MAX_COLUMNS: usize = 400;

/// What the Basins view remembers between runs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct BasinsSettings {
    /// θν columns ([`MIN_COLUMNS`] … [`MAX_COLUMNS`]).
    pub columns: usize,
    /// The zoomed θν ranges, innermost last (empty: the diagram's range).
    pub zoom: Vec<(f64, f64)>,
}

impl Default for BasinsSettings {
    fn default() -> Self {
        BasinsSettings {
            columns: 48,
            zoom: Vec::new(),
        }
    }
}

impl BasinsSettings {
    /// Columns within the view's bounds; each zoom level a usable θν range
    /// inside [−π, π], its ends in order, at most [`MAX_ZOOM_LEVELS`] of
    /// them (a session or the saved state may hold anything: θν ± 100
    /// drew columns 2π apart as different attractors).
    pub fn sanitised(mut self) -> Self {
        use std::f64::consts::PI;
        self.columns = self.columns.clamp(MIN_COLUMNS, MAX_COLUMNS);
        self.zoom
            .retain(|&(a, b)| is_usable_range((a, b)) && a < b && a >= -PI && b <= PI);
        self.zoom.truncate(MAX_ZOOM_LEVELS);
        self
    }

    /// The θν range computed: the innermost usable zoom, else the
    /// bifurcation diagram's whole range.
    pub fn range(&self, s: &Settings) -> (f64, f64) {
        match self.zoom.last() {
            Some(&r) if is_usable_range(r) => r,
            _ => s.theta_nu_range(),
        }
    }
}
