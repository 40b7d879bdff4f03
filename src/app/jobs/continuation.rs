//! The continuation jobs: "Find bifurcations" over the bifurcation
//! diagram's θν range, and "Boundaries" over the phase diagram's box. Both
//! run on the worker's own lanes when asked for, never again by
//! themselves; a change of what they depend on cancels a running one (its
//! later updates are then stale and dropped) and clears a result of other
//! parameters, by the window's one rule ([`super::stale`]).

use super::{JobKind, JobState, Jobs, solver};
use crate::app::branches::{BranchData, CurveData};
use crate::app::settings::Settings;
use crate::sim::continuation::ContParam;
use crate::worker::{BoundarySpec, CascadeFrom, Command, ContinuationSpec};

/// The longest period "Find bifurcations" follows a cascade to: the P64
/// level alone costs seconds, too long to wait for at the window.
pub const MAX_CASCADE_PERIOD: usize = 32;

/// The θν range the bifurcation diagram shows: its zoom, or the whole range.
pub fn diagram_range(s: &Settings, zoom: Option<(f64, f64)>) -> (f64, f64) {
    zoom.unwrap_or_else(|| s.sweep_range())
}

impl Jobs {
    /// Finds the bifurcations over the θν range `range` (the diagram's).
    pub fn find_bifurcations(&mut self, s: &Settings, range: (f64, f64)) {
        let g = self.generation();
        self.branches.start(
            g,
            BranchData {
                param: Some(ContParam::ThetaNu),
                range,
                ..BranchData::default()
            },
        );
        self.send(Command::run(
            g,
            ContinuationSpec {
                params: s.params,
                settings: solver(JobKind::Branches, s),
                param: ContParam::ThetaNu,
                from: range.0,
                to: range.1,
                max_period: MAX_CASCADE_PERIOD,
                cycle: None,
                cascade: CascadeFrom::Branch,
                curves: None,
            },
        ));
        self.bind(JobKind::Branches, s, range);
    }

    /// Follows the doubling curves over the phase diagram's box, from the
    /// doublings at the slider's κ (the box's middle κ if it is outside).
    pub fn compute_boundaries(&mut self, s: &Settings) {
        let range = s.phase.current();
        let (k0, k1) = range.kappa;
        let mut params = s.params;
        if !(k0..=k1).contains(&params.kappa) {
            params.kappa = 0.5 * (k0 + k1);
        }
        let g = self.generation();
        self.curves.start(g, CurveData::default());
        self.send(Command::run(
            g,
            BoundarySpec {
                params,
                settings: solver(JobKind::Curves, s),
                theta_nu: range.theta_nu,
                kappa: range.kappa,
            },
        ));
        self.bind(JobKind::Curves, s, diagram_range(s, None));
    }

    /// Stops "Find bifurcations": the branches so far stay.
    pub fn stop_bifurcations(&mut self) {
        self.cancel_on(JobKind::Branches, "stopped");
    }

    /// Stops "Boundaries": the curves so far stay.
    pub fn stop_boundaries(&mut self) {
        self.cancel_on(JobKind::Curves, "stopped");
    }

    /// Whether "Find bifurcations" has ended (a failed or stopped one
    /// counts).
    pub fn branches_settled(&self) -> bool {
        self.branches.issued() && self.branches.state != JobState::Running
    }
}
