//! The Events view's two computations as jobs: the creep channel's passage
//! time (a few hundred map evaluations, for the parameters on screen) and
//! the tangency scan (orbits near θν, a continuation, then orbits at
//! distances from the fold). Each is one unit that pauses between its
//! pieces (a slip cycle, a map evaluation; the scan's continuation is one
//! piece) when the host wants its thread back ([`Sink::pause`]), and
//! resumes with the same result bit for bit.

use std::sync::Mutex;

use super::protocol::Update;
use super::{Job, JobError, Sink, Status, lock};
use crate::integrate::SolverSettings;
use crate::model::Params;
use crate::sim::intermittency::{Passage, PassageRun, Scaling, ScalingRun};
use crate::sim::{SimError, Simulator};

/// The creep channel's passage time at `params` through the channel that
/// holds the creep onset `near` (`sim::intermittency::passage`).
#[derive(Clone, Debug, PartialEq)]
pub struct PassageSpec {
    /// The model's parameters.
    pub params: Params,
    /// The solver and its accuracy.
    pub settings: SolverSettings,
    /// A creep onset on the exit arc (the channel's).
    pub near: f64,
}

/// The tangency nearest θν and the mean laminar length against the
/// distance to it (`sim::intermittency::scaling`).
#[derive(Clone, Debug, PartialEq)]
pub struct ScanSpec {
    /// The model's parameters.
    pub params: Params,
    /// The solver and its accuracy.
    pub settings: SolverSettings,
}

/// A computation in pieces: one piece per call, its answer once done.
trait Pieces: Send {
    type Out;
    fn advance(&mut self, cancel: &dyn Fn() -> bool) -> Option<Result<Self::Out, SimError>>;
    /// The update that carries the answer.
    fn update(generation: u64, out: Self::Out) -> Update;
}

struct PassagePieces {
    sim: Simulator,
    run: PassageRun,
}

impl Pieces for PassagePieces {
    type Out = Passage;
    fn advance(&mut self, cancel: &dyn Fn() -> bool) -> Option<Result<Passage, SimError>> {
        self.run.advance(&self.sim, cancel)
    }
    fn update(generation: u64, passage: Passage) -> Update {
        Update::Passage {
            generation,
            passage,
        }
    }
}

impl Pieces for ScalingRun {
    type Out = Scaling;
    fn advance(&mut self, cancel: &dyn Fn() -> bool) -> Option<Result<Scaling, SimError>> {
        ScalingRun::advance(self, cancel)
    }
    fn update(generation: u64, scaling: Scaling) -> Update {
        Update::Scan {
            generation,
            scaling,
        }
    }
}

/// A job of one pausable unit: `P`'s pieces until its answer.
pub(crate) struct PiecesJob<P> {
    /// `None` once answered.
    run: Mutex<Option<P>>,
}

/// The channel passage's job; a simulator that
/// cannot be made is the job's error.
pub(crate) fn passage_job(spec: PassageSpec) -> Result<Box<dyn Job>, JobError> {
    let sim = Simulator::new(spec.params, spec.settings)?;
    let run = PassageRun::new(&sim, spec.near);
    Ok(Box::new(PiecesJob {
        run: Mutex::new(Some(PassagePieces { sim, run })),
    }))
}

/// The tangency scan's job.
pub(crate) fn scan_job(spec: ScanSpec) -> Result<Box<dyn Job>, JobError> {
    Simulator::new(spec.params, spec.settings)?;
    Ok(Box::new(PiecesJob {
        run: Mutex::new(Some(ScalingRun::new(spec.params, spec.settings))),
    }))
}

impl<P: Pieces> Job for PiecesJob<P> {
    /// Pieces until the answer (sent) or until the host wants its thread
    /// back, after one piece at least.
    fn step(&self, _width: usize, sink: &dyn Sink) -> Result<Status, JobError> {
        let mut guard = lock(&self.run);
        let Some(run) = guard.as_mut() else {
            return Ok(Status::Done);
        };
        let cancel = || sink.cycle();
        loop {
            if let Some(r) = run.advance(&cancel) {
                *guard = None;
                sink.send(P::update(sink.generation(), r?))?;
                return Ok(Status::Done);
            }
            if sink.pause() {
                return Ok(Status::Working);
            }
        }
    }
}
