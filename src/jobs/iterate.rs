//! The iterate job: an orbit of the map, one slip cycle a unit (on the
//! interpolant, one bounded piece of it), by the core's one orbit loop
//! ([`OrbitRun`], the loop of `Simulator::orbit` and of
//! `orbit_interpolated`), so its numbers are the core's bit for bit.
//! Kept iterates stream in batches
//! with the period of all kept so far and the running Lyapunov exponent;
//! the last batch carries what the orbit settles to; then, as the options
//! ask, the whole orbit ([`Update::Orbit`], for `oneblock orbit`; its
//! events only if asked for) and the graph of the map (for the window's
//! return map). The job holds the iterates not yet sent and, unless the
//! events are asked for, nothing that grows with the orbit: whoever keeps
//! the stream (the window) keeps the iterates.

use std::sync::Mutex;
use web_time::Instant;

use super::orbit::{FLUSH_INTERVAL, GRAPH_POINTS, ITERATE_BATCH, Pacer, progress};
use super::protocol::{IterateSpec, MAX_GRAPH_POWER, Update};
use super::{Job, JobError, Sink, Status, Stop, lock};
use crate::sim::interpolant::{InterpolantOptions, MapUsed};
use crate::sim::{
    LANES, Orbit, OrbitOptions, OrbitRun, Period, SimError, Simulator, cycles_in_lanes,
    map_graph_grid, return_map_window, settled_period,
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
    /// The kept onsets not yet sent.
    pending: Vec<f64>,
    /// Kept onsets taken from the run (sent or pending).
    taken: usize,
    /// Kept onsets sent.
    sent: usize,
    /// The least and greatest finite kept onset: all the graph's window
    /// depends on (`return_map_window`).
    bounds: Option<(f64, f64)>,
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
        let mut run = if options.map.interpolates(transient.saturating_add(keep)) {
            let iopts = InterpolantOptions::for_settings(sim.settings());
            OrbitRun::interpolated(&sim, theta0, &opts, iopts)?
        } else {
            OrbitRun::new(&sim, theta0, &opts)?
        };
        if !(options.report && options.events) {
            run = run.summary_only();
        }
        Ok(IterateJob {
            sim,
            report: options.report,
            graph_powers,
            state: Mutex::new(IterateState {
                stage: Stage::Cycles(Box::new(run)),
                pending: Vec::with_capacity(keep.min(1 << 10)),
                taken: 0,
                sent: 0,
                bounds: None,
                last_flush: Instant::now(),
                pacer: Pacer::new(),
            }),
        })
    }

    /// The kept onsets not yet sent, with the period of all so far (from
    /// the run's recent onsets, all the test reads) and the running
    /// exponent.
    fn batch(st: &mut IterateState, run: &OrbitRun, generation: u64) -> Update {
        let period = match settled_period(run.recent_onsets(), run.options().period_tol) {
            Some(p) => Period::Periodic(p),
            None => Period::Aperiodic,
        };
        let first_index = st.sent;
        st.sent = st.taken;
        // A running mean has no error yet (the batches fill at the end):
        // an aperiodic orbit's is sent, shown as approximate; a periodic
        // one's λ waits for the solved cycle, exact, at the end.
        let lyapunov = match period {
            Period::Periodic(_) => None,
            Period::Aperiodic => run.lyapunov_so_far(),
        };
        Update::MapIterates {
            generation,
            first_index,
            thetas: std::mem::take(&mut st.pending),
            period,
            lyapunov,
            lyapunov_stderr: None,
        }
    }

    /// The onsets `run` kept since the last call, into `pending`.
    fn take_kept(st: &mut IterateState, run: &OrbitRun) {
        let new = run.kept() - st.taken;
        let recent = run.recent_onsets();
        let fresh = &recent[recent.len() - new..];
        for &t in fresh.iter().filter(|t| t.is_finite()) {
            let (lo, hi) = st.bounds.get_or_insert((t, t));
            *lo = lo.min(t);
            *hi = hi.max(t);
        }
        st.pending.extend_from_slice(fresh);
        st.taken = run.kept();
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
        if run.kept() > st.taken {
            Self::take_kept(st, run);
            if st.pending.len() >= ITERATE_BATCH || st.last_flush.elapsed() >= FLUSH_INTERVAL {
                sink.send(Self::batch(st, run, sink.generation()))?;
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
        // The settling keeps no iterate: every kept one was taken.
        debug_assert_eq!(st.taken, orbit.kept);
        sink.send(Update::MapIterates {
            generation,
            first_index: st.sent,
            thetas: std::mem::take(&mut st.pending),
            period: orbit.period,
            lyapunov: orbit.lyapunov,
            lyapunov_stderr: orbit.lyapunov_stderr,
        })?;
        st.sent = st.taken;
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
        map_graph(&self.sim, st.bounds, self.graph_powers, sink)
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

/// The graph of f over the orbit's window (`return_map_window` of the kept
/// onsets, which depends only on `bounds`, their least and greatest finite
/// values), so that the return map shows the whole curve the cobweb runs on
/// and not only the visited points. It costs `GRAPH_POINTS` cycles, a
/// fraction of the kept iterates'.
fn map_graph(
    sim: &Simulator,
    bounds: Option<(f64, f64)>,
    graph_powers: usize,
    sink: &dyn Sink,
) -> Result<(), JobError> {
    let Some((lo, hi)) = bounds.and_then(|(lo, hi)| return_map_window(&[lo, hi])) else {
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
