//! Commands and a worker for the headless worker tests (`tests/worker_*.rs`).
#![allow(dead_code)]

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use super::fixture::preset;
use oneblock::integrate::SolverSettings;
use oneblock::model::Params;
use oneblock::sim::MapChoice;
use oneblock::sim::default_settings;
use oneblock::worker::{
    Axis, Command, Generation, IterateSpec, Lane, Outcome, SweepSpec, TrajectorySpec, Update,
    Worker, WorkerConfig,
};

pub fn settings() -> SolverSettings {
    default_settings(1e-8)
}

pub fn fig3b(theta_nu: f64) -> Params {
    preset("fig3b").with_theta_nu(theta_nu)
}

pub fn spawn(
    update_capacity: usize,
    sweep_threads: usize,
    coarse_columns: usize,
) -> (Worker, Arc<AtomicUsize>) {
    let wakes = Arc::new(AtomicUsize::new(0));
    let w = wakes.clone();
    let worker = Worker::spawn(
        WorkerConfig {
            update_capacity,
            sweep_threads,
            coarse_columns,
        },
        Arc::new(move || {
            w.fetch_add(1, Ordering::SeqCst);
        }),
    );
    (worker, wakes)
}

pub fn iterate(generation: Generation, params: Params, transient: usize, keep: usize) -> Command {
    Command::run(
        generation,
        IterateSpec {
            params,
            settings: settings(),
            theta0: None,
            transient,
            keep,
            graph_powers: 1,
            options: oneblock::jobs::IterateOptions::default(),
        },
    )
}

pub fn trajectory(generation: Generation, cycles: Option<usize>) -> Command {
    Command::run(
        generation,
        TrajectorySpec {
            params: fig3b(1.0),
            settings: settings(),
            theta0: Some(0.5),
            transient: 0,
            spacing: 0.05,
            cycles,
            max_samples: None,
        },
    )
}

pub fn sweep(generation: Generation, columns: usize, transient: usize, keep: usize) -> Command {
    Command::run(
        generation,
        SweepSpec {
            params: fig3b(0.0),
            settings: settings(),
            param: oneblock::sim::continuation::ContParam::ThetaNu,
            axis: Axis::new(0.05, 1.5, columns),
            transient,
            keep,
            map: MapChoice::Auto,
            theta0: None,
            seeds: 0,
        },
    )
}

/// After a job's `Finished{Cancelled}` or a `Cancelled` acknowledgement, no
/// update of an older generation on that lane arrives.
pub fn assert_nothing_older_after_acks(ups: &[Update]) {
    let mut floor = [0u64; Lane::ALL.len()];
    let lane_ix = |l: Lane| l.index();
    for u in ups {
        let lane = match u {
            Update::TrajectoryChunk { .. }
            | Update::Slip { .. }
            | Update::MapIterates { .. }
            | Update::MapGraph { .. }
            | Update::Orbit { .. } => Some(Lane::Orbit),
            Update::Column { .. } => Some(Lane::Sweep),
            Update::WorkPrecisionSample { .. }
            | Update::WorkPrecisionRow { .. }
            | Update::WorkPrecisionSkipped { .. } => Some(Lane::Numerics),
            Update::PhaseCells { .. } => Some(Lane::Phase),
            Update::Branch { .. } | Update::Special { .. } | Update::Cascade { .. } => {
                Some(Lane::Continuation)
            }
            Update::Curve { .. } => Some(Lane::Curves),
            Update::Passage { .. } => Some(Lane::Passage),
            Update::Scan { .. } => Some(Lane::Scan),
            Update::Basins { lane, .. } | Update::BasinEvents { lane, .. } => Some(*lane),
            Update::Summary { lane, .. }
            | Update::Progress { lane, .. }
            | Update::Error { lane, .. }
            | Update::Finished { lane, .. } => Some(*lane),
            Update::Cancelled { .. } => None,
        };
        if let Some(l) = lane {
            assert!(
                u.generation() >= floor[lane_ix(l)],
                "{u:?} arrived after generation {} was acknowledged",
                floor[lane_ix(l)]
            );
        }
        match u {
            Update::Finished {
                generation,
                lane,
                outcome: Outcome::Cancelled,
            } => {
                let f = &mut floor[lane_ix(*lane)];
                *f = (*f).max(generation + 1);
            }
            Update::Cancelled { generation, lane } => {
                for l in [
                    Lane::Orbit,
                    Lane::Sweep,
                    Lane::Numerics,
                    Lane::Phase,
                    Lane::Continuation,
                    Lane::Curves,
                    Lane::Passage,
                    Lane::Scan,
                ] {
                    if lane.is_none_or(|x| x == l) {
                        let f = &mut floor[lane_ix(l)];
                        *f = (*f).max(*generation);
                    }
                }
            }
            _ => {}
        }
    }
}
