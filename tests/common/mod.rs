//! Helpers the test crates share: parameter fixtures by name (`fixture`),
//! and for the headless worker tests, waiting for updates (never for
//! wall-clock time except as a guard against a hung worker).
// Each test crate uses its own subset.
#![allow(dead_code)]

#[cfg(feature = "gui")]
pub mod figure;
pub mod fixture;
pub mod jobs;
pub mod seeded;
#[cfg(feature = "gui")]
pub mod tour_layout;
pub mod xvfb;

use std::time::Duration;

use oneblock::worker::{Generation, Lane, Outcome, Update, Worker};

/// Long enough that only a hung worker hits it.
pub const HANG: Duration = Duration::from_secs(120);

pub fn recv(w: &Worker) -> Update {
    w.recv_timeout(HANG).expect("the worker went silent")
}

/// Every update up to and including the `Finished` of `generation` on `lane`.
pub fn until_finished(w: &Worker, generation: Generation, lane: Lane) -> (Vec<Update>, Outcome) {
    let mut out = Vec::new();
    loop {
        let u = recv(w);
        if let Update::Finished {
            generation: g,
            lane: l,
            outcome,
        } = &u
            && *g == generation
            && *l == lane
        {
            let o = outcome.clone();
            out.push(u);
            return (out, o);
        }
        out.push(u);
    }
}

/// Every update up to and including the `Cancelled` acknowledgement of
/// `generation`.
pub fn until_ack(w: &Worker, generation: Generation) -> Vec<Update> {
    let mut out = Vec::new();
    loop {
        let u = recv(w);
        let ack = matches!(u, Update::Cancelled { generation: g, .. } if g == generation);
        out.push(u);
        if ack {
            return out;
        }
    }
}
