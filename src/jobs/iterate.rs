//! The iterate job: an orbit of the map, one slip cycle a unit (on the
//! interpolant, one bounded piece of it), by the core's one orbit loop
//! ([`OrbitRun`], the loop of `Simulator::orbit` and of
//! `orbit_interpolated`), so its numbers are the core's bit for bit.
//! Kept iterates stream in batches
//! with the period of all kept so far and the running Lyapunov exponent;
//! the last batch carries what the orbit settles to; then, as the options
//! ask, the whole orbit ([`Update::Orbit`], for `oneblock orbit`) and the
//! graph of the map (for the window's return map).

use std::sync::Mutex;
use web_time::Instant;

use super::orbit::{FLUSH_INTERVAL, GRAPH_POINTS, ITERATE_BATCH, Pacer, progress};
use super::protocol::{IterateSpec, MAX_GRAPH_POWER, Update};
use super::{Job, JobError, Sink, Status, Stop, lock};
use crate::sim::interpolant::{InterpolantOptions, MapUsed};
use crate::sim::{
    LANES, Orbit, OrbitOptions, OrbitRun, Period, SimError, Simulator, cycles_in_lanes,
    map_graph_grid, mean_and_stderr, return_map_window, settled_period,
};

/// Map iterates (see the module's comment). A unit is one slip cycle, or
/// on the interpolant (`MapChoice::Interpolant`, or `Auto` on a long run)
/// one piece of [`OrbitRun::interpolated`]: a scout's cycle, a piece of
/// the build or of an extension, or a batch of iterates from the series.
pub(crate) struct IterateJob {
    sim: Simulator,
    report: bool,
    graph_powers: usize,
    state: Mutex<IterateState>,
}

/// Where the job is.
enum Stage {
    /// Piece by piece.
    Cycles(Box<OrbitRun>),
    /// Finished: the graph, if any, drawn.
    Done,
}

struct IterateState {
    stage: Stage,
    /// The kept onsets so far (the period test's input).
    kept: Vec<f64>,
    sent: usize,
    last_flush: Instant,
    pacer: Pacer,
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
            options,
        } = spec;
        let sim = Simulator::new(params, settings)?;
        let theta0 = theta0.unwrap_or(params.theta_nu);
        sim.check_onset(theta0)?;
        let opts = OrbitOptions {
            transient,
            keep,
            lyapunov: options.lyapunov,
            period_tol: options
                .period_tol
                .unwrap_or_else(|| OrbitOptions::period_tol_of(&settings)),
        };
        let run = if options.map.interpolates(transient.saturating_add(keep)) {
            let iopts = InterpolantOptions::for_settings(sim.settings());
            OrbitRun::interpolated(&sim, theta0, &opts, iopts)?
        } else {
            OrbitRun::new(&sim, theta0, &opts)?
        };
        Ok(IterateJob {
            sim,
            report: options.report,
            graph_powers,
            state: Mutex::new(IterateState {
                stage: Stage::Cycles(Box::new(run)),
                kept: Vec::with_capacity(keep.min(1 << 16)),
                sent: 0,
                last_flush: Instant::now(),
                pacer: Pacer::new(),
            }),
        })
    }

    /// The kept onsets not yet sent, with the period of all so far and the
    /// running exponent.
    fn batch(st: &IterateState, run: &OrbitRun, generation: u64) -> Update {
        let period = match settled_period(&st.kept, run.options().period_tol) {
            Some(p) => Period::Periodic(p),
            None => Period::Aperiodic,
        };
        let (lyapunov, lyapunov_stderr) = mean_and_stderr(run.logs());
        Update::MapIterates {
            generation,
            first_index: st.sent,
            thetas: st.kept[st.sent..].to_vec(),
            period,
            lyapunov,
            lyapunov_stderr,
        }
    }

    /// One slip cycle of `run`; its kept onset streamed when a batch is
    /// due. `Some(orbit)` once the orbit is settled.
    fn cycle(
        &self,
        st: &mut IterateState,
        run: &mut OrbitRun,
        sink: &dyn Sink,
    ) -> Result<Option<Orbit>, JobError> {
        let poll = || sink.cycle();
        match run.advance(&self.sim, &poll) {
            Some(Ok(orbit)) => return Ok(Some(orbit)),
            Some(Err(SimError::Cancelled)) => return Err(Stop::Stale.into()),
            Some(Err(e)) => return Err(e.into()),
            None => {}
        }
        if run.events().len() > st.kept.len() {
            st.kept
                .extend(run.events()[st.kept.len()..].iter().map(|e| e.theta));
            if st.kept.len() - st.sent >= ITERATE_BATCH || st.last_flush.elapsed() >= FLUSH_INTERVAL
            {
                sink.send(Self::batch(st, run, sink.generation()))?;
                st.sent = st.kept.len();
                st.last_flush = Instant::now();
            }
        }
        if st.pacer.due() {
            let fraction = run.cycles_done() as f64 / run.cycles().max(1) as f64;
            progress(sink, fraction, &st.pacer, run.cycles_done() as u64)?;
        }
        Ok(None)
    }

    /// The last word: the kept onsets not yet sent with what the orbit
    /// settles to, the whole orbit if asked for, then the graph of the map.
    fn conclude(
        &self,
        st: &mut IterateState,
        orbit: Orbit,
        map: MapUsed,
        sink: &dyn Sink,
    ) -> Result<(), JobError> {
        let generation = sink.generation();
        if st.kept.len() < orbit.events.len() {
            st.kept = orbit.thetas();
        }
        sink.send(Update::MapIterates {
            generation,
            first_index: st.sent,
            thetas: st.kept[st.sent..].to_vec(),
            period: orbit.period,
            lyapunov: orbit.lyapunov,
            lyapunov_stderr: orbit.lyapunov_stderr,
        })?;
        st.sent = st.kept.len();
        if self.report {
            sink.send(Update::Orbit {
                generation,
                orbit: Box::new(orbit),
                map,
            })?;
        }
        if self.graph_powers == 0 {
            return Ok(());
        }
        map_graph(&self.sim, &st.kept, self.graph_powers, sink)
    }
}

impl Job for IterateJob {
    fn step(&self, width: usize, sink: &dyn Sink) -> Result<Status, JobError> {
        let mut guard = lock(&self.state);
        let st = &mut *guard;
        let Stage::Cycles(mut run) = std::mem::replace(&mut st.stage, Stage::Done) else {
            return Ok(Status::Done);
        };
        for _ in 0..width.max(1) {
            if let Some(orbit) = self.cycle(st, &mut run, sink)? {
                self.conclude(st, orbit, run.map_used(), sink)?;
                return Ok(Status::Done);
            }
        }
        st.stage = Stage::Cycles(run);
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
        if sink.cycle() {
            return Err(Stop::Stale.into());
        }
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
