//! The job model: one slot (generation, state, progress, data) per kind of
//! job, the commands that start and stop them, [`Jobs::apply`] for what the
//! worker sends back, and [`Jobs::sync`], which restarts whatever the
//! settings now call for (with the debounces and the phase grid's policy of
//! [`policy`]). Updates of an older generation than the latest issued for
//! their job are dropped here. Nothing here draws.

mod apply;
pub mod basins;
mod continuation;
mod events;
pub mod kind;
pub mod policy;
mod slots;
pub mod stale;

use continuation::diagram_range;
pub use continuation::{MAX_CASCADE_PERIOD, diagram_range as continuation_range};
pub use events::{Answer, events_settings};
pub use kind::JobKind;
pub use policy::{PhaseKey, PhasePolicy, PhaseStep, SweepKey};
pub use slots::{JobState, LaneProgress, Receive, Slot, SlotHead, Slots};

use super::backend::Backend;
use super::data::{IterateData, SweepData, WorkPrecisionData};
use super::phase_data::PhaseData;
use super::settings::Settings;
use crate::integrate::SolverSettings;
use crate::model::Params;
use crate::numerics::quick::{
    QUICK_POINTS, QUICK_TIME_PER_SETTING, QUICK_TRANSIENT, current_attractor, quick_subjects,
};
use crate::sim::MapChoice;
use crate::worker::{
    Axis, Command, Generation, IterateOptions, IterateSpec, Lane, PhaseSpec, PhaseTuning,
    SweepSpec, Timing, TrajectorySpec, WorkPrecisionSpec,
};
use policy::{PLAY_CYCLES, PLAY_HOLD, PLAY_KEEP};

/// A generation never issued: a job that waits for its turn, or has never
/// run.
pub const NO_GENERATION: Generation = Generation::MAX;
/// Sample spacing of trajectories, in time units.
pub const SAMPLE_SPACING: f64 = 0.02;
/// Map iterates dropped and kept by the orbit analysis.
pub const ITERATE_TRANSIENT: usize = 1000;
pub const ITERATE_KEEP: usize = 300;

/// What the window shows that decides which jobs run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shown {
    /// The ui time, seconds.
    pub now: f64,
    /// The bifurcation diagram's zoomed θν range, if zoomed.
    pub sweep_zoom: Option<(f64, f64)>,
    /// Whether the phase diagram is on screen.
    pub phase: bool,
}

/// What [`Jobs::sync`] asks of the window.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SyncOutcome {
    /// A change waits for its debounce: look again after this long (s).
    pub repaint_after: Option<f64>,
    /// The parameters changed under a zoomed diagram: its zoom no longer
    /// applies (the sweep restarted, or will, over the whole range).
    pub zoom_stale: bool,
}

impl SyncOutcome {
    /// Look again after `seconds` at the latest.
    fn wait(&mut self, seconds: f64) {
        self.repaint_after = Some(self.repaint_after.map_or(seconds, |x| x.min(seconds)));
    }
}

impl std::ops::Deref for Jobs {
    type Target = Slots;
    fn deref(&self) -> &Slots {
        &self.slots
    }
}

impl std::ops::DerefMut for Jobs {
    fn deref_mut(&mut self) -> &mut Slots {
        &mut self.slots
    }
}

