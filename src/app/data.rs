//! What the worker has sent for the current jobs: the trajectory, its slip
//! events, the map iterates with their analysis, the bifurcation columns
//! and the phase-diagram cells. Updates of an older generation than the
//! latest issued for their job are dropped here.

use super::phase_data::PhaseData;
use crate::sim::{Period, Sample, SlipEvent};
use crate::worker::{Generation, Lane, Outcome, Update};

/// The kinds of job the window runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Job {
    Trajectory,
    Iterate,
    Sweep,
    Phase,
}

/// Where a job stands.
#[derive(Clone, Debug, PartialEq, Default)]
pub enum JobState {
    #[default]
    Idle,
    Running,
    Done,
    Cancelled,
    Failed(String),
}

/// The most samples and events kept (a rolling window: an endless
/// trajectory keeps the newest; the view shows the last cycles only).
const MAX_SAMPLES: usize = 2_000_000;
const MAX_EVENTS: usize = 200_000;

/// The trajectory job's results.
#[derive(Clone, Debug, Default)]
pub struct TrajectoryData {
    pub samples: Vec<Sample>,
    pub events: Vec<SlipEvent>,
    pub state: JobState,
    /// The oldest samples or events were dropped to stay under the caps.
    pub truncated: bool,
}

/// The iterate job's results.
#[derive(Clone, Debug, Default)]
pub struct IterateData {
    pub thetas: Vec<f64>,
    /// Points (θ, f(θ)) of the map's graph over the orbit's window (NaN
    /// where a cycle failed), once the job has drawn it.
    pub graph: Vec<[f64; 2]>,
    pub period: Option<Period>,
    pub lyapunov: Option<f64>,
    pub state: JobState,
}

/// The sweep job's results: one slot per column of the final grid.
#[derive(Clone, Debug, Default)]
pub struct SweepData {
    /// θν range of the sweep.
    pub from: f64,
    pub to: f64,
    pub columns: Vec<Option<Column>>,
    pub filled: usize,
    pub state: JobState,
    /// Bumped on every change, so views rebuild only when it moves.
    pub revision: u64,
}

/// One received column.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    pub theta_nu: f64,
    pub thetas: Vec<f64>,
    pub coarse: bool,
}

impl SweepData {
    pub fn new(from: f64, to: f64, columns: usize) -> Self {
        SweepData {
            from,
            to,
            columns: vec![None; columns],
            filled: 0,
            state: JobState::Running,
            revision: 0,
        }
    }

    /// How many points the diagram holds.
    pub fn points(&self) -> usize {
        self.columns.iter().flatten().map(|c| c.thetas.len()).sum()
    }
}

/// Progress of one lane, as the worker last reported it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LaneProgress {
    pub fraction: f64,
    pub iterates_per_second: f64,
}

/// Everything received, with the generations that are current.
#[derive(Clone, Debug, Default)]
pub struct Data {
    pub trajectory_gen: Generation,
    pub iterate_gen: Generation,
    pub sweep_gen: Generation,
    pub phase_gen: Generation,
    pub trajectory: TrajectoryData,
    pub iterate: IterateData,
    pub sweep: SweepData,
    pub phase: PhaseData,
    pub orbit_progress: LaneProgress,
    pub sweep_progress: LaneProgress,
    pub phase_progress: LaneProgress,
    /// The last error the worker reported, with the parameter it names.
    pub last_error: Option<String>,
    /// Updates dropped as stale (for the status bar and tests).
    pub stale_dropped: u64,
    /// Bumped whenever the trajectory changes.
    pub trajectory_revision: u64,
}

impl Data {
    /// Starts a new trajectory job under `generation`.
    pub fn start_trajectory(&mut self, generation: Generation) {
        self.trajectory_gen = generation;
        self.trajectory = TrajectoryData {
            state: JobState::Running,
            ..Default::default()
        };
        self.trajectory_revision += 1;
    }

    pub fn start_iterate(&mut self, generation: Generation) {
        self.iterate_gen = generation;
        self.iterate = IterateData {
            state: JobState::Running,
            ..Default::default()
        };
    }

    pub fn start_sweep(&mut self, generation: Generation, from: f64, to: f64, columns: usize) {
        let revision = self.sweep.revision + 1;
        self.sweep_gen = generation;
        self.sweep = SweepData::new(from, to, columns);
        self.sweep.revision = revision;
    }

    pub fn start_phase(
        &mut self,
        generation: Generation,
        theta_nu: (f64, f64),
        kappa: (f64, f64),
        columns: usize,
        rows: usize,
    ) {
        let revision = self.phase.revision + 1;
        self.phase_gen = generation;
        self.phase = PhaseData::new(theta_nu, kappa, columns, rows);
        self.phase.revision = revision;
        self.phase_progress = LaneProgress::default();
    }

