//! The single-threaded host: a job run on the caller's thread, a few units
//! per call, within a time budget. A browser build has no threads and runs
//! its jobs this way between frames; tests drive it deterministically.
//!
//! Updates queue in the host until [`Local::drain`] takes them; how the job
//! ended is queued last (`Error` if it failed, then `Finished`), as the
//! worker sends it.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;
use web_time::Instant;

use super::{Generation, Job, JobError, Lane, Outcome, Shape, Sink, Spec, Status, Stop, Update};
use super::{ending, lock};

/// A step's share of a frame: from `start` (when the frame's computing
/// began) to `end`. Units pause at its end; heavy pieces of them start only
/// in its first quarter, so that one does not begin just before the end
/// and hold the frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimeSlice {
    pub start: Instant,
    pub end: Instant,
}

impl TimeSlice {
    /// The slice from now for `budget`.
    pub fn from_now(budget: Duration) -> Self {
        let start = Instant::now();
        TimeSlice {
            start,
            end: start + budget,
        }
    }

    /// Whether a heavy piece starting at `now` would start too late.
    fn heavy_too_late(&self, now: Instant) -> bool {
        now >= self.end || (now - self.start) * 4 >= self.end - self.start
    }
}

/// One job on the caller's thread.
pub struct Local {
    lane: Lane,
    job: Option<Box<dyn Job>>,
    sink: Queue,
}

/// The host's sink: a queue, and a flag that stops the job.
struct Queue {
    generation: Generation,
    lane: Lane,
    /// A step has run with a slice of time ([`Sink::sliced`]).
    sliced: AtomicBool,
    updates: Mutex<Vec<Update>>,
    cancelled: AtomicBool,
    cycles: AtomicU64,
    /// The running step's slice of time ([`Sink::pause`]).
    slice: Mutex<Option<TimeSlice>>,
    /// How long the job's pieces take, as its pauses are polled.
    pace: Mutex<Pace>,
}

/// Steps whose longest piece the pace remembers.
const PACE_STEPS: usize = 16;

/// The longest piece of a job seen in this step and the [`PACE_STEPS`]
/// before it (a piece is the time between two polls of [`Sink::pause`]):
/// a piece that would end past the slice is not begun. A job's pieces
/// vary (a cell's iterates, then a solve's steps, then its cell graph's
/// levels), so one step's longest says too little.
#[derive(Clone, Copy, Debug)]
struct Pace {
    last_poll: Instant,
    this_step: Duration,
    /// The longest piece of each of the last steps, the oldest overwritten.
    before: [Duration; PACE_STEPS],
    next: usize,
}

impl Pace {
    fn new() -> Self {
        Pace {
            last_poll: Instant::now(),
            this_step: Duration::ZERO,
            before: [Duration::ZERO; PACE_STEPS],
            next: 0,
        }
    }

    /// A new step from `start`.
    fn begin(&mut self, start: Instant) {
        self.before[self.next] = self.this_step;
        self.next = (self.next + 1) % PACE_STEPS;
        self.this_step = Duration::ZERO;
        self.last_poll = start;
    }

    /// A poll at `now`: the longest piece seen lately, this one included.
    fn poll(&mut self, now: Instant) -> Duration {
        self.this_step = self.this_step.max(now - self.last_poll);
        self.last_poll = now;
        self.before.iter().fold(self.this_step, |m, &d| m.max(d))
    }
}

impl Sink for Queue {
    fn generation(&self) -> Generation {
        self.generation
    }

    fn lane(&self) -> Lane {
        self.lane
    }

    fn sliced(&self) -> bool {
        self.sliced.load(Ordering::Relaxed)
    }

    fn send(&self, update: Update) -> Result<(), Stop> {
        if self.stale() {
            return Err(Stop::Stale);
        }
        lock(&self.updates).push(update);
        Ok(())
    }

    fn stale(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }

    fn cycle(&self) -> bool {
        if self.stale() {
            return true;
        }
        self.cycles.fetch_add(1, Ordering::Relaxed);
        false
    }

    /// Past the slice's end, or so near it that a piece half as long
    /// again as the longest seen lately would end past it.
    fn pause(&self) -> bool {
        let Some(slice) = *lock(&self.slice) else {
            return false;
        };
        let now = Instant::now();
        let piece = lock(&self.pace).poll(now);
        // Half as long again: the next piece may be the longest yet.
        now + piece + piece / 2 >= slice.end
    }

    fn defer_heavy(&self) -> bool {
        lock(&self.slice).is_some_and(|s| s.heavy_too_late(Instant::now()))
    }
}

impl Local {
    /// The job of `spec` under `generation`, not yet stepped. A spec that
    /// does not validate ends at once (its `Error` and `Finished` queued).
    pub fn start(spec: Spec, generation: Generation, shape: Shape) -> Local {
        let lane = spec.lane();
        let mut host = Local {
            lane,
            job: None,
            sink: Queue {
                generation,
                lane,
                sliced: AtomicBool::new(false),
                updates: Mutex::new(Vec::new()),
                cancelled: AtomicBool::new(false),
                cycles: AtomicU64::new(0),
                slice: Mutex::new(None),
                pace: Mutex::new(Pace::new()),
            },
        };
        match catch_unwind(AssertUnwindSafe(|| spec.start(shape))) {
            Ok(Ok(job)) => host.job = Some(job),
            Ok(Err(e)) => host.end(Ok(Err(e))),
            Err(payload) => host.end(Err(payload)),
        }
        host
    }

