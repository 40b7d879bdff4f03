//! Bounds, failures and shutdown, headless: the update channel's bound holds
//! for a slow consumer, a bad parameter and a panic are reported and the worker
//! keeps serving, shutdown joins every thread, and worker threads run at a
//! lower priority than the window.

use crate::common;
use common::jobs::*;
use common::{recv, until_finished};
use oneblock::worker::Spec;
use std::time::Duration;

use oneblock::integrate::SolverSettings;
use oneblock::model::Params;
use oneblock::sim::MapChoice;
use oneblock::worker::{Axis, Command, Lane, Outcome, SweepSpec, TrajectorySpec, Update};

#[test]
fn a_slow_consumer_never_sees_more_than_the_channel_bound() {
    let capacity = 8;
    let (w, _) = spawn(capacity, 2, 8);
    assert!(w.send(sweep(5, 48, 6, 4)));
    assert!(w.send(trajectory(6, Some(40))));
    let mut max_queued = 0;
    let mut finished = 0;
    while finished < 2 {
        std::thread::sleep(Duration::from_millis(2));
        let q = w.queued();
        assert!(q <= capacity, "{q} updates queued");
        max_queued = max_queued.max(q);
        if let Update::Finished { outcome, .. } = recv(&w) {
            assert_eq!(outcome, Outcome::Completed);
            finished += 1;
        }
    }
    assert_eq!(max_queued, capacity, "the producers had to wait for room");
    w.shutdown();
}

#[test]
fn an_invalid_parameter_is_named_and_the_next_job_still_runs() {
    let (w, _) = spawn(64, 2, 64);
    let bad_kappa = Params {
        kappa: -1.0,
        ..fig3b(1.0)
    };
    let cases: Vec<(Command, Lane, &str)> = vec![
        (iterate(1, bad_kappa, 0, 5), Lane::Orbit, "kappa"),
        (
            Command::run(
                2,
                TrajectorySpec {
                    params: fig3b(1.0),
                    settings: settings(),
                    theta0: Some(-2.0),
                    transient: 0,
                    spacing: 0.05,
                    cycles: Some(3),
                    max_samples: None,
                },
            ),
            Lane::Orbit,
            "theta",
        ),
        (
            Command::run(
                3,
                TrajectorySpec {
                    params: fig3b(1.0),
                    settings: settings(),
                    theta0: None,
                    transient: 0,
                    spacing: 0.0,
                    cycles: Some(3),
                    max_samples: None,
                },
            ),
            Lane::Orbit,
            "spacing",
        ),
        (
            Command::run(
                4,
                SweepSpec {
                    params: Params {
                        gamma: f64::NAN,
                        ..fig3b(0.0)
                    },
                    settings: settings(),
                    param: oneblock::sim::continuation::ContParam::ThetaNu,
                    axis: Axis::new(0.0, 1.0, 10),
                    transient: 2,
                    keep: 2,
                    map: MapChoice::Auto,
                    theta0: None,
                    seeds: 0,
                },
            ),
            Lane::Sweep,
            "gamma",
        ),
        (
            Command::run(
                5,
                SweepSpec {
                    params: fig3b(0.0),
                    settings: SolverSettings {
                        rtol: 1.0,
                        ..settings()
                    },
                    param: oneblock::sim::continuation::ContParam::ThetaNu,
                    axis: Axis::new(0.0, 1.0, 10),
                    transient: 2,
                    keep: 2,
                    map: MapChoice::Auto,
                    theta0: None,
                    seeds: 0,
                },
            ),
            Lane::Sweep,
            "tol",
        ),
    ];
    for (cmd, lane, name) in cases {
        let generation = match &cmd {
            Command::Run {
                generation,
                spec: Spec::Iterate(..),
            }
            | Command::Run {
                generation,
                spec: Spec::Trajectory(..),
            }
            | Command::Run {
                generation,
                spec: Spec::Sweep(..),
            } => *generation,
            _ => unreachable!(),
        };
        assert!(w.send(cmd));
        let (ups, outcome) = until_finished(&w, generation, lane);
        assert!(matches!(outcome, Outcome::Failed(_)), "{outcome:?}");
        let named = ups.iter().find_map(|u| match u {
            Update::Error { parameter, .. } => Some(*parameter),
            _ => None,
        });
        assert_eq!(named, Some(Some(name)), "{ups:?}");
    }
    assert!(w.send(iterate(6, fig3b(1.0), 2, 5)));
    let (_, outcome) = until_finished(&w, 6, Lane::Orbit);
    assert_eq!(outcome, Outcome::Completed);
    assert!(w.send(sweep(7, 3, 2, 2)));
    let (_, outcome) = until_finished(&w, 7, Lane::Sweep);
    assert_eq!(outcome, Outcome::Completed);
    w.shutdown();
}

