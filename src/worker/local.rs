//! The worker without threads: the same commands and updates as
//! [`super::Worker`], its jobs run on the caller's thread by
//! [`crate::jobs::Local`], a few units at a time within the budget of each
//! [`LocalWorker::pump`]. A browser build has no threads and runs the window
//! this way, pumping once per frame; the numbers are the threaded worker's,
//! bit for bit (the jobs' plans do not depend on their host).
//!
//! Generations work as in the threaded worker: a job starts only if its
//! generation is not older than its lane's, a newer one supersedes it (its
//! `Finished { Cancelled }` is queued first), and after a `Cancelled`
//! acknowledgement nothing older of that lane follows.

use std::collections::VecDeque;
use std::time::Duration;
use web_time::Instant;

use super::Command;
use super::orders::{Latest, Order};
use crate::jobs::{Generation, Lane, Local, Shape, Spec, TimeSlice, Update};

/// The most updates kept waiting for the front end: a front end that stops
/// draining stops the jobs' progress instead of growing the queue.
const QUEUE_LIMIT: usize = 4096;

/// One lane: its current generation and its job, if one runs.
#[derive(Default)]
struct LocalLane {
    current: Generation,
    job: Option<Local>,
}

/// The single-threaded worker.
pub struct LocalWorker {
    lanes: Vec<LocalLane>,
    latest: Latest,
    queue: VecDeque<Update>,
    shape: Shape,
    /// Units a job runs per step (1: the finest slices of time).
    width: usize,
    /// Where the round-robin over the lanes goes on.
    next_lane: usize,
    stopped: bool,
    /// Lanes whose jobs are dropped unrun (a headless figure of one view
    /// needs only that view's jobs).
    skip: Vec<Lane>,
    /// Threads a parallel job runs on at once, to its end; `None`: every
    /// job stepped a slice at a time (the page's host).
    threads: Option<usize>,
}

impl Default for LocalWorker {
    fn default() -> Self {
        LocalWorker::new(Shape::default(), 1)
    }
}

impl LocalWorker {
    /// A worker whose progressive jobs have plans of `shape` and run
    /// `width` units per step.
    pub fn new(shape: Shape, width: usize) -> Self {
        LocalWorker {
            lanes: Lane::ALL.iter().map(|_| LocalLane::default()).collect(),
            latest: Latest::default(),
            queue: VecDeque::new(),
            shape,
            width: width.max(1),
            next_lane: 0,
            stopped: false,
            skip: Vec::new(),
            threads: None,
        }
    }

    /// The same worker, running each parallel job (a diagram's columns,
    /// a grid's rows, the Basins columns) to its end on `threads` threads
    /// at once instead of a slice at a time: a headless figure's host on a
    /// machine with threads. The numbers are the same.
    pub fn with_threads(mut self, threads: usize) -> Self {
        self.threads = Some(threads.max(1));
        self
    }

    /// The same worker, dropping the jobs of `lanes` unrun (no update of
    /// theirs ever comes).
    pub fn skipping(mut self, lanes: Vec<Lane>) -> Self {
        self.skip = lanes;
        self
    }

    /// Takes a command (never blocks); false once shut down.
    pub fn send(&mut self, cmd: Command) -> bool {
        if self.stopped {
            return false;
        }
        for order in self.latest.orders(cmd) {
            match order {
                Order::Shutdown => {
                    for lane in Lane::ALL {
                        if let Some(mut job) = self.lanes[lane.index()].job.take() {
                            job.cancel();
                        }
                    }
                    self.stopped = true;
                }
                Order::Start(generation, spec) => self.start(generation, spec),
                Order::StopRunning(lane, generation) => {
                    if self.lanes[lane.index()].job.is_some() {
                        self.cancel(&[lane], generation, Some(lane));
                    }
                }
                Order::Cancel(lanes, generation, ack) => self.cancel(&lanes, generation, ack),
            }
        }
        true
    }

    /// The next update, if one is queued.
    pub fn try_recv(&mut self) -> Option<Update> {
        self.queue.pop_front()
    }

    /// Runs the lanes' jobs, a step at a time in turn, until `budget` has
    /// passed or none is left (at least one step if any runs); true while
    /// jobs remain.
    pub fn pump(&mut self, budget: Duration) -> bool {
        let slice = TimeSlice::from_now(budget);
        let n = self.lanes.len();
        while self.busy() && self.queue.len() < QUEUE_LIMIT {
            let i = self.next_lane % n;
            self.next_lane = (i + 1) % n;
            let Some(job) = self.lanes[i].job.as_mut() else {
                continue;
            };
            let more = if let Some(threads) = self.threads {
                job.step_threads(self.width, threads)
            } else {
                job.step_until(self.width, Some(slice))
            };
            self.queue.extend(job.drain());
            if !more {
                self.lanes[i].job = None;
            }
            if Instant::now() >= slice.end {
                break;
            }
        }
        self.busy()
    }

    /// Whether any job runs.
    pub fn busy(&self) -> bool {
        self.lanes.iter().any(|l| l.job.is_some())
    }

