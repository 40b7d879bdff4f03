//! The Events view's jobs: the creep channel's passage time (started by
//! the view for the parameters on screen) and the tangency scan (on
//! demand). They run on lanes of their own through the same backend as
//! every job (the worker's threads, or the page's single-threaded host
//! within its frame slice); new parameters stop them (`Spec::on_params`),
//! and an answer is kept with the parameters it is for.

use super::slots::Receive;
use super::stale::Bound;
use super::{Jobs, Slot};
use crate::integrate::{Method, SolverSettings};
use crate::jobs::{PassageSpec, ScanSpec, Spec};
use crate::model::Params;
use crate::sim::intermittency::{Passage, Scaling};
use crate::worker::Command;
use crate::worker::Update;

/// The accuracy of the view's own map evaluations: slip onsets to ~1e-8.
pub fn events_settings() -> SolverSettings {
    SolverSettings::adaptive(Method::Dop853, 1e-8)
}

/// What one of the Events view's jobs was asked for and answered.
#[derive(Clone, Debug, PartialEq)]
pub struct Answer<T> {
    /// The parameters it was started for (`None`: never started).
    pub params: Option<Params>,
    /// Its answer, once it has one.
    pub value: Option<T>,
}

impl<T> Default for Answer<T> {
    fn default() -> Self {
        Answer {
            params: None,
            value: None,
        }
    }
}

impl<T> Slot<Answer<T>> {
    /// The answer for `params`, if there is one.
    pub fn answer(&self, params: &Params) -> Option<&T> {
        self.data.value.as_ref().filter(|_| self.asked(params))
    }

    /// Whether it was started for `params` (whatever came of it).
    pub fn asked(&self, params: &Params) -> bool {
        self.data.params.as_ref() == Some(params)
    }
}

impl Jobs {
    /// Starts the channel passage at `params` through the channel holding
    /// the creep onset `near`.
    pub fn start_passage(&mut self, params: Params, near: f64) {
        let g = self.generation();
        self.passage.start(
            g,
            Answer {
                params: Some(params),
                value: None,
            },
        );
        self.passage.bound = Some(Bound::of_params(&params));
        let spec = PassageSpec {
            params,
            settings: events_settings(),
            near,
        };
        self.send(Command::Run {
            generation: g,
            spec: Spec::Passage(spec),
        });
    }

    /// Starts the tangency scan at `params`.
    pub fn start_scan(&mut self, params: Params) {
        let g = self.generation();
        self.scan.start(
            g,
            Answer {
                params: Some(params),
                value: None,
            },
        );
        self.scan.bound = Some(Bound::of_params(&params));
        let spec = ScanSpec {
            params,
            settings: events_settings(),
        };
        self.send(Command::Run {
            generation: g,
            spec: Spec::Scan(spec),
        });
    }
}

impl Receive for Answer<Passage> {
    fn receive(&mut self, u: Update) -> Option<Update> {
        match u {
            Update::Passage { passage, .. } => {
                self.value = Some(passage);
                None
            }
            u => Some(u),
        }
    }
}

impl Receive for Answer<Scaling> {
    fn receive(&mut self, u: Update) -> Option<Update> {
        match u {
            Update::Scan { scaling, .. } => {
                self.value = Some(scaling);
                None
            }
            u => Some(u),
        }
    }
}