#[test]
fn a_panicking_job_is_reported_and_the_worker_keeps_serving() {
    let (w, _) = spawn(64, 2, 64);
    for round in 0..2 {
        let g = 10 * round + 1;
        assert!(w.send(Command::inject_panic(g, 3)));
        let (ups, outcome) = until_finished(&w, g, Lane::Orbit);
        assert!(matches!(outcome, Outcome::Failed(ref m) if m.contains("panicked")));
        assert!(ups.iter().any(|u| matches!(
            u,
            Update::Error { message, parameter: None, .. } if message.contains("injected panic")
        )));
        assert!(w.send(iterate(g + 1, fig3b(1.0), 1, 4)));
        let (_, outcome) = until_finished(&w, g + 1, Lane::Orbit);
        assert_eq!(outcome, Outcome::Completed);
    }
    w.shutdown();
}

#[test]
fn shutdown_mid_sweep_joins_within_one_cycle_per_thread() {
    let threads = 2;
    let (w, _) = spawn(256, threads, 16);
    let stats = w.stats();
    assert!(w.send(sweep(1, 400, 300, 200)));
    assert!(w.send(trajectory(2, None)));
    // Wait until both lanes are busy.
    let mut col = false;
    while !col {
        col = matches!(recv(&w), Update::Column { .. });
    }
    assert!(stats.cycles_after_stop().is_none());
    w.shutdown();
    let after = stats.cycles_after_stop().expect("stopped");
    assert!(
        after <= 1 + threads as u64,
        "{after} cycles started after the stop"
    );
}

#[test]
fn dropping_the_handle_with_a_full_channel_joins_every_thread() {
    let threads = 2;
    let (w, _) = spawn(2, threads, 16);
    let stats = w.stats();
    assert!(w.send(sweep(1, 400, 300, 200)));
    assert!(w.send(trajectory(2, None)));
    // Nobody reads: the producers block on the full channel.
    while w.queued() < 2 {
        std::thread::yield_now();
    }
    std::thread::sleep(Duration::from_millis(20));
    drop(w);
    let after = stats.cycles_after_stop().expect("stopped");
    assert!(after <= 1 + threads as u64);
}

/// The nice value and name of every thread of this process (Linux /proc).
#[cfg(target_os = "linux")]
fn threads() -> Vec<(String, i32)> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir("/proc/self/task").expect("/proc") {
        let dir = entry.expect("entry").path();
        let (Ok(comm), Ok(stat)) = (
            std::fs::read_to_string(dir.join("comm")),
            std::fs::read_to_string(dir.join("stat")),
        ) else {
            continue; // the thread ended meanwhile
        };
        // Fields after the parenthesised name: state is field 3, nice 19.
        let rest = &stat[stat.rfind(')').expect("stat") + 2..];
        let nice: i32 = rest.split(' ').nth(16).expect("nice").parse().expect("int");
        out.push((comm.trim().to_string(), nice));
    }
    out
}

#[cfg(target_os = "linux")]
#[test]
fn worker_threads_run_at_a_lower_priority_than_the_window() {
    let before = oneblock::worker::priority::current_thread_nice();
    let (w, _) = spawn(64, 2, 8);
    // A sweep long enough (~1 s) that its pool threads are seen too.
    assert!(w.send(sweep(1, 400, 300, 200)));
    let lanes = [
        "oneblock-orbit",
        "oneblock-sweep",
        "oneblock-numeri",
        "oneblock-phase",
    ];
    let deadline = std::time::Instant::now() + Duration::from_secs(20);
    loop {
        let ts = threads();
        let seen: Vec<&(String, i32)> = ts
            .iter()
            .filter(|(n, _)| n.starts_with("oneblock-"))
            .collect();
        let lanes_up = lanes.iter().all(|l| seen.iter().any(|(n, _)| n == l));
        let pool_up = seen.iter().any(|(n, _)| n.starts_with("oneblock-sweep-"));
        if lanes_up && pool_up {
            for (name, nice) in &seen {
                if name == "oneblock-worker" {
                    continue; // the dispatcher only routes commands
                }
                assert!(
                    *nice >= oneblock::worker::priority::WORKER_NICE,
                    "{name} runs at nice {nice}"
                );
            }
            // The calling thread (the window's, in the app) is untouched.
            assert_eq!(oneblock::worker::priority::current_thread_nice(), before);
            break;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "threads seen: {seen:?}"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}