/// Every job of the window.
pub struct Jobs {
    backend: Box<dyn Backend>,
    next_generation: Generation,
    /// Count of commands sent (tests, status).
    pub sent_count: usize,
    /// One slot per kind of job (`jobs.sweep`, …, through `Deref`).
    slots: Slots,
    basins_sent: basins::BasinsSent,
    /// The last error the worker reported (not the Numerics view's own),
    /// with the parameter it names.
    pub last_error: Option<String>,
    /// Updates dropped as stale (for the status bar and tests).
    pub stale_dropped: u64,
    /// Bumped whenever the trajectory changes.
    pub trajectory_revision: u64,
    /// When the phase grid runs.
    pub phase_policy: PhasePolicy,
    /// Keep the orbit lane streaming indefinitely (frame-time measurement).
    pub stream_forever: bool,
    /// θν plays (the window sets it every frame): the orbit restarts once
    /// the last one is done ([`PLAY_HOLD`]), shorter ([`PLAY_CYCLES`]), and
    /// the trajectory and the analysis keep showing their last result
    /// until the new one's first arrives.
    pub playing: bool,
    /// The trajectory's and the analysis's data are held from the last
    /// orbit, to be replaced by the running job's first update.
    held: (bool, bool),
    /// What the running orbit jobs were started with: the parameters, and
    /// the trajectory's and the map iterates' solver settings.
    sent_orbit: Option<(Params, SolverSettings, SolverSettings)>,
    sent_sweep: Option<(SweepKey, Option<(f64, f64)>)>,
    last_orbit_send: f64,
    sweep_changed_at: Option<f64>,
    /// The orbit analysis waits for the trajectory (the worker's orbit lane
    /// runs one job at a time; a new job there cancels the running one):
    /// the trajectory's generation and what to iterate once it is done.
    pending_iterate: Option<(Generation, Params, SolverSettings)>,
    /// The highest power of f the return map asks to see, and the highest
    /// the latest iterate job was asked for.
    want_powers: usize,
    sent_powers: usize,
}

/// The solver setting of a job that has one.
fn solver(kind: JobKind, s: &Settings) -> SolverSettings {
    kind.solver(s).unwrap_or_else(|| s.custom_solver())
}

impl Jobs {
    /// No job yet; commands go to `backend`.
    pub fn new(backend: Box<dyn Backend>) -> Self {
        Jobs {
            backend,
            next_generation: 1,
            sent_count: 0,
            slots: Slots::default(),
            basins_sent: basins::BasinsSent::default(),
            last_error: None,
            stale_dropped: 0,
            trajectory_revision: 0,
            phase_policy: PhasePolicy::default(),
            stream_forever: false,
            playing: false,
            held: (false, false),
            sent_orbit: None,
            sent_sweep: None,
            last_orbit_send: f64::NEG_INFINITY,
            sweep_changed_at: None,
            pending_iterate: None,
            want_powers: 1,
            sent_powers: 1,
        }
    }

    fn generation(&mut self) -> Generation {
        let g = self.next_generation;
        self.next_generation += 1;
        g
    }

    fn send(&mut self, cmd: Command) {
        self.sent_count += 1;
        if !self.backend.send(cmd) {
            self.last_error = Some("the simulation worker is not running".into());
        }
    }

    /// The orbit lane's progress: the analysis's while it runs, else the
    /// trajectory's.
    pub fn orbit_progress(&self) -> LaneProgress {
        if self.iterate.state == JobState::Running {
            self.iterate.progress
        } else {
            self.trajectory.progress
        }
    }

    /// Whether the orbit lane still works on its last start: the
    /// trajectory, or the analysis that waits for it or runs.
    fn orbit_busy(&self) -> bool {
        self.trajectory.state == JobState::Running
            || self.pending_iterate.is_some()
            || self.iterate.state == JobState::Running
    }

    /// Whether the trajectory's (`.0`) or the analysis's (`.1`) data is
    /// the last orbit's, held while the new one has sent nothing.
    pub fn held(&self) -> (bool, bool) {
        self.held
    }

