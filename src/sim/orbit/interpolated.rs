//! Orbits on the interpolated map: the same [`Orbit`] as
//! [`Simulator::orbit`] gives, its iterates from the series wherever they
//! are verified and from direct integration elsewhere. The orbit loop is
//! [`OrbitRun`]'s; [`OnInterpolant`] is what it carries when its iterates
//! come from the interpolant: the scout, the build and the series, each in
//! bounded pieces.

use super::{Orbit, OrbitOptions, OrbitRun};
use crate::model::exit_arc;
use crate::sim::interpolant::{
    InterpolantBuild, InterpolantError, InterpolantOptions, InterpolantSummary, MapInterpolant,
    MapUsed, Reach, Stepper, onset_span,
};
use crate::sim::{SimError, Simulator, SlipEvent};

/// Direct iterates run from θ0 to see where the orbit goes before the
/// interpolant's first interval is chosen.
const SCOUT: usize = 300;

/// Iterates from the series one [`OrbitRun::advance`] makes at most (an
/// integrated iterate counts as [`DIRECT_COST`] of them; a piece of an
/// extension ends the batch): a fraction of a millisecond.
const SERIES_BATCH: usize = 512;

/// What an integrated iterate counts for against [`SERIES_BATCH`].
const DIRECT_COST: usize = 32;

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
/// verified interpolant ([`OrbitRun::interpolated`], run to its end).
/// Refuses (so that the caller integrates the whole orbit) when the first
/// interval cannot be resolved.
pub fn orbit_interpolated(
    sim: &Simulator,
    theta0: f64,
    opts: &OrbitOptions,
    iopts: InterpolantOptions,
    cancel: &dyn Fn() -> bool,
) -> Result<InterpolatedOrbit, InterpolantError> {
    let mut run = OrbitRun::interpolated(sim, theta0, opts, iopts)?;
    let orbit = loop {
        if let Some(e) = run.on_interpolant().and_then(OnInterpolant::refusal) {
            return Err(e.clone());
        }
        if let Some(r) = run.advance(sim, cancel) {
            break r?;
        }
    };
    let on = run.take_interpolant().ok_or(InterpolantError::Options(
        "the orbit ran without its interpolant",
    ))?;
    let direct_iterates = on.direct_iterates();
    match on.stage {
        Stage::On(st) => {
            let (interpolant, cover) = st.into_parts();
            Ok(InterpolatedOrbit {
                orbit,
                interpolant,
                direct_iterates,
                extensions: cover.extensions,
                refused_extension: cover.refused,
            })
        }
        Stage::Refused(e) => Err(e),
        Stage::Scout { .. } | Stage::Build { .. } => Err(InterpolantError::Options(
            "the orbit ended before its interpolant was built",
        )),
    }
}

impl InterpolatedOrbit {
    /// How the orbit used its interpolant, for a summary.
    pub fn summary(&self) -> InterpolantSummary {
        let refused = self.refused_extension.clone();
        InterpolantSummary::of(&self.interpolant, self.direct_iterates, refused)
    }
}

/// An [`OrbitRun`]'s interpolant: the first [`SCOUT`] iterates of the
/// transient are integrated, the interpolant is built over the range of
/// their last two thirds (padded by a tenth), and the rest come from its
/// series; an iterate outside the interval extends it, and where that is
/// refused the iterate is integrated. A first interval that cannot be
/// resolved leaves the rest of the orbit to direct integration.
#[derive(Debug)]
pub struct OnInterpolant {
    iopts: InterpolantOptions,
    /// The orbit's iterates integrated before the build.
    scouted: usize,
    stage: Stage,
}

/// Where an [`OnInterpolant`] is.
#[derive(Debug)]
enum Stage {
    /// The scout's onsets so far; `probe`, once the transient is too short
    /// to scout on, where the scout goes on without moving the orbit.
    Scout { seen: Vec<f64>, probe: Option<f64> },
    Build {
        build: Box<InterpolantBuild>,
        pad: f64,
    },
    /// The series, extended where the orbit goes; the stepper counts the
    /// iterates integrated since the build.
    On(Box<Stepper>),
    /// The first interval was refused: the orbit is integrated.
    Refused(InterpolantError),
}

/// What [`OnInterpolant::piece`] leaves to the orbit loop.
pub(crate) enum OrbitPiece {
    /// A piece was done (iterates of the orbit, or work towards them).
    Done,
    /// The next iterate is to be integrated, as a direct orbit does.
    Direct,
}

impl OnInterpolant {
    pub(crate) fn new(iopts: InterpolantOptions) -> Self {
        OnInterpolant {
            iopts,
            scouted: 0,
            stage: Stage::Scout {
                seen: Vec::with_capacity(SCOUT),
                probe: None,
            },
        }
    }

    /// Why the first interval was refused, if it was.
    pub fn refusal(&self) -> Option<&InterpolantError> {
        match &self.stage {
            Stage::Refused(e) => Some(e),
            _ => None,
        }
    }

    /// Iterates integrated: the scout's and those outside every verified
    /// series.
    fn direct_iterates(&self) -> usize {
        match &self.stage {
            Stage::On(st) => self.scouted + st.direct_iterates(),
            _ => self.scouted,
        }
    }

