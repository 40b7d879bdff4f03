//! Orbits of the map: a transient, then kept iterates with their period and
//! Lyapunov exponent. A period is either seen (the kept iterates repeat) or,
//! where the orbit contracts onto a cycle too slowly to wait for, solved
//! (`super::cycles`); either way the cycle is then solved exactly and its
//! exponent is ln|multiplier|/p.

use serde::{Deserialize, Serialize};

mod interpolated;
#[cfg(test)]
mod tests;

use interpolated::OrbitPiece;
pub use interpolated::{InterpolatedOrbit, OnInterpolant, orbit_interpolated};

use super::analysis::cycle_with_derivative;
use super::cycles::{Cycle, CycleOptions, confirm_contraction, near_cycle, solve_counting};
use super::interpolant::{InterpolantOptions, MapUsed};
use super::period::{WINDOW_MAX, contraction, settled_period};
use super::stats::BatchMeans;
use super::{SimError, Simulator, SlipEvent};
use crate::model::{EventAnomaly, event_anomalies, is_on_exit_arc, project_onto_exit_arc};

/// The detected period of the kept iterates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Period {
    Periodic(usize),
    Aperiodic,
}

impl std::fmt::Display for Period {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Period::Periodic(p) => write!(f, "{p}"),
            Period::Aperiodic => f.write_str("aperiodic"),
        }
    }
}

/// What an orbit run computes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitOptions {
    /// Iterates dropped before keeping any.
    pub transient: usize,
    /// Iterates kept.
    pub keep: usize,
    /// Compute the Lyapunov exponent (3 map evaluations per kept iterate).
    pub lyapunov: bool,
    /// Tolerance of the period test, in radians.
    pub period_tol: f64,
}

impl OrbitOptions {
    /// The period test's tolerance tied to the integrator's accuracy: map
    /// errors are ~rtol, and a converging orbit still moves by its
    /// multiplier times its distance to the attractor, so 1e4·rtol, kept
    /// within [1e-9, 1e-3].
    pub fn period_tol_for(rtol: f64) -> f64 {
        (1e4 * rtol).clamp(1e-9, 1e-3)
    }

    /// The period test's tolerance for `settings`: [`period_tol_for`] its
    /// rtol for an adaptive method; 1e-6 for a fixed step, whose map error
    /// no rtol states.
    ///
    /// [`period_tol_for`]: OrbitOptions::period_tol_for
    pub fn period_tol_of(settings: &crate::integrate::SolverSettings) -> f64 {
        if settings.method.is_adaptive() {
            Self::period_tol_for(settings.rtol)
        } else {
            1e-6
        }
    }
}

/// A computed orbit.
#[derive(Clone, Debug, PartialEq)]
pub struct Orbit {
    /// The kept events, in order; empty for an orbit run for its summary
    /// only ([`OrbitRun::summary_only`]).
    pub events: Vec<SlipEvent>,
    /// How many iterates were kept (`events.len()` where they are kept).
    pub kept: usize,
    /// How many kept events are outside the model
    /// (`crate::model::event_anomalies`), and the first one's first anomaly.
    pub anomalies: usize,
    pub first_anomaly: Option<EventAnomaly>,
    /// How many cycles ended in a restart (stop on or outside C).
    pub restarts: usize,
    pub period: Period,
    /// The solved attracting cycle of a periodic orbit: ln|multiplier|/p
    /// is then its exponent. `None` when aperiodic, or when the period was
    /// seen but its cycle could not be solved or does not attract.
    pub cycle: Option<Cycle>,
    /// The cycle's ln|multiplier|/p, or else the mean of ln|f'(θ)| over the
    /// kept iterates.
    pub lyapunov: Option<f64>,
    /// The mean's standard error (batch means:
    /// [`mean_and_stderr`](super::stats::mean_and_stderr)); `None` for a
    /// solved cycle, whose exponent is exact.
    pub lyapunov_stderr: Option<f64>,
    /// Right-hand-side evaluations for the whole run, derivatives included.
    pub rhs_evals: u64,
    /// The onset θ after the last kept event (where a continuation starts).
    pub theta_last: f64,
}

impl Orbit {
    pub fn thetas(&self) -> Vec<f64> {
        self.events.iter().map(|e| e.theta).collect()
    }
}