    /// Starts the trajectory and the orbit analysis for the current parameters.
    pub fn restart_orbit(&mut self, s: &Settings, now: f64) {
        let params = s.params;
        let traj_solver = solver(JobKind::Trajectory, s);
        let iterate_solver = solver(JobKind::Iterate, s);
        let g = self.generation();
        let hold = self.playing;
        let kept = hold.then(|| std::mem::take(&mut self.trajectory.data));
        self.trajectory.start(g, kept.unwrap_or_default());
        self.held.0 = hold;
        self.bind(JobKind::Trajectory, s, diagram_range(s, None));
        self.trajectory.stale = hold;
        self.trajectory_revision += 1;
        let cycles = if self.playing {
            s.trajectory_cycles.min(PLAY_CYCLES)
        } else {
            s.trajectory_cycles
        };
        let cycles = (!self.stream_forever).then_some(cycles);
        self.send(Command::run(
            g,
            TrajectorySpec {
                params,
                settings: traj_solver,
                theta0: None,
                transient: 0,
                spacing: SAMPLE_SPACING,
                cycles,
                max_samples: None,
            },
        ));
        self.pending_iterate = (!self.stream_forever).then_some((g, params, iterate_solver));
        // The analysis shows "computing" until its job starts (while θν
        // plays, the last one's result).
        let kept = hold.then(|| std::mem::take(&mut self.iterate.data));
        self.iterate.start(NO_GENERATION, kept.unwrap_or_default());
        self.held.1 = hold;
        self.bind(JobKind::Iterate, s, diagram_range(s, None));
        self.iterate.stale = hold;
        self.sent_orbit = Some((params, traj_solver, iterate_solver));
        self.last_orbit_send = now;
    }

    /// Once the trajectory is done, analyses the orbit from where it ended
    /// (already on the attractor, so a short transient suffices).
    fn chain_iterate(&mut self) {
        let Some((g, params, solver)) = self.pending_iterate else {
            return;
        };
        if self.trajectory.generation != g {
            self.pending_iterate = None;
            return;
        }
        let slots = &mut self.slots;
        let events = &slots.trajectory.data.events;
        let (theta0, transient) = match &slots.trajectory.state {
            JobState::Done => (
                events.last().map(|e| e.theta_next),
                if events.is_empty() {
                    ITERATE_TRANSIENT
                } else {
                    ITERATE_TRANSIENT / 10
                },
            ),
            JobState::Failed(m) => {
                slots.iterate.state = JobState::Failed(m.clone());
                self.pending_iterate = None;
                return;
            }
            JobState::Cancelled => {
                self.pending_iterate = None;
                return;
            }
            _ => return,
        };
        self.pending_iterate = None;
        let g = self.generation();
        let bound = self.iterate.bound.take();
        let kept = self.held.1.then(|| std::mem::take(&mut self.iterate.data));
        self.iterate.start(g, kept.unwrap_or_default());
        self.iterate.bound = bound;
        self.iterate.stale = self.held.1;
        self.send(Command::run(
            g,
            IterateSpec {
                params,
                settings: solver,
                theta0,
                transient,
                keep: if self.playing {
                    PLAY_KEEP
                } else {
                    ITERATE_KEEP
                },
                graph_powers: self.want_powers,
                options: IterateOptions::default(),
            },
        ));
        self.sent_powers = self.want_powers;
    }

    /// Draws f², f³, … asked for after the orbit analysis ran without
    /// them: the same orbit again from its first kept onset (the kept
    /// iterates come out bitwise as before), then the graphs.
    fn add_graph_powers(&mut self, s: &Settings) {
        let Some(&theta0) = self.iterate.data.thetas.first() else {
            return;
        };
        let g = self.generation();
        self.iterate.start(g, IterateData::default());
        self.bind(JobKind::Iterate, s, diagram_range(s, None));
        self.send(Command::run(
            g,
            IterateSpec {
                params: s.params,
                settings: solver(JobKind::Iterate, s),
                theta0: Some(theta0),
                transient: 0,
                keep: ITERATE_KEEP,
                graph_powers: self.want_powers,
                options: IterateOptions::default(),
            },
        ));
        self.sent_powers = self.want_powers;
    }