    /// Right-hand-side evaluations of the interpolant's construction and
    /// extensions (the orbit's own are the run's).
    pub(crate) fn rhs_evals(&self) -> u64 {
        match &self.stage {
            Stage::On(st) => st.interpolant().rhs_evals(),
            _ => 0,
        }
    }

    /// How the orbit evaluated the map, for its summary.
    pub fn map_used(&self) -> MapUsed {
        match &self.stage {
            Stage::On(st) => MapUsed::Interpolant(InterpolantSummary::of(
                st.interpolant(),
                self.direct_iterates(),
                st.cover().refused.clone(),
            )),
            Stage::Refused(e) => MapUsed::Refused(e.to_string()),
            Stage::Scout { .. } | Stage::Build { .. } => MapUsed::Direct,
        }
    }

    /// One bounded piece of `run`'s orbit: a scout's iterate, a piece of
    /// the build, or up to [`SERIES_BATCH`] iterates from the series.
    pub(crate) fn piece(
        &mut self,
        sim: &Simulator,
        run: &mut OrbitRun,
    ) -> Result<OrbitPiece, SimError> {
        match &mut self.stage {
            Stage::Scout { seen, probe } => {
                if run.cycles_done() < SCOUT.min(run.options().transient) {
                    // The orbit's own first iterates, integrated.
                    run.direct_cycle(sim)?;
                    self.scouted += 1;
                    seen.push(run.theta());
                } else if seen.len() < SCOUT / 3 {
                    // A short transient: scout on, without moving the orbit
                    // (a cycle that fails here refuses the interpolant).
                    let from = *probe.get_or_insert(run.theta());
                    match sim.cycle(from, 0.0, None) {
                        Ok(ev) => {
                            run.add_evals(ev.rhs_evals);
                            let next = sim.next_onset(&ev);
                            *probe = Some(next);
                            seen.push(next);
                        }
                        Err(e) => self.stage = Stage::Refused(e.into()),
                    }
                } else {
                    self.stage = build(sim, seen, self.iopts);
                }
                Ok(OrbitPiece::Done)
            }
            Stage::Build { build, .. } => {
                match build.advance() {
                    Ok(false) => {}
                    Ok(true) => self.built(),
                    Err(e) => {
                        // What the refused build cost is the orbit's.
                        run.add_evals(build.spent().1);
                        self.stage = Stage::Refused(e);
                    }
                }
                Ok(OrbitPiece::Done)
            }
            Stage::On(st) => series_batch(sim, run, st),
            Stage::Refused(_) => Ok(OrbitPiece::Direct),
        }
    }

    /// The finished build's interpolant, in use.
    fn built(&mut self) {
        let placeholder = Stage::Scout {
            seen: Vec::new(),
            probe: None,
        };
        if let Stage::Build { build, pad } = std::mem::replace(&mut self.stage, placeholder) {
            self.stage = Stage::On(Box::new(Stepper::on(build.finish(), pad)));
        }
    }
}

/// The build over the range of the scout's onsets `seen`, or the
/// refusal that leaves the orbit to direct integration.
fn build(sim: &Simulator, seen: &[f64], iopts: InterpolantOptions) -> Stage {
    let p = sim.params();
    let (psi, _) = exit_arc(p.kappa, p.theta_nu);
    let Some((a, b, pad)) = onset_span(psi, seen, 0.1) else {
        return Stage::Refused(InterpolantError::Options("no onsets to build over"));
    };
    match InterpolantBuild::start(sim, psi + a, psi + b, iopts, false) {
        Ok(build) => Stage::Build {
            build: Box::new(build),
            pad,
        },
        Err(e) => Stage::Refused(e),
    }
}

/// Up to [`SERIES_BATCH`] iterates of `run` from the series (the
/// transient's as steps, the kept as slip events with f'(θ) for the
/// exponent), integrated where no verified series serves, as
/// [`OrbitRun`]'s own cycles are.
fn series_batch(
    sim: &Simulator,
    run: &mut OrbitRun,
    st: &mut Stepper,
) -> Result<OrbitPiece, SimError> {
    let mut budget = SERIES_BATCH;
    while budget > 0 && !run.settling() {
        let theta = run.theta();
        let (kept, t) = (run.cycles_done() >= run.options().transient, run.time());
        let next = |i: &MapInterpolant| {
            if kept {
                i.slip_event(theta, t).map(|(ev, d)| Next::Keep(ev, d))
            } else {
                i.step(theta)
                    .map(|(next, duration)| Next::Skip(next, duration))
            }
        };
        let cost = match st.reach(theta, next) {
            Reach::Series(Next::Skip(next, duration)) => {
                run.skip(next, duration);
                1
            }
            Reach::Series(Next::Keep(ev, d)) => {
                run.keep(ev, d);
                1
            }
            Reach::Extending => break,
            Reach::Direct => {
                st.count_direct();
                run.direct_cycle(sim)?;
                DIRECT_COST
            }
        };
        budget = budget.saturating_sub(cost);
    }
    Ok(OrbitPiece::Done)
}

/// An iterate from the series: a transient one's next onset and duration,
/// or a kept one's event and f'(θ).
enum Next {
    Skip(f64, f64),
    Keep(SlipEvent, f64),
}
