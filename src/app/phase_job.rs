//! When the phase diagram is computed, and over what: the persisted grid
//! choice (range, resolution, budget, zoom stack) and the rule that a grid
//! runs only while its view is shown, or after an explicit Compute. A grid
//! keeps both cores busy for seconds (30 × 30) to minutes (200 × 200), so it
//! is not computed for a view nobody looks at: hiding the view stops the
//! job, showing it again starts it afresh.

use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, PI};

use super::accuracy::JobKind;
use super::settings::Settings;
use crate::integrate::SolverSettings;

/// Quiet time after the last change of γ, ν, Ω, the solver, the resolution or
/// the budget before the grid restarts (seconds), as for the sweep.
pub const PHASE_DEBOUNCE: f64 = 0.25;
/// The grid resolution the view offers, per axis.
pub const MIN_STEPS: usize = 2;
pub const MAX_STEPS: usize = 200;
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

    /// Finite, increasing ends, θν within [−π, π] and κ within the model's
    /// [1e-6, 1e6].
    pub fn is_valid(&self) -> bool {
        let (t0, t1) = self.theta_nu;
        let (k0, k1) = self.kappa;
        t0.is_finite()
            && t1.is_finite()
            && -PI <= t0
            && t0 < t1
            && t1 <= PI
            && k0.is_finite()
            && k1.is_finite()
            && 1e-6 <= k0
            && k0 < k1
            && k1 <= 1e6
    }
}

/// What the phase view remembers between runs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct PhaseSettings {
    /// θν columns and κ rows of the grid (each 2 … 200).
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
        if !self.range.is_valid() {
            self.range = d.range;
            self.zoom.clear();
        }
        self.zoom.retain(PhaseRange::is_valid);
        self
    }
}

/// Everything a phase grid depends on (κ and θν are its axes, so the
/// sliders' κ and θν are not in it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseKey {
    pub gamma: f64,
    pub nu: f64,
    pub omega: f64,
    pub solver: SolverSettings,
    pub range: PhaseRange,
    /// (θν columns, κ rows).
    pub steps: (usize, usize),
    pub transient: usize,
    pub keep: usize,
}

impl PhaseKey {
    pub fn of(s: &Settings) -> Self {
        let p = &s.phase;
        PhaseKey {
            gamma: s.params.gamma,
            nu: s.params.nu,
            omega: s.params.omega,
            solver: s.solver_for(JobKind::Phase),
            range: p.current(),
            steps: (p.theta_nu_steps, p.kappa_steps),
            transient: p.transient,
            keep: p.keep,
        }
    }

    /// Whether only the range differs (a zoom: recompute at once).
    fn same_but_range(&self, other: &PhaseKey) -> bool {
        PhaseKey {
            range: other.range,
            ..*self
        } == *other
    }
}

/// What the window should do about the phase job this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PhaseStep {
    Nothing,
    /// Start a grid for the current key.
    Start,
    /// Stop the running grid (its view was hidden).
    Cancel,
    /// A change is waiting for its debounce: look again after this long.
    WaitFor(f64),
}

/// The phase job's runtime state (not persisted).
#[derive(Clone, Debug, Default)]
pub struct PhaseJob {
    /// What the running or last grid was started with; `None` before the
    /// first and after a pause, so that showing the view starts one.
    pub sent: Option<PhaseKey>,
    changed_at: Option<f64>,
    /// Started with Compute: keeps running while the view is hidden.
    pub pinned: bool,
    /// Stopped with Stop: not restarted until something changes.
    pub stopped: bool,
}

