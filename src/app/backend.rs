//! The one door between the window and the simulation: commands out, updates
//! in, never blocking. The threaded worker implements it, and so does the
//! worker without threads ([`LocalWorker`], run a time slice per frame by
//! [`Backend::pump`]); tests use a [`Recorder`] that keeps every command and
//! lets the test feed updates.

use std::collections::VecDeque;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use crate::worker::{Command, LocalWorker, Update};

/// Where simulation commands go and updates come from.
pub trait Backend {
    /// Hands a command over without blocking; false if it was refused.
    fn send(&mut self, cmd: Command) -> bool;
    /// The next update, if one is waiting.
    fn try_recv(&mut self) -> Option<Update>;
    /// Runs jobs on the caller's thread for about `budget` (a backend
    /// without threads; the others run on their own): true while work
    /// remains, so that the window asks for another frame.
    fn pump(&mut self, _budget: Duration) -> bool {
        false
    }
}

impl Backend for LocalWorker {
    fn send(&mut self, cmd: Command) -> bool {
        LocalWorker::send(self, cmd)
    }
    fn try_recv(&mut self) -> Option<Update> {
        LocalWorker::try_recv(self)
    }
    fn pump(&mut self, budget: Duration) -> bool {
        LocalWorker::pump(self, budget)
    }
}

impl Backend for crate::worker::Worker {
    fn send(&mut self, cmd: Command) -> bool {
        crate::worker::Worker::send(self, cmd)
    }
    fn try_recv(&mut self) -> Option<Update> {
        crate::worker::Worker::try_recv(self)
    }
}

/// A backend for tests: records the commands, replays queued updates.
#[derive(Clone, Default)]
pub struct Recorder {
    /// Every command sent, in order.
    pub sent: Arc<Mutex<Vec<Command>>>,
    /// Updates the app will receive, in order.
    pub inbox: Arc<Mutex<VecDeque<Update>>>,
}

impl Recorder {
    pub fn new() -> Self {
        Self::default()
    }

    /// The commands sent so far.
    pub fn commands(&self) -> Vec<Command> {
        self.sent
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .clone()
    }

    /// Forgets the commands sent so far.
    pub fn clear(&self) {
        self.sent
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .clear();
    }

    /// Queues an update for the app.
    pub fn push(&self, u: Update) {
        self.inbox
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push_back(u);
    }
}

impl Backend for Recorder {
    fn send(&mut self, cmd: Command) -> bool {
        self.sent
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(cmd);
        true
    }
    fn try_recv(&mut self) -> Option<Update> {
        self.inbox
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .pop_front()
    }
}
