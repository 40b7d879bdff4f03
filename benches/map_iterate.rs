//! Map iterates per second on the two chaotic attractors of the issue
//! (γ = 6.5, κ = 18.95, ν = 1e-3, θν = 1.25 and γ = 6.5, κ = 50, ν = 1e-4,
//! θν = 1.4), for DP5(4) and DOP853 at several tolerances.
//!
//! Criterion reports the median time per iterate; before timing, each
//! setting's map error (max and median |θ' − θ'_ref| over 200 attractor
//! points, committed, θ'_ref from DOP853 at 1e-14) and RHS evaluations per iterate
//! (machine-independent) are printed, so speed and accuracy are read off
//! the same run. At DOP853 1e-9 a `/derivatives` row times the same
//! iterates with the map's six exact derivatives, and a `/slope` row with
//! f' alone.  Run: `cargo bench --features bench --bench map_iterate`.

#![allow(clippy::unwrap_used)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use oneblock::numerics::sample::default_attractors;
use oneblock::sim::cycles_in_lanes;
use oneblock::{Method, Params, Simulator, SolverSettings};

/// The benchmark's names for the two chaotic attractors of the default
/// sample (`numerics::sample::default_attractors`), whose parameters and
/// 200 committed orbit points (`numerics::fixed_sample`) it measures, so that
/// the points do not move when the integrator's roundings change.
const ATTRACTORS: [(&str, &str); 2] = [
    ("fig3b_chaos", "stick-slip chaos"),
    ("fig3a_intermittent", "mixed intermittent"),
];

const SETTINGS: [(Method, f64); 7] = [
    (Method::Dp54, 1e-8),
    (Method::Dp54, 1e-10),
    (Method::Dop853, 1e-8),
    (Method::Dop853, 1e-9),
    (Method::Dop853, 1e-10),
    (Method::Dop853, 1e-12),
    (Method::Dp54, 1e-9),
];

fn params(kappa: f64, nu: f64, theta_nu: f64) -> Params {
    Params {
        kappa,
        gamma: 6.5,
        nu,
        theta_nu,
        omega: 50.0,
    }
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("map_iterate");
    group.throughput(Throughput::Elements(1));
    group
        .measurement_time(Duration::from_secs(3))
        .sample_size(30)
        .warm_up_time(Duration::from_millis(500));
    let attractors = default_attractors();
    for (name, sample_name) in ATTRACTORS {
        let a = attractors.iter().find(|a| a.name == sample_name).unwrap();
        let (p, fixed) = (a.params, a.fixed.unwrap());
        let reference = Simulator::new(p, SolverSettings::adaptive(Method::Dop853, 1e-14)).unwrap();
        let thetas = fixed.to_vec();
        let refs: Vec<f64> = thetas.iter().map(|&t| reference.map(t).unwrap()).collect();
        for (method, tol) in SETTINGS {
            let sim = Simulator::new(p, SolverSettings::adaptive(method, tol)).unwrap();
            let mut errs = vec![];
            let mut evals = 0;
            for (&t, &r) in thetas.iter().zip(&refs) {
                let e = sim.cycle(t, 0.0, None).unwrap();
                evals += e.rhs_evals;
                errs.push((e.theta_next - r).abs());
            }
            errs.sort_by(f64::total_cmp);
            eprintln!(
                "{name} {method} tol {tol:e}: map error max {:.1e} median {:.1e}, {:.0} rhs evaluations per iterate",
                errs[errs.len() - 1],
                errs[errs.len() / 2],
                evals as f64 / thetas.len() as f64
            );
            // Time the map along the attractor's own points, cycling through them.
            let mut i = 0;
            group.bench_function(format!("{name}/{method}/{tol:e}"), |b| {
                b.iter(|| {
                    i = (i + 1) % thetas.len();
                    black_box(sim.map(black_box(thetas[i])).unwrap())
                })
            });
            // The same iterates with all six exact derivatives
            // (`Simulator::cycle_derivatives`); its ratio to the plain row
            // above is the derivatives' cost (docs/derivatives.md).
            if method == Method::Dop853 && tol == 1e-9 {
                derivatives_by_thread_time(name, &sim, &thetas);
                let mut i = 0;
                group.bench_function(format!("{name}/{method}/{tol:e}/derivatives"), |b| {
                    b.iter(|| {
                        i = (i + 1) % thetas.len();
                        black_box(sim.cycle_derivatives(black_box(thetas[i]), 0.0).unwrap())
                    })
                });
                // f' alone (`Simulator::cycle_slope`), what the Lyapunov
                // exponents and the cycle solver ask for.
                let mut i = 0;
                group.bench_function(format!("{name}/{method}/{tol:e}/slope"), |b| {
                    b.iter(|| {
                        i = (i + 1) % thetas.len();
                        black_box(sim.cycle_slope(black_box(thetas[i]), 0.0).unwrap())
                    })
                });
            }
            // Only DOP853 steps slips together (DP5(4) would time the
            // driver alone); tol 1e-12 adds nothing to the comparison.
            if method != Method::Dop853 || tol < 1e-11 {
                continue;
            }
            // The same iterates in lanes (`sim::cycles_in_lanes`: up to
            // `sim::LANES` slips' stages computed together on this one
            // thread), all 200 per iteration, as independent work (a sweep's
            // columns, the sample) runs them. Bitwise the same values; the
            // time per iterate is what counts.
            let tasks: Vec<_> = thetas.iter().map(|&t| (&sim, t, 0.0)).collect();
            group.throughput(Throughput::Elements(tasks.len() as u64));
            group.bench_function(format!("{name}/{method}/{tol:e}/lanes"), |b| {
                b.iter(|| black_box(cycles_in_lanes(black_box(&tasks))))
            });
            group.throughput(Throughput::Elements(1));
        }
    }
    group.finish();
}

