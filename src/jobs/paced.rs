//! A job whose work is one `async` walk (the continuation's, which awaits
//! a piece after every map evaluation: [`crate::sim::continuation::Pace`]),
//! polled by its steps. A step polls until the walk ends, or until the
//! host wants its thread back ([`Sink::pause`]) at a piece; the walk's
//! questions (must it stop?) are the sink's [`Sink::cycle`], asked at the
//! same points as a synchronous run asks them, and its updates queue in
//! an outbox the step sends on after each poll. So every host, paused or
//! not, sees the same updates and the same numbers, bit for bit.

use std::future::Future;
use std::pin::Pin;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::task::{Context, Poll, Waker};

use super::protocol::{Generation, Update};
use super::{Job, JobError, Sink, Status, lock};
use crate::sim::continuation::{Ask, Pace};

/// What a walk shares with the steps that poll it.
#[derive(Default)]
pub(super) struct Shared {
    /// Its pieces and cancels.
    pub(super) pace: Pace,
    /// Updates sent since the last poll.
    outbox: Mutex<Vec<Update>>,
    /// The sink's generation, lane and staleness, as of the poll.
    generation: AtomicU64,
    lane: Mutex<Option<super::Lane>>,
    stale: AtomicBool,
}

impl Shared {
    /// Queues an update for the step to send.
    pub(super) fn send(&self, update: Update) {
        lock(&self.outbox).push(update);
    }

    /// The generation the job runs under.
    pub(super) fn generation(&self) -> Generation {
        self.generation.load(Ordering::Relaxed)
    }

    /// The lane the host runs the job on (as of the poll; a walk is first
    /// polled before it sends).
    pub(super) fn lane(&self) -> super::Lane {
        lock(&self.lane).unwrap_or(super::Lane::Continuation)
    }

    /// Whether the job must stop ([`Sink::stale`] as of this poll).
    pub(super) fn stale(&self) -> bool {
        self.stale.load(Ordering::Relaxed)
    }

    /// Sends the queued updates to `sink`; `Err` at the first it refuses.
    fn flush(&self, sink: &dyn Sink) -> Result<(), JobError> {
        let queued = std::mem::take(&mut *lock(&self.outbox));
        for update in queued {
            sink.send(update)?;
        }
        Ok(())
    }
}

type Walk = Pin<Box<dyn Future<Output = Result<(), JobError>> + Send>>;

/// A job of one walk, paused at pieces where the host asks.
pub(crate) struct PacedJob {
    shared: Arc<Shared>,
    /// `None` once it has ended.
    walk: Mutex<Option<Walk>>,
}

impl PacedJob {
    /// The job of the walk `make` builds on the shared state.
    pub(super) fn new<F>(make: impl FnOnce(Arc<Shared>) -> F) -> Self
    where
        F: Future<Output = Result<(), JobError>> + Send + 'static,
    {
        let shared = Arc::new(Shared::default());
        let walk: Walk = Box::pin(make(shared.clone()));
        PacedJob {
            shared,
            walk: Mutex::new(Some(walk)),
        }
    }

    /// Polls `walk` until it ends (its result) or pauses at a piece
    /// (`None`), sending its updates.
    fn poll(&self, walk: &mut Walk, sink: &dyn Sink) -> Result<Option<()>, JobError> {
        let sh = &self.shared;
        sh.generation.store(sink.generation(), Ordering::Relaxed);
        *lock(&sh.lane) = Some(sink.lane());
        let mut cx = Context::from_waker(Waker::noop());
        loop {
            sh.stale.store(sink.stale(), Ordering::Relaxed);
            let polled = walk.as_mut().poll(&mut cx);
            // What it sent before it asked (or ended) goes first.
            sh.flush(sink)?;
            if let Poll::Ready(ended) = polled {
                return ended.map(Some);
            }
            match sh.pace.ask() {
                Some(Ask::Cancel) => sh.pace.answer(sink.cycle()),
                Some(Ask::Piece) if sink.pause() => return Ok(None),
                Some(Ask::Piece) => {}
                None => {
                    return Err(JobError::Failed(
                        "the continuation waited for nothing".into(),
                    ));
                }
            }
        }
    }
}

impl Job for PacedJob {
    fn step(&self, _width: usize, sink: &dyn Sink) -> Result<Status, JobError> {
        let mut slot = lock(&self.walk);
        let Some(walk) = slot.as_mut() else {
            return Ok(Status::Done);
        };
        match self.poll(walk, sink) {
            Ok(None) => Ok(Status::Working),
            ended => {
                *slot = None;
                ended.map(|_| Status::Done)
            }
        }
    }
}
