//! The orbit lane's trajectory job (one slip cycle a unit), the pacing of
//! progress every job shares, and the test fault. The map iterates are
//! [`super::iterate`]'s.

use std::sync::Mutex;
use std::time::Duration;
use web_time::Instant;

use super::protocol::{TrajectorySpec, Update};
use super::{Job, JobError, Sink, Status, Stop, lock};
use crate::model::{ParamError, Params};
use crate::sim::{Sampler, SimError, Simulator, default_settings};

/// Most samples in one `TrajectoryChunk` (a slip sampled finely is split).
pub const CHUNK_SAMPLES: usize = 1024;
/// The finest sampling a trajectory accepts: finer than any plot needs.
/// A slip lasts O(1–10) time units, so this is up to ~10⁷ samples per
/// slip: a caller that may ask for it caps the path
/// (`TrajectorySpec::max_samples`).
pub const MIN_SPACING: f64 = 1e-6;
/// `MapIterates` go out every this many kept iterates …
pub const ITERATE_BATCH: usize = 16;
/// … or at least this often, whichever comes first.
pub const FLUSH_INTERVAL: Duration = Duration::from_millis(50);
/// Onsets at which an iterate job draws the graph of f.
pub const GRAPH_POINTS: usize = 200;
/// `Progress` goes out at most this often per job.
pub const PROGRESS_INTERVAL: Duration = Duration::from_millis(50);

/// Sends `Progress` no more often than `PROGRESS_INTERVAL`.
pub(crate) struct Pacer {
    start: Instant,
    last: Instant,
}

impl Pacer {
    pub fn new() -> Self {
        let now = Instant::now();
        Pacer {
            start: now,
            last: now,
        }
    }

    /// Whether a progress update is due (and if so, restarts the interval).
    pub fn due(&mut self) -> bool {
        let now = Instant::now();
        if now - self.last >= PROGRESS_INTERVAL {
            self.last = now;
            true
        } else {
            false
        }
    }

    /// Iterates per second for `n` iterates since the start.
    pub fn rate(&self, n: u64) -> f64 {
        let s = self.start.elapsed().as_secs_f64();
        if s > 0.0 { n as f64 / s } else { 0.0 }
    }
}

/// Sends a progressive job's `Progress` (`done` of `total` units after `n`
/// iterates), at most every `PROGRESS_INTERVAL` and at the end.
pub(crate) fn paced_progress(
    pacer: &std::sync::Mutex<Pacer>,
    (done, total, n): (usize, usize, u64),
    sink: &dyn Sink,
) -> Result<(), JobError> {
    let rate = {
        let mut pc = lock(pacer);
        (pc.due() || done == total).then(|| pc.rate(n))
    };
    if let Some(iterates_per_second) = rate {
        sink.send(Update::Progress {
            generation: sink.generation(),
            lane: sink.lane(),
            fraction: done as f64 / total as f64,
            iterates_per_second,
        })?;
    }
    Ok(())
}

/// Polls `sink` before a cycle: `Err` when the job must stop.
fn poll(sink: &dyn Sink) -> Result<(), JobError> {
    if sink.cycle() {
        Err(Stop::Stale.into())
    } else {
        Ok(())
    }
}

/// Sends the job's progress: `fraction` done after `n` iterates.
pub(crate) fn progress(
    sink: &dyn Sink,
    fraction: f64,
    pacer: &Pacer,
    n: u64,
) -> Result<(), JobError> {
    sink.send(Update::Progress {
        generation: sink.generation(),
        lane: sink.lane(),
        fraction,
        iterates_per_second: pacer.rate(n),
    })?;
    Ok(())
}

/// A trajectory: the block followed cycle by cycle, its sampled path and
/// each slip event streamed; a unit is one slip cycle (a transient's cycle
/// sends nothing).
pub(crate) struct TrajectoryJob {
    sim: Simulator,
    transient: usize,
    cycles: Option<usize>,
    max_samples: Option<usize>,
    state: Mutex<TrajectoryState>,
}

struct TrajectoryState {
    theta: f64,
    t: f64,
    /// Cycles done, the transient's included.
    done: usize,
    /// Samples sent so far.
    recorded: usize,
    sampler: Sampler,
    pacer: Pacer,
}

