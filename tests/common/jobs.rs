//! Commands and a worker for the headless worker tests (`tests/worker_*.rs`).
#![allow(dead_code)]

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use super::fixture::preset;
use oneblock::integrate::SolverSettings;
use oneblock::model::Params;
use oneblock::sim::default_settings;
use oneblock::worker::{
    Axis, Command, Generation, IterateSpec, SweepSpec, TrajectorySpec, Worker, WorkerConfig,
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
    Command::Iterate {
        generation,
        spec: IterateSpec {
            params,
            settings: settings(),
            theta0: None,
            transient,
            keep,
        },
    }
}

pub fn trajectory(generation: Generation, cycles: Option<usize>) -> Command {
    Command::Trajectory {
        generation,
        spec: TrajectorySpec {
            params: fig3b(1.0),
            settings: settings(),
            theta0: Some(0.5),
            spacing: 0.05,
            cycles,
        },
    }
}

pub fn sweep(generation: Generation, columns: usize, transient: usize, keep: usize) -> Command {
    Command::Sweep {
        generation,
        spec: SweepSpec {
            params: fig3b(0.0),
            settings: settings(),
            theta_nu: Axis::new(0.05, 1.5, columns),
            transient,
            keep,
        },
    }
}
