//! The orbit lane: one trajectory or map-iterate job at a time, polling its
//! generation once per slip cycle. Everything it computes goes through the
//! core (`Simulator::cycle`, `map_derivative`, `settled_period`, `settle`), in the same
//! order as `Simulator::orbit`, so the results are bit-for-bit the core's.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::{Duration, Instant};

use super::gate::{Gate, Stop};
use super::protocol::{
    Command, Generation, IterateSpec, Lane, MAX_GRAPH_POWER, Outcome, TrajectorySpec, Update,
};
use super::{Shared, panic_message};
use crate::integrate::SolverSettings;
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

/// Why a job ended early.
pub(crate) enum JobError {
    /// Cancelled, superseded or the worker is gone: end silently.
    Stop,
    /// The simulation refused or failed: report it.
    Sim(SimError),
    /// Failed, already reported by an `Error` update: just finish.
    Failed(String),
}

impl From<Stop> for JobError {
    fn from(_: Stop) -> Self {
        JobError::Stop
    }
}

impl From<SimError> for JobError {
    fn from(e: SimError) -> Self {
        JobError::Sim(e)
    }
}

/// Runs `job` for generation `generation` on `gate`, catching panics, and
/// sends how it ended.
pub(crate) fn run_guarded(
    gate: &Gate,
    generation: Generation,
    job: impl FnOnce() -> Result<(), JobError>,
) {
    if gate.is_stale(generation) {
        return;
    }
    match catch_unwind(AssertUnwindSafe(job)) {
        Ok(Ok(())) => gate.finish(generation, None, Outcome::Completed),
        Ok(Err(JobError::Stop)) => {}
        Ok(Err(JobError::Sim(SimError::Cancelled))) => {}
        Ok(Err(JobError::Sim(e))) => {
            let msg = e.to_string();
            gate.finish(
                generation,
                Some((msg.clone(), e.parameter())),
                Outcome::Failed(msg),
            );
        }
        Ok(Err(JobError::Failed(msg))) => gate.finish(generation, None, Outcome::Failed(msg)),
        Err(payload) => {
            let msg = format!("the job panicked: {}", panic_message(&*payload));
            gate.finish(generation, Some((msg.clone(), None)), Outcome::Failed(msg));
        }
    }
}

/// Runs one orbit-lane command.
pub(crate) fn run(shared: &Shared, cmd: Command) {
    let job = OrbitJob { shared };
    match cmd {
        Command::Trajectory { generation, spec } => run_guarded(&shared.orbit, generation, || {
            let TrajectorySpec {
                params,
                settings,
                theta0,
                spacing,
                cycles,
            } = spec;
            job.trajectory(generation, params, settings, theta0, spacing, cycles)
        }),
        Command::Iterate { generation, spec } => run_guarded(&shared.orbit, generation, || {
            let IterateSpec {
                params,
                settings,
                theta0,
                transient,
                keep,
                graph_powers,
            } = spec;
            job.iterate(
                generation,
                params,
                settings,
                theta0,
                (transient, keep),
                graph_powers,
            )
        }),
        Command::InjectPanic {
            generation,
            after_cycles,
        } => run_guarded(&shared.orbit, generation, || {
            job.panic_after(generation, after_cycles)
        }),
        _ => {}
    }
}

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

struct OrbitJob<'a> {
    shared: &'a Shared,
}

