//! The one rule for results bound to parameters. Each job's slot keeps
//! what its result was computed for (its [`Bound`]: the parameters it
//! depends on, and the range it covers), set when it starts. On every
//! [`Jobs::sync`], before anything is restarted, each slot's bound is
//! compared with the settings':
//!
//! - **its parameters changed**: a job the window runs again by itself
//!   (the kinds whose table entry says `new_params: rerun`: trajectory,
//!   iterates, diagram, phase grid, basins) is marked stale until its new
//!   run starts (its data are replaced then), and so is the work-precision
//!   table (`keep`: a measurement of the parameters it names); a job that
//!   new parameters stop (`cancel`: branches, boundaries, the Events
//!   view's answers, the return map's basins) is stopped if it runs, and
//!   its result, its special points, its table and its status line are
//!   cleared; a zoom of
//!   the diagram no longer applies ([`super::SyncOutcome::zoom_stale`]);
//!   the status bar's last error is cleared;
//! - **only its range changed** (a zoom, a phase box): a running job is
//!   stopped, what it found stays, and the bound takes the new range, so
//!   a later parameter change still clears it.
//!
//! Nothing else in the window clears a result for new parameters.

use super::{JobKind, JobState, Jobs, Shown};
use crate::app::settings::Settings;
use crate::integrate::SolverSettings;
use crate::jobs::{Depends, NewParams, ParamsKey};
use crate::sim::continuation::ContParam;

/// What a result was computed for: bit patterns of the parameters (and
/// solver) it depends on, and of the range it covers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bound {
    params: Option<ParamsKey>,
    solver: Option<SolverSettings>,
    range: Vec<u64>,
}

fn bits(xs: &[f64]) -> Vec<u64> {
    xs.iter().map(|x| x.to_bits()).collect()
}

impl Bound {
    /// What a job of `kind` started now would be computed for, with the
    /// diagram's range `diagram` (its zoom's, or the whole range, in the
    /// parameter it varies).
    pub fn of(kind: JobKind, s: &Settings, diagram: (f64, f64)) -> Bound {
        // The range it covers, and the parameter it varies (read only by
        // a kind that depends on all parameters but that one).
        let (varied, range) = match kind {
            JobKind::Sweep | JobKind::Branches => {
                let (a, b) = diagram;
                let (c, d) = s.sweep_range();
                (s.diagram.param, vec![a, b, c, d])
            }
            JobKind::Basins => {
                let (a, b) = s.basins.range(s);
                (ContParam::ThetaNu, vec![a, b, s.basins.columns as f64])
            }
            JobKind::Phase | JobKind::Curves => {
                let r = s.phase.current();
                let (t, k) = (r.theta_nu, r.kappa);
                (ContParam::ThetaNu, vec![t.0, t.1, k.0, k.1])
            }
            _ => (ContParam::ThetaNu, Vec::new()),
        };
        Bound {
            params: Some(kind.depends().key(&s.params, varied)),
            solver: kind.solver(s),
            range: bits(&range),
        }
    }

    /// What a job that depends on every parameter and on no solver of the
    /// window's (the Events view's) is computed for.
    pub fn of_params(p: &crate::model::Params) -> Bound {
        Bound {
            params: Some(Depends::All.key(p, ContParam::ThetaNu)),
            solver: None,
            range: Vec::new(),
        }
    }
}

impl Jobs {
    /// The rule: every slot whose bound the settings no longer match is
    /// made stale, stopped or cleared (module docs). Returns whether the
    /// diagram's result was bound to other parameters (its zoom no longer
    /// applies).
    pub(super) fn apply_bounds(&mut self, s: &Settings, shown: &Shown) -> bool {
        let diagram_range = super::diagram_range(s, shown.sweep_zoom);
        let mut diagram = false;
        for kind in JobKind::ALL {
            let Some(was) = self.slot(kind).bound.clone() else {
                continue;
            };
            let now = Bound::of(kind, s, diagram_range);
            if (&was.params, was.solver) != (&now.params, now.solver) {
                diagram |= kind == JobKind::Sweep;
                self.last_error = None;
                self.params_changed(kind);
            } else if was.range != now.range {
                if kind.new_params() == NewParams::Cancel {
                    self.range_changed(kind);
                }
                self.slot_mut(kind).bound = Some(now);
            }
        }
        diagram
    }

