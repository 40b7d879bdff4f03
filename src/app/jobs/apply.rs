//! What the worker sends back, applied to the job it belongs to: each
//! update lands in the slot whose generation it names (the Numerics view's
//! job like every other), or is dropped as stale.

use super::{JobKind, JobState, Jobs, LaneProgress, NO_GENERATION, SlotHead};
use crate::worker::{Generation, Outcome, Update};

/// The most updates taken from the worker in one frame.
const MAX_UPDATES_PER_FRAME: usize = 20_000;

impl Jobs {
    /// The state of the job of `kind`.
    pub fn state(&self, kind: JobKind) -> &JobState {
        &self.slot(kind).state
    }

    /// The bookkeeping of the job of `kind`, whatever its data.
    pub(super) fn slot(&self, kind: JobKind) -> &SlotHead {
        self.slots.head(kind)
    }

    pub(super) fn slot_mut(&mut self, kind: JobKind) -> &mut SlotHead {
        self.slots.head_mut(kind)
    }

    /// Which current job `generation` belongs to, if any.
    fn job_of(&self, generation: Generation) -> Option<JobKind> {
        JobKind::ALL
            .into_iter()
            .find(|&k| generation != NO_GENERATION && self.slot(k).generation == generation)
    }

    /// Lets a backend without threads run its jobs for about `budget`;
    /// true while work remains.
    pub fn pump(&mut self, budget: std::time::Duration) -> bool {
        self.backend.pump(budget)
    }

    /// Takes what the worker sent (at most a frame's worth) and chains the
    /// orbit analysis; returns whether more may be waiting.
    pub fn receive(&mut self) -> bool {
        let mut n = 0;
        let mut more = false;
        while let Some(u) = self.backend.try_recv() {
            self.apply(u);
            n += 1;
            if n >= MAX_UPDATES_PER_FRAME {
                more = true;
                break;
            }
        }
        self.chain_iterate();
        more
    }

    /// Applies one update; returns false if it was stale and dropped.
    pub fn apply(&mut self, u: Update) -> bool {
        let Some(job) = self.job_of(u.generation()) else {
            self.stale_dropped += 1;
            return false;
        };
        match u {
            Update::Progress { .. }
            | Update::Error { .. }
            | Update::Finished { .. }
            | Update::Cancelled { .. } => self.apply_status(job, u),
            data => self.apply_data(job, data),
        }
        true
    }

    /// A partial result of job `job` into its data.
    fn apply_data(&mut self, job: JobKind, u: Update) {
        let Some(u) = self.apply_orbit(job, u) else {
            return;
        };
        match u {
            Update::Summary { text, .. } => {
                self.slot_mut(job).summary = Some(text);
            }
            // Its data's own variants; an update of the right generation
            // but another kind's is dropped.
            u => {
                let _ = self.slots.receive(job, u);
            }
        }
    }

    /// The new trajectory's first update replaces the one held while θν
    /// plays.
    fn release_held_trajectory(&mut self) {
        if self.held.0 {
            self.held.0 = false;
            self.trajectory.stale = false;
            self.trajectory.data = crate::app::data::TrajectoryData::default();
        }
    }

    /// A partial result of an orbit job (trajectory or iterates) into its
    /// data; any other update is given back.
    fn apply_orbit(&mut self, job: JobKind, u: Update) -> Option<Update> {
        match u {
            Update::TrajectoryChunk { samples, .. } if job == JobKind::Trajectory => {
                self.release_held_trajectory();
                self.trajectory.data.push_samples(samples);
                self.trajectory_revision += 1;
                None
            }
            Update::Slip { event, .. } if job == JobKind::Trajectory => {
                self.release_held_trajectory();
                self.trajectory.data.push_event(event);
                self.trajectory_revision += 1;
                None
            }
            Update::MapIterates {
                first_index,
                thetas,
                period,
                lyapunov,
                lyapunov_stderr,
                ..
            } if job == JobKind::Iterate => {
                if self.held.1 {
                    // The new orbit's first batch replaces the held one's
                    // iterates; the held graph stays until the new one
                    // comes, at the job's end.
                    self.held.1 = false;
                    self.iterate.stale = false;
                    let it = &mut self.iterate.data;
                    (it.thetas, it.period, it.lyapunov, it.lyapunov_stderr) =
                        (Vec::new(), None, None, None);
                }
                let it = &mut self.iterate.data;
                it.thetas.truncate(first_index);
                it.thetas.extend(thetas);
                it.period = Some(period);
                it.lyapunov = lyapunov;
                it.lyapunov_stderr = lyapunov_stderr;
                None
            }
            Update::MapGraph {
                thetas,
                values,
                powers,
                ..
            } if job == JobKind::Iterate => {
                self.iterate.data.powers = powers;
                self.iterate.data.graph = thetas
                    .into_iter()
                    .zip(values)
                    .map(|(t, v)| [t, v])
                    .collect();
                None
            }
            u => Some(u),
        }
    }