impl OrbitJob<'_> {
    fn gate(&self) -> &Gate {
        &self.shared.orbit
    }

    /// Polls the generation before a cycle: `Err` when the job must stop.
    fn poll(&self, generation: Generation) -> Result<(), JobError> {
        if self.shared.stats.poll(self.gate(), generation) {
            Err(Stop::Stale.into())
        } else {
            Ok(())
        }
    }

    fn send(&self, generation: Generation, u: Update) -> Result<(), JobError> {
        Ok(self.gate().send(generation, u)?)
    }

    fn progress(
        &self,
        generation: Generation,
        fraction: f64,
        pacer: &Pacer,
        n: u64,
    ) -> Result<(), JobError> {
        self.send(
            generation,
            Update::Progress {
                generation,
                lane: Lane::Orbit,
                fraction,
                iterates_per_second: pacer.rate(n),
            },
        )
    }

    /// Follows the block cycle by cycle, streaming the sampled path and each
    /// slip event.
    fn trajectory(
        &self,
        generation: Generation,
        params: Params,
        settings: SolverSettings,
        theta0: Option<f64>,
        spacing: f64,
        cycles: Option<usize>,
    ) -> Result<(), JobError> {
        let sim = Simulator::new(params, settings)?;
        if !(spacing.is_finite() && spacing >= MIN_SPACING) {
            return Err(SimError::from(ParamError::new(
                "spacing",
                spacing,
                "must be a finite number >= 1e-4",
            ))
            .into());
        }
        let mut theta = theta0.unwrap_or(params.theta_nu);
        sim.check_onset(theta)?;
        let mut sampler = Sampler::new(spacing);
        let mut pacer = Pacer::new();
        let mut t = 0.0;
        let total = cycles.unwrap_or(usize::MAX);
        for i in 0..total {
            self.poll(generation)?;
            let ev = sim.cycle(theta, t, Some(&mut sampler))?;
            let samples = sampler.take();
            if samples.len() <= CHUNK_SAMPLES {
                self.send(
                    generation,
                    Update::TrajectoryChunk {
                        generation,
                        samples,
                    },
                )?;
            } else {
                for c in samples.chunks(CHUNK_SAMPLES) {
                    let samples = c.to_vec();
                    self.send(
                        generation,
                        Update::TrajectoryChunk {
                            generation,
                            samples,
                        },
                    )?;
                }
            }
            self.send(
                generation,
                Update::Slip {
                    generation,
                    event: ev,
                },
            )?;
            t += ev.slip_duration + ev.stick_duration;
            theta = sim.next_onset(&ev);
            if cycles.is_some() && pacer.due() {
                let fraction = (i + 1) as f64 / total as f64;
                self.progress(generation, fraction, &pacer, i as u64 + 1)?;
            }
        }
        Ok(())
    }

    /// Iterates the map: a transient, then kept iterates streamed in batches
    /// with the period of all kept so far and the running Lyapunov exponent
    /// (the mean of ln|f'(θ)| over them); the last batch carries what
    /// `Simulator::orbit` reports with `lyapunov: true` (`Simulator::settle`).
    fn iterate(
        &self,
        generation: Generation,
        params: Params,
        settings: SolverSettings,
        theta0: Option<f64>,
        (transient, keep): (usize, usize),
        graph_powers: usize,
    ) -> Result<(), JobError> {
        let sim = Simulator::new(params, settings)?;
        let mut theta = theta0.unwrap_or(params.theta_nu);
        sim.check_onset(theta)?;
        let tol = OrbitOptions::period_tol_for(settings.rtol);
        let total = transient.saturating_add(keep);
        let mut kept: Vec<f64> = Vec::with_capacity(keep.min(1 << 16));
        let mut logs: Vec<f64> = Vec::with_capacity(keep.min(1 << 16));
        let mut sent = 0;
        let mut last_flush = Instant::now();
        let mut pacer = Pacer::new();
        let mut t = 0.0;
        let flush = |kept: &[f64], logs: &[f64], sent: usize| {
            let period = match settled_period(kept, tol) {
                Some(p) => Period::Periodic(p),
                None => Period::Aperiodic,
            };
            Update::MapIterates {
                generation,
                first_index: sent,
                thetas: kept[sent..].to_vec(),
                period,
                lyapunov: mean_and_stderr(logs).0,
            }
        };
        for i in 0..total {
            self.poll(generation)?;
            // A kept iterate's f'(θ) cycles are stepped together with its own.
            let ev = if i >= transient {
                let (ev, d, _) = cycle_with_derivative(&sim, theta, t)?;
                logs.push(d.abs().ln());
                ev
            } else {
                sim.cycle(theta, t, None)?
            };
            t += ev.slip_duration + ev.stick_duration;
            if i >= transient {
                kept.push(ev.theta);
                if kept.len() - sent >= ITERATE_BATCH || last_flush.elapsed() >= FLUSH_INTERVAL {
                    self.send(generation, flush(&kept, &logs, sent))?;
                    sent = kept.len();
                    last_flush = Instant::now();
                }
            }
            theta = sim.next_onset(&ev);
            if pacer.due() {
                let fraction = (i + 1) as f64 / total as f64;
                self.progress(generation, fraction, &pacer, i as u64 + 1)?;
            }
        }
        // The last word settles what waiting could not: a slow approach to
        // a cycle is solved, and a periodic orbit's exponent is its cycle's.
        let settled = sim.settle(&kept, theta, &logs, tol, &mut (0, 0));
        self.send(
            generation,
            Update::MapIterates {
                generation,
                first_index: sent,
                thetas: kept[sent..].to_vec(),
                period: settled.period,
                lyapunov: settled.lyapunov,
            },
        )?;
        self.map_graph(generation, &sim, &kept, graph_powers)
    }

    /// f at each of `thetas`, LANES cycles at a time stepped together
    /// (bitwise the values one at a time would give), polling the job
    /// between batches. A cycle that fails here (a bound hit far from the
    /// attractor) leaves a gap in the picture (NaN), not an error for the
    /// whole job; so does a NaN argument.
    fn map_values(
        &self,
        generation: Generation,
        sim: &Simulator,
        thetas: &[f64],
    ) -> Result<Vec<f64>, JobError> {
        let mut values = vec![f64::NAN; thetas.len()];
        let todo: Vec<usize> = (0..thetas.len())
            .filter(|&i| thetas[i].is_finite())
            .collect();
        for batch in todo.chunks(LANES) {
            self.poll(generation)?;
            let tasks: Vec<_> = batch.iter().map(|&i| (sim, thetas[i], 0.0)).collect();
            for (&i, r) in batch.iter().zip(cycles_in_lanes(&tasks)) {
                values[i] = r.map_or(f64::NAN, |e| e.theta_next);
            }
        }
        Ok(values)
    }

    /// The graph of f over the orbit's window, so that the return map shows
    /// the whole curve the cobweb runs on and not only the visited points.
    /// It costs `GRAPH_POINTS` cycles, a fraction of the kept iterates'.
    fn map_graph(
        &self,
        generation: Generation,
        sim: &Simulator,
        kept: &[f64],
        graph_powers: usize,
    ) -> Result<(), JobError> {
        let Some((lo, hi)) = return_map_window(kept) else {
            return Ok(());
        };
        let p = sim.params();
        let thetas = map_graph_grid(p.kappa, p.theta_nu, lo, hi, GRAPH_POINTS);
        let values = self.map_values(generation, sim, &thetas)?;
        let graph = |powers| Update::MapGraph {
            generation,
            thetas: thetas.clone(),
            values: values.clone(),
            powers,
        };
        self.send(generation, graph(Vec::new()))?;
        let top = graph_powers.min(MAX_GRAPH_POWER);
        if top < 2 {
            return Ok(());
        }
        // f^k(θ) = f(f^(k−1)(θ)): one more cycle from each point's last
        // onset, so each power costs GRAPH_POINTS cycles.
        let mut powers: Vec<Vec<f64>> = Vec::with_capacity(top - 1);
        let mut last = values.clone();
        for _ in 2..=top {
            last = self.map_values(generation, sim, &last)?;
            powers.push(last.clone());
        }
        self.send(generation, graph(powers))
    }

    /// Test-only fault injection: a few real cycles, then a panic.
    fn panic_after(&self, generation: Generation, after_cycles: usize) -> Result<(), JobError> {
        let params = Params::default();
        let sim = Simulator::new(params, default_settings(1e-8))?;
        let mut theta = params.theta_nu;
        for _ in 0..after_cycles {
            self.poll(generation)?;
            let ev = sim.cycle(theta, 0.0, None)?;
            theta = sim.next_onset(&ev);
        }
        panic!("injected panic after {after_cycles} cycles");
    }
}
