//! When a job restarts: the keys that say what a running sweep or phase
//! grid was started with, the debounces, and the phase grid's rule that it
//! runs only while its view is shown, or after an explicit Compute. A grid
//! keeps both cores busy for seconds (30 × 30) to minutes (200 × 200), so it
//! is not computed for a view nobody looks at: hiding the view stops the
//! job, showing it again starts it afresh.

use super::super::settings::{PhaseRange, Settings};
use super::kind::JobKind;
use crate::integrate::SolverSettings;
use crate::jobs::ParamsKey;
use crate::sim::continuation::ContParam;

/// While θν plays, the orbit restarts once the last one is finished (its
/// trajectory and its analysis), or after this long (seconds): each view
/// shows the latest finished result meanwhile, never an empty plot.
pub const PLAY_HOLD: f64 = 1.0;
/// While θν plays, the trajectory runs at most this many slip cycles: the
/// analysis follows it at once, and the views keep up with the clock.
pub const PLAY_CYCLES: usize = 80;
/// While θν plays, the analysis keeps this many iterates (300 otherwise).
pub const PLAY_KEEP: usize = 120;

/// What a bifurcation sweep depends on: the parameters but the one it
/// varies (its x-axis, by the job table's rule), which one that is, and
/// its whole range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepKey {
    /// The model's parameters it depends on.
    pub params: ParamsKey,
    /// The parameter varied.
    pub param: ContParam,
    /// Its whole (unzoomed) range.
    pub range: (f64, f64),
    pub solver: SolverSettings,
    pub columns: usize,
    pub transient: usize,
    pub keep: usize,
    pub seeds: usize,
}

impl SweepKey {
    /// The key of the settings `s`.
    pub fn of(s: &Settings) -> Self {
        let param = s.diagram.param;
        SweepKey {
            params: JobKind::Sweep.depends().key(&s.params, param),
            param,
            range: s.sweep_range(),
            solver: JobKind::Sweep
                .solver(s)
                .unwrap_or_else(|| s.custom_solver()),
            columns: s.columns,
            transient: s.sweep_transient,
            keep: s.sweep_keep,
            seeds: s.sweep_seeds,
        }
    }
}

/// Everything a phase grid depends on (κ and θν are its axes, so by the
/// job table's rule the sliders' κ and θν are not in it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseKey {
    pub params: ParamsKey,
    pub solver: SolverSettings,
    pub range: PhaseRange,
    /// (θν columns, κ rows).
    pub steps: (usize, usize),
    pub transient: usize,
    pub keep: usize,
    /// Seeds per cell (0: attractors not counted).
    pub seeds: usize,
}

impl PhaseKey {
    pub fn of(s: &Settings) -> Self {
        let p = &s.phase;
        PhaseKey {
            params: JobKind::Phase.depends().key(&s.params, ContParam::ThetaNu),
            solver: JobKind::Phase
                .solver(s)
                .unwrap_or_else(|| s.custom_solver()),
            range: p.current(),
            steps: (p.theta_nu_steps, p.kappa_steps),
            transient: p.transient,
            keep: p.keep,
            seeds: p.seeds,
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
pub struct PhasePolicy {
    /// What the running or last grid was started with; `None` before the
    /// first and after a pause, so that showing the view starts one.
    pub sent: Option<PhaseKey>,
    changed_at: Option<f64>,
    /// Started with Compute: keeps running while the view is hidden.
    pub pinned: bool,
    /// Stopped with Stop: not restarted until something changes.
    pub stopped: bool,
}

impl PhasePolicy {
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
                let debounce = JobKind::Phase.debounce();
                if now - since >= debounce {
                    PhaseStep::Start
                } else {
                    PhaseStep::WaitFor(debounce - (now - since))
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
        let mut j = PhasePolicy::default();
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
}