    /// How job `job` stands: its progress, an error, its end.
    fn apply_status(&mut self, job: JobKind, u: Update) {
        match u {
            Update::Progress {
                fraction,
                iterates_per_second,
                ..
            } => {
                self.slot_mut(job).progress = LaneProgress {
                    fraction,
                    iterates_per_second,
                };
            }
            Update::Error {
                message, parameter, ..
            } => {
                let named = match parameter {
                    Some(p) => format!("{p}: {message}"),
                    None => message.clone(),
                };
                match job {
                    // The Events view shows its own jobs' errors.
                    JobKind::Passage | JobKind::Scan => {
                        self.slot_mut(job).state = JobState::Failed(named);
                    }
                    // The Numerics view shows its own job's error.
                    JobKind::Numerics => {
                        self.numerics.data.error = Some(named);
                        self.numerics.state = JobState::Failed(message);
                    }
                    // A failed cell does not end the grid: its Finished says
                    // how the job ended; the view shows the message.
                    JobKind::Phase => {
                        self.phase.data.error = Some(named.clone());
                        self.last_error = Some(named);
                    }
                    _ => {
                        self.last_error = Some(named);
                        self.slot_mut(job).state = JobState::Failed(message);
                    }
                }
            }
            Update::Finished { outcome, .. } => {
                let state = match outcome {
                    Outcome::Completed => JobState::Done,
                    Outcome::Cancelled => JobState::Cancelled,
                    Outcome::Failed(m) => {
                        if !matches!(job, JobKind::Numerics | JobKind::Passage | JobKind::Scan) {
                            self.last_error = Some(m.clone());
                        }
                        JobState::Failed(m)
                    }
                };
                self.slot_mut(job).state = state;
                match job {
                    JobKind::Sweep => self.sweep.data.revision += 1,
                    JobKind::Phase => self.phase.data.revision += 1,
                    _ => {}
                }
            }
            Update::Cancelled { .. }
                if job == JobKind::Numerics && self.numerics.state == JobState::Running =>
            {
                self.numerics.state = JobState::Cancelled;
            }
            // An acknowledgement: nothing to do.
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::backend::Recorder;
    use crate::app::settings::Settings;
    use crate::integrate::{Method, SolverSettings};
    use crate::numerics::Subject;
    use crate::worker::{Command, Lane, Spec};

    fn row() -> crate::numerics::Row {
        crate::numerics::measure(
            &[],
            &Subject::Own(SolverSettings::adaptive(Method::Dop853, 1e-6)),
            std::time::Duration::ZERO,
        )
    }

    #[test]
    fn the_numerics_job_takes_its_own_updates_and_drops_older_ones() {
        let rec = Recorder::new();
        let mut jobs = Jobs::new(Box::new(rec.clone()));
        let s = Settings::default();
        jobs.start_work_precision(&s);
        let g = rec
            .commands()
            .iter()
            .find_map(|c| match c {
                Command::Run {
                    generation,
                    spec: Spec::Numerics(..),
                } => Some(*generation),
                _ => None,
            })
            .expect("the measurement was sent");
        let mine = Update::WorkPrecisionRow {
            generation: g,
            index: 0,
            total: 2,
            row: row(),
        };
        assert!(jobs.apply(mine));
        let older = Update::WorkPrecisionRow {
            generation: g - 1,
            index: 1,
            total: 2,
            row: row(),
        };
        assert!(!jobs.apply(older), "an older run's row is dropped");
        assert_eq!(jobs.numerics.data.rows.len(), 1);
        assert_eq!(jobs.stale_dropped, 1);
        // Its error is the view's own, not the status bar's.
        jobs.apply(Update::Error {
            generation: g,
            lane: Lane::Numerics,
            message: "kappa = -1 is out of range".into(),
            parameter: Some("kappa"),
        });
        assert_eq!(
            jobs.numerics.data.error.as_deref(),
            Some("kappa: kappa = -1 is out of range")
        );
        assert!(matches!(jobs.numerics.state, JobState::Failed(_)));
        assert_eq!(jobs.last_error, None);
        // Stopped: anything later of the stopped run is dropped.
        jobs.stop(JobKind::Numerics);
        assert!(!jobs.apply(Update::WorkPrecisionRow {
            generation: g,
            index: 1,
            total: 2,
            row: row(),
        }));
        assert_eq!(jobs.numerics.data.rows.len(), 1);
    }

    #[test]
    fn a_failed_phase_cell_does_not_end_the_grid_but_a_failed_sweep_does() {
        let rec = Recorder::new();
        let mut jobs = Jobs::new(Box::new(rec.clone()));
        let s = Settings::default();
        jobs.restart_phase(&s);
        jobs.restart_sweep(&s, None);
        let (gp, gs) = (jobs.phase.generation, jobs.sweep.generation);
        for (g, lane) in [(gp, Lane::Phase), (gs, Lane::Sweep)] {
            jobs.apply(Update::Error {
                generation: g,
                lane,
                message: "bad cell".into(),
                parameter: None,
            });
        }
        assert_eq!(jobs.phase.state, JobState::Running);
        assert_eq!(jobs.phase.data.error.as_deref(), Some("bad cell"));
        assert_eq!(jobs.sweep.state, JobState::Failed("bad cell".into()));
        assert_eq!(jobs.last_error.as_deref(), Some("bad cell"));
        // Progress lands in the job's own slot.
        jobs.apply(Update::Progress {
            generation: gs,
            lane: Lane::Sweep,
            fraction: 0.5,
            iterates_per_second: 1e4,
        });
        assert_eq!(jobs.sweep.progress.fraction, 0.5);
        assert_eq!(jobs.phase.progress.fraction, 0.0);
    }
}