impl Simulator {
    /// Where the next cycle starts after `ev`: its θ', moved back onto the
    /// exit arc if a restart left it off (the restart rule's onset is not on
    /// C, and the map is defined on C).
    pub fn next_onset(&self, ev: &SlipEvent) -> f64 {
        let p = self.params();
        if ev.restarted && !is_on_exit_arc(p.kappa, p.theta_nu, ev.theta_next) {
            project_onto_exit_arc(p.kappa, p.theta_nu, ev.theta_next, 1e-9)
        } else {
            ev.theta_next
        }
    }

    /// Follows the orbit from θ0. `cancel` is polled once per cycle.
    pub fn orbit(
        &self,
        theta0: f64,
        opts: &OrbitOptions,
        cancel: &dyn Fn() -> bool,
    ) -> Result<Orbit, SimError> {
        let mut run = OrbitRun::new(self, theta0, opts)?;
        loop {
            if let Some(r) = run.advance(self, cancel) {
                return r;
            }
        }
    }

    /// What the kept onsets `kept` of an orbit (its last [`WINDOW_MAX`]
    /// at least: no test reads further back), followed by the next onset
    /// `next`, settle to, with `mean` the mean of ln|f'(θ)| over the kept
    /// iterates and its standard error
    /// ([`mean_and_stderr`](super::stats::mean_and_stderr); `(None, None)`
    /// without them):
    /// - a period seen within `period_tol` ([`settled_period`]): its cycle is
    ///   solved from `next`; if it attracts, its exponent is ln|m|/p;
    /// - no period, but the iterates contract onto a cycle slowly
    ///   ([`contraction`]): that cycle, if it attracts and the orbit keeps
    ///   approaching it ([`confirm_contraction`]);
    /// - no period, but the iterates nearly repeat on a cycle that attracts
    ///   ([`near_cycle`]): that cycle;
    /// - else aperiodic, with `mean`.
    ///
    /// The evaluations spent solving are added to `spent` (map, rhs).
    pub fn settle(
        &self,
        kept: &[f64],
        next: f64,
        mean: (Option<f64>, Option<f64>),
        period_tol: f64,
        spent: &mut (u64, u64),
    ) -> Settled {
        let opts = CycleOptions::for_classifier(self.settings());
        if let Some(p) = settled_period(kept, period_tol) {
            let solved = solve_counting(self, next, p, &opts, spent)
                .ok()
                .filter(|c| c.minimal_period == p && c.stable);
            let (lyapunov, lyapunov_stderr) = match &solved {
                Some(c) => (Some(c.lyapunov()), None),
                None => mean,
            };
            return Settled {
                period: Period::Periodic(p),
                cycle: solved,
                lyapunov,
                lyapunov_stderr,
            };
        }
        let mut seq = kept.to_vec();
        seq.push(next);
        let noise = 1e-2 * period_tol;
        if let Some(c) = contraction(&seq, noise)
            && let Some(cycle) = confirm_contraction(self, &seq, &c, &opts, noise, spent)
        {
            return Settled {
                period: Period::Periodic(cycle.period()),
                lyapunov: Some(cycle.lyapunov()),
                lyapunov_stderr: None,
                cycle: Some(cycle),
            };
        }
        if let Some(cycle) = near_cycle(self, &seq, &opts, spent) {
            return Settled {
                period: Period::Periodic(cycle.period()),
                lyapunov: Some(cycle.lyapunov()),
                lyapunov_stderr: None,
                cycle: Some(cycle),
            };
        }
        let (lyapunov, lyapunov_stderr) = mean;
        Settled {
            period: Period::Aperiodic,
            cycle: None,
            lyapunov,
            lyapunov_stderr,
        }
    }
}

/// What an orbit's kept iterates settle to ([`Simulator::settle`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Settled {
    pub period: Period,
    /// The solved attracting cycle, when there is one.
    pub cycle: Option<Cycle>,
    /// ln|multiplier|/p of the cycle, or the mean of ln|f'(θ)|.
    pub lyapunov: Option<f64>,
    /// The mean's standard error (`None` for a solved cycle).
    pub lyapunov_stderr: Option<f64>,
}