    /// Starts the bifurcation sweep over `zoom`, or the whole range.
    pub fn restart_sweep(&mut self, s: &Settings, zoom: Option<(f64, f64)>) {
        let key = SweepKey::of(s);
        let (from, to) = zoom.unwrap_or_else(|| s.sweep_range());
        let g = self.generation();
        let revision = self.sweep.data.revision + 1;
        let mut data = SweepData::new(from, to, s.columns);
        data.param = key.param;
        data.revision = revision;
        self.sweep.start(g, data);
        self.bind(JobKind::Sweep, s, (from, to));
        self.send(Command::run(
            g,
            SweepSpec {
                params: s.params,
                settings: key.solver,
                param: key.param,
                axis: Axis::new(from, to, s.columns),
                transient: s.sweep_transient,
                keep: s.sweep_keep,
                map: MapChoice::Auto,
                theta0: None,
                seeds: s.sweep_seeds,
            },
        ));
        self.sent_sweep = Some((key, zoom));
        self.sweep_changed_at = None;
    }

    /// Measures work against precision on the current parameters (the
    /// Numerics view), on the worker's numerics lane.
    pub fn start_work_precision(&mut self, s: &Settings) {
        let params = s.params;
        // The orbit analysis's last point, if it is of these parameters, is
        // on the attractor already: the reference needs a short transient.
        let theta0 = match self.sent_orbit {
            Some((p, ..)) if p == params => self.iterate.data.thetas.last().copied(),
            _ => None,
        };
        let transient = if theta0.is_some() {
            20
        } else {
            QUICK_TRANSIENT
        };
        let subjects = quick_subjects();
        let g = self.generation();
        let mut data = WorkPrecisionData::new(params, subjects.len());
        data.load = super::data::load_average();
        self.numerics.start(g, data);
        self.bind(JobKind::Numerics, s, diagram_range(s, None));
        self.send(Command::run(
            g,
            WorkPrecisionSpec {
                attractors: vec![current_attractor(params, theta0, transient)],
                points: QUICK_POINTS,
                timing: Timing::PerSetting(QUICK_TIME_PER_SETTING),
                subjects,
            },
        ));
    }

    /// Stops the job of `kind` (the Stop buttons): what it found so far
    /// stays, anything later of it is dropped; a stopped phase grid stays
    /// stopped until something it depends on changes.
    pub fn stop(&mut self, kind: JobKind) {
        if kind == JobKind::Phase {
            self.phase_policy.stop();
        }
        let g = self.generation();
        let head = self.slot_mut(kind);
        head.generation = g;
        if head.state == JobState::Running {
            head.state = JobState::Cancelled;
            head.summary = Some("stopped".into());
        }
        self.send(Command::Cancel {
            generation: g,
            lane: Some(kind.lane()),
        });
    }

    /// Starts the phase diagram over the current range with the sliders'
    /// γ, ν, Ω and solver.
    pub fn restart_phase(&mut self, s: &Settings) {
        let key = PhaseKey::of(s);
        let g = self.generation();
        let (columns, rows) = key.steps;
        let revision = self.phase.data.revision + 1;
        let mut data = PhaseData::new(key.range.theta_nu, key.range.kappa, columns, rows);
        data.revision = revision;
        self.phase.start(g, data);
        self.bind(JobKind::Phase, s, diagram_range(s, None));
        let (theta_nu, kappa) = (key.range.theta_nu, key.range.kappa);
        self.send(Command::run(
            g,
            PhaseSpec {
                params: s.params,
                settings: key.solver,
                theta_nu: Axis::new(theta_nu.0, theta_nu.1, columns),
                kappa: Axis::new(kappa.0, kappa.1, rows),
                transient: key.transient,
                keep: key.keep,
                // With seeds, each multistable cell's attractors are
                // listed for the view's click.
                tuning: PhaseTuning {
                    seeds: key.seeds,
                    list_attractors: key.seeds > 0,
                    ..PhaseTuning::default()
                },
            },
        ));
        self.phase_policy.started(key);
    }

    fn cancel_phase(&mut self) {
        let g = self.generation();
        self.send(Command::Cancel {
            generation: g,
            lane: Some(Lane::Phase),
        });
        if self.phase.state == JobState::Running {
            self.phase.state = JobState::Cancelled;
        }
    }

    /// Compute: a grid now, that goes on while its view is hidden.
    pub fn compute_phase(&mut self, s: &Settings) {
        self.restart_phase(s);
        self.phase_policy.pinned = true;
    }

