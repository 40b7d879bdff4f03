//! The orbit lane's jobs: a trajectory (one slip cycle a unit) and map
//! iterates (one iterate a unit, then the map's graph). Everything they
//! compute goes through the core (`Simulator::cycle`, `map_derivative`,
//! `settled_period`, `settle`), in the same order as `Simulator::orbit`, so
//! the results are bit for bit the core's.

use std::sync::Mutex;
use std::time::Duration;
use web_time::Instant;

use super::protocol::{IterateSpec, Lane, MAX_GRAPH_POWER, TrajectorySpec, Update};
use super::{Job, JobError, Sink, Status, Stop, lock};
use crate::model::{ParamError, Params};
use crate::sim::{
    LANES, OrbitOptions, Period, Sampler, SimError, Simulator, cycle_with_derivative,
    cycles_in_lanes, default_settings, map_graph_grid, mean_and_stderr, return_map_window,
    settled_period,
};

/// Most samples in one `TrajectoryChunk` (a slip sampled finely is split).
pub const CHUNK_SAMPLES: usize = 1024;
/// The finest sampling a trajectory accepts: a slip lasts O(1–10) time
/// units, so this is at most ~10⁵ samples per slip.
pub const MIN_SPACING: f64 = 1e-4;
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
    lane: Lane,
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
            lane,
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

/// Sends the lane's progress: `fraction` done after `n` iterates.
fn progress(sink: &dyn Sink, fraction: f64, pacer: &Pacer, n: u64) -> Result<(), JobError> {
    sink.send(Update::Progress {
        generation: sink.generation(),
        lane: Lane::Orbit,
        fraction,
        iterates_per_second: pacer.rate(n),
    })?;
    Ok(())
}

/// A trajectory: the block followed cycle by cycle, its sampled path and
/// each slip event streamed; a unit is one slip cycle.
pub(crate) struct TrajectoryJob {
    sim: Simulator,
    cycles: Option<usize>,
    state: Mutex<TrajectoryState>,
}

struct TrajectoryState {
    theta: f64,
    t: f64,
    done: usize,
    sampler: Sampler,
    pacer: Pacer,
}

impl TrajectoryJob {
    pub fn new(spec: TrajectorySpec) -> Result<Self, JobError> {
        let TrajectorySpec {
            params,
            settings,
            theta0,
            spacing,
            cycles,
        } = spec;
        let sim = Simulator::new(params, settings)?;
        if !(spacing.is_finite() && spacing >= MIN_SPACING) {
            return Err(SimError::from(ParamError::new(
                "spacing",
                spacing,
                "must be a finite number >= 1e-4",
            ))
            .into());
        }
        let theta = theta0.unwrap_or(params.theta_nu);
        sim.check_onset(theta)?;
        Ok(TrajectoryJob {
            sim,
            cycles,
            state: Mutex::new(TrajectoryState {
                theta,
                t: 0.0,
                done: 0,
                sampler: Sampler::new(spacing),
                pacer: Pacer::new(),
            }),
        })
    }

    /// One slip cycle: its samples (in chunks), then its event.
    fn one(&self, st: &mut TrajectoryState, sink: &dyn Sink) -> Result<(), JobError> {
        poll(sink)?;
        let generation = sink.generation();
        let ev = self.sim.cycle(st.theta, st.t, Some(&mut st.sampler))?;
        let samples = st.sampler.take();
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
        if let Some(total) = self.cycles
            && st.pacer.due()
        {
            let fraction = st.done as f64 / total as f64;
            progress(sink, fraction, &st.pacer, st.done as u64)?;
        }
        Ok(())
    }
}

