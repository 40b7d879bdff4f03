//! The simulation worker, headless: results equal to the core's bit for bit,
//! generations and cancellation, bounded queues, errors and panics, shutdown,
//! and the progressive sweep's order. Assertions are on cycles, generations
//! and orderings, never on wall-clock time (timeouts only guard against
//! hangs).

mod common;
use common::fixture::preset;
use common::{recv, until_finished};
use std::collections::HashSet;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use oneblock::integrate::{Method, SolverSettings};
use oneblock::model::Params;
use oneblock::numerics::quick::{current_attractor, quick_subjects};
use oneblock::numerics::{Row, Subject, build_sample, measure};
use oneblock::sim::{
    Column, Handover, LANES, OrbitOptions, Sampler, Simulator, SweepOptions, column_start,
    default_settings, return_map_window, theta_nu_grid,
};
use oneblock::worker::{
    Axis, Command, Generation, IterateSpec, Lane, Outcome, SweepSpec, TrajectorySpec, Update,
    WorkPrecisionSpec, Worker, WorkerConfig, sweep_plan,
};

fn settings() -> SolverSettings {
    default_settings(1e-8)
}

fn fig3b(theta_nu: f64) -> Params {
    preset("fig3b").with_theta_nu(theta_nu)
}

fn spawn(
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

fn iterate(generation: Generation, params: Params, transient: usize, keep: usize) -> Command {
    Command::Iterate {
        generation,
        spec: IterateSpec {
            params,
            settings: settings(),
            theta0: None,
            transient,
            keep,
            graph_powers: 1,
        },
    }
}

fn trajectory(generation: Generation, cycles: Option<usize>) -> Command {
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

fn sweep(generation: Generation, columns: usize, transient: usize, keep: usize) -> Command {
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

#[test]
fn map_iterates_equal_the_core_bit_for_bit() {
    let (w, wakes) = spawn(256, 2, 64);
    let params = fig3b(1.2);
    assert!(w.send(iterate(7, params, 30, 50)));
    let (ups, outcome) = until_finished(&w, 7, Lane::Orbit);
    assert_eq!(outcome, Outcome::Completed);
    let mut thetas = Vec::new();
    let mut last = None;
    for u in &ups {
        assert_eq!(u.generation(), 7);
        if let Update::MapIterates {
            first_index,
            thetas: t,
            period,
            lyapunov,
            ..
        } = u
        {
            assert_eq!(*first_index, thetas.len(), "batches are contiguous");
            thetas.extend_from_slice(t);
            last = Some((*period, *lyapunov));
        }
    }
    let sim = Simulator::new(params, settings()).expect("valid");
    let opts = OrbitOptions {
        transient: 30,
        keep: 50,
        lyapunov: true,
        period_tol: OrbitOptions::period_tol_for(settings().rtol),
    };
    let orbit = sim.orbit(params.theta_nu, &opts, &|| false).expect("orbit");
    let core: Vec<u64> = orbit.thetas().iter().map(|t| t.to_bits()).collect();
    let mine: Vec<u64> = thetas.iter().map(|t| t.to_bits()).collect();
    assert_eq!(mine, core);
    let (period, lyapunov) = last.expect("some iterates");
    assert_eq!(period, orbit.period);
    assert_eq!(lyapunov.map(f64::to_bits), orbit.lyapunov.map(f64::to_bits));
    assert!(
        wakes.load(Ordering::SeqCst) > 0,
        "the wake callback was called"
    );
    w.shutdown();
}

#[test]
fn an_iterate_job_ends_with_the_graph_of_f_over_its_orbits_window() {
    let (w, _) = spawn(256, 2, 64);
    let params = fig3b(1.25);
    assert!(w.send(iterate(3, params, 100, 60)));
    let (ups, outcome) = until_finished(&w, 3, Lane::Orbit);
    assert_eq!(outcome, Outcome::Completed);
    let mut kept = Vec::new();
    let mut graph = None;
    for u in &ups {
        match u {
            Update::MapIterates { thetas, .. } => {
                assert!(graph.is_none(), "the graph comes after the iterates");
                kept.extend_from_slice(thetas);
            }
            Update::MapGraph { thetas, values, .. } => graph = Some((thetas, values)),
            _ => {}
        }
    }
    let (thetas, values) = graph.expect("a MapGraph update");
    assert_eq!(thetas.len(), values.len());
    let (lo, hi) = return_map_window(&kept).expect("finite iterates");
    assert!(thetas.len() > 150, "most of the window is on the exit arc");
    assert!(thetas.windows(2).all(|p| p[0] < p[1]));
    assert!(thetas[0] >= lo && *thetas.last().unwrap() <= hi);
    // Each value is the core's map there, bit for bit, and the orbit lies on
    // the graph: f at each kept iterate is interpolated by the curve to well
    // within the picture's resolution.
    let sim = Simulator::new(params, settings()).expect("valid");
    for (t, v) in thetas.iter().zip(values) {
        assert_eq!(v.to_bits(), sim.map(*t).expect("map").to_bits(), "f({t})");
    }
    for pair in kept.windows(2) {
        let i = thetas
            .partition_point(|t| *t < pair[0])
            .clamp(1, thetas.len() - 1);
        let (t0, t1) = (thetas[i - 1], thetas[i]);
        let (f0, f1) = (values[i - 1], values[i]);
        let lin = f0 + (f1 - f0) * (pair[0] - t0) / (t1 - t0);
        assert!(
            (lin - pair[1]).abs() < 1e-2 * (hi - lo),
            "{pair:?} vs {lin}"
        );
    }
    w.shutdown();
}

#[test]
fn trajectory_equals_the_core_bit_for_bit() {
    let (w, _) = spawn(256, 2, 64);
    assert!(w.send(trajectory(3, Some(6))));
    let (ups, outcome) = until_finished(&w, 3, Lane::Orbit);
    assert_eq!(outcome, Outcome::Completed);
    let samples: Vec<_> = ups
        .iter()
        .filter_map(|u| match u {
            Update::TrajectoryChunk { samples, .. } => Some(samples.clone()),
            _ => None,
        })
        .flatten()
        .collect();
    let events: Vec<_> = ups
        .iter()
        .filter_map(|u| match u {
            Update::Slip { event, .. } => Some(*event),
            _ => None,
        })
        .collect();
    assert_eq!(events.len(), 6, "one Slip per cycle");

    let sim = Simulator::new(fig3b(1.0), settings()).expect("valid");
    let mut sampler = Sampler::new(0.05);
    let (mut theta, mut t) = (0.5, 0.0);
    let mut core_events = Vec::new();
    for _ in 0..6 {
        let ev = sim.cycle(theta, t, Some(&mut sampler)).expect("cycle");
        t += ev.slip_duration + ev.stick_duration;
        theta = sim.next_onset(&ev);
        core_events.push(ev);
    }
    assert_eq!(events, core_events);
    assert_eq!(samples, sampler.samples);
    w.shutdown();
}

#[test]
fn progressive_sweep_equals_the_core_and_delivers_each_column_once_coarse_first() {
    let (columns, coarse, threads, transient, keep) = (29, 6, 2, 12, 8);
    let (w, _) = spawn(256, threads, coarse);
    assert!(w.send(sweep(11, columns, transient, keep)));
    let (ups, outcome) = until_finished(&w, 11, Lane::Sweep);
    assert_eq!(outcome, Outcome::Completed);
    let delivered: Vec<(usize, f64, Vec<f64>, bool)> = ups
        .iter()
        .filter_map(|u| match u {
            Update::Column {
                index,
                theta_nu,
                thetas,
                coarse,
                ..
            } => Some((*index, *theta_nu, thetas.clone(), *coarse)),
            _ => None,
        })
        .collect();

    // Each column exactly once.
    assert_eq!(delivered.len(), columns);
    let seen: HashSet<usize> = delivered.iter().map(|d| d.0).collect();
    assert_eq!(seen, (0..columns).collect());

    // The whole coarse pass first, and it spans the range evenly.
    let n_coarse = delivered.iter().filter(|d| d.3).count();
    assert_eq!(n_coarse, coarse);
    assert!(delivered[..n_coarse].iter().all(|d| d.3));
    let mut ci: Vec<usize> = delivered[..n_coarse].iter().map(|d| d.0).collect();
    ci.sort();
    assert_eq!((ci[0], ci[n_coarse - 1]), (0, columns - 1));
    let max_gap = ci.windows(2).map(|p| p[1] - p[0]).max().unwrap_or(0);
    assert!(max_gap <= (columns - 1).div_ceil(coarse - 1));

    // Progress ends at 1.
    let last_progress = ups.iter().rev().find_map(|u| match u {
        Update::Progress { fraction, .. } => Some(*fraction),
        _ => None,
    });
    assert_eq!(last_progress, Some(1.0));

    // Bit for bit against the core, following the same plan.
    let grid = theta_nu_grid(0.05, 1.5, columns);
    let params = fig3b(0.0);
    let opts = SweepOptions { transient, keep };
    let mut last: Vec<Option<Handover>> = vec![None; columns];
    // Each thread steps LANES columns together: LANES chains per thread.
    let plan = sweep_plan(columns, coarse, threads * LANES);
    for p in &plan {
        let neighbour = p.parent.and_then(|q| last[q]);
        let start = column_start(params.kappa, grid[p.index], neighbour.map(|h| h.theta));
        let slow = neighbour.and_then(|h| h.slow_period);
        let col = Column::run_from(
            params,
            settings(),
            grid[p.index],
            start,
            slow,
            &opts,
            &|| false,
        );
        assert!(col.error.is_none(), "{:?}", col.error);
        last[p.index] = col.handover();
        let d = delivered
            .iter()
            .find(|d| d.0 == p.index)
            .expect("delivered");
        assert_eq!(d.1.to_bits(), grid[p.index].to_bits());
        let a: Vec<u64> = d.2.iter().map(|t| t.to_bits()).collect();
        let b: Vec<u64> = col.thetas.iter().map(|t| t.to_bits()).collect();
        assert_eq!(a, b, "column {}", p.index);
        assert_eq!(d.3, p.coarse);
    }
    w.shutdown();
}

/// After a job's `Finished{Cancelled}` or a `Cancelled` acknowledgement, no
/// update of an older generation on that lane arrives.
fn assert_nothing_older_after_acks(ups: &[Update]) {
    let mut floor = [0u64; 4];
    let lane_ix = |l: Lane| match l {
        Lane::Orbit => 0,
        Lane::Sweep => 1,
        Lane::Numerics => 2,
        Lane::Phase => 3,
    };
    for u in ups {
        let lane = match u {
            Update::TrajectoryChunk { .. }
            | Update::Slip { .. }
            | Update::MapIterates { .. }
            | Update::MapGraph { .. } => Some(Lane::Orbit),
            Update::Column { .. } => Some(Lane::Sweep),
            Update::WorkPrecisionSample { .. }
            | Update::WorkPrecisionRow { .. }
            | Update::WorkPrecisionSkipped { .. } => Some(Lane::Numerics),
            Update::PhaseCells { .. } => Some(Lane::Phase),
            Update::Progress { lane, .. }
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
                for l in [Lane::Orbit, Lane::Sweep, Lane::Numerics, Lane::Phase] {
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

#[test]
fn cancel_acknowledgement_is_never_followed_by_an_older_generation() {
    let (w, _) = spawn(4, 2, 64);
    let mut all = Vec::new();
    let mut generation = 0;
    for round in 0..25 {
        generation += 1;
        let job = generation;
        assert!(w.send(trajectory(job, None)));
        // Let it run a little: wait for its first slip.
        loop {
            let u = recv(&w);
            let first_slip = matches!(u, Update::Slip { generation: g, .. } if g == job);
            all.push(u);
            if first_slip {
                break;
            }
        }
        generation += 1;
        let lane = if round % 3 == 2 {
            None
        } else {
            Some(Lane::Orbit)
        };
        assert!(w.send(Command::Cancel { generation, lane }));
        // The job's Finished{Cancelled} comes first, then the acknowledgement.
        let mut finished = false;
        loop {
            let u = recv(&w);
            if let Update::Finished {
                generation: g,
                outcome,
                ..
            } = &u
                && *g == job
            {
                assert_eq!(*outcome, Outcome::Cancelled);
                finished = true;
            }
            let ack = matches!(u, Update::Cancelled { generation: g, .. } if g == generation);
            all.push(u);
            if ack {
                break;
            }
        }
        assert!(
            finished,
            "the cancelled job got its Finished before the ack"
        );
    }
    // Drain what is left with a final job, then check the whole stream.
    generation += 1;
    assert!(w.send(iterate(generation, fig3b(1.0), 0, 3)));
    let (rest, _) = until_finished(&w, generation, Lane::Orbit);
    all.extend(rest);
    assert_nothing_older_after_acks(&all);
    w.shutdown();
}

#[test]
fn a_new_job_supersedes_the_old_one_within_a_few_cycles() {
    let capacity = 4;
    let (w, _) = spawn(capacity, 2, 64);
    let stats = w.stats();
    let mut all = Vec::new();
    for round in 0..10u64 {
        let (old, new) = (round + 1, round + 2);
        if round == 0 {
            assert!(w.send(trajectory(old, None)));
        }
        // Wait until the old job is well under way.
        let mut slips = 0;
        while slips < 3 {
            let u = recv(&w);
            slips += matches!(u, Update::Slip { generation: g, .. } if g == old) as usize;
            all.push(u);
        }
        assert!(w.send(trajectory(new, None)));
        // The old job is finished as cancelled when the new one starts …
        let c0 = loop {
            let u = recv(&w);
            let done = matches!(
                u,
                Update::Finished { generation: g, outcome: Outcome::Cancelled, .. } if g == old
            );
            all.push(u);
            if done {
                break stats.cycles();
            }
        };
        // … and the new one's first update comes within a bounded number of
        // cycles: the old job's cycle in flight, the new job's first, and at
        // most what fits in the channel ahead of the receiver.
        loop {
            let u = recv(&w);
            let g = u.generation();
            all.push(u);
            if g == new {
                let ran = stats.cycles() - c0;
                assert!(
                    ran <= 2 + capacity as u64,
                    "{ran} cycles before the new job's first update"
                );
                break;
            }
            assert!(g < new);
        }
    }
    assert!(w.send(Command::Cancel {
        generation: 100,
        lane: None
    }));
    loop {
        let u = recv(&w);
        let ack = matches!(
            u,
            Update::Cancelled {
                generation: 100,
                ..
            }
        );
        all.push(u);
        if ack {
            break;
        }
    }
    assert_nothing_older_after_acks(&all);
    w.shutdown();
}

#[test]
fn cancel_of_both_lanes_stops_a_sweep_and_a_trajectory() {
    let (w, _) = spawn(8, 2, 4);
    assert!(w.send(sweep(1, 400, 300, 200)));
    assert!(w.send(trajectory(2, None)));
    let mut all = Vec::new();
    // Wait for a column and a slip.
    let (mut col, mut slip) = (false, false);
    while !(col && slip) {
        let u = recv(&w);
        col |= matches!(u, Update::Column { .. });
        slip |= matches!(u, Update::Slip { .. });
        all.push(u);
    }
    assert!(w.send(Command::Cancel {
        generation: 3,
        lane: None
    }));
    let mut finished = HashSet::new();
    loop {
        let u = recv(&w);
        if let Update::Finished {
            generation,
            outcome: Outcome::Cancelled,
            ..
        } = &u
        {
            finished.insert(*generation);
        }
        let ack = matches!(
            u,
            Update::Cancelled {
                generation: 3,
                lane: None
            }
        );
        all.push(u);
        if ack {
            break;
        }
    }
    assert_eq!(finished, HashSet::from([1, 2]));
    // Nothing more comes: both lanes are idle.
    assert!(w.send(iterate(4, fig3b(1.0), 0, 2)));
    let (rest, outcome) = until_finished(&w, 4, Lane::Orbit);
    assert_eq!(outcome, Outcome::Completed);
    all.extend(rest);
    assert_nothing_older_after_acks(&all);
    w.shutdown();
}

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
            Command::Trajectory {
                generation: 2,
                spec: TrajectorySpec {
                    params: fig3b(1.0),
                    settings: settings(),
                    theta0: Some(-2.0),
                    spacing: 0.05,
                    cycles: Some(3),
                },
            },
            Lane::Orbit,
            "theta",
        ),
        (
            Command::Trajectory {
                generation: 3,
                spec: TrajectorySpec {
                    params: fig3b(1.0),
                    settings: settings(),
                    theta0: None,
                    spacing: 0.0,
                    cycles: Some(3),
                },
            },
            Lane::Orbit,
            "spacing",
        ),
        (
            Command::Sweep {
                generation: 4,
                spec: SweepSpec {
                    params: Params {
                        gamma: f64::NAN,
                        ..fig3b(0.0)
                    },
                    settings: settings(),
                    theta_nu: Axis::new(0.0, 1.0, 10),
                    transient: 2,
                    keep: 2,
                },
            },
            Lane::Sweep,
            "gamma",
        ),
        (
            Command::Sweep {
                generation: 5,
                spec: SweepSpec {
                    params: fig3b(0.0),
                    settings: SolverSettings {
                        rtol: 1.0,
                        ..settings()
                    },
                    theta_nu: Axis::new(0.0, 1.0, 10),
                    transient: 2,
                    keep: 2,
                },
            },
            Lane::Sweep,
            "tol",
        ),
    ];
    for (cmd, lane, name) in cases {
        let generation = match &cmd {
            Command::Iterate { generation, .. }
            | Command::Trajectory { generation, .. }
            | Command::Sweep { generation, .. } => *generation,
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
        assert!(w.send(Command::InjectPanic {
            generation: g,
            after_cycles: 3
        }));
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

#[test]
fn a_command_of_an_older_generation_starts_nothing() {
    let (w, _) = spawn(64, 2, 64);
    assert!(w.send(Command::Cancel {
        generation: 50,
        lane: Some(Lane::Orbit)
    }));
    assert!(matches!(recv(&w), Update::Cancelled { generation: 50, .. }));
    assert!(w.send(iterate(49, fig3b(1.0), 0, 2)));
    assert!(w.send(iterate(51, fig3b(1.0), 0, 2)));
    let (ups, outcome) = until_finished(&w, 51, Lane::Orbit);
    assert_eq!(outcome, Outcome::Completed);
    assert!(ups.iter().all(|u| u.generation() == 51), "{ups:?}");
    w.shutdown();
}

#[test]
fn dragging_a_slider_ends_with_only_the_last_jobs_results() {
    // Commands arrive faster than jobs run and nobody reads meanwhile, as
    // when a slider is dragged: every superseded job ends exactly once, as
    // cancelled (or completed, if it won the race), nothing older follows a
    // cancellation, and the last ones complete.
    let (w, _) = spawn(8, 2, 4);
    let (columns, last_sweep, last_iterate) = (12, 39, 40);
    for g in 1..=20u64 {
        let theta_nu = 0.5 + 0.02 * g as f64;
        assert!(w.send(sweep(2 * g - 1, columns, 4, 3)));
        assert!(w.send(iterate(2 * g, fig3b(theta_nu), 5, 20)));
    }
    let mut all = Vec::new();
    let mut done = 0;
    while done < 2 {
        let u = recv(&w);
        if let Update::Finished { generation, .. } = u
            && (generation == last_sweep || generation == last_iterate)
        {
            done += 1;
        }
        all.push(u);
    }
    assert_nothing_older_after_acks(&all);
    let mut finished = std::collections::HashMap::new();
    for u in &all {
        if let Update::Finished {
            generation,
            outcome,
            ..
        } = u
        {
            assert!(
                finished.insert(*generation, outcome.clone()).is_none(),
                "generation {generation} finished twice"
            );
        }
    }
    assert_eq!(finished.len(), 40, "every job ends exactly once");
    for (g, o) in &finished {
        // A superseded job may have completed before its successor arrived
        // (the dispatcher waits for room to send acknowledgements).
        let last = *g == last_sweep || *g == last_iterate;
        assert!(
            *o == Outcome::Completed || (!last && *o == Outcome::Cancelled),
            "generation {g}: {o:?}"
        );
    }
    let last_columns: Vec<usize> = all
        .iter()
        .filter_map(|u| match u {
            Update::Column {
                generation, index, ..
            } if *generation == last_sweep => Some(*index),
            _ => None,
        })
        .collect();
    let unique: HashSet<usize> = last_columns.iter().copied().collect();
    assert_eq!((last_columns.len(), unique.len()), (columns, columns));
    w.shutdown();
}

#[test]
fn set_params_reruns_the_current_jobs_with_the_new_parameters() {
    let (w, _) = spawn(256, 2, 4);
    assert!(w.send(trajectory(1, Some(3))));
    let (_, outcome) = until_finished(&w, 1, Lane::Orbit);
    assert_eq!(outcome, Outcome::Completed);
    // New κ for the same job: the re-run equals the core with the new κ.
    let new = Params {
        kappa: 10.0,
        theta_nu: 1.0,
        ..fig3b(1.0)
    };
    assert!(w.send(Command::SetParams {
        generation: 2,
        params: new,
        settings: Some(settings())
    }));
    let (ups, outcome) = until_finished(&w, 2, Lane::Orbit);
    assert_eq!(outcome, Outcome::Completed);
    let events: Vec<_> = ups
        .iter()
        .filter_map(|u| match u {
            Update::Slip {
                generation: 2,
                event,
            } => Some(*event),
            _ => None,
        })
        .collect();
    let sim = Simulator::new(new, settings()).expect("valid");
    // Sampled as the trajectory job samples (dense output costs evaluations).
    let mut sampler = Sampler::new(0.05);
    let (mut theta, mut t) = (0.5, 0.0);
    let mut core = Vec::new();
    for _ in 0..3 {
        let ev = sim.cycle(theta, t, Some(&mut sampler)).expect("cycle");
        t += ev.slip_duration + ev.stick_duration;
        theta = sim.next_onset(&ev);
        core.push(ev);
    }
    assert_eq!(events, core);
    // An invalid set is named by the re-run job; the next valid one runs.
    let bad = Params { nu: -1.0, ..new };
    assert!(w.send(Command::SetParams {
        generation: 3,
        params: bad,
        settings: Some(settings())
    }));
    let (ups, outcome) = until_finished(&w, 3, Lane::Orbit);
    assert!(matches!(outcome, Outcome::Failed(_)));
    assert!(
        ups.iter().any(|u| matches!(
            u,
            Update::Error {
                parameter: Some("nu"),
                ..
            }
        )),
        "{ups:?}"
    );
    assert!(w.send(Command::SetParams {
        generation: 4,
        params: new,
        settings: Some(settings())
    }));
    let (_, outcome) = until_finished(&w, 4, Lane::Orbit);
    assert_eq!(outcome, Outcome::Completed);
    w.shutdown();
}

#[test]
fn set_params_without_settings_keeps_each_jobs_own() {
    let (w, _) = spawn(256, 2, 4);
    // A job with its own setting (the app's Auto gives each kind its own).
    let own = SolverSettings::adaptive(Method::Dp54, 1e-6);
    assert!(w.send(Command::Iterate {
        generation: 1,
        spec: IterateSpec {
            params: fig3b(1.0),
            settings: own,
            theta0: None,
            transient: 5,
            keep: 10,
            graph_powers: 1,
        },
    }));
    let (_, outcome) = until_finished(&w, 1, Lane::Orbit);
    assert_eq!(outcome, Outcome::Completed);
    let new = fig3b(1.2);
    assert!(w.send(Command::SetParams {
        generation: 2,
        params: new,
        settings: None,
    }));
    let (ups, outcome) = until_finished(&w, 2, Lane::Orbit);
    assert_eq!(outcome, Outcome::Completed);
    let thetas: Vec<f64> = ups
        .iter()
        .filter_map(|u| match u {
            Update::MapIterates { thetas, .. } => Some(thetas.clone()),
            _ => None,
        })
        .flatten()
        .collect();
    // The re-run kept dp54 at 1e-6: equal to the core with it, bit for bit,
    // and not to the core at the test's default setting.
    let core = |s: SolverSettings| {
        let sim = Simulator::new(new, s).expect("valid");
        let opts = OrbitOptions {
            transient: 5,
            keep: 10,
            lyapunov: false,
            period_tol: 1e-9,
        };
        sim.orbit(new.theta_nu, &opts, &|| false)
            .expect("orbit")
            .thetas()
    };
    assert_eq!(thetas, core(own));
    assert_ne!(thetas, core(settings()));
    w.shutdown();
}

fn work_precision(generation: Generation, params: Params, subjects: Vec<Subject>) -> Command {
    Command::WorkPrecision {
        generation,
        spec: WorkPrecisionSpec {
            params,
            theta0: None,
            transient: 100,
            points: 4,
            time_per_setting: Duration::ZERO,
            subjects,
        },
    }
}

fn dop853(tol: f64) -> Subject {
    Subject::Own(SolverSettings::adaptive(Method::Dop853, tol))
}

/// The rows of a work-precision job's updates, checking they come in order.
fn rows_of(ups: &[Update]) -> Vec<Row> {
    let mut rows = Vec::new();
    for u in ups {
        if let Update::WorkPrecisionRow { index, row, .. } = u {
            assert_eq!(*index, rows.len(), "rows arrive in the subjects' order");
            rows.push(row.clone());
        }
    }
    rows
}

#[test]
fn work_precision_streams_a_row_per_setting_equal_to_the_core() {
    let (w, _) = spawn(256, 2, 64);
    let params = fig3b(1.25);
    let subjects = vec![
        dop853(1e-4),
        dop853(1e-7),
        dop853(1e-10),
        Subject::Own(SolverSettings::fixed(Method::Rk4, 0.02)),
        Subject::Peer(oneblock::numerics::peer::PeerMethod::Dop853, 1e-8),
    ];
    assert!(w.send(work_precision(1, params, subjects.clone())));
    let (ups, outcome) = until_finished(&w, 1, Lane::Numerics);
    assert_eq!(outcome, Outcome::Completed);
    let first_row = ups
        .iter()
        .position(|u| matches!(u, Update::WorkPrecisionRow { .. }));
    let sample_at = ups
        .iter()
        .position(|u| matches!(u, Update::WorkPrecisionSample { points: 4, .. }));
    assert!(
        sample_at < first_row,
        "the sample is announced first: {ups:?}"
    );
    let rows = rows_of(&ups);
    assert_eq!(rows.len(), subjects.len(), "one row per setting");
    for u in &ups {
        assert_eq!(u.generation(), 1);
        if let Update::WorkPrecisionRow { total, .. } = u {
            assert_eq!(*total, subjects.len());
        }
    }
    // DOP853: the error falls and the cost rises with the tolerance.
    assert!(rows[2].max_error < rows[1].max_error && rows[1].max_error < rows[0].max_error);
    assert!(rows[2].max_error < 1e-8, "{:?}", rows[2]);
    assert!(rows[0].evals_per_iterate < rows[1].evals_per_iterate);
    assert!(rows[1].evals_per_iterate < rows[2].evals_per_iterate);
    // The same numbers as measuring the same sample in the core.
    let sample = build_sample(&[current_attractor(params, None, 100)], 4).expect("sample");
    for (row, subject) in rows.iter().zip(&subjects) {
        let core = measure(&sample, subject, Duration::ZERO);
        assert_eq!(
            (row.method, row.points, row.failed),
            (core.method, 4, core.failed)
        );
        assert_eq!(row.max_error.to_bits(), core.max_error.to_bits(), "{row:?}");
        assert_eq!(row.median_error.to_bits(), core.median_error.to_bits());
        assert_eq!(row.evals_per_iterate, core.evals_per_iterate);
    }
    w.shutdown();
}

#[test]
fn work_precision_is_cancelled_by_a_stop_and_by_a_newer_job() {
    let (w, _) = spawn(256, 2, 64);
    let mut all = Vec::new();
    // The whole panel's list, timed: seconds of work, stopped after a row.
    let long = |g| Command::WorkPrecision {
        generation: g,
        spec: WorkPrecisionSpec {
            params: fig3b(1.25),
            theta0: None,
            transient: 100,
            points: 8,
            time_per_setting: Duration::from_millis(40),
            subjects: quick_subjects(),
        },
    };
    let first_row_of = |w: &Worker, g: Generation, all: &mut Vec<Update>| loop {
        let u = recv(w);
        let row = matches!(u, Update::WorkPrecisionRow { generation, .. } if generation == g);
        all.push(u);
        if row {
            break;
        }
    };
    assert!(w.send(long(1)));
    first_row_of(&w, 1, &mut all);
    assert!(w.send(Command::Cancel {
        generation: 2,
        lane: Some(Lane::Numerics),
    }));
    let mut finished = false;
    loop {
        let u = recv(&w);
        if let Update::Finished {
            generation: 1,
            outcome,
            ..
        } = &u
        {
            assert_eq!(*outcome, Outcome::Cancelled);
            finished = true;
        }
        let ack = matches!(u, Update::Cancelled { generation: 2, .. });
        all.push(u);
        if ack {
            break;
        }
    }
    assert!(finished, "the stopped job got its Finished before the ack");
    // A newer job supersedes a running one.
    assert!(w.send(long(3)));
    first_row_of(&w, 3, &mut all);
    assert!(w.send(work_precision(4, fig3b(1.0), vec![dop853(1e-6)])));
    let (rest, outcome) = until_finished(&w, 4, Lane::Numerics);
    assert_eq!(outcome, Outcome::Completed);
    assert!(rest.iter().any(|u| matches!(
        u,
        Update::Finished {
            generation: 3,
            outcome: Outcome::Cancelled,
            ..
        }
    )));
    let rows_of_4 = rest
        .iter()
        .filter(|u| matches!(u, Update::WorkPrecisionRow { generation: 4, .. }))
        .count();
    assert_eq!(rows_of_4, 1);
    all.extend(rest);
    let rows_of_1 = all
        .iter()
        .filter(|u| matches!(u, Update::WorkPrecisionRow { generation: 1, .. }))
        .count();
    assert!(
        rows_of_1 < quick_subjects().len(),
        "the stopped job did not run to the end"
    );
    assert_nothing_older_after_acks(&all);
    w.shutdown();
}

#[test]
fn work_precision_names_a_bad_parameter_and_the_next_job_runs() {
    let (w, _) = spawn(256, 2, 64);
    let bad_kappa = Params {
        kappa: -1.0,
        ..fig3b(1.0)
    };
    let cases = [
        (work_precision(1, bad_kappa, vec![dop853(1e-6)]), "kappa"),
        (
            Command::WorkPrecision {
                generation: 2,
                spec: WorkPrecisionSpec {
                    params: fig3b(1.0),
                    theta0: None,
                    transient: 100,
                    points: 0,
                    time_per_setting: Duration::ZERO,
                    subjects: vec![dop853(1e-6)],
                },
            },
            "points",
        ),
        (
            Command::WorkPrecision {
                generation: 3,
                spec: WorkPrecisionSpec {
                    params: fig3b(1.0),
                    theta0: None,
                    transient: 100,
                    points: 4,
                    time_per_setting: Duration::from_secs(60),
                    subjects: vec![dop853(1e-6)],
                },
            },
            "time_per_setting",
        ),
    ];
    for (g, (cmd, name)) in cases.into_iter().enumerate() {
        let g = g as Generation + 1;
        assert!(w.send(cmd));
        let (ups, outcome) = until_finished(&w, g, Lane::Numerics);
        assert!(matches!(outcome, Outcome::Failed(_)), "{ups:?}");
        let err = ups.iter().find_map(|u| match u {
            Update::Error {
                parameter, message, ..
            } => Some((*parameter, message.clone())),
            _ => None,
        });
        let (parameter, message) = err.expect("an Error update");
        assert_eq!(parameter, Some(name), "{message}");
        assert!(
            message.contains(name) && !message.contains('\n'),
            "{message}"
        );
    }
    // A setting that fails on every point is a row with its failures, not an error.
    let too_coarse = Subject::Own(SolverSettings::fixed(Method::Rk4, 0.9));
    assert!(w.send(work_precision(
        9,
        fig3b(1.0),
        vec![too_coarse, dop853(1e-6)]
    )));
    let (ups, outcome) = until_finished(&w, 9, Lane::Numerics);
    assert_eq!(outcome, Outcome::Completed);
    let rows = rows_of(&ups);
    assert_eq!((rows[0].failed, rows[1].failed), (4, 0));
    assert!(rows[0].failure.is_some());
    w.shutdown();
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
