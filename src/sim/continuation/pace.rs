//! Pausing a continuation between map evaluations.
//!
//! The continuation's walks are `async fn`s: they await [`Pace::piece`]
//! after every map evaluation (one slip cycle with its derivatives) and
//! [`Pace::cancelled`] where they poll for a stop. Whoever polls the
//! future answers: at a piece it may stop polling for now (the browser's
//! host gives its frame back and polls again on the next step), and a
//! cancel it asks of its own caller. The arithmetic between two awaits is
//! the synchronous code's, so a run paused after every piece computes the
//! same numbers, bit for bit, as one run in a go. [`drive`] polls a walk
//! to its end at once: the synchronous API ([`super::continue_branch`],
//! …) is that.

use std::future::Future;
use std::pin::Pin;
use std::sync::atomic::{AtomicU8, Ordering};
use std::task::{Context, Poll, Waker};

use crate::sim::Simulator;
use crate::sim::cycles::{Cycle, CycleFailure, CycleOptions, CycleSolve};

/// Nothing asked.
const IDLE: u8 = 0;
/// A map evaluation is done: the poller may pause.
const PIECE: u8 = 1;
/// The walk asks whether it must stop.
const ASKED: u8 = 2;
/// The poller's answers to [`ASKED`].
const STOP: u8 = 3;
const GO_ON: u8 = 4;

/// What a pending walk waits for ([`Pace::ask`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ask {
    /// A map evaluation is done: pause here if the host wants its thread
    /// back, or poll again.
    Piece,
    /// Whether the walk must stop: [`Pace::answer`], then poll again.
    Cancel,
}

/// The mailbox between a walk and whoever polls it.
#[derive(Debug, Default)]
pub struct Pace {
    state: AtomicU8,
}

impl Pace {
    pub fn new() -> Self {
        Self::default()
    }

    /// A point where the walk may pause: after each map evaluation.
    pub async fn piece(&self) {
        Wait::new(self, PIECE).await;
    }

    /// Whether the walk must stop (the poller's [`Pace::answer`]).
    pub async fn cancelled(&self) -> bool {
        Wait::new(self, ASKED).await
    }

    /// What the pending walk waits for (`None`: it is not waiting here).
    pub fn ask(&self) -> Option<Ask> {
        match self.state.load(Ordering::Acquire) {
            PIECE => Some(Ask::Piece),
            ASKED => Some(Ask::Cancel),
            _ => None,
        }
    }

    /// The answer to [`Ask::Cancel`]: true when the walk must stop.
    pub fn answer(&self, stop: bool) {
        let _ = self.state.compare_exchange(
            ASKED,
            if stop { STOP } else { GO_ON },
            Ordering::AcqRel,
            Ordering::Acquire,
        );
    }
}

/// One await on the mailbox: pending once with its question, then ready
/// with the answer.
struct Wait<'a> {
    pace: &'a Pace,
    kind: u8,
    asked: bool,
}

impl<'a> Wait<'a> {
    fn new(pace: &'a Pace, kind: u8) -> Self {
        Wait {
            pace,
            kind,
            asked: false,
        }
    }
}

impl Future for Wait<'_> {
    type Output = bool;

    fn poll(mut self: Pin<&mut Self>, _cx: &mut Context<'_>) -> Poll<bool> {
        if !self.asked {
            self.asked = true;
            self.pace.state.store(self.kind, Ordering::Release);
            return Poll::Pending;
        }
        match self.pace.state.load(Ordering::Acquire) {
            // A question not answered yet: still waiting.
            ASKED => Poll::Pending,
            answer => {
                self.pace.state.store(IDLE, Ordering::Release);
                Poll::Ready(answer == STOP)
            }
        }
    }
}

/// Polls `walk` to its end at once, answering its cancels with `cancel`
/// (the synchronous API).
pub fn drive<F: Future>(pace: &Pace, walk: F, cancel: &dyn Fn() -> bool) -> F::Output {
    // On the heap: a cascade's state holds every level's walk.
    let mut walk = Box::pin(walk);
    loop {
        if let Some(out) = one_piece(pace, walk.as_mut(), cancel) {
            return out;
        }
    }
}

/// Polls `walk` up to its next piece (`None`) or its end (its output),
/// answering its cancels with `cancel`: one map evaluation at most.
pub fn one_piece<F: Future + ?Sized>(
    pace: &Pace,
    mut walk: Pin<&mut F>,
    cancel: &dyn Fn() -> bool,
) -> Option<F::Output> {
    let mut cx = Context::from_waker(Waker::noop());
    loop {
        if let Poll::Ready(out) = walk.as_mut().poll(&mut cx) {
            return Some(out);
        }
        match pace.ask() {
            Some(Ask::Cancel) => pace.answer(cancel()),
            Some(Ask::Piece) | None => return None,
        }
    }
}

/// [`crate::sim::cycles::solve_counting`] with a piece after each map
/// evaluation: the same solve, the evaluations it spends added to `spent`.
pub(super) async fn solve_cycle(
    pace: &Pace,
    sim: &Simulator,
    seed: f64,
    p: usize,
    opts: &CycleOptions,
    spent: &mut (u64, u64),
) -> Result<Cycle, CycleFailure> {
    let mut solve = CycleSolve::start(sim, seed, p, opts)?;
    let result = loop {
        let step = solve.advance(sim);
        pace.piece().await;
        if let Some(r) = step {
            break r;
        }
    };
    let (maps, rhs) = solve.spent();
    spent.0 += maps;
    spent.1 += rhs;
    result
}