    /// Whether the result of `kind` was computed for the parameters and
    /// solver of `s` (its range aside).
    pub fn is_current(&self, kind: JobKind, s: &Settings) -> bool {
        self.slot(kind).bound.as_ref().is_some_and(|b| {
            let now = Bound::of(kind, s, s.sweep_range());
            (&b.params, b.solver) == (&now.params, now.solver)
        })
    }

    /// Records what the job of `kind`, started now, is computed for.
    pub(super) fn bind(&mut self, kind: JobKind, s: &Settings, diagram: (f64, f64)) {
        let head = self.slot_mut(kind);
        head.bound = Some(Bound::of(kind, s, diagram));
        head.stale = false;
    }

    /// The parameters of `kind`'s result changed.
    fn params_changed(&mut self, kind: JobKind) {
        if kind.new_params() != NewParams::Cancel {
            self.slot_mut(kind).stale = true;
            return;
        }
        let was_running = self.cancel_on(kind, "stopped: the parameters changed");
        self.slots.clear(kind);
        let head = self.slot_mut(kind);
        head.bound = None;
        if !was_running {
            head.state = JobState::Idle;
            head.summary = None;
        }
    }

    /// Only the range of `kind`'s result changed: a running job stops.
    fn range_changed(&mut self, kind: JobKind) {
        let what = match kind {
            JobKind::Phase | JobKind::Curves => "the box",
            _ => "the θν range",
        };
        self.cancel_on(kind, &format!("stopped: {what} changed"));
    }

