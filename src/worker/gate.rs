//! One lane's generation gate: the single place where updates of that lane
//! leave the worker, so that cancellation and sending cannot interleave.
//!
//! The lane's current generation lives in an atomic that jobs poll once per
//! slip cycle (cheap, lock-free), but it is only ever *changed* while the
//! gate's mutex is held, and every update of the lane is sent while holding
//! that same mutex after re-checking the generation. Hence when the
//! dispatcher moves the generation on and sends `Cancelled` (or the old
//! job's `Finished{Cancelled}`) under the lock, any update of the old
//! generation is either already in the channel before it, or is never sent.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};
use std::time::Duration;

use crossbeam_channel::{SendTimeoutError, Sender};

use crate::jobs::{Generation, Lane, Outcome, Stop, Update};

/// The generation a stopped worker moves every lane to: no job matches it.
pub(crate) const STOPPED: Generation = Generation::MAX;

/// How long a job's send waits for room before letting go of the lock, so
/// that a cancellation is never stuck behind a job blocked on a full channel.
const SEND_SLICE: Duration = Duration::from_millis(5);

/// Bookkeeping guarded by the gate's lock.
#[derive(Debug, Default)]
struct GateState {
    /// The job that was started and has not yet sent its `Finished`.
    running: Option<Generation>,
}

/// The generation gate of one lane, shared by the dispatcher and the lane's
/// job thread(s).
pub(crate) struct Gate {
    pub lane: Lane,
    current: AtomicU64,
    state: Mutex<GateState>,
    tx: Sender<Update>,
    wake: std::sync::Arc<dyn Fn() + Send + Sync>,
}

impl Gate {
    pub fn new(
        lane: Lane,
        tx: Sender<Update>,
        wake: std::sync::Arc<dyn Fn() + Send + Sync>,
    ) -> Self {
        Gate {
            lane,
            current: AtomicU64::new(0),
            state: Mutex::new(GateState::default()),
            tx,
            wake,
        }
    }

    fn lock(&self) -> MutexGuard<'_, GateState> {
        // A panic never happens under this lock (only sends do), but if one
        // did the state is still consistent: ignore the poison.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The lane's current generation (what jobs poll).
    pub fn current(&self) -> Generation {
        self.current.load(Ordering::SeqCst)
    }

    /// Whether a job of generation `gen` should stop.
    pub fn is_stale(&self, generation: Generation) -> bool {
        self.current() != generation
    }

    /// Whether a job was started and has not yet sent its `Finished`.
    pub fn is_running(&self) -> bool {
        self.lock().running.is_some()
    }

    /// Sends from the dispatcher side (blocking: waits for room).
    fn send_now(&self, u: Update) {
        if self.tx.send(u).is_ok() {
            (self.wake)();
        }
    }

    /// Makes `generation` the lane's current job, cancelling the running one
    /// (which gets its `Finished{Cancelled}` here, in order). Returns false,
    /// and starts nothing, when `generation` is older than the current one,
    /// or is the current one and its job is still running (a repeat).
    pub fn start(&self, generation: Generation) -> bool {
        let mut st = self.lock();
        let current = self.current();
        if generation < current || (generation == current && st.running.is_some()) {
            return false;
        }
        self.cancel_locked(&mut st, generation);
        st.running = Some(generation);
        true
    }

    /// Cancels the running job (if `generation` is not older than it).
    fn cancel_locked(&self, st: &mut GateState, generation: Generation) {
        if generation < self.current() {
            return;
        }
        if let Some(old) = st.running.take() {
            self.send_now(Update::Finished {
                generation: old,
                lane: self.lane,
                outcome: Outcome::Cancelled,
            });
        }
        self.current.store(generation, Ordering::SeqCst);
    }

    /// Stops every job for good (shutdown): no lock, so it cannot wait
    /// behind a blocked sender; senders re-check under the lock anyway.
    pub fn stop(&self) {
        self.current.store(STOPPED, Ordering::SeqCst);
    }

    /// Sends a job's update if its generation is still current. Waits for
    /// room in slices, re-checking the generation between them.
    pub fn send(&self, generation: Generation, u: Update) -> Result<(), Stop> {
        self.send_then(generation, u, |_| {})
    }

    /// `send`, then `after` on the guarded state under the same lock.
    fn send_then(
        &self,
        generation: Generation,
        mut u: Update,
        after: impl FnOnce(&mut GateState),
    ) -> Result<(), Stop> {
        loop {
            {
                let mut st = self.lock();
                if self.is_stale(generation) {
                    return Err(Stop::Stale);
                }
                match self.tx.send_timeout(u, SEND_SLICE) {
                    Ok(()) => {
                        after(&mut st);
                        drop(st);
                        (self.wake)();
                        return Ok(());
                    }
                    Err(SendTimeoutError::Disconnected(_)) => return Err(Stop::Gone),
                    Err(SendTimeoutError::Timeout(back)) => u = back,
                }
            }
            // Let a waiting canceller take the lock before trying again.
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    /// Ends job `generation` with `outcome`: sends the `Error` (if any) and
    /// `Finished`, unless the job was cancelled meanwhile (then the
    /// dispatcher already sent its `Finished{Cancelled}`). The job stops
    /// being the running one under the same lock as its `Finished` is sent,
    /// so it never gets two.
    pub fn finish(
        &self,
        generation: Generation,
        error: Option<(String, Option<&'static str>)>,
        outcome: Outcome,
    ) {
        if let Some((message, parameter)) = error {
            let e = Update::Error {
                generation,
                lane: self.lane,
                message,
                parameter,
            };
            if self.send(generation, e).is_err() {
                return;
            }
        }
        let fin = Update::Finished {
            generation,
            lane: self.lane,
            outcome,
        };
        self.send_then(generation, fin, |st| {
            if st.running == Some(generation) {
                st.running = None;
            }
        })
        .ok();
    }
}

/// Cancels on every gate in `gates` at once and acknowledges with
/// `Cancelled{generation, lane}` while holding all their locks, so nothing
/// of an older generation on those lanes can follow the acknowledgement.
pub(crate) fn cancel(gates: &[&Gate], generation: Generation, lane: Option<Lane>) {
    let mut guards: Vec<_> = gates.iter().map(|g| (g, g.lock())).collect();
    for (g, st) in guards.iter_mut() {
        g.cancel_locked(st, generation);
    }
    if let Some((g, _)) = guards.first() {
        g.send_now(Update::Cancelled { generation, lane });
    }
    drop(guards);
}