/// [`Simulator::orbit`] one slip cycle at a time (its settling last, as a
/// piece of its own), so that a host on a slice of time (the browser's) can
/// stop between two and go on later: the same cycles in the same order, so
/// the same orbit bit for bit.
///
/// What it holds does not grow with the orbit but for the kept events
/// themselves, which [`OrbitRun::summary_only`] drops: the settling reads
/// only the last [`WINDOW_MAX`] kept onsets, and the Lyapunov exponent and
/// its error are summed as the iterates come ([`BatchMeans`]).
pub struct OrbitRun {
    opts: OrbitOptions,
    theta: f64,
    t: f64,
    restarts: usize,
    evals: u64,
    /// Whether the kept events are kept (not for a summary only).
    whole: bool,
    events: Vec<SlipEvent>,
    /// The kept onsets of the last [`OrbitRun::advance`] and at least
    /// [`WINDOW_MAX`] before them (all, when fewer).
    recent: Vec<f64>,
    kept: usize,
    anomalies: usize,
    first_anomaly: Option<EventAnomaly>,
    /// ln|f'(θ)| of the kept iterates, summed.
    logs: BatchMeans,
    /// Cycles done.
    i: usize,
    /// Where the iterates come from the map's verified interpolant
    /// ([`OrbitRun::interpolated`]).
    interp: Option<Box<OnInterpolant>>,
}

impl OrbitRun {
    /// The orbit from θ0 (which must be on the exit arc), nothing computed.
    pub fn new(sim: &Simulator, theta0: f64, opts: &OrbitOptions) -> Result<Self, SimError> {
        sim.check_onset(theta0)?;
        Ok(OrbitRun {
            opts: *opts,
            theta: theta0,
            t: 0.0,
            restarts: 0,
            evals: 0,
            whole: true,
            events: Vec::with_capacity(opts.keep.min(1 << 16)),
            recent: Vec::with_capacity(4 * WINDOW_MAX),
            kept: 0,
            anomalies: 0,
            first_anomaly: None,
            logs: BatchMeans::new(if opts.lyapunov { opts.keep } else { 0 }),
            i: 0,
            interp: None,
        })
    }

    /// The orbit from θ0 with its iterates from the map's verified
    /// interpolant where it serves ([`OnInterpolant`]: the same orbit as
    /// the integrated one to the interpolant's tolerance), each
    /// [`OrbitRun::advance`] a bounded piece: one integrated cycle, a piece
    /// of the interpolant's build or extension, or a batch of iterates
    /// from its series.
    pub fn interpolated(
        sim: &Simulator,
        theta0: f64,
        opts: &OrbitOptions,
        iopts: InterpolantOptions,
    ) -> Result<Self, SimError> {
        let mut run = Self::new(sim, theta0, opts)?;
        run.interp = Some(Box::new(OnInterpolant::new(iopts)));
        Ok(run)
    }

    /// The run for the orbit's summary only: its kept events are not kept
    /// ([`Orbit::events`] is empty), so that its memory stays bounded
    /// however long the orbit; the rest of the [`Orbit`] is the same.
    pub fn summary_only(mut self) -> Self {
        self.whole = false;
        self.events = Vec::new();
        self
    }

    /// The interpolant an [`OrbitRun::interpolated`] runs on.
    pub fn on_interpolant(&self) -> Option<&OnInterpolant> {
        self.interp.as_deref()
    }

    /// The interpolant, taken out (once the orbit is done).
    pub fn take_interpolant(&mut self) -> Option<OnInterpolant> {
        self.interp.take().map(|b| *b)
    }

    /// How the orbit evaluated the map so far.
    pub fn map_used(&self) -> MapUsed {
        self.interp
            .as_ref()
            .map_or(MapUsed::Direct, |on| on.map_used())
    }

    /// What the run computes.
    pub fn options(&self) -> &OrbitOptions {
        &self.opts
    }

    /// The onset the next cycle starts from.
    pub fn theta(&self) -> f64 {
        self.theta
    }

    /// The time at that onset.
    pub(crate) fn time(&self) -> f64 {
        self.t
    }

    /// Right-hand-side evaluations spent outside the orbit's own cycles.
    pub(crate) fn add_evals(&mut self, n: u64) {
        self.evals += n;
    }

    /// A transient iterate from elsewhere (the series): the next onset and
    /// the cycle's duration.
    pub(crate) fn skip(&mut self, next: f64, duration: f64) {
        self.t += duration;
        self.theta = next;
        self.i += 1;
    }

    /// A kept iterate from elsewhere (the series): its event and f'(θ).
    pub(crate) fn keep(&mut self, ev: SlipEvent, derivative: f64) {
        if self.opts.lyapunov {
            self.logs.push(derivative.abs().ln());
        }
        self.t += ev.slip_duration + ev.stick_duration;
        self.theta = ev.theta_next;
        self.note_kept(ev);
        self.i += 1;
    }

    /// A kept event: its onset among the recent ones, its anomalies
    /// counted, and itself kept unless for a summary only.
    fn note_kept(&mut self, ev: SlipEvent) {
        self.recent.push(ev.theta);
        self.kept += 1;
        let anomalies = event_anomalies(ev.theta, ev.theta_next, ev.energy_released);
        if let Some(&first) = anomalies.first() {
            self.anomalies += 1;
            self.first_anomaly.get_or_insert(first);
        }
        if self.whole {
            self.events.push(ev);
        }
    }

