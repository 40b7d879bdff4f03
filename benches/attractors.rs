//! The cost targets of issue 28's seeding (docs/attractors.md), each as a
//! pair of benchmarks whose ratio is the target's:
//!
//! - `attractors` at one point with the default 64 seeds against one
//!   `orbit` of 400 + 128 iterates there (target: at most 3×), at the
//!   chaos preset (κ = 18.95, θν = 1.25), inside the κ = 10 hysteresis
//!   range (θν = 1.40), and at the creep and intermittent presets;
//! - the Fig. 3b diagram (400 columns × 200 points) with 16 seeds and the
//!   neighbour pass (both sweep directions) against the single-seed
//!   diagram (target: at most 3×), both through the sweep job as
//!   `oneblock bifurcation` runs it;
//! - the Fig. 4 grid with attractor counts from 16 seeds against the plain
//!   grid (target: at most 4×), both through the phase job.
//!
//! The seeded ones take minutes a sample. Run on an idle machine:
//! `cargo bench --features bench --bench attractors -- --warm-up-time 1 --measurement-time 3`.

#![allow(clippy::unwrap_used)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use oneblock::jobs::{Axis, PhaseSpec, PhaseTuning, Spec, SweepSpec, run_collect};
use oneblock::model::{Params, preset};
use oneblock::sim::attractors::{CellOptions, KEEP, TRANSIENT, attractors};
use oneblock::sim::{MapChoice, OrbitOptions, Simulator, default_settings};

fn point(c: &mut Criterion) {
    let never = || false;
    let settings = default_settings(1e-10);
    let mut g = c.benchmark_group("attractors_point");
    g.sample_size(10).warm_up_time(Duration::from_secs(1));
    let hysteresis = Params {
        kappa: 10.0,
        gamma: 6.5,
        nu: 1e-3,
        theta_nu: 1.40,
        omega: 50.0,
    };
    for (name, params) in [
        ("chaos", preset("chaos").unwrap().params),
        ("hysteresis", hysteresis),
        ("creep", preset("creep").unwrap().params),
        ("intermittent", preset("intermittent").unwrap().params),
        (
            "pure_creep",
            Params {
                kappa: 22.2,
                gamma: 0.5,
                nu: 1e-3,
                theta_nu: 0.6,
                omega: 50.0,
            },
        ),
    ] {
        let sim = Simulator::new(params, settings).unwrap();
        let opts = OrbitOptions {
            transient: TRANSIENT,
            keep: KEEP,
            lyapunov: true,
            period_tol: OrbitOptions::period_tol_for(settings.rtol),
        };
        g.bench_function(format!("{name}/one_orbit"), |b| {
            b.iter(|| black_box(sim.orbit(params.theta_nu, &opts, &never).unwrap()))
        });
        let cells = CellOptions::default();
        g.bench_function(format!("{name}/attractors_cells"), |b| {
            b.iter(|| black_box(attractors(&sim, &cells, &never).unwrap()))
        });
    }
}

fn run(spec: Spec) -> usize {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    run_collect(spec, threads, |_| {}, || false).unwrap().len()
}

fn diagram(c: &mut Criterion) {
    let mut g = c.benchmark_group("attractors_diagram");
    g.sample_size(10).warm_up_time(Duration::from_secs(1));
    let spec = |seeds| {
        Spec::Sweep(SweepSpec {
            params: preset("fig3b").unwrap().params,
            settings: default_settings(1e-10),
            param: oneblock::sim::continuation::ContParam::ThetaNu,
            axis: Axis::new(0.0, std::f64::consts::FRAC_PI_2, 400),
            transient: 500,
            keep: 200,
            map: MapChoice::Auto,
            theta0: None,
            seeds,
        })
    };
    g.bench_function("fig3b/plain", |b| b.iter(|| black_box(run(spec(0)))));
    g.bench_function("fig3b/16_seeds", |b| b.iter(|| black_box(run(spec(16)))));
}

fn grid(c: &mut Criterion) {
    let mut g = c.benchmark_group("attractors_grid");
    g.sample_size(10).warm_up_time(Duration::from_secs(1));
    let spec = |seeds| {
        Spec::Phase(PhaseSpec {
            params: preset("fig4").unwrap().params,
            settings: default_settings(1e-10),
            theta_nu: Axis::new(0.0, std::f64::consts::FRAC_PI_2, 61),
            kappa: Axis::new(1.0, 42.0, 42),
            transient: 400,
            keep: 128,
            tuning: PhaseTuning {
                seeds,
                ..PhaseTuning::default()
            },
        })
    };
    g.bench_function("fig4/plain", |b| b.iter(|| black_box(run(spec(0)))));
    g.bench_function("fig4/16_seeds", |b| b.iter(|| black_box(run(spec(16)))));
}

criterion_group!(benches, point, diagram, grid);
criterion_main!(benches);
