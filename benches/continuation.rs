//! Continuation (docs/continuation.md) at γ = 6.5, ν = 1e-3, DOP853 at
//! 1e-10: locating the fixed point's period doubling at Fig. 3b (κ = 18.95,
//! the P1 branch over θν ∈ [1.0, 1.2], the doubling located to 1e-10) and
//! at Fig. 3a (κ = 50, ν = 1e-4, from θν = 1.56 down to 1.50), and the
//! criticality at each located doubling alone (`flip_at`, as the
//! location calls it: two evaluations of f^p);
//! the cascades at κ = 18.95 and κ = 16 from θν = 1.0 (as far as each
//! goes, printed before timing); and the whole FP→P2 boundary over
//! θν ∈ [0.1, 1.55] × κ ∈ [1, 42] (both arms, from the two doublings at
//! κ = 16).
//! Run: `cargo bench --features bench --bench continuation -- --warm-up-time 1
//! --measurement-time 3`.

#![allow(clippy::unwrap_used)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use oneblock::model::Params;
use oneblock::sim::continuation::{
    ContOptions, ContParam, CurveKind, CurveOf, CurveOptions, Problem, Reach, SpecialKind, cascade,
    continue_branch, continue_curves, flip_at,
};
use oneblock::sim::default_settings;

fn problem(kappa: f64) -> Problem {
    Problem {
        base: Params {
            kappa,
            gamma: 6.5,
            nu: 1e-3,
            theta_nu: 1.0,
            omega: 50.0,
        },
        settings: default_settings(1e-10),
        param: ContParam::ThetaNu,
        period: 1,
    }
}

fn bench(c: &mut Criterion) {
    let never = || false;
    let mut g = c.benchmark_group("continuation");
    g.sample_size(10).warm_up_time(Duration::from_secs(1));
    let fig3a = Problem {
        base: Params {
            nu: 1e-4,
            ..problem(50.0).base
        },
        ..problem(50.0)
    };
    for (name, p, [from, to], seed) in [
        ("fig3b", problem(18.95), [1.0, 1.2], 0.4),
        ("fig3a", fig3a, [1.56, 1.50], 1.0),
    ] {
        let opts = ContOptions::for_range(&p.settings, from, to);
        let run = || continue_branch(&p, from, to, seed, &opts, &never).unwrap();
        g.bench_function(format!("locate_pd_{name}"), |b| b.iter(|| black_box(run())));
        let branch = run();
        let pd = branch
            .of_kind(SpecialKind::PeriodDoubling)
            .next()
            .unwrap()
            .clone();
        let mut n = 0;
        let at = p.eval(pd.theta, pd.lambda, &mut n).unwrap();
        let dm = pd.flip.unwrap().dm_dlambda;
        eprintln!(
            "{name}: the branch took {} map evaluations, the criticality 2",
            branch.map_evals
        );
        g.bench_function(format!("criticality_{name}"), |b| {
            b.iter(|| {
                let f = flip_at(&p, pd.lambda, pd.theta, Some(&at), dm, &mut n);
                black_box(f.unwrap())
            })
        });
    }
    for kappa in [18.95, 16.0] {
        let p = problem(kappa);
        let opts = ContOptions::for_range(&p.settings, 1.0, 1.6);
        let c = cascade(Reach::new(&p, 1.0, 1.6, &opts), 0.4, 16, &never).unwrap();
        let periods: Vec<usize> = c.doublings.iter().map(|d| d.period).collect();
        eprintln!(
            "kappa {kappa}: doublings of periods {periods:?}; {}",
            c.stop
        );
        g.bench_function(format!("cascade_kappa_{kappa}"), |b| {
            b.iter(|| black_box(cascade(Reach::new(&p, 1.0, 1.6, &opts), 0.4, 16, &never).unwrap()))
        });
    }
    // The whole FP→P2 boundary, as `continue --curve pd` follows it: the
    // curve through each doubling of the fixed point along θν at κ = 16
    // that is not on an earlier curve.
    let p = problem(16.0);
    let opts = ContOptions::for_range(&p.settings, 0.1, 1.55);
    let starts: Vec<_> = continue_branch(&p, 0.1, 1.55, 0.1, &opts, &never)
        .unwrap()
        .of_kind(SpecialKind::PeriodDoubling)
        .cloned()
        .collect();
    let copts = CurveOptions::for_box([[0.1, 1.55], [1.0, 42.0]]);
    let run = || {
        let of = CurveOf {
            base: p.base,
            settings: p.settings,
            params: [ContParam::ThetaNu, ContParam::Kappa],
            period: 1,
            kind: CurveKind::PeriodDoubling,
        };
        continue_curves(&of, &starts, &copts, &never)
    };
    for (i, c) in run().iter().enumerate() {
        eprintln!(
            "FP->P2 curve {i}: {} points, ends: {:?}",
            c.points.len(),
            c.ends
        );
    }
    g.bench_function("pd_curve_kappa_1_42", |b| b.iter(|| black_box(run())));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