    /// Which current job `generation` belongs to, if any.
    fn job_of(&self, generation: Generation) -> Option<Job> {
        if generation == self.trajectory_gen {
            Some(Job::Trajectory)
        } else if generation == self.iterate_gen {
            Some(Job::Iterate)
        } else if generation == self.sweep_gen {
            Some(Job::Sweep)
        } else if generation == self.phase_gen {
            Some(Job::Phase)
        } else {
            None
        }
    }

    fn state_mut(&mut self, job: Job) -> &mut JobState {
        match job {
            Job::Trajectory => &mut self.trajectory.state,
            Job::Iterate => &mut self.iterate.state,
            Job::Sweep => &mut self.sweep.state,
            Job::Phase => &mut self.phase.state,
        }
    }

    /// Applies one update; returns false if it was stale and dropped.
    pub fn apply(&mut self, u: Update) -> bool {
        let Some(job) = self.job_of(u.generation()) else {
            self.stale_dropped += 1;
            return false;
        };
        match u {
            Update::TrajectoryChunk { samples, .. } if job == Job::Trajectory => {
                let t = &mut self.trajectory;
                if t.samples.len() + samples.len() > MAX_SAMPLES {
                    // A rolling window: the oldest half goes, the view keeps
                    // following the newest cycles.
                    t.samples.drain(..t.samples.len() / 2);
                    t.truncated = true;
                }
                t.samples.extend(samples);
                self.trajectory_revision += 1;
            }
            Update::Slip { event, .. } if job == Job::Trajectory => {
                let evs = &mut self.trajectory.events;
                if evs.len() >= MAX_EVENTS {
                    evs.drain(..MAX_EVENTS / 2);
                    self.trajectory.truncated = true;
                }
                evs.push(event);
                self.trajectory_revision += 1;
            }
            Update::MapIterates {
                first_index,
                thetas,
                period,
                lyapunov,
                ..
            } if job == Job::Iterate => {
                let it = &mut self.iterate;
                it.thetas.truncate(first_index);
                it.thetas.extend(thetas);
                it.period = Some(period);
                it.lyapunov = lyapunov;
            }
            Update::MapGraph { thetas, values, .. } if job == Job::Iterate => {
                self.iterate.graph = thetas
                    .into_iter()
                    .zip(values)
                    .map(|(t, v)| [t, v])
                    .collect();
            }
            Update::Column {
                index,
                theta_nu,
                thetas,
                coarse,
                ..
            } if job == Job::Sweep => {
                let s = &mut self.sweep;
                if let Some(slot) = s.columns.get_mut(index) {
                    if slot.is_none() {
                        s.filled += 1;
                    }
                    *slot = Some(Column {
                        theta_nu,
                        thetas,
                        coarse,
                    });
                    s.revision += 1;
                }
            }
            Update::PhaseCells { cells, coarse, .. } if job == Job::Phase => {
                self.phase.insert(cells, coarse);
            }
            Update::Progress {
                lane,
                fraction,
                iterates_per_second,
                ..
            } => {
                let p = LaneProgress {
                    fraction,
                    iterates_per_second,
                };
                match lane {
                    Lane::Orbit => self.orbit_progress = p,
                    Lane::Sweep => self.sweep_progress = p,
                    // The Numerics view keeps its own job's progress.
                    Lane::Numerics => {}
                    Lane::Phase => self.phase_progress = p,
                }
            }
            Update::Error {
                message, parameter, ..
            } => {
                self.last_error = Some(match parameter {
                    Some(p) => format!("{p}: {message}"),
                    None => message.clone(),
                });
                if job == Job::Phase {
                    // A failed cell does not end the grid: its Finished says
                    // how the job ended; the view shows the message.
                    self.phase.error = self.last_error.clone();
                } else {
                    *self.state_mut(job) = JobState::Failed(message);
                }
            }
            Update::Finished { outcome, .. } => {
                let state = match outcome {
                    Outcome::Completed => JobState::Done,
                    Outcome::Cancelled => JobState::Cancelled,
                    Outcome::Failed(m) => {
                        self.last_error = Some(m.clone());
                        JobState::Failed(m)
                    }
                };
                *self.state_mut(job) = state;
                match job {
                    Job::Sweep => self.sweep.revision += 1,
                    Job::Phase => self.phase.revision += 1,
                    _ => {}
                }
            }
            Update::Cancelled { .. } => {}
            // An update of the right generation but the wrong kind: ignore.
            _ => {}
        }
        true
    }

    /// The orbit's period as the iterate job detected it, or from the
    /// trajectory's events when no iterate job reported yet.
    pub fn period(&self) -> Option<Period> {
        self.iterate.period
    }

    /// Whether everything the window asked for has arrived.
    pub fn complete(&self, min_cycles: usize) -> bool {
        let traj_ok = self.trajectory.events.len() >= min_cycles
            || matches!(self.trajectory.state, JobState::Done);
        let it_ok = !matches!(self.iterate.state, JobState::Running | JobState::Idle);
        let sweep_ok = !matches!(self.sweep.state, JobState::Running | JobState::Idle);
        traj_ok && it_ok && sweep_ok
    }
}
