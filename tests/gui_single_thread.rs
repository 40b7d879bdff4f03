//! The window's job model over the worker without threads (`LocalWorker`,
//! as the browser build runs it): pumped a frame's slice at a time, the
//! trajectory, the orbit analysis and the diagram complete with the same
//! numbers as over the threaded worker, and no pump runs far past its
//! budget.
#![cfg(feature = "gui")]

use std::sync::Arc;
use std::time::{Duration, Instant};

use oneblock::app::Settings;
use oneblock::app::jobs::{JobState, Jobs, Shown};
use oneblock::worker::{LocalWorker, Worker, WorkerConfig};

/// A small diagram and a short trajectory, so that the test is quick.
fn settings() -> Settings {
    Settings {
        columns: 24,
        sweep_transient: 60,
        sweep_keep: 20,
        trajectory_cycles: 20,
        ..Settings::default()
    }
}

fn shown(now: f64) -> Shown {
    Shown {
        now,
        sweep_zoom: None,
        phase: false,
    }
}

/// Frames until the orbit views and the diagram are complete; the longest
/// pump.
fn run(jobs: &mut Jobs, budget: Duration) -> Duration {
    let s = settings();
    let start = Instant::now();
    let mut longest = Duration::ZERO;
    let mut now = 0.0;
    while start.elapsed() < Duration::from_secs(120) {
        jobs.sync(&s, shown(now));
        let t = Instant::now();
        jobs.pump(budget);
        longest = longest.max(t.elapsed());
        jobs.receive();
        if jobs.complete(s.trajectory_cycles) && jobs.iterate.state == JobState::Done {
            return longest;
        }
        now += 0.016;
        std::thread::sleep(Duration::from_millis(1));
    }
    panic!("the jobs did not complete: {:?}", jobs.sweep.state);
}

#[test]
fn the_window_computes_the_same_over_the_single_threaded_worker() {
    let mut local = Jobs::new(Box::new(LocalWorker::default()));
    let budget = Duration::from_millis(12);
    let longest = run(&mut local, budget);
    let worker = Worker::spawn(WorkerConfig::default(), Arc::new(|| {}));
    let mut threaded = Jobs::new(Box::new(worker));
    run(&mut threaded, budget);

    assert_eq!(local.sweep.state, JobState::Done);
    assert_eq!(local.sweep.data.filled, 24);
    assert_eq!(local.sweep.data.columns, threaded.sweep.data.columns);
    assert_eq!(local.iterate.data.thetas, threaded.iterate.data.thetas);
    assert_eq!(
        local.trajectory.data.events,
        threaded.trajectory.data.events
    );
    // One unit (a slip cycle, a column of 80 iterates) never takes long:
    // a pump ends soon after its budget.
    assert!(longest < budget * 10, "a pump took {longest:?}");
}
