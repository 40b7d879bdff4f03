//! The continuation jobs: "Find bifurcations" over the bifurcation
//! diagram's θν range, and "Boundaries" over the phase diagram's box. Both
//! run on the worker's own lanes when asked for, never again by
//! themselves; a change of what they depend on cancels a running one (its
//! later updates are then stale and dropped) and clears a result of other
//! parameters, by the window's one rule ([`super::stale`]).

use super::{JobKind, JobState, Jobs, SlotHead, solver};
use crate::app::branches::{BranchData, CurveData};
use crate::app::session_results::{Kept, Results};
use crate::app::settings::Settings;
use crate::worker::{BoundarySpec, CascadeFrom, Command, ContinuationSpec};

/// The longest period "Find bifurcations" follows a cascade to: the P64
/// level alone costs seconds, too long to wait for at the window.
pub const MAX_CASCADE_PERIOD: usize = 32;

/// The range the bifurcation diagram shows, in the parameter it varies:
/// its zoom, or the whole range.
pub fn diagram_range(s: &Settings, zoom: Option<(f64, f64)>) -> (f64, f64) {
    zoom.unwrap_or_else(|| s.sweep_range())
}

impl Jobs {
    /// Finds the bifurcations over `range` (the diagram's) of the
    /// parameter the diagram varies, the others held at the sliders'.
    pub fn find_bifurcations(&mut self, s: &Settings, range: (f64, f64)) {
        let g = self.generation();
        let param = s.diagram.param;
        self.branches.start(
            g,
            BranchData {
                param: Some(param),
                range,
                ..BranchData::default()
            },
        );
        self.send(Command::run(
            g,
            ContinuationSpec {
                params: s.params,
                settings: solver(JobKind::Branches, s),
                param,
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

    /// Shows the results a session kept as computed for `s` (the
    /// session's own settings) over the diagram's θν range `diagram`, with
    /// their status lines: no job is sent. Each is bound to `s`, so the
    /// window's one rule ([`super::stale`]) clears it on the first change
    /// of what it depends on, as it would a computed one; a job of its
    /// kind that runs is stopped (its later updates are dropped).
    pub fn restore(&mut self, s: &Settings, diagram: (f64, f64), results: Results) {
        if let Some(k) = results.branches {
            self.restore_head(JobKind::Branches, s, diagram, k.summary);
            self.branches.data = k.data;
        }
        if let Some(k) = results.curves {
            self.restore_head(JobKind::Curves, s, diagram, k.summary);
            self.curves.data = k.data;
        }
    }

    /// The slot of `kind` as a job's that has ended, bound to `s`.
    fn restore_head(
        &mut self,
        kind: JobKind,
        s: &Settings,
        diagram: (f64, f64),
        summary: Option<String>,
    ) {
        self.cancel_on(kind, "stopped: a session was opened");
        // A generation of its own (never sent), so that it counts as
        // issued and nothing of an older job is taken for it.
        let generation = self.generation();
        *self.slot_mut(kind) = SlotHead {
            generation,
            state: JobState::Done,
            summary,
            ..SlotHead::default()
        };
        self.bind(kind, s, diagram);
    }

    /// The results a session keeps: Find bifurcations' and Boundaries'
    /// when they have ended (stopped counts) and are of the parameters of
    /// `s` (what runs, or belongs to other parameters, is left out).
    pub fn results_to_keep(&self, s: &Settings) -> Results {
        let keep = |kind: JobKind| {
            let head = self.slot(kind);
            head.state != JobState::Running && !head.stale && self.is_current(kind, s)
        };
        let branches =
            (keep(JobKind::Branches) && !self.branches.data.branches.is_empty()).then(|| Kept {
                data: self.branches.data.clone(),
                summary: self.branches.summary.clone(),
            });
        let curves = (keep(JobKind::Curves) && !self.curves.data.curves.is_empty()).then(|| Kept {
            data: self.curves.data.clone(),
            summary: self.curves.summary.clone(),
        });
        Results { branches, curves }
    }

    /// Whether "Find bifurcations" has ended (a failed or stopped one
    /// counts).
    pub fn branches_settled(&self) -> bool {
        self.branches.issued() && self.branches.state != JobState::Running
    }
}