/// The derivatives' cost as a ratio, by this thread's CPU time (which a
/// loaded host's other work does not count): plain iterates, all six
/// derivatives and f' alone over the attractor's points, alternated in 21
/// rounds of 1000 iterates each; the medians and their ratios.
fn derivatives_by_thread_time(name: &str, sim: &Simulator, thetas: &[f64]) {
    #[cfg(target_os = "linux")]
    {
        let cpu = || {
            let mut t = libc::timespec {
                tv_sec: 0,
                tv_nsec: 0,
            };
            // SAFETY: `t` is a valid timespec for the call to write.
            unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) };
            t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
        };
        const N: usize = 1000;
        let mut times: [Vec<f64>; 3] = Default::default();
        for _ in 0..21 {
            for (v, times) in times.iter_mut().enumerate() {
                let t0 = cpu();
                for k in 0..N {
                    let t = black_box(thetas[k % thetas.len()]);
                    match v {
                        0 => drop(black_box(sim.map(t))),
                        1 => drop(black_box(sim.cycle_derivatives(t, 0.0))),
                        _ => drop(black_box(sim.cycle_slope(t, 0.0))),
                    }
                }
                times.push((cpu() - t0) / N as f64 * 1e6);
            }
        }
        let [plain, all, slope] = times.map(|mut v| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        });
        eprintln!(
            "{name}: by thread CPU time, plain {plain:.1} µs, all six derivatives {all:.1} µs ({:.2}×), f' alone {slope:.1} µs ({:.2}×)",
            all / plain,
            slope / plain
        );
    }
    #[cfg(not(target_os = "linux"))]
    let _ = (name, sim, thetas);
}

criterion_group!(benches, bench, rhs, lockstep);
criterion_main!(benches);

/// The two right-hand sides alone, over 256 states spread like a slip's
/// (positions inside C, relative speeds 1e-5 … 0.3 in every direction): what
/// one evaluation costs without the stepping around it.
fn rhs(c: &mut Criterion) {
    use oneblock::sim::field::SlipField;
    let p = params(18.95, 1e-3, 1.25);
    let field = SlipField::new(&p);
    let states: Vec<[f64; 4]> = (0..256)
        .map(|i| {
            let f = i as f64;
            let (th, r) = (f * 2.399, 0.3 + 0.7 * ((f * 0.618) % 1.0));
            let (sp, ph) = (10f64.powf(-5.0 + 4.5 * ((f * 0.382) % 1.0)), f * 1.7);
            [
                r * th.cos() / p.kappa,
                r * th.sin(),
                sp * ph.cos(),
                sp * ph.sin(),
            ]
        })
        .collect();
    let mut group = c.benchmark_group("rhs");
    group.throughput(Throughput::Elements(states.len() as u64));
    group
        .measurement_time(Duration::from_secs(2))
        .warm_up_time(Duration::from_millis(300));
    group.bench_function("accel", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for y in &states {
                s += field.accel(black_box(y))[2];
            }
            s
        })
    });
    group.bench_function("decel", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for y in &states {
                s += field.decel(black_box(y))[2];
            }
            s
        })
    });
    // The same, each evaluation's argument depending on the previous
    // result, as the stages of a Runge–Kutta step do: the latency.
    for (name, accel) in [("accel_chained", true), ("decel_chained", false)] {
        group.bench_function(name, |b| {
            b.iter(|| {
                let mut s = 0.0;
                for y in &states {
                    let mut y = *y;
                    y[2] += 1e-300 * s;
                    let k = if accel {
                        field.accel(&y)
                    } else {
                        field.decel(&y)
                    };
                    s = k[2] + k[3];
                }
                s
            })
        });
    }
    group.finish();
}

