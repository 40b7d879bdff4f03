//! The one door between the window and the simulation: commands out, updates
//! in, never blocking. The real worker implements it; tests use a
//! [`Recorder`] that keeps every command and lets the test feed updates.

use std::collections::VecDeque;
use std::sync::{Arc, Mutex, PoisonError};

use crate::worker::{Command, Update};

/// Where simulation commands go and updates come from.
pub trait Backend {
    /// Hands a command over without blocking; false if it was refused.
    fn send(&mut self, cmd: Command) -> bool;
    /// The next update, if one is waiting.
    fn try_recv(&mut self) -> Option<Update>;
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

/// A backend without threads: each job runs to its end on the caller's
/// thread as it is sent (the job model's [`crate::jobs::Local`] host), its
/// updates queued for [`Backend::try_recv`]. What `oneblock figure` computes
/// a view's data with, headless; never behind a window, whose thread must
/// not integrate. Jobs on a lane in `skip` are dropped unrun (a figure of
/// one view needs only its own jobs).
pub struct LocalBackend {
    inbox: VecDeque<Update>,
    skip: Vec<crate::jobs::Lane>,
    shape: crate::jobs::Shape,
}

impl LocalBackend {
    /// Runs every job but those on the lanes in `skip`, with the plan
    /// shape the window's worker uses (so its diagram is the window's).
    pub fn new(skip: Vec<crate::jobs::Lane>) -> Self {
        LocalBackend {
            inbox: VecDeque::new(),
            skip,
            shape: crate::jobs::Shape {
                coarse_columns: crate::worker::WorkerConfig::default().coarse_columns,
                ..crate::jobs::Shape::default()
            },
        }
    }
}

impl Backend for LocalBackend {
    fn send(&mut self, cmd: Command) -> bool {
        if let Some((generation, spec)) = cmd.into_job()
            && !self.skip.contains(&spec.lane())
        {
            let host = crate::jobs::Local::start(spec, generation, self.shape);
            self.inbox.extend(host.run_to_end(usize::MAX));
        }
        true
    }
    fn try_recv(&mut self) -> Option<Update> {
        self.inbox.pop_front()
    }
}
