//! The worker's results, headless: map iterates, the graph of f, the
//! trajectory and the progressive sweep equal the core's bit for bit, and the
//! sweep delivers each column once, coarse pass first.

use crate::common;
use common::jobs::*;
use common::until_finished;
use std::collections::HashSet;
use std::sync::atomic::Ordering;

use oneblock::sim::{
    Column, Handover, LANES, OrbitOptions, Sampler, Simulator, SweepOptions, column_start,
    return_map_window, theta_nu_grid,
};
use oneblock::worker::{Lane, Outcome, Update, sweep_plan};

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
                value: theta_nu,
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
    let opts = SweepOptions {
        transient,
        keep,
        map: oneblock::sim::MapChoice::Auto,
    };
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
