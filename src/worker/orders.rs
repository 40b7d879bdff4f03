//! What a command asks of the lanes, whoever runs them: the threaded worker
//! and the single-threaded one ([`super::LocalWorker`]) both turn each
//! command into these orders, so new parameters, cancels and supersession
//! mean the same on both.

use super::Command;
use crate::jobs::{Generation, Lane, OnParams, Spec};

/// One thing a command asks of the lanes.
#[derive(Debug)]
pub(crate) enum Order {
    /// Start `spec` under the generation on its lane, superseding the
    /// lane's job (unless the generation is stale).
    Start(Generation, Spec),
    /// Stop the lane's job if one runs (answered by `Cancelled` for it).
    StopRunning(Lane, Generation),
    /// Stop the jobs of these lanes and acknowledge with
    /// `Cancelled { generation, lane }` (the last field: `None` for all).
    Cancel(Vec<Lane>, Generation, Option<Lane>),
    /// End every job and the host.
    Shutdown,
}

/// Each lane's latest job, for new parameters to run again.
#[derive(Default)]
pub(crate) struct Latest {
    last: [Option<Spec>; Lane::ALL.len()],
}

impl Latest {
    /// The orders of `cmd`.
    pub fn orders(&mut self, cmd: Command) -> Vec<Order> {
        match cmd {
            Command::Shutdown => vec![Order::Shutdown],
            Command::SetParams {
                generation,
                params,
                settings,
            } => self
                .last
                .iter()
                .flatten()
                .filter_map(|last| match last.on_params(params, settings) {
                    OnParams::Rerun(spec) => Some(Order::Start(generation, *spec)),
                    OnParams::Cancel => Some(Order::StopRunning(last.lane(), generation)),
                    OnParams::Keep => None,
                })
                .collect(),
            Command::Cancel { generation, lane } => {
                let lanes: Vec<Lane> = Lane::ALL
                    .into_iter()
                    .filter(|&l| lane.is_none_or(|x| x == l))
                    .collect();
                for &l in &lanes {
                    let slot = &mut self.last[l.index()];
                    if slot.as_ref().is_some_and(Spec::forgotten_when_cancelled) {
                        *slot = None;
                    }
                }
                vec![Order::Cancel(lanes, generation, lane)]
            }
            job => job
                .into_job()
                .map(|(generation, spec)| Order::Start(generation, spec))
                .into_iter()
                .collect(),
        }
    }

    /// Remembers a job that started, for new parameters to run again.
    pub fn started(&mut self, spec: &Spec) {
        if spec.remembered() {
            self.last[spec.lane().index()] = Some(spec.clone());
        }
    }
}