    /// Updates queued for the front end.
    pub fn queued(&self) -> usize {
        self.queue.len()
    }

    /// Starts `spec` on its lane under `generation`, superseding the lane's
    /// job, unless the generation is older than the lane's (or is the
    /// running job's own).
    fn start(&mut self, generation: Generation, spec: Spec) {
        let lane = spec.lane();
        if self.skip.contains(&lane) {
            return;
        }
        let slot = &mut self.lanes[lane.index()];
        if generation < slot.current || (generation == slot.current && slot.job.is_some()) {
            return;
        }
        if let Some(mut old) = slot.job.take() {
            old.cancel();
            self.queue.extend(old.drain());
        }
        slot.current = generation;
        self.latest.started(&spec);
        let job = Local::start(spec, generation, self.shape);
        let slot = &mut self.lanes[lane.index()];
        if job.is_done() {
            // It did not validate: its Error and Finished are queued.
            let mut job = job;
            self.queue.extend(job.drain());
        } else {
            slot.job = Some(job);
        }
    }

    /// Stops the jobs of `lanes` (each gets its `Finished { Cancelled }`)
    /// and acknowledges with `Cancelled { generation, lane: ack }`.
    fn cancel(&mut self, lanes: &[Lane], generation: Generation, ack: Option<Lane>) {
        for &lane in lanes {
            let slot = &mut self.lanes[lane.index()];
            if generation < slot.current {
                continue;
            }
            if let Some(mut job) = slot.job.take() {
                job.cancel();
                self.queue.extend(job.drain());
            }
            slot.current = generation;
        }
        self.queue.push_back(Update::Cancelled {
            generation,
            lane: ack,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jobs::{Axis, Outcome, SweepSpec, TrajectorySpec};
    use crate::model::Params;
    use crate::sim::{MapChoice, default_settings};

    fn trajectory(generation: Generation, cycles: usize) -> Command {
        Command::run(
            generation,
            TrajectorySpec {
                params: Params::default(),
                settings: default_settings(1e-8),
                theta0: None,
                transient: 0,
                spacing: 0.05,
                cycles: Some(cycles),
                max_samples: None,
            },
        )
    }

    fn drain(w: &mut LocalWorker) -> Vec<Update> {
        std::iter::from_fn(|| w.try_recv()).collect()
    }

    #[test]
    fn a_newer_job_supersedes_and_nothing_older_follows_a_cancel() {
        let mut w = LocalWorker::default();
        assert!(w.send(trajectory(1, 1000)));
        w.pump(Duration::ZERO);
        assert!(w.send(trajectory(2, 3)));
        while w.pump(Duration::from_millis(5)) {}
        let ups = drain(&mut w);
        let fin: Vec<(Generation, Outcome)> = ups
            .iter()
            .filter_map(|u| match u {
                Update::Finished {
                    generation,
                    outcome,
                    ..
                } => Some((*generation, outcome.clone())),
                _ => None,
            })
            .collect();
        assert_eq!(
            fin,
            [(1, Outcome::Cancelled), (2, Outcome::Completed)],
            "{ups:?}"
        );
        let slips_of_2 = ups
            .iter()
            .filter(|u| matches!(u, Update::Slip { generation: 2, .. }))
            .count();
        assert_eq!(slips_of_2, 3);
        // An older generation is refused; a cancel is acknowledged last.
        assert!(w.send(trajectory(1, 3)));
        assert!(!w.busy());
        assert!(w.send(trajectory(3, 1000)));
        w.pump(Duration::ZERO);
        assert!(w.send(Command::Cancel {
            generation: 4,
            lane: None
        }));
        let ups = drain(&mut w);
        assert!(matches!(
            ups.last(),
            Some(Update::Cancelled {
                generation: 4,
                lane: None
            })
        ));
        assert!(!w.pump(Duration::from_millis(5)));
        assert!(drain(&mut w).is_empty());
    }

    #[test]
    fn new_parameters_run_the_latest_sweep_again() {
        let mut w = LocalWorker::new(Shape::default(), 4);
        let spec = SweepSpec {
            params: Params::default(),
            settings: default_settings(1e-6),
            param: crate::sim::continuation::ContParam::ThetaNu,
            axis: Axis::new(0.5, 1.0, 6),
            transient: 20,
            keep: 5,
            map: MapChoice::Auto,
            theta0: None,
            seeds: 0,
        };
        assert!(w.send(Command::run(1, spec)));
        let params = Params {
            kappa: 12.0,
            ..Params::default()
        };
        assert!(w.send(Command::SetParams {
            generation: 2,
            params,
            settings: None,
        }));
        while w.pump(Duration::from_millis(5)) {}
        let ups = drain(&mut w);
        let columns = ups
            .iter()
            .filter(|u| matches!(u, Update::Column { generation: 2, .. }))
            .count();
        assert_eq!(columns, 6);
        assert!(ups.iter().any(|u| matches!(
            u,
            Update::Finished {
                generation: 2,
                outcome: Outcome::Completed,
                ..
            }
        )));
    }
}
