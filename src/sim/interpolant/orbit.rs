//! Orbits on the interpolated map: the same [`Orbit`] as
//! [`Simulator::orbit`] gives, its iterates from the series wherever they
//! are verified and from direct integration elsewhere.

use super::{InterpolantError, InterpolantOptions, MapInterpolant, onset_span};
use crate::model::exit_arc;
use crate::sim::analysis::cycle_with_derivative;
use crate::sim::{Orbit, OrbitOptions, SimError, Simulator};

/// How an orbit evaluates the map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapChoice {
    /// Every iterate integrated.
    Direct,
    /// The verified interpolant, with direct integration where it has no
    /// verified series.
    Interpolant,
    /// The interpolant from [`MapChoice::AUTO_ITERATES`] iterates on, direct
    /// below.
    Auto,
}

impl MapChoice {
    /// From this many iterates (transient + kept) on, `Auto` builds the
    /// interpolant: its construction (a few hundred to a few thousand map
    /// evaluations) is then a small part of the run.
    pub const AUTO_ITERATES: usize = 20_000;

    /// The kept points from which `Auto` continues a bifurcation column
    /// that has not settled on the interpolant: on Fig. 3b's chaotic
    /// columns its construction costs about 3 300 map evaluations (a
    /// refusal up to its cap, twice the kept points), so that 5000 points
    /// cost about what integrating them does and more points cost less.
    pub const AUTO_COLUMN_KEEP: usize = 5000;

    /// Whether a run of `iterates` iterates uses the interpolant.
    pub fn interpolates(self, iterates: usize) -> bool {
        match self {
            MapChoice::Direct => false,
            MapChoice::Interpolant => true,
            MapChoice::Auto => iterates >= Self::AUTO_ITERATES,
        }
    }

    /// Whether a run with `iterates` still to go after its direct part uses
    /// the interpolant, when `Auto` needs at least `threshold` of them.
    pub fn interpolates_beyond(self, iterates: usize, threshold: usize) -> bool {
        match self {
            MapChoice::Direct => false,
            MapChoice::Interpolant => iterates > 0,
            MapChoice::Auto => iterates >= threshold,
        }
    }
}

/// Direct iterates run from θ0 to see where the orbit goes before the
/// interpolant's first interval is chosen.
const SCOUT: usize = 300;

/// An orbit computed on the interpolant, with how it was computed.
#[derive(Clone, Debug)]
pub struct InterpolatedOrbit {
    pub orbit: Orbit,
    /// The interpolant as it ended (extended where the orbit went).
    pub interpolant: MapInterpolant,
    /// Iterates integrated directly: outside every verified series (a jump's
    /// bracket, or where an extension was refused).
    pub direct_iterates: usize,
    /// Times the interval was extended to take in an iterate.
    pub extensions: usize,
    /// Why an extension was refused, if one was (the iterates there were
    /// integrated).
    pub refused_extension: Option<String>,
}

/// The orbit of [`Simulator::orbit`] from θ0, its iterates from the map's
/// verified interpolant. The first [`SCOUT`] iterates of the transient are
/// integrated, and the interpolant is first built over the range of their
/// last two thirds (padded by a tenth); an iterate outside it extends it,
/// and where that is refused the iterate is integrated.
/// Refuses (so that the caller integrates the whole orbit) when the first
/// interval cannot be resolved.
pub fn orbit_interpolated(
    sim: &Simulator,
    theta0: f64,
    opts: &OrbitOptions,
    iopts: InterpolantOptions,
    cancel: &dyn Fn() -> bool,
) -> Result<InterpolatedOrbit, InterpolantError> {
    sim.check_onset(theta0)?;
    let p = sim.params();
    let (psi, _) = exit_arc(p.kappa, p.theta_nu);
    // The first iterates of the transient, integrated: where they settle
    // is where the interpolant is first built.
    let mut start = Start {
        theta: theta0,
        ..Start::default()
    };
    let mut seen = Vec::with_capacity(SCOUT);
    for _ in 0..SCOUT.min(opts.transient) {
        let ev = sim.cycle(start.theta, start.t, None)?;
        start.evals += ev.rhs_evals;
        start.restarts += ev.restarted as usize;
        start.t += ev.slip_duration + ev.stick_duration;
        start.theta = sim.next_onset(&ev);
        start.done += 1;
        seen.push(start.theta);
    }
    // A short transient: scout on, without moving the orbit.
    let mut probe = start.theta;
    while seen.len() < SCOUT / 3 {
        let ev = sim.cycle(probe, 0.0, None)?;
        start.evals += ev.rhs_evals;
        probe = sim.next_onset(&ev);
        seen.push(probe);
    }
    let (a, b, pad) =
        onset_span(psi, &seen, 0.1).ok_or(InterpolantError::Options("no onsets to build over"))?;
    let mut interp = MapInterpolant::build(sim, psi + a, psi + b, iopts)?;
    let mut run = Run {
        sim,
        interp: &mut interp,
        pad,
        direct: 0,
        extensions: 0,
        refused: None,
        evals: start.evals,
    };
    let orbit = run.orbit(&start, opts, cancel)?;
    let (direct_iterates, extensions, refused_extension) =
        (run.direct, run.extensions, run.refused);
    let mut orbit = orbit;
    orbit.rhs_evals += interp.rhs_evals();
    Ok(InterpolatedOrbit {
        orbit,
        interpolant: interp,
        direct_iterates: direct_iterates + start.done,
        extensions,
        refused_extension,
    })
}

