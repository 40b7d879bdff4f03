//! One map iterate at a time on the interpolant, for the callers that run
//! their own loop over the iterates (a phase cell, a bifurcation column):
//! the series where it is verified, the interval extended where an iterate
//! leaves it, and direct integration where neither serves.

use super::{
    Cover, InterpolantBuild, InterpolantError, InterpolantOptions, MapInterpolant, Reach,
    onset_span,
};
use crate::model::exit_arc;
use crate::sim::analysis::cycle_with_derivative;
use crate::sim::{SimError, Simulator};

/// How a run evaluated the map, for the caller's summary.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum MapUsed {
    /// Every iterate integrated (the interpolant was not asked for, or the
    /// run was too short for it).
    #[default]
    Direct,
    /// The interpolant was asked for but refused (the reason): every
    /// iterate was integrated.
    Refused(String),
    /// The interpolant.
    Interpolant(InterpolantSummary),
}

/// How a set of runs (a grid's cells, a diagram's columns) used the
/// interpolant.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MapTally {
    /// Runs that iterated it.
    pub used: usize,
    /// Runs it was refused for (they integrated).
    pub refused: usize,
    /// Map evaluations the used ones' constructions took.
    pub evaluations: usize,
    /// The largest map error measured on any of them.
    pub max_error: f64,
}

impl MapTally {
    /// The tally of `runs`; `None` when none asked for the interpolant.
    pub fn of<'a>(runs: impl IntoIterator<Item = &'a MapUsed>) -> Option<MapTally> {
        let mut t = MapTally::default();
        for m in runs {
            match m {
                MapUsed::Interpolant(s) => {
                    t.used += 1;
                    t.evaluations += s.evaluations;
                    t.max_error = t.max_error.max(s.max_map_error);
                }
                MapUsed::Refused(_) => t.refused += 1,
                MapUsed::Direct => {}
            }
        }
        (t.used + t.refused > 0).then_some(t)
    }
}

/// What an interpolated run reports about its interpolant.
#[derive(Clone, Debug, PartialEq)]
pub struct InterpolantSummary {
    /// Pieces, jump brackets included.
    pub pieces: usize,
    /// The largest number of coefficients of θ' on a piece, less one.
    pub degree: usize,
    /// The interval covered, in θ.
    pub interval: (f64, f64),
    /// Map evaluations spent building and checking it.
    pub evaluations: usize,
    /// Independent points it was checked at.
    pub points: usize,
    /// The largest |θ' − θ'_direct| measured there.
    pub max_map_error: f64,
    /// The other tabulated quantities' largest relative error there.
    pub max_event_error: f64,
    /// Iterates integrated directly after it was built (a jump's bracket,
    /// or beyond a refused extension).
    pub direct_iterates: usize,
    /// Why an extension was refused, if one was.
    pub refused_extension: Option<String>,
}

impl InterpolantSummary {
    /// The summary of a run on `interp` that integrated `direct_iterates`
    /// iterates itself, an extension refused for `refused_extension`.
    pub fn of(
        interp: &MapInterpolant,
        direct_iterates: usize,
        refused_extension: Option<String>,
    ) -> Self {
        let v = interp.verification();
        InterpolantSummary {
            pieces: interp.pieces().0,
            degree: interp.max_degree(),
            interval: interp.interval(),
            evaluations: interp.evaluations(),
            points: v.points,
            max_map_error: v.max_map_error,
            max_event_error: v.max_event_error,
            direct_iterates,
            refused_extension,
        }
    }
}

/// Direct iterates a caller runs before it builds the interpolant over
/// their range: fewer give a poor picture of where the orbit goes.
pub const MIN_DIRECT: usize = 100;

/// A [`Stepper`]'s interpolant being built, a bounded piece a call
/// ([`InterpolantBuild`]).
#[derive(Debug)]
pub struct StepperBuild {
    build: InterpolantBuild,
    pad: f64,
}

impl StepperBuild {
    /// The build over the range of `recent` onsets, as [`Stepper::over`].
    pub fn over(
        sim: &Simulator,
        recent: &[f64],
        iopts: InterpolantOptions,
    ) -> Result<Self, InterpolantError> {
        let p = sim.params();
        let (psi, _) = exit_arc(p.kappa, p.theta_nu);
        let (a, b, pad) = onset_span(psi, recent, 0.02)
            .ok_or(InterpolantError::Options("no onsets to build over"))?;
        let build = InterpolantBuild::start(sim, psi + a, psi + b, iopts, false)?;
        Ok(StepperBuild { build, pad })
    }

    /// One piece of the work; whether the interpolant is done. An error
    /// refuses it, and the build must not be advanced again.
    pub fn advance(&mut self) -> Result<bool, InterpolantError> {
        self.build.advance()
    }

    /// Map evaluations and right-hand-side evaluations spent so far.
    pub fn spent(&self) -> (u64, u64) {
        self.build.spent()
    }

    /// The stepper, once [`Self::advance`] has said the build is done; its
    /// construction counts as charged ([`Stepper::take_cost`]).
    pub fn finish(self) -> Stepper {
        Stepper::on(self.build.finish(), self.pad)
    }
}

/// The map for a run's remaining iterates: the interpolant where it is
/// verified, direct integration elsewhere.
#[derive(Debug)]
pub struct Stepper {
    interp: MapInterpolant,
    pad: f64,
    /// Iterates integrated since it was built.
    direct: usize,
    /// Right-hand-side evaluations those cost.
    rhs_evals: u64,
    /// The interval's extensions to iterates that left it.
    cover: Cover,
    /// The cost already handed to the caller: (map evaluations, RHS
    /// evaluations), construction and direct iterates together.
    charged: (u64, u64),
}

