//! Long orbits on the map's verified interpolant (`sim::MapInterpolant`)
//! beside direct integration, at Fig. 3b's chaotic point (κ = 18.95,
//! ν = 1e-3, θν = 1.25) and the intermittent point (κ = 50, ν = 1e-4,
//! θν = 1.4), γ = 6.5, DOP853 at 1e-10 (the default).
//!
//! Before timing, each point's map error is printed for both ways of
//! evaluating the map: max |θ' − θ'_ref| over its 200 committed attractor
//! points (θ'_ref from DOP853 at 1e-14), and the interpolant's own
//! a-posteriori check against the direct map. Timed: `orbit` with 10⁶ kept
//! iterates (transient 1000, Lyapunov exponent on) construction included;
//! plain iterates of the built interpolant; and 1000 directly integrated
//! iterates, for the direct figure. Run:
//! `cargo bench --features bench --bench interpolant -- --warm-up-time 1 --measurement-time 3`.

#![allow(clippy::unwrap_used)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use oneblock::model::wrap_angle;
use oneblock::numerics::sample::{default_attractors, reference_settings};
use oneblock::sim::{
    InterpolantOptions, MapInterpolant, OrbitOptions, cycles_in_lanes, orbit_interpolated,
};
use oneblock::{Simulator, SolverSettings};

const POINTS: [(&str, &str); 2] = [
    ("fig3b_chaos", "stick-slip chaos"),
    ("intermittent", "mixed intermittent"),
];

fn orbit_opts(keep: usize) -> OrbitOptions {
    OrbitOptions {
        transient: 1000,
        keep,
        lyapunov: true,
        period_tol: 1e-9,
    }
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("interpolant");
    group
        .sample_size(10)
        .measurement_time(Duration::from_secs(3))
        .warm_up_time(Duration::from_millis(500));
    let attractors = default_attractors();
    for (name, sample_name) in POINTS {
        let a = attractors.iter().find(|a| a.name == sample_name).unwrap();
        let pts = a.fixed.unwrap();
        let sim = Simulator::new(a.params, SolverSettings::default()).unwrap();
        let reference = Simulator::new(a.params, reference_settings()).unwrap();
        let iopts = InterpolantOptions::for_settings(sim.settings());
        let built = orbit_interpolated(&sim, a.theta0, &orbit_opts(1000), iopts, &|| false)
            .unwrap()
            .interpolant;
        let theta_next = |s: &Simulator| -> Vec<f64> {
            let tasks: Vec<_> = pts.iter().map(|&t| (s, t, 0.0)).collect();
            cycles_in_lanes(&tasks)
                .into_iter()
                .map(|r| r.unwrap().theta_next)
                .collect()
        };
        let (exact, direct) = (theta_next(&reference), theta_next(&sim));
        let max_err = |got: &dyn Fn(usize) -> Option<f64>| {
            (0..pts.len())
                .filter_map(|i| got(i).map(|g| wrap_angle(g - exact[i]).abs()))
                .fold(0.0_f64, f64::max)
        };
        let v = built.verification();
        println!(
            "{name}: map error vs DOP853 1e-14 over {} points: direct {:.1e}, interpolant {:.1e}; interpolant vs direct at {} check points {:.1e}; {} pieces, degree <= {}, {} map evaluations to build",
            pts.len(),
            max_err(&|i| Some(direct[i])),
            max_err(&|i| built.map(pts[i])),
            v.points,
            v.max_map_error,
            built.pieces().0,
            built.max_degree(),
            built.evaluations(),
        );

        group.throughput(Throughput::Elements(1_000_000));
        group.bench_function(format!("{name}/orbit_1e6_kept_with_construction"), |b| {
            b.iter(|| {
                let o =
                    orbit_interpolated(&sim, a.theta0, &orbit_opts(1_000_000), iopts, &|| false)
                        .unwrap();
                black_box(o.orbit.lyapunov)
            })
        });
        let interp: &MapInterpolant = &built;
        group.throughput(Throughput::Elements(100_000));
        group.bench_function(format!("{name}/plain_iterates_built"), |b| {
            b.iter(|| {
                let mut th = pts[0];
                for _ in 0..100_000 {
                    th = interp.map(th).unwrap_or_else(|| sim.map(th).unwrap());
                }
                black_box(th)
            })
        });
        group.throughput(Throughput::Elements(1000));
        group.bench_function(format!("{name}/direct_orbit_1000"), |b| {
            let opts = OrbitOptions {
                transient: 0,
                keep: 1000,
                lyapunov: false,
                period_tol: 1e-9,
            };
            b.iter(|| black_box(sim.orbit(pts[0], &opts, &|| false).unwrap().theta_last))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
