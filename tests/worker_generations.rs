//! Generations and cancellation, headless: nothing older follows a
//! cancellation, a new job supersedes the old one within a few cycles, a
//! slider drag ends with only the last job's results, and new parameters rerun
//! the current jobs. Assertions are on generations and orderings, never on
//! wall-clock time (timeouts only guard against hangs).

use crate::common;
use common::jobs::*;
use common::{recv, until_finished};
use std::collections::HashSet;

use oneblock::integrate::{Method, SolverSettings};
use oneblock::model::Params;
use oneblock::sim::{OrbitOptions, Sampler, Simulator};
use oneblock::worker::{Command, IterateSpec, Lane, Outcome, Update};

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
    assert!(w.send(Command::run(
        1,
        IterateSpec {
            params: fig3b(1.0),
            settings: own,
            theta0: None,
            transient: 5,
            keep: 10,
            graph_powers: 1,
            options: oneblock::jobs::IterateOptions::default(),
        }
    )));
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