impl InterpolatedOrbit {
    /// How the orbit used its interpolant, for a summary.
    pub fn summary(&self) -> super::InterpolantSummary {
        let refused = self.refused_extension.clone();
        super::InterpolantSummary::of(&self.interpolant, self.direct_iterates, refused)
    }
}

/// Where the interpolated part of an orbit starts: after `done` integrated
/// transient iterates, at θ and time t.
#[derive(Default)]
struct Start {
    theta: f64,
    t: f64,
    done: usize,
    restarts: usize,
    evals: u64,
}

/// The state of an interpolated orbit run.
struct Run<'a> {
    sim: &'a Simulator,
    interp: &'a mut MapInterpolant,
    pad: f64,
    direct: usize,
    extensions: usize,
    refused: Option<String>,
    evals: u64,
}

impl Run<'_> {
    /// Makes sure θ is inside the interval, extending it once per excursion
    /// until an extension is refused.
    fn cover(&mut self, theta: f64) {
        if self.interp.cover(theta, self.pad, &mut self.refused) {
            self.extensions += 1;
        }
    }

    fn orbit(
        &mut self,
        start: &Start,
        opts: &OrbitOptions,
        cancel: &dyn Fn() -> bool,
    ) -> Result<Orbit, SimError> {
        let sim = self.sim;
        let mut theta = start.theta;
        let mut t = start.t;
        let mut restarts = start.restarts;
        let mut events = Vec::with_capacity(opts.keep);
        let mut logs = Vec::with_capacity(if opts.lyapunov { opts.keep } else { 0 });
        for i in start.done..opts.transient + opts.keep {
            if i % 4096 == 0 && cancel() {
                return Err(SimError::Cancelled);
            }
            let kept = i >= opts.transient;
            if !kept {
                if let Some((next, duration)) = self.interp.step(theta) {
                    t += duration;
                    theta = next;
                    continue;
                }
                self.cover(theta);
                if let Some((next, duration)) = self.interp.step(theta) {
                    t += duration;
                    theta = next;
                    continue;
                }
            } else {
                let mut tab = self.interp.slip_event(theta, t);
                if tab.is_none() {
                    self.cover(theta);
                    tab = self.interp.slip_event(theta, t);
                }
                if let Some((ev, d)) = tab {
                    if opts.lyapunov {
                        logs.push(d.abs().ln());
                    }
                    t += ev.slip_duration + ev.stick_duration;
                    theta = ev.theta_next;
                    events.push(ev);
                    continue;
                }
            }
            // No verified series here: integrate, as `Simulator::orbit` does.
            self.direct += 1;
            let ev = if kept && opts.lyapunov {
                let (ev, d, n) = cycle_with_derivative(sim, theta, t)?;
                self.evals += n;
                logs.push(d.abs().ln());
                ev
            } else {
                sim.cycle(theta, t, None)?
            };
            self.evals += ev.rhs_evals;
            restarts += ev.restarted as usize;
            t += ev.slip_duration + ev.stick_duration;
            if kept {
                events.push(ev);
            }
            theta = sim.next_onset(&ev);
        }
        let thetas: Vec<f64> = events.iter().map(|e| e.theta).collect();
        let mut spent = (0, 0);
        let settled = sim.settle(&thetas, theta, &logs, opts.period_tol, &mut spent);
        Ok(Orbit {
            events,
            restarts,
            period: settled.period,
            cycle: settled.cycle,
            lyapunov: settled.lyapunov,
            lyapunov_stderr: settled.lyapunov_stderr,
            rhs_evals: self.evals + spent.1,
            theta_last: theta,
        })
    }
}