    /// The kept events so far (none for a summary only).
    pub fn events(&self) -> &[SlipEvent] {
        &self.events
    }

    /// Iterates kept so far.
    pub fn kept(&self) -> usize {
        self.kept
    }

    /// The kept onsets of the last [`OrbitRun::advance`], and at least the
    /// [`WINDOW_MAX`] before them (all, when fewer): enough for
    /// [`settled_period`] of all kept so far.
    pub fn recent_onsets(&self) -> &[f64] {
        &self.recent
    }

    /// The mean of ln|f'(θ)| over the kept iterates so far (the running
    /// Lyapunov exponent; `None` before the first, or without it).
    pub fn lyapunov_so_far(&self) -> Option<f64> {
        self.logs.mean()
    }

    /// Slip cycles done so far (transient included), of
    /// [`OrbitRun::cycles`].
    pub fn cycles_done(&self) -> usize {
        self.i
    }

    /// Slip cycles in all: the transient and the kept.
    pub fn cycles(&self) -> usize {
        self.opts.transient + self.opts.keep
    }

    /// Whether every cycle is done: the next [`OrbitRun::advance`] is the
    /// settling (it polls no cancel).
    pub fn settling(&self) -> bool {
        self.i == self.opts.transient + self.opts.keep
    }

    /// One slip cycle (`cancel` polled before it) and `None`, or, once
    /// every cycle is done, the settling and the orbit. On the interpolant,
    /// a bounded piece instead of a cycle ([`OrbitRun::interpolated`]).
    /// `sim` must be the simulator it was made with.
    pub fn advance(
        &mut self,
        sim: &Simulator,
        cancel: &dyn Fn() -> bool,
    ) -> Option<Result<Orbit, SimError>> {
        let opts = &self.opts;
        if self.i == opts.transient + opts.keep {
            return Some(Ok(self.settle(sim)));
        }
        if cancel() {
            return Some(Err(SimError::Cancelled));
        }
        if self.recent.len() >= 4 * WINDOW_MAX {
            self.recent.drain(..self.recent.len() - WINDOW_MAX);
        }
        if let Some(mut on) = self.interp.take() {
            let piece = on.piece(sim, self);
            self.interp = Some(on);
            return match piece {
                Ok(OrbitPiece::Done) => None,
                Ok(OrbitPiece::Direct) => self.direct_cycle(sim).err().map(Err),
                Err(e) => Some(Err(e)),
            };
        }
        self.direct_cycle(sim).err().map(Err)
    }

    /// The next iterate, integrated. Kept iterates of a Lyapunov run take
    /// f'(θ) too, its cycles stepped together with the iterate's own.
    pub(crate) fn direct_cycle(&mut self, sim: &Simulator) -> Result<(), SimError> {
        let kept = self.i >= self.opts.transient;
        let ev = if kept && self.opts.lyapunov {
            let (ev, d, n) = cycle_with_derivative(sim, self.theta, self.t)?;
            self.evals += n;
            self.logs.push(d.abs().ln());
            ev
        } else {
            sim.cycle(self.theta, self.t, None)?
        };
        self.evals += ev.rhs_evals;
        self.restarts += ev.restarted as usize;
        self.t += ev.slip_duration + ev.stick_duration;
        if kept {
            self.note_kept(ev);
        }
        self.theta = sim.next_onset(&ev);
        self.i += 1;
        Ok(())
    }

    /// What the kept iterates settle to, and the orbit.
    fn settle(&mut self, sim: &Simulator) -> Orbit {
        debug_assert!(self.logs.is_empty() || self.logs.len() == self.kept);
        let mut spent = (0, 0);
        let s = sim.settle(
            &self.recent,
            self.theta,
            self.logs.mean_and_stderr(),
            self.opts.period_tol,
            &mut spent,
        );
        Orbit {
            events: std::mem::take(&mut self.events),
            kept: self.kept,
            anomalies: self.anomalies,
            first_anomaly: self.first_anomaly,
            restarts: self.restarts,
            period: s.period,
            cycle: s.cycle,
            lyapunov: s.lyapunov,
            lyapunov_stderr: s.lyapunov_stderr,
            rhs_evals: self.evals + spent.1 + self.interp.as_ref().map_or(0, |on| on.rhs_evals()),
            theta_last: self.theta,
        }
    }
}
