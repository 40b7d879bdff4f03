//! The cost targets of issue 56's long orbits and cheap period test:
//!
//! - `long_orbit`: `oneblock orbit`'s job for its summary alone (no CSV),
//!   10⁵ and 10⁶ kept iterates on Fig. 3b's chaos (κ = 18.95, θν = 1.25,
//!   θ0 = 0.4, 1000 transient, the map's interpolant as `--map auto`
//!   chooses); target: 10⁶ at most 3× 10⁵. Its peak memory (target under
//!   40 MB) is a process's, checked by tests/orbit_memory.rs and measured
//!   with `/usr/bin/time -v oneblock orbit … --keep 1000000 --json`.
//! - `one_core_diagram`: the Fig. 3b diagram, 200 columns × (300 + 200)
//!   at tol 1e-9, through the sweep job on one thread, as
//!   `taskset -c 0 oneblock bifurcation --preset fig3b --columns 200
//!   --transient 300 --keep 200 --tol 1e-9` runs it.
//! - `period_test`: the period test at every length of 2000 onsets of
//!   that chaos (tol 1e-7, the diagram's): `settled_period` from scratch
//!   each time, as the columns and cells did, against `PeriodWatch`.
//!
//! `cargo bench --features bench --no-default-features --bench long_runs`

#![allow(clippy::unwrap_used)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use oneblock::jobs::{
    Axis, IterateOptions, IterateSpec, Spec, SweepSpec, Update, run_collect_some,
};
use oneblock::model::{Params, preset};
use oneblock::sim::continuation::ContParam;
use oneblock::sim::period::{PeriodWatch, settled_period};
use oneblock::sim::{MapChoice, Simulator, default_settings};

/// The chaotic orbit.
fn chaos() -> Params {
    Params {
        theta_nu: 1.25,
        ..preset("fig3b").unwrap().params
    }
}

/// Runs `spec` on `threads`, keeping only its end (the orbit), as the
/// command line does; how many updates were kept.
fn run(spec: Spec, threads: usize) -> usize {
    let keep: fn(&Update) -> bool = |u| matches!(u, Update::Orbit { .. });
    run_collect_some(spec, threads, |_| {}, || false, keep)
        .unwrap()
        .len()
}

fn long_orbit(c: &mut Criterion) {
    let mut g = c.benchmark_group("long_orbit");
    g.sample_size(10).warm_up_time(Duration::from_secs(1));
    for (name, keep) in [("1e5", 100_000), ("1e6", 1_000_000)] {
        let spec = IterateSpec {
            params: chaos(),
            settings: default_settings(1e-10),
            theta0: Some(0.4),
            transient: 1000,
            keep,
            graph_powers: 0,
            options: IterateOptions {
                map: MapChoice::Auto,
                period_tol: None,
                lyapunov: true,
                report: true,
                events: false,
            },
        };
        g.bench_function(format!("summary/{name}"), |b| {
            b.iter(|| black_box(run(Spec::Iterate(spec.clone()), 1)))
        });
    }
}

fn one_core_diagram(c: &mut Criterion) {
    let mut g = c.benchmark_group("one_core_diagram");
    g.sample_size(10).warm_up_time(Duration::from_secs(1));
    let spec = SweepSpec {
        params: preset("fig3b").unwrap().params,
        settings: default_settings(1e-9),
        param: ContParam::ThetaNu,
        axis: Axis::new(0.0, std::f64::consts::FRAC_PI_2, 200),
        transient: 300,
        keep: 200,
        map: MapChoice::Auto,
        theta0: None,
        seeds: 0,
    };
    g.bench_function("fig3b/200x500", |b| {
        b.iter(|| black_box(run(Spec::Sweep(spec.clone()), 1)))
    });
}

fn period_test(c: &mut Criterion) {
    let sim = Simulator::new(chaos(), default_settings(1e-9)).unwrap();
    let mut theta = 0.4;
    let seq: Vec<f64> = (0..2000)
        .map(|_| {
            let ev = sim.cycle(theta, 0.0, None).unwrap();
            theta = sim.next_onset(&ev);
            ev.theta
        })
        .collect();
    let tol = 1e-7;
    let mut g = c.benchmark_group("period_test");
    g.bench_function("settled_period/2000", |b| {
        b.iter(|| {
            (1..=seq.len())
                .filter_map(|n| settled_period(&seq[..n], tol))
                .count()
        })
    });
    g.bench_function("watch/2000", |b| {
        b.iter(|| {
            let mut watch = PeriodWatch::new(tol);
            (1..=seq.len())
                .filter_map(|n| watch.settled(&seq[..n], n))
                .count()
        })
    });
}

criterion_group!(benches, long_orbit, one_core_diagram, period_test);
criterion_main!(benches);