    /// Sends whatever the settings now call for: a new orbit at once (at
    /// most every 40 ms while dragging), a new sweep once κ, γ, ν, Ω or the
    /// solver have been still for 250 ms, the phase grid by its policy.
    pub fn sync(&mut self, s: &Settings, shown: Shown) -> SyncOutcome {
        let now = shown.now;
        let mut out = SyncOutcome::default();
        let diagram_stale = self.apply_bounds(s, &shown);
        let orbit_now = Some((
            s.params,
            solver(JobKind::Trajectory, s),
            solver(JobKind::Iterate, s),
        ));
        self.want_powers = s.graph_power();
        if self.sent_orbit == orbit_now
            && self.want_powers > self.sent_powers
            && self.pending_iterate.is_none()
            && self.iterate.issued()
            && self.iterate.state == JobState::Done
        {
            self.add_graph_powers(s);
        }
        if self.sent_orbit != orbit_now {
            let debounce = JobKind::Trajectory.debounce();
            let left = self.last_orbit_send + debounce - now;
            // While θν plays, the last orbit finishes first (within
            // PLAY_HOLD), so that its views have something to show.
            let busy = self.playing && self.orbit_busy() && now - self.last_orbit_send < PLAY_HOLD;
            if busy {
                out.wait(debounce);
            } else if left <= 0.0 || self.sent_orbit.is_none() {
                self.restart_orbit(s, now);
            } else {
                out.wait(left);
            }
        }
        let key = SweepKey::of(s);
        match self.sent_sweep {
            None => self.restart_sweep(s, shown.sweep_zoom),
            Some(sent) if sent != (key, shown.sweep_zoom) => {
                let zoom_only = sent.0 == key;
                // A new parameter set, axis or range: the zoom's θ box
                // no longer applies.
                let axis_moved = (key.param, key.range) != (sent.0.param, sent.0.range);
                let stale = !zoom_only && (axis_moved || sent.1.is_some());
                out.zoom_stale = stale;
                let zoom = if stale { None } else { shown.sweep_zoom };
                let changed_at = *self.sweep_changed_at.get_or_insert(now);
                let debounce = JobKind::Sweep.debounce();
                if zoom_only || now - changed_at >= debounce {
                    self.restart_sweep(s, zoom);
                } else {
                    out.wait(debounce - (now - changed_at));
                }
            }
            _ => {}
        }
        self.sync_basins(s, &shown, &mut out);
        out.zoom_stale |= diagram_stale && shown.sweep_zoom.is_some();
        let running = self.phase.state == JobState::Running;
        match self
            .phase_policy
            .step(PhaseKey::of(s), shown.phase, running, now)
        {
            PhaseStep::Start => self.restart_phase(s),
            PhaseStep::Cancel => self.cancel_phase(),
            PhaseStep::WaitFor(w) => out.wait(w),
            PhaseStep::Nothing => {}
        }
        out
    }

    /// Whether everything a picture of the orbit views needs has arrived.
    pub fn complete(&self, min_cycles: usize) -> bool {
        let traj_ok = self.trajectory.data.events.len() >= min_cycles
            || matches!(self.trajectory.state, JobState::Done);
        let it_ok = !matches!(self.iterate.state, JobState::Running | JobState::Idle);
        let sweep_ok = !matches!(self.sweep.state, JobState::Running | JobState::Idle);
        traj_ok && it_ok && sweep_ok
    }

    /// Whether the Numerics view's measurement has ended (a failed or
    /// stopped one counts: its view shows why).
    pub fn numerics_settled(&self) -> bool {
        self.numerics.issued() && self.numerics.state != JobState::Running
    }
}

impl Drop for Jobs {
    fn drop(&mut self) {
        // Stop every lane promptly; the worker's own Drop joins its threads.
        self.backend.send(Command::Cancel {
            generation: self.next_generation,
            lane: None,
        });
    }
}
