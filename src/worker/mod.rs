//! The background simulation worker: all simulation the GUI needs runs here,
//! fed by a bounded crossbeam channel of [`Command`]s and answering on a
//! bounded channel of [`Update`]s. No GUI types: the front end passes a
//! wake-up callback (`ctx.request_repaint`), tests pass a counter.

mod protocol;

pub use protocol::{Command, Generation, Lane, Outcome, Update};