impl PhaseJob {
    /// Decides, from the settings' `key`, whether the view is `visible` and
    /// whether a grid is `running`, at time `now` (seconds).
    pub fn step(&mut self, key: PhaseKey, visible: bool, running: bool, now: f64) -> PhaseStep {
        if !running {
            // Compute keeps one grid going, not every later one.
            self.pinned = false;
        }
        if running && !visible && !self.pinned {
            self.sent = None;
            self.changed_at = None;
            return PhaseStep::Cancel;
        }
        if self.sent == Some(key) {
            self.changed_at = None;
            return PhaseStep::Nothing;
        }
        if !(visible || self.pinned) {
            return PhaseStep::Nothing;
        }
        match self.sent {
            None => PhaseStep::Start,
            Some(old) if old.same_but_range(&key) => PhaseStep::Start,
            Some(_) => {
                let since = *self.changed_at.get_or_insert(now);
                if now - since >= PHASE_DEBOUNCE {
                    PhaseStep::Start
                } else {
                    PhaseStep::WaitFor(PHASE_DEBOUNCE - (now - since))
                }
            }
        }
    }

    /// A grid for `key` was sent.
    pub fn started(&mut self, key: PhaseKey) {
        self.sent = Some(key);
        self.changed_at = None;
        self.stopped = false;
    }

    /// The user stopped the grid: it stays stopped until the key changes.
    pub fn stop(&mut self) {
        self.pinned = false;
        self.stopped = true;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(gamma: f64) -> PhaseKey {
        let mut s = Settings::default();
        s.params.gamma = gamma;
        PhaseKey::of(&s)
    }

    #[test]
    fn a_grid_runs_only_while_shown_unless_pinned() {
        let mut j = PhaseJob::default();
        assert_eq!(j.step(key(6.5), false, false, 0.0), PhaseStep::Nothing);
        assert_eq!(j.step(key(6.5), true, false, 0.1), PhaseStep::Start);
        j.started(key(6.5));
        assert_eq!(j.step(key(6.5), true, true, 0.2), PhaseStep::Nothing);
        // Hidden while running: paused, and started again when shown.
        assert_eq!(j.step(key(6.5), false, true, 0.3), PhaseStep::Cancel);
        assert_eq!(j.step(key(6.5), false, false, 0.4), PhaseStep::Nothing);
        assert_eq!(j.step(key(6.5), true, false, 0.5), PhaseStep::Start);
        j.started(key(6.5));
        // Pinned (Compute): goes on while hidden, until it ends.
        j.pinned = true;
        assert_eq!(j.step(key(6.5), false, true, 0.6), PhaseStep::Nothing);
        assert_eq!(j.step(key(6.5), false, false, 0.7), PhaseStep::Nothing);
        assert!(!j.pinned);
        // A new γ waits for the debounce, a zoom does not.
        assert_eq!(j.step(key(6.0), true, false, 1.0), PhaseStep::WaitFor(0.25));
        assert_eq!(j.step(key(6.0), true, false, 1.3), PhaseStep::Start);
        j.started(key(6.0));
        let mut zoomed = key(6.0);
        zoomed.range.kappa = (10.0, 20.0);
        assert_eq!(j.step(zoomed, true, false, 1.4), PhaseStep::Start);
        // Stopped: stays stopped for the same key.
        j.started(zoomed);
        j.stop();
        assert_eq!(j.step(zoomed, true, false, 1.5), PhaseStep::Nothing);
    }

    #[test]
    fn saved_settings_are_brought_into_range() {
        let s = PhaseSettings {
            theta_nu_steps: 0,
            kappa_steps: 100_000,
            transient: 10_000_000,
            keep: 2,
            range: PhaseRange {
                theta_nu: (0.0, f64::NAN),
                kappa: (-1.0, 5.0),
            },
            zoom: vec![PhaseRange {
                theta_nu: (1.0, 0.5),
                kappa: (1.0, 2.0),
            }],
        }
        .sanitised();
        assert_eq!((s.theta_nu_steps, s.kappa_steps), (MIN_STEPS, MAX_STEPS));
        assert_eq!((s.transient, s.keep), (MAX_BUDGET, 16));
        assert_eq!(s.range, PhaseRange::PAPER);
        assert!(s.zoom.is_empty());
    }
}