    /// The lane of the job.
    pub fn lane(&self) -> Lane {
        self.lane
    }

    /// The generation it runs under.
    pub fn generation(&self) -> Generation {
        self.sink.generation
    }

    /// Whether the job has ended (completed, failed or cancelled).
    pub fn is_done(&self) -> bool {
        self.job.is_none()
    }

    /// Slip cycles the job has started.
    pub fn cycles(&self) -> u64 {
        self.sink.cycles.load(Ordering::Relaxed)
    }

    /// Runs units of `width` until `budget` has passed (at least one step,
    /// so a job always moves on; a unit that can pause stops at the
    /// budget's end); true once the job has ended.
    pub fn run_for(&mut self, budget: Duration, width: usize) -> bool {
        let slice = TimeSlice::from_now(budget);
        while self.job.is_some() {
            if !self.step_until(width, Some(slice)) || Instant::now() >= slice.end {
                break;
            }
        }
        self.is_done()
    }

    /// One step of `width` units, each run whole; false once the job has
    /// ended.
    pub fn step(&mut self, width: usize) -> bool {
        self.step_until(width, None)
    }

    /// One step of `width` units, a unit that can pause stopping at the
    /// end of `slice` (to resume on the next step); false once the job has
    /// ended.
    pub fn step_until(&mut self, width: usize, slice: Option<TimeSlice>) -> bool {
        let Some(job) = self.job.as_ref() else {
            return false;
        };
        let sink = &self.sink;
        *lock(&sink.slice) = slice;
        if let Some(slice) = slice {
            sink.sliced.store(true, Ordering::Relaxed);
            lock(&sink.pace).begin(slice.start);
        }
        let stepped = catch_unwind(AssertUnwindSafe(|| job.step(width, sink)));
        *lock(&sink.slice) = None;
        let result = match stepped {
            Ok(Ok(Status::Working)) => return true,
            Ok(Ok(Status::Done)) => Ok(job.finish(sink)),
            Ok(Err(e)) => Ok(Err(e)),
            Err(payload) => Err(payload),
        };
        self.end(result);
        false
    }

    /// Runs a parallel job ([`Job::parallel`]) to its end on `threads`
    /// scoped threads at once (this one and `threads − 1` more, as
    /// [`super::run_threads`] does; no unit pauses); any other job one
    /// step of `width` units. False once the job has ended. Every host
    /// computes the same numbers, whatever its threads.
    pub fn step_threads(&mut self, width: usize, threads: usize) -> bool {
        let Some(job) = self.job.as_ref() else {
            return false;
        };
        if !job.parallel() {
            return self.step_until(width, None);
        }
        let sink = &self.sink;
        let drive = || -> Result<(), JobError> {
            while job.step(width, sink)? == Status::Working {}
            Ok(())
        };
        let ran = catch_unwind(AssertUnwindSafe(|| {
            std::thread::scope(|scope| {
                let others: Vec<_> = (1..threads).map(|_| scope.spawn(drive)).collect();
                let mine = drive();
                let theirs = others.into_iter().map(|h| {
                    h.join()
                        .unwrap_or_else(|payload| std::panic::resume_unwind(payload))
                });
                // The first error, once every thread has stopped.
                let errors: Vec<JobError> = theirs.filter_map(Result::err).collect();
                mine.and(errors.into_iter().next().map_or(Ok(()), Err))
            })
        }));
        let result = match ran {
            Ok(Ok(())) => Ok(job.finish(sink)),
            Ok(Err(e)) => Ok(Err(e)),
            Err(payload) => Err(payload),
        };
        self.end(result);
        false
    }

    /// Runs the job to its end and returns every update (tests).
    pub fn run_to_end(mut self, width: usize) -> Vec<Update> {
        while self.step(width) {}
        self.drain()
    }

    /// Stops the job: nothing more of it is queued but its
    /// `Finished{Cancelled}`.
    pub fn cancel(&mut self) {
        if self.job.take().is_some() {
            self.sink.cancelled.store(true, Ordering::Relaxed);
            lock(&self.sink.updates).push(Update::Finished {
                generation: self.sink.generation,
                lane: self.lane,
                outcome: Outcome::Cancelled,
            });
        }
    }

    /// The updates queued so far, in order.
    pub fn drain(&mut self) -> Vec<Update> {
        std::mem::take(&mut *lock(&self.sink.updates))
    }

    /// Ends the job with how it ended.
    fn end(&mut self, result: std::thread::Result<Result<(), JobError>>) {
        self.job = None;
        let Some((error, outcome)) = ending(result) else {
            return;
        };
        let generation = self.sink.generation;
        let mut q = lock(&self.sink.updates);
        if let Some((message, parameter)) = error {
            q.push(Update::Error {
                generation,
                lane: self.lane,
                message,
                parameter,
            });
        }
        q.push(Update::Finished {
            generation,
            lane: self.lane,
            outcome,
        });
    }
}