/// One DOP853 step's stages for `L` slips computed together, stage by stage
/// (`Solver::stages_lanes`, as `sim::run_lanes` runs them), starting with
/// each slip's f(y): the field and stage arithmetic without step control.
mod lanes {
    use oneblock::integrate::{LaneAttempt, Solver, State};
    use oneblock::sim::field::SlipField;
    use oneblock::{Method, SolverSettings};

    #[inline(always)]
    fn step_impl<const L: usize>(
        f: &SlipField,
        decel: bool,
        solvers: &mut [Solver; L],
        y: &[State; L],
        h: f64,
    ) -> [State; L] {
        let rhs = |s: &State| if decel { f.decel(s) } else { f.accel(s) };
        let k0 = y.each_ref().map(rhs);
        let mut l = 0;
        let attempts = solvers.each_mut().map(|solver| {
            let a = LaneAttempt {
                solver,
                f: rhs,
                y: &y[l],
                k0: &k0[l],
                h,
            };
            l += 1;
            a
        });
        Solver::stages_lanes(attempts)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn step_avx2<const L: usize>(
        f: &SlipField,
        decel: bool,
        solvers: &mut [Solver; L],
        y: &[State; L],
        h: f64,
    ) -> [State; L] {
        step_impl(f, decel, solvers, y, h)
    }

    /// Solvers for `L` slips (their stage storage; no step is controlled).
    pub fn solvers<const L: usize>() -> [Solver; L] {
        let settings = SolverSettings::adaptive(Method::Dop853, 1e-8);
        std::array::from_fn(|_| Solver::new(settings, [1.0; 4], 1e-3))
    }

    /// One step for each of the `L` slips; compiled with AVX2 where the
    /// CPU has it, as the solver's slips are.
    pub fn step<const L: usize>(
        f: &SlipField,
        decel: bool,
        solvers: &mut [Solver; L],
        y: &[State; L],
        h: f64,
    ) -> [State; L] {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { step_avx2(f, decel, solvers, y, h) };
        }
        step_impl(f, decel, solvers, y, h)
    }
}

/// How much throughput stepping independent slips together buys
/// (docs/performance.md, "Slips in lanes"): time per slip-step, one slip
/// against two (Throughput: slips), for both fields, each step starting
/// from the last one's result as an integration does (pulled halfway back
/// so the states stay in range).
fn lockstep(c: &mut Criterion) {
    use oneblock::sim::field::SlipField;
    let field = SlipField::new(&params(18.95, 1e-3, 1.25));
    let start = |l: usize| [0.01, 0.3, -0.04 + 1e-3 * l as f64, 0.07];
    let mut group = c.benchmark_group("lockstep");
    group
        .measurement_time(Duration::from_secs(2))
        .warm_up_time(Duration::from_millis(300));
    for decel in [false, true] {
        let phase = if decel { "decel" } else { "accel" };
        group.throughput(Throughput::Elements(1));
        group.bench_function(format!("{phase}_1_slip"), |b| {
            let mut y = [start(0)];
            let mut solvers = lanes::solvers::<1>();
            b.iter(|| {
                let yn = lanes::step(&field, decel, &mut solvers, black_box(&y), 1e-3);
                for m in 0..4 {
                    y[0][m] = 0.5 * (yn[0][m] + y[0][m]);
                }
            })
        });
        group.throughput(Throughput::Elements(2));
        group.bench_function(format!("{phase}_2_slips"), |b| {
            let mut y = [start(0), start(1)];
            let mut solvers = lanes::solvers::<2>();
            b.iter(|| {
                let yn = lanes::step(&field, decel, &mut solvers, black_box(&y), 1e-3);
                for l in 0..2 {
                    for m in 0..4 {
                        y[l][m] = 0.5 * (yn[l][m] + y[l][m]);
                    }
                }
            })
        });
    }
    group.finish();
}