impl Job for TrajectoryJob {
    fn step(&self, width: usize, sink: &dyn Sink) -> Result<Status, JobError> {
        let mut st = lock(&self.state);
        let total = self.cycles.unwrap_or(usize::MAX);
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

/// Map iterates: a transient, then kept iterates streamed in batches with
/// the period of all kept so far and the running Lyapunov exponent (the mean
/// of ln|f'(θ)| over them); the last batch carries what `Simulator::orbit`
/// reports with `lyapunov: true` (`Simulator::settle`); then the graph of
/// the map. A unit is one iterate; the graph is the last one.
pub(crate) struct IterateJob {
    sim: Simulator,
    transient: usize,
    total: usize,
    tol: f64,
    graph_powers: usize,
    state: Mutex<IterateState>,
}

struct IterateState {
    theta: f64,
    t: f64,
    i: usize,
    kept: Vec<f64>,
    logs: Vec<f64>,
    sent: usize,
    last_flush: Instant,
    pacer: Pacer,
    graphed: bool,
}

impl IterateJob {
    pub fn new(spec: IterateSpec) -> Result<Self, JobError> {
        let IterateSpec {
            params,
            settings,
            theta0,
            transient,
            keep,
            graph_powers,
        } = spec;
        let sim = Simulator::new(params, settings)?;
        let theta = theta0.unwrap_or(params.theta_nu);
        sim.check_onset(theta)?;
        Ok(IterateJob {
            sim,
            transient,
            total: transient.saturating_add(keep),
            tol: OrbitOptions::period_tol_for(settings.rtol),
            graph_powers,
            state: Mutex::new(IterateState {
                theta,
                t: 0.0,
                i: 0,
                kept: Vec::with_capacity(keep.min(1 << 16)),
                logs: Vec::with_capacity(keep.min(1 << 16)),
                sent: 0,
                last_flush: Instant::now(),
                pacer: Pacer::new(),
                graphed: false,
            }),
        })
    }

    /// The kept iterates not yet sent, with the analysis of all so far.
    fn batch(&self, st: &IterateState, generation: u64) -> Update {
        let period = match settled_period(&st.kept, self.tol) {
            Some(p) => Period::Periodic(p),
            None => Period::Aperiodic,
        };
        Update::MapIterates {
            generation,
            first_index: st.sent,
            thetas: st.kept[st.sent..].to_vec(),
            period,
            lyapunov: mean_and_stderr(&st.logs).0,
        }
    }

    /// One iterate (a kept one with f'(θ), its cycles stepped together with
    /// its own).
    fn one(&self, st: &mut IterateState, sink: &dyn Sink) -> Result<(), JobError> {
        poll(sink)?;
        let i = st.i;
        let ev = if i >= self.transient {
            let (ev, d, _) = cycle_with_derivative(&self.sim, st.theta, st.t)?;
            st.logs.push(d.abs().ln());
            ev
        } else {
            self.sim.cycle(st.theta, st.t, None)?
        };
        st.t += ev.slip_duration + ev.stick_duration;
        if i >= self.transient {
            st.kept.push(ev.theta);
            if st.kept.len() - st.sent >= ITERATE_BATCH || st.last_flush.elapsed() >= FLUSH_INTERVAL
            {
                sink.send(self.batch(st, sink.generation()))?;
                st.sent = st.kept.len();
                st.last_flush = Instant::now();
            }
        }
        st.theta = self.sim.next_onset(&ev);
        st.i += 1;
        if st.pacer.due() {
            let fraction = st.i as f64 / self.total as f64;
            progress(sink, fraction, &st.pacer, st.i as u64)?;
        }
        Ok(())
    }

    /// The last word settles what waiting could not (a slow approach to a
    /// cycle is solved, and a periodic orbit's exponent is its cycle's),
    /// then the graph of the map.
    fn conclude(&self, st: &mut IterateState, sink: &dyn Sink) -> Result<(), JobError> {
        let settled = self
            .sim
            .settle(&st.kept, st.theta, &st.logs, self.tol, &mut (0, 0));
        sink.send(Update::MapIterates {
            generation: sink.generation(),
            first_index: st.sent,
            thetas: st.kept[st.sent..].to_vec(),
            period: settled.period,
            lyapunov: settled.lyapunov,
        })?;
        st.sent = st.kept.len();
        map_graph(&self.sim, &st.kept, self.graph_powers, sink)
    }
}

impl Job for IterateJob {
    fn step(&self, width: usize, sink: &dyn Sink) -> Result<Status, JobError> {
        let mut st = lock(&self.state);
        if st.graphed {
            return Ok(Status::Done);
        }
        for _ in 0..width.max(1) {
            if st.i >= self.total {
                self.conclude(&mut st, sink)?;
                st.graphed = true;
                return Ok(Status::Done);
            }
            self.one(&mut st, sink)?;
        }
        Ok(Status::Working)
    }
}

/// f at each of `thetas`, LANES cycles at a time stepped together (bitwise
/// the values one at a time would give), polling the job between batches.
/// A cycle that fails here (a bound hit far from the attractor) leaves a gap
/// in the picture (NaN), not an error for the whole job; so does a NaN
/// argument.
fn map_values(sim: &Simulator, thetas: &[f64], sink: &dyn Sink) -> Result<Vec<f64>, JobError> {
    let mut values = vec![f64::NAN; thetas.len()];
    let todo: Vec<usize> = (0..thetas.len())
        .filter(|&i| thetas[i].is_finite())
        .collect();
    for batch in todo.chunks(LANES) {
        poll(sink)?;
        let tasks: Vec<_> = batch.iter().map(|&i| (sim, thetas[i], 0.0)).collect();
        for (&i, r) in batch.iter().zip(cycles_in_lanes(&tasks)) {
            values[i] = r.map_or(f64::NAN, |e| e.theta_next);
        }
    }
    Ok(values)
}

/// The graph of f over the orbit's window, so that the return map shows the
/// whole curve the cobweb runs on and not only the visited points. It costs
/// `GRAPH_POINTS` cycles, a fraction of the kept iterates'.
fn map_graph(
    sim: &Simulator,
    kept: &[f64],
    graph_powers: usize,
    sink: &dyn Sink,
) -> Result<(), JobError> {
    let Some((lo, hi)) = return_map_window(kept) else {
        return Ok(());
    };
    let p = sim.params();
    let thetas = map_graph_grid(p.kappa, p.theta_nu, lo, hi, GRAPH_POINTS);
    let values = map_values(sim, &thetas, sink)?;
    let graph = |powers| Update::MapGraph {
        generation: sink.generation(),
        thetas: thetas.clone(),
        values: values.clone(),
        powers,
    };
    sink.send(graph(Vec::new()))?;
    let top = graph_powers.min(MAX_GRAPH_POWER);
    if top < 2 {
        return Ok(());
    }
    // f^k(θ) = f(f^(k−1)(θ)): one more cycle from each point's last onset,
    // so each power costs GRAPH_POINTS cycles.
    let mut powers: Vec<Vec<f64>> = Vec::with_capacity(top - 1);
    let mut last = values.clone();
    for _ in 2..=top {
        last = map_values(sim, &last, sink)?;
        powers.push(last.clone());
    }
    sink.send(graph(powers))?;
    Ok(())
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
