//! The continuation jobs: "Find bifurcations" over the bifurcation
//! diagram's θν range, and "Boundaries" over the phase diagram's box. Both
//! run on the worker's own lanes when asked for, never again by
//! themselves; a change of what they depend on cancels a running one (its
//! later updates are then stale and dropped) and clears a result of other
//! parameters.

use super::{JobKind, JobState, Jobs, Shown, Slot, solver};
use crate::app::branches::{BranchData, CurveData};
use crate::app::settings::{PhaseRange, Settings};
use crate::integrate::SolverSettings;
use crate::sim::continuation::ContParam;
use crate::worker::{BoundarySpec, CascadeFrom, Command, ContinuationSpec};

/// The longest period "Find bifurcations" follows a cascade to: the P64
/// level alone costs seconds, too long to wait for at the window.
pub const MAX_CASCADE_PERIOD: usize = 32;

/// What a "Find bifurcations" job depends on: the parameters but θν (the
/// axis), its solver, and the θν range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BranchKey {
    /// κ, γ, ν, Ω.
    pub params: [f64; 4],
    pub solver: SolverSettings,
    pub range: (f64, f64),
}

impl BranchKey {
    /// The key of `s` over the θν range `range`.
    pub fn of(s: &Settings, range: (f64, f64)) -> Self {
        let p = &s.params;
        BranchKey {
            params: [p.kappa, p.gamma, p.nu, p.omega],
            solver: solver(JobKind::Branches, s),
            range,
        }
    }
}

/// What a "Boundaries" job depends on: γ, ν, Ω (κ and θν are the box's
/// axes), its solver, and the box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveKey {
    /// γ, ν, Ω.
    pub params: [f64; 3],
    pub solver: SolverSettings,
    pub range: PhaseRange,
}

impl CurveKey {
    /// The key of `s` over its phase diagram's current box.
    pub fn of(s: &Settings) -> Self {
        let p = &s.params;
        CurveKey {
            params: [p.gamma, p.nu, p.omega],
            solver: solver(JobKind::Curves, s),
            range: s.phase.current(),
        }
    }
}

/// The θν range the bifurcation diagram shows: its zoom, or the whole range.
pub fn diagram_range(s: &Settings, zoom: Option<(f64, f64)>) -> (f64, f64) {
    zoom.unwrap_or_else(|| s.sweep_range())
}

impl Jobs {
    /// Finds the bifurcations over the θν range `range` (the diagram's).
    pub fn find_bifurcations(&mut self, s: &Settings, range: (f64, f64)) {
        let key = BranchKey::of(s, range);
        let g = self.generation();
        self.branches.start(
            g,
            BranchData {
                param: Some(ContParam::ThetaNu),
                range,
                ..BranchData::default()
            },
        );
        self.send(Command::FindBifurcations {
            generation: g,
            spec: ContinuationSpec {
                params: s.params,
                settings: key.solver,
                param: ContParam::ThetaNu,
                from: range.0,
                to: range.1,
                max_period: MAX_CASCADE_PERIOD,
                cycle: None,
                cascade: CascadeFrom::Branch,
                curves: None,
            },
        });
        self.sent_branches = Some(key);
    }

    /// Follows the doubling curves over the phase diagram's box, from the
    /// doublings at the slider's κ (the box's middle κ if it is outside).
    pub fn compute_boundaries(&mut self, s: &Settings) {
        let key = CurveKey::of(s);
        let (k0, k1) = key.range.kappa;
        let mut params = s.params;
        if !(k0..=k1).contains(&params.kappa) {
            params.kappa = 0.5 * (k0 + k1);
        }
        let g = self.generation();
        self.curves.start(g, CurveData::default());
        self.send(Command::Boundaries {
            generation: g,
            spec: BoundarySpec {
                params,
                settings: key.solver,
                theta_nu: key.range.theta_nu,
                kappa: key.range.kappa,
            },
        });
        self.sent_curves = Some(key);
    }

    /// Stops "Find bifurcations": the branches so far stay.
    pub fn stop_bifurcations(&mut self) {
        self.cancel_on(JobKind::Branches, "stopped");
    }

    /// Stops "Boundaries": the curves so far stay.
    pub fn stop_boundaries(&mut self) {
        self.cancel_on(JobKind::Curves, "stopped");
    }

    /// Cancels the job of `kind` if it runs (what it sends later is then
    /// stale), saying `why` in its summary.
    fn cancel_on(&mut self, kind: JobKind, why: &str) {
        let running = self.state(kind) == &JobState::Running;
        if !running {
            return;
        }
        let g = self.generation();
        let why = Some(why.to_string());
        match kind {
            JobKind::Branches => cancelled(&mut self.branches, g, why, |d| &mut d.summary),
            JobKind::Curves => cancelled(&mut self.curves, g, why, |d| &mut d.summary),
            _ => return,
        }
        self.send(Command::Cancel {
            generation: g,
            lane: Some(kind.lane()),
        });
    }

    /// Cancels a continuation job whose parameters or range changed; a
    /// result of other parameters is cleared (of another range only, it
    /// stays: the branches are those of these parameters).
    pub(super) fn cancel_stale_continuation(&mut self, s: &Settings, shown: Shown) {
        if let Some(sent) = self.sent_branches {
            let now = BranchKey::of(s, diagram_range(s, shown.sweep_zoom));
            let params = sent.params != now.params || sent.solver != now.solver;
            if params || sent.range != now.range {
                self.sent_branches = None;
                self.stale(JobKind::Branches, params, "the θν range");
            }
        }
        if let Some(sent) = self.sent_curves {
            let now = CurveKey::of(s);
            let params = sent.params != now.params || sent.solver != now.solver;
            if params || sent.range != now.range {
                self.sent_curves = None;
                self.stale(JobKind::Curves, params, "the box");
            }
        }
    }

    /// The job of `kind` no longer matches the settings: stopped if it
    /// runs; its result cleared if the parameters (not only `range`)
    /// changed.
    fn stale(&mut self, kind: JobKind, params: bool, range: &str) {
        let why = if params {
            "stopped: the parameters changed".to_string()
        } else {
            format!("stopped: {range} changed")
        };
        self.cancel_on(kind, &why);
        if !params {
            return;
        }
        let was_running = self.state(kind) == &JobState::Cancelled;
        match kind {
            JobKind::Branches => {
                let summary = self.branches.data.summary.take().filter(|_| was_running);
                self.branches.data = BranchData {
                    summary,
                    ..BranchData::default()
                };
                if !was_running {
                    self.branches.state = JobState::Idle;
                }
            }
            JobKind::Curves => {
                let summary = self.curves.data.summary.take().filter(|_| was_running);
                self.curves.data = CurveData {
                    summary,
                    ..CurveData::default()
                };
                if !was_running {
                    self.curves.state = JobState::Idle;
                }
            }
            _ => {}
        }
    }

    /// Whether "Find bifurcations" has ended (a failed or stopped one
    /// counts).
    pub fn branches_settled(&self) -> bool {
        self.branches.issued() && self.branches.state != JobState::Running
    }
}

/// Marks `slot` cancelled under the new generation `g`, with `why` as its
/// summary.
fn cancelled<T>(
    slot: &mut Slot<T>,
    g: crate::worker::Generation,
    why: Option<String>,
    summary: impl Fn(&mut T) -> &mut Option<String>,
) {
    slot.generation = g;
    slot.state = JobState::Cancelled;
    *summary(&mut slot.data) = why;
}