    /// Cancels the job of `kind` if it runs (what it sends later is then
    /// stale), saying `why` in its status line; true if it ran.
    pub(super) fn cancel_on(&mut self, kind: JobKind, why: &str) -> bool {
        if self.state(kind) != &JobState::Running {
            return false;
        }
        let g = self.generation();
        let head = self.slot_mut(kind);
        head.generation = g;
        head.state = JobState::Cancelled;
        head.summary = Some(why.to_string());
        self.send(crate::worker::Command::Cancel {
            generation: g,
            lane: Some(kind.lane()),
        });
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::backend::Recorder;
    use crate::worker::{Command, Lane, Outcome, Update};

    /// Starts the job of `kind` as the window does.
    fn start(jobs: &mut Jobs, kind: JobKind, s: &Settings) {
        jobs.start(kind, s, &shown());
    }

    fn shown() -> Shown {
        Shown {
            now: 0.0,
            sweep_zoom: None,
            phase: false,
        }
    }

    fn cancels(rec: &Recorder, lane: Lane) -> usize {
        let is = |c: &Command| matches!(c, Command::Cancel { lane: Some(l), .. } if *l == lane);
        rec.commands().iter().filter(|c| is(c)).count()
    }

    /// Every kind: a change of a parameter it does not depend on leaves it
    /// be; a change of one it depends on stops and clears it (`cancel`
    /// kinds) or marks it stale until it runs again (the others), whether
    /// it was running or had ended.
    #[test]
    fn new_parameters_clear_or_mark_every_kind_of_result_in_one_place() {
        for kind in JobKind::ALL {
            for ended in [false, true] {
                let rec = Recorder::new();
                let mut jobs = Jobs::new(Box::new(rec.clone()));
                let mut s = Settings::default();
                start(&mut jobs, kind, &s);
                let g = jobs.slot(kind).generation;
                let text = "1 PD, 0 fold".to_string();
                let lane = kind.lane();
                jobs.apply(Update::Summary {
                    generation: g,
                    lane,
                    text: text.clone(),
                });
                if ended {
                    let outcome = Outcome::Completed;
                    jobs.apply(Update::Finished {
                        generation: g,
                        lane,
                        outcome,
                    });
                }
                // Ω: no kind's axis; θν is the diagram's, the phase grid's,
                // and the Basins view's axis.
                let untouched = matches!(
                    kind,
                    JobKind::Sweep
                        | JobKind::Branches
                        | JobKind::Phase
                        | JobKind::Curves
                        | JobKind::Basins
                );
                if untouched {
                    s.params.theta_nu += 0.01;
                    jobs.apply_bounds(&s, &shown());
                    let head = jobs.slot(kind);
                    assert!(!head.stale && head.bound.is_some(), "{kind:?}");
                }
                s.params.omega *= 1.5;
                rec.clear();
                jobs.apply_bounds(&s, &shown());
                let head = jobs.slot(kind).clone();
                let what = format!("{kind:?}, ended: {ended}");
                if kind.new_params() == NewParams::Cancel {
                    assert!(head.bound.is_none() && !head.stale, "{what}");
                    assert_eq!(cancels(&rec, lane), usize::from(!ended), "{what}");
                    let (state, summary) = if ended {
                        (JobState::Idle, None)
                    } else {
                        let why = "stopped: the parameters changed";
                        (JobState::Cancelled, Some(why.to_string()))
                    };
                    assert_eq!((head.state, head.summary), (state, summary), "{what}");
                    // Cleared: a second look changes nothing more.
                    rec.clear();
                    jobs.apply_bounds(&s, &shown());
                    assert!(rec.commands().is_empty(), "{what}");
                } else {
                    // (The map iterates wait for the trajectory: no
                    // generation yet, so nothing of theirs was taken.)
                    let waits = g == super::super::NO_GENERATION;
                    assert!(
                        head.stale && (waits || head.summary == Some(text)),
                        "{what}"
                    );
                    assert_eq!(cancels(&rec, lane), 0, "{what}");
                    // Running again under the new parameters: fresh.
                    start(&mut jobs, kind, &s);
                    assert!(!jobs.slot(kind).stale, "{what}");
                    jobs.apply_bounds(&s, &shown());
                    assert!(!jobs.slot(kind).stale, "{what}");
                }
            }
        }
    }

    /// The spec the window sent for the job of `kind` it started (the map
    /// iterates once the trajectory they wait for is done).
    fn sent_spec(jobs: &mut Jobs, rec: &Recorder, kind: JobKind) -> crate::jobs::Spec {
        if kind == JobKind::Iterate {
            rec.push(Update::Finished {
                generation: jobs.trajectory.generation,
                lane: Lane::Orbit,
                outcome: Outcome::Completed,
            });
            jobs.receive();
        }
        let sent = rec.commands().into_iter().rev().find_map(|c| match c {
            Command::Run { spec, .. } if spec.kind() == kind => Some(spec),
            _ => None,
        });
        sent.unwrap_or_else(|| panic!("{kind:?} sent no spec"))
    }

    /// One rule for the window and the worker: after a change of θν alone,
    /// then of κ alone, the window's slots that are run again (marked
    /// stale) or stopped and cleared are exactly the kinds whose spec, as
    /// the window sent it, the worker runs again or stops on
    /// `Command::SetParams` (`Spec::on_params`, what its orders read).
    #[test]
    fn the_window_and_the_worker_rerun_and_stop_the_same_kinds() {
        use crate::jobs::OnParams;
        type Change = fn(&mut crate::model::Params);
        let changes: [(&str, Change, &[JobKind], &[JobKind]); 2] = [
            (
                "θν",
                |p| p.theta_nu += 0.01,
                &[JobKind::Trajectory, JobKind::Iterate],
                &[JobKind::Passage, JobKind::Scan, JobKind::MapBasins],
            ),
            (
                "κ",
                |p| p.kappa *= 1.1,
                &[
                    JobKind::Trajectory,
                    JobKind::Sweep,
                    JobKind::Iterate,
                    JobKind::Basins,
                ],
                &[
                    JobKind::Branches,
                    JobKind::Passage,
                    JobKind::Scan,
                    JobKind::MapBasins,
                ],
            ),
        ];
        for (what, change, reruns, stops) in changes {
            let (mut window, mut worker) = ((Vec::new(), Vec::new()), (Vec::new(), Vec::new()));
            for kind in JobKind::ALL {
                let rec = Recorder::new();
                let mut jobs = Jobs::new(Box::new(rec.clone()));
                let s = Settings::default();
                start(&mut jobs, kind, &s);
                let spec = sent_spec(&mut jobs, &rec, kind);
                let mut t = s.clone();
                change(&mut t.params);
                jobs.apply_bounds(&t, &shown());
                let head = jobs.slot(kind);
                match kind.new_params() {
                    NewParams::Rerun if head.stale => window.0.push(kind),
                    NewParams::Cancel if head.bound.is_none() => window.1.push(kind),
                    _ => {}
                }
                match spec.on_params(t.params, None) {
                    OnParams::Rerun(_) => worker.0.push(kind),
                    OnParams::Cancel => worker.1.push(kind),
                    OnParams::Keep => {}
                }
            }
            assert_eq!(window, worker, "{what} alone");
            assert_eq!(
                (&window.0[..], &window.1[..]),
                (reruns, stops),
                "{what} alone"
            );
        }
    }

    /// Branches found in κ belong to the diagram's axis: κ itself may
    /// move (it is the axis), θν may not; another range of κ only stops a
    /// running job; another varied parameter clears them, as new
    /// parameters do.
    #[test]
    fn branches_in_kappa_follow_the_rule_with_kappa_as_the_axis() {
        use crate::sim::continuation::ContParam;
        let found = |s: &Settings| {
            let rec = Recorder::new();
            let mut jobs = Jobs::new(Box::new(rec));
            jobs.find_bifurcations(s, s.sweep_range());
            let g = jobs.branches.generation;
            jobs.apply(Update::Finished {
                generation: g,
                lane: Lane::Continuation,
                outcome: Outcome::Completed,
            });
            jobs.branches.data.range = s.sweep_range();
            jobs
        };
        let mut s = Settings::default();
        s.diagram.param = ContParam::Kappa;
        s.diagram.kappa = (2.0, 5.0);
        let kept = |jobs: &Jobs| jobs.branches.state == JobState::Done;

        let mut t = s.clone();
        t.params.kappa = 3.0;
        let mut jobs = found(&s);
        jobs.apply_bounds(&t, &shown());
        assert!(kept(&jobs), "κ is the axis");

        t.diagram.kappa = (2.0, 4.0);
        jobs.apply_bounds(&t, &shown());
        assert!(kept(&jobs), "a new range keeps what was found");
        assert_eq!(jobs.branches.data.range, (2.0, 5.0));

        let mut jobs = found(&s);
        let mut t = s.clone();
        t.params.theta_nu += 0.01;
        jobs.apply_bounds(&t, &shown());
        assert_eq!(jobs.branches.state, JobState::Idle, "θν is held fixed");

        let mut jobs = found(&s);
        let mut t = s.clone();
        t.diagram.param = ContParam::Gamma;
        jobs.apply_bounds(&t, &shown());
        assert_eq!(jobs.branches.state, JobState::Idle, "another axis");
        assert!(jobs.branches.data.branches.is_empty());
    }

    /// A zoom (the range only) stops a running Find bifurcations and keeps
    /// its branches; a later κ change still clears them (the bound kept
    /// the parameters across the zoom).
    #[test]
    fn a_zoom_keeps_the_branches_and_a_later_kappa_change_clears_them() {
        let rec = Recorder::new();
        let mut jobs = Jobs::new(Box::new(rec.clone()));
        let mut s = Settings::default();
        jobs.find_bifurcations(&s, s.sweep_range());
        let g = jobs.branches.generation;
        jobs.apply(Update::Finished {
            generation: g,
            lane: Lane::Continuation,
            outcome: Outcome::Completed,
        });
        jobs.branches.data.range = (0.0, 1.5);
        let zoomed = Shown {
            sweep_zoom: Some((1.0, 1.2)),
            ..shown()
        };
        jobs.apply_bounds(&s, &zoomed);
        assert_eq!(jobs.branches.state, JobState::Done);
        assert_eq!(jobs.branches.data.range, (0.0, 1.5));
        s.params.kappa = 16.0;
        assert!(!jobs.apply_bounds(&s, &zoomed), "no diagram was bound");
        assert_eq!(jobs.branches.state, JobState::Idle);
        assert_eq!(jobs.branches.data.range, (0.0, 0.0));
    }
}