impl TrajectoryJob {
    pub fn new(spec: TrajectorySpec) -> Result<Self, JobError> {
        let TrajectorySpec {
            params,
            settings,
            theta0,
            transient,
            spacing,
            cycles,
            max_samples,
        } = spec;
        let sim = Simulator::new(params, settings)?;
        if !(spacing.is_finite() && spacing >= MIN_SPACING) {
            return Err(SimError::from(ParamError::new(
                "spacing",
                spacing,
                "must be a finite number >= 1e-6",
            ))
            .into());
        }
        let theta = theta0.unwrap_or(params.theta_nu);
        sim.check_onset(theta)?;
        Ok(TrajectoryJob {
            sim,
            transient,
            cycles,
            max_samples,
            state: Mutex::new(TrajectoryState {
                theta,
                t: 0.0,
                done: 0,
                recorded: 0,
                sampler: Sampler::new(spacing),
                pacer: Pacer::new(),
            }),
        })
    }

    /// Cycles in all (`usize::MAX`: until stopped).
    fn total(&self) -> usize {
        self.cycles
            .map_or(usize::MAX, |c| c.saturating_add(self.transient))
    }

    /// One slip cycle: a transient's, or its samples (in chunks), then its
    /// event.
    fn one(&self, st: &mut TrajectoryState, sink: &dyn Sink) -> Result<(), JobError> {
        poll(sink)?;
        if st.done < self.transient {
            // As the path does not start before it, the transient's time
            // stays at 0.
            let ev = self.sim.cycle(st.theta, 0.0, None)?;
            st.theta = self.sim.next_onset(&ev);
            st.done += 1;
            return self.paced(st, sink);
        }
        let generation = sink.generation();
        if let Some(max) = self.max_samples {
            st.sampler.set_limit(max.saturating_sub(st.recorded));
        }
        let ev = self.sim.cycle(st.theta, st.t, Some(&mut st.sampler))?;
        if st.sampler.dropped() > 0 {
            let limit = self.max_samples.unwrap_or(usize::MAX);
            return Err(SimError::TooManySamples { limit }.into());
        }
        let samples = st.sampler.take();
        st.recorded += samples.len();
        if samples.len() <= CHUNK_SAMPLES {
            sink.send(Update::TrajectoryChunk {
                generation,
                samples,
            })?;
        } else {
            for c in samples.chunks(CHUNK_SAMPLES) {
                let samples = c.to_vec();
                sink.send(Update::TrajectoryChunk {
                    generation,
                    samples,
                })?;
            }
        }
        sink.send(Update::Slip {
            generation,
            event: ev,
        })?;
        st.t += ev.slip_duration + ev.stick_duration;
        st.theta = self.sim.next_onset(&ev);
        st.done += 1;
        self.paced(st, sink)
    }

    /// The progress of a job with an end, when due.
    fn paced(&self, st: &mut TrajectoryState, sink: &dyn Sink) -> Result<(), JobError> {
        if self.cycles.is_some() && st.pacer.due() {
            let fraction = st.done as f64 / self.total() as f64;
            progress(sink, fraction, &st.pacer, st.done as u64)?;
        }
        Ok(())
    }
}

impl Job for TrajectoryJob {
    fn step(&self, width: usize, sink: &dyn Sink) -> Result<Status, JobError> {
        let mut st = lock(&self.state);
        let total = self.total();
        for _ in 0..width.max(1) {
            if st.done >= total {
                return Ok(Status::Done);
            }
            self.one(&mut st, sink)?;
        }
        Ok(if st.done >= total {
            Status::Done
        } else {
            Status::Working
        })
    }
}

/// Test-only fault injection: a few real cycles, then a panic.
pub(crate) struct PanicJob {
    after_cycles: usize,
}

impl PanicJob {
    pub fn new(after_cycles: usize) -> Self {
        PanicJob { after_cycles }
    }
}

impl Job for PanicJob {
    fn step(&self, _width: usize, sink: &dyn Sink) -> Result<Status, JobError> {
        let params = Params::default();
        let sim = Simulator::new(params, default_settings(1e-8))?;
        let mut theta = params.theta_nu;
        for _ in 0..self.after_cycles {
            poll(sink)?;
            let ev = sim.cycle(theta, 0.0, None)?;
            theta = sim.next_onset(&ev);
        }
        panic!("injected panic after {} cycles", self.after_cycles);
    }
}