impl Stepper {
    /// Builds the interpolant over the range of `recent` onsets (the later
    /// two thirds of them, where the orbit has settled most), padded by a
    /// tenth of that range and at least 1e-3, all at once
    /// ([`StepperBuild`] in pieces). The map evaluations and right-hand-side
    /// evaluations spent are added to `spent`, also when the build is
    /// refused.
    pub fn over(
        sim: &Simulator,
        recent: &[f64],
        iopts: InterpolantOptions,
        spent: &mut (u64, u64),
    ) -> Result<Self, InterpolantError> {
        let StepperBuild { build, pad } = StepperBuild::over(sim, recent, iopts)?;
        Ok(Stepper::on(build.run_counting(spent)?, pad))
    }

    /// The stepper on `interp`, its construction charged; `pad` is how far
    /// beyond an iterate an extension reaches.
    pub(crate) fn on(interp: MapInterpolant, pad: f64) -> Self {
        Stepper {
            charged: (interp.evaluations() as u64, interp.rhs_evals()),
            interp,
            pad,
            direct: 0,
            rhs_evals: 0,
            cover: Cover::default(),
        }
    }

    /// The cost (map evaluations, RHS evaluations) since the last call (or
    /// since [`Self::over`], which charged the construction): extensions of
    /// the interval and iterates integrated directly.
    pub fn take_cost(&mut self) -> (u64, u64) {
        let total = (
            self.interp.evaluations() as u64 + self.direct as u64,
            self.interp.rhs_evals() + self.rhs_evals,
        );
        let new = (total.0 - self.charged.0, total.1 - self.charged.1);
        self.charged = total;
        new
    }

    /// The interpolant as it is now.
    pub fn interpolant(&self) -> &MapInterpolant {
        &self.interp
    }

    /// Right-hand-side evaluations of the iterates integrated directly (the
    /// construction's are [`MapInterpolant::rhs_evals`]).
    pub fn direct_rhs_evals(&self) -> u64 {
        self.rhs_evals
    }

    /// Iterates integrated directly so far.
    pub fn direct_iterates(&self) -> usize {
        self.direct
    }

    /// The summary of the run so far.
    pub fn summary(&self) -> InterpolantSummary {
        InterpolantSummary::of(&self.interp, self.direct, self.cover.refused.clone())
    }

    /// What the series give at θ ([`Cover::reach`] on this stepper's
    /// interpolant).
    pub(crate) fn reach<T>(
        &mut self,
        theta: f64,
        f: impl Fn(&MapInterpolant) -> Option<T>,
    ) -> Reach<T> {
        self.cover.reach(&mut self.interp, theta, self.pad, f)
    }

    /// An iterate the caller integrated itself where [`Self::reach`] found
    /// no series (an orbit's, with its time and derivative): counted, not
    /// charged.
    pub(crate) fn count_direct(&mut self) {
        self.direct += 1;
    }

    /// The interval's extensions so far, and why one was refused.
    pub fn cover(&self) -> &Cover {
        &self.cover
    }

    /// The interpolant as it ended, with the extensions' record.
    pub fn into_parts(self) -> (MapInterpolant, Cover) {
        (self.interp, self.cover)
    }

    /// One bounded piece towards the next onset after θ: `Some` with it,
    /// from the series or integrated, or `None` after a piece of the
    /// interval's extension to θ (ask again with the same θ). Asked until
    /// `Some`, it gives what [`Self::next`] gives.
    pub fn next_piece(&mut self, theta: f64) -> Result<Option<f64>, SimError> {
        match self.reach(theta, |i| i.map(theta)) {
            Reach::Series(next) => Ok(Some(next)),
            Reach::Extending => Ok(None),
            Reach::Direct => {
                self.direct += 1;
                let sim = self.interp.simulator();
                let ev = sim.cycle(theta, 0.0, None)?;
                self.rhs_evals += ev.rhs_evals;
                Ok(Some(sim.next_onset(&ev)))
            }
        }
    }

    /// The next onset after θ, from the series or integrated (the
    /// interval extended first, all at once, if θ is outside it).
    pub fn next(&mut self, theta: f64) -> Result<f64, SimError> {
        loop {
            if let Some(next) = self.next_piece(theta)? {
                return Ok(next);
            }
        }
    }

    /// [`Self::next_piece`] with f'(θ) too.
    pub fn next_with_derivative_piece(
        &mut self,
        theta: f64,
    ) -> Result<Option<(f64, f64)>, SimError> {
        let from_series = |i: &MapInterpolant| i.event(theta).map(|t| (t.theta_next, t.derivative));
        match self.reach(theta, from_series) {
            Reach::Series(r) => Ok(Some(r)),
            Reach::Extending => Ok(None),
            Reach::Direct => {
                self.direct += 1;
                let sim = self.interp.simulator();
                let (ev, d, n) = cycle_with_derivative(sim, theta, 0.0)?;
                self.rhs_evals += ev.rhs_evals + n;
                Ok(Some((sim.next_onset(&ev), d)))
            }
        }
    }

    /// The next onset after θ and f'(θ), from the series or integrated.
    pub fn next_with_derivative(&mut self, theta: f64) -> Result<(f64, f64), SimError> {
        loop {
            if let Some(r) = self.next_with_derivative_piece(theta)? {
                return Ok(r);
            }
        }
    }
}
