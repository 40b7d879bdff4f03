//! The worker's continuation lanes: "Find bifurcations" at Fig. 3b finds
//! the fixed point's doubling where the library finds it when called
//! directly, streams each branch as it ends, and a newer job or a
//! parameter change stops it with nothing stale after; "Boundaries" sends
//! doubling curves on which the multiplier is −1.
#![allow(clippy::unwrap_used)]

use crate::common;

use common::jobs::{assert_nothing_older_after_acks, fig3b, spawn};
use common::{until_ack, until_finished};
use oneblock::integrate::SolverSettings;
use oneblock::model::Params;
use oneblock::sim::continuation::{
    Branch, ContOptions, ContParam, CurveKind, Problem, Reach, SpecialKind, cascade,
    continue_branch,
};
use oneblock::sim::{CycleOptions, Simulator, default_settings, solve_cycle};
use oneblock::worker::{
    BoundarySpec, CascadeFrom, Command, ContinuationSpec, Generation, Lane, Outcome, Update,
};

fn settings() -> SolverSettings {
    default_settings(1e-10)
}

fn find(generation: Generation, params: Params, from: f64, to: f64) -> Command {
    Command::run(
        generation,
        ContinuationSpec {
            params,
            settings: settings(),
            param: ContParam::ThetaNu,
            from,
            to,
            max_period: 32,
            cycle: None,
            cascade: CascadeFrom::Branch,
            curves: None,
        },
    )
}

fn branches(ups: &[Update], generation: Generation) -> Vec<Branch> {
    ups.iter()
        .filter_map(|u| match u {
            Update::Branch {
                generation: g,
                branch,
            } if *g == generation => Some(branch.clone()),
            _ => None,
        })
        .collect()
}

/// The fixed point at θν = 1.0 solved from θν itself (not from the
/// attractor the worker iterates to), and its problem.
fn direct_fixed_point() -> (Problem, f64) {
    let prob = Problem {
        base: fig3b(1.0),
        settings: settings(),
        param: ContParam::ThetaNu,
        period: 1,
    };
    let sim = Simulator::new(prob.base, prob.settings).unwrap();
    let c = solve_cycle(&sim, 1.0, 1, &CycleOptions::for_settings(&prob.settings)).unwrap();
    (prob, c.points[0])
}

#[test]
fn find_bifurcations_at_fig3b_agrees_with_the_library_called_directly() {
    let (w, _) = spawn(64, 1, 8);
    assert!(w.send(find(1, fig3b(1.0), 1.0, 1.2)));
    let (ups, outcome) = until_finished(&w, 1, Lane::Continuation);
    assert_eq!(outcome, Outcome::Completed, "{ups:?}");
    let got = branches(&ups, 1);
    assert!(
        got.len() >= 2,
        "the P1 branch and its doubled level: {got:?}"
    );

    // The first branch is the fixed point's over the whole range, stable
    // then unstable past its doubling.
    let p1 = &got[0];
    assert_eq!(p1.period, 1);
    let pd = p1
        .of_kind(SpecialKind::PeriodDoubling)
        .next()
        .expect("the fixed point doubles in [1.0, 1.2]");
    let (prob, seed) = direct_fixed_point();
    let opts = ContOptions::for_range(&prob.settings, 1.0, 1.2);
    let direct = continue_branch(&prob, 1.0, 1.2, seed, &opts, &|| false).unwrap();
    let direct_pd = direct.of_kind(SpecialKind::PeriodDoubling).next().unwrap();
    assert!(
        (pd.lambda - direct_pd.lambda).abs() < 1e-8,
        "worker {} vs direct {}",
        pd.lambda,
        direct_pd.lambda
    );
    assert!((pd.multiplier + 1.0).abs() < 1e-6, "{}", pd.multiplier);
    assert!(p1.points.first().unwrap().stable && !p1.points.last().unwrap().stable);
    assert!(p1.points.last().unwrap().multiplier < -1.0);
    let end = p1.points.last().unwrap().lambda;
    assert!(
        (end - 1.2).abs() < 1e-12,
        "the branch reaches the range's end: {end}"
    );

    // Then the P2 level, born at that doubling, to its own doubling, as
    // the library's cascade finds it.
    let p2 = &got[1];
    assert_eq!(p2.period, 2);
    let c = cascade(Reach::new(&prob, 1.0, 1.2, &opts), seed, 32, &|| false).unwrap();
    let lib: Vec<f64> = c.doublings.iter().map(|d| d.lambda).collect();
    let streamed: Vec<f64> = got
        .iter()
        .flat_map(|b| b.of_kind(SpecialKind::PeriodDoubling).take(1))
        .map(|d| d.lambda)
        .collect();
    assert_eq!(lib.len(), streamed.len(), "{lib:?} vs {streamed:?}");
    for (a, b) in lib.iter().zip(&streamed) {
        assert!((a - b).abs() < 1e-8, "{lib:?} vs {streamed:?}");
    }
    assert!(p2.points.first().unwrap().lambda > pd.lambda);
    // Progress and a closing summary, on the lane.
    assert!(ups.iter().any(|u| matches!(u,
        Update::Progress { lane: Lane::Continuation, fraction, .. } if *fraction == 1.0)));
    let summary = ups
        .iter()
        .rev()
        .find_map(|u| match u {
            Update::Summary { text, .. } => Some(text.clone()),
            _ => None,
        })
        .expect("a summary");
    assert!(summary.contains("stopped"), "{summary}");
}

#[test]
fn a_newer_job_or_a_parameter_change_cancels_and_nothing_stale_follows() {
    let (w, _) = spawn(64, 1, 8);
    // A long cascade (to P32), then at once the same job at another κ.
    assert!(w.send(find(1, fig3b(1.0), 1.0, 1.25)));
    let other = Params {
        kappa: 16.0,
        ..fig3b(1.0)
    };
    assert!(w.send(find(2, other, 1.0, 1.25)));
    let (ups, outcome) = until_finished(&w, 2, Lane::Continuation);
    assert_eq!(outcome, Outcome::Completed);
    assert!(
        ups.iter().any(|u| matches!(
            u,
            Update::Finished {
                generation: 1,
                outcome: Outcome::Cancelled,
                ..
            }
        )),
        "the first job is cancelled: {ups:?}"
    );
    assert_nothing_older_after_acks(&ups);
    // The second job's fixed point doubles where κ = 16's does.
    let got = branches(&ups, 2);
    let pd = got[0].of_kind(SpecialKind::PeriodDoubling).next().unwrap();
    let prob = Problem {
        base: other,
        settings: settings(),
        param: ContParam::ThetaNu,
        period: 1,
    };
    let direct = continue_branch(
        &prob,
        1.0,
        1.25,
        1.0,
        &ContOptions::for_range(&prob.settings, 1.0, 1.25),
        &|| false,
    )
    .unwrap();
    let d = direct.of_kind(SpecialKind::PeriodDoubling).next().unwrap();
    assert!((pd.lambda - d.lambda).abs() < 1e-8);

    // A parameter change stops a running job; it is not run again.
    assert!(w.send(find(3, fig3b(1.0), 1.0, 1.25)));
    assert!(w.send(Command::SetParams {
        generation: 4,
        params: other,
        settings: None,
    }));
    let ups = until_ack(&w, 4);
    assert!(
        ups.iter().any(|u| matches!(
            u,
            Update::Finished {
                generation: 3,
                lane: Lane::Continuation,
                outcome: Outcome::Cancelled
            }
        )),
        "{ups:?}"
    );
    assert_nothing_older_after_acks(&ups);
    // Nothing of generation 3 (and no re-run) arrives later.
    std::thread::sleep(std::time::Duration::from_millis(300));
    while let Some(u) = w.try_recv() {
        assert!(u.generation() >= 4, "stale after the change: {u:?}");
        assert!(!matches!(u, Update::Branch { .. }), "re-run: {u:?}");
    }
}

#[test]
fn boundaries_are_doubling_curves_through_the_box() {
    let (w, _) = spawn(64, 1, 8);
    let params = oneblock::model::preset("fig4").unwrap().params;
    assert!(w.send(Command::run(
        7,
        BoundarySpec {
            params,
            settings: settings(),
            theta_nu: (0.1, 1.55),
            kappa: (10.0, 22.0),
        }
    )));
    let (ups, outcome) = until_finished(&w, 7, Lane::Curves);
    assert_eq!(outcome, Outcome::Completed, "{ups:?}");
    let curves: Vec<_> = ups
        .iter()
        .filter_map(|u| match u {
            Update::Curve { curve, .. } => Some(curve.clone()),
            _ => None,
        })
        .collect();
    assert!(curves.iter().any(|c| c.period == 1), "FP→P2");
    assert!(curves.iter().any(|c| c.period == 2), "P2→P4");
    for c in &curves {
        assert!(c.points.len() > 5, "{c:?}");
        // Within the box, but for the step that leaves it (at most the
        // longest step, 1/50 of the box's side).
        for q in &c.points {
            let [tn, k] = q.lambda;
            let (dt, dk) = (0.02 * 1.45, 0.02 * 12.0);
            assert!((0.1 - dt..=1.55 + dt).contains(&tn), "{tn}");
            assert!((10.0 - dk..=22.0 + dk).contains(&k), "{k}");
            assert!((q.multiplier + 1.0).abs() < 1e-4, "{}", q.multiplier);
        }
        // It crosses κ from the box's bottom towards its top: a boundary
        // of the grid, not a point.
        let (lo, hi) = c.points.iter().fold((f64::MAX, f64::MIN), |(a, b), q| {
            (a.min(q.lambda[1]), b.max(q.lambda[1]))
        });
        assert!(hi - lo > 3.0, "κ spans only [{lo}, {hi}]");
    }
}

/// Boundaries draws fold curves too: at κ = 2.5 the fixed point's branch
/// along θν ∈ [1.1, 1.5] folds twice (1.157, 1.294: one curve through
/// both), and the fold curve the job sends is the one `oneblock continue
/// --curve fold` follows from the same branch, point for point.
#[test]
fn boundaries_add_the_fold_curve_of_continue_curve_fold() {
    let (w, _) = spawn(64, 1, 8);
    let mut params = fig3b(1.1);
    params.kappa = 2.5;
    assert!(w.send(Command::run(
        8,
        BoundarySpec {
            params,
            settings: settings(),
            theta_nu: (1.1, 1.5),
            kappa: (2.0, 4.0),
        }
    )));
    let (ups, outcome) = until_finished(&w, 8, Lane::Curves);
    assert_eq!(outcome, Outcome::Completed, "{ups:?}");
    let folds: Vec<_> = ups
        .iter()
        .filter_map(|u| match u {
            Update::Curve { curve, .. } if curve.kind == CurveKind::Fold => Some(curve.clone()),
            _ => None,
        })
        .collect();
    assert_eq!(folds.len(), 1, "{folds:?}");
    let fold = &folds[0];
    assert!(
        fold.points
            .iter()
            .all(|q| (q.multiplier - 1.0).abs() < 1e-4)
    );

    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("fold.csv");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args([
            "continue",
            "--preset",
            "fig3b",
            "--kappa",
            "2.5",
            "--curve",
            "fold",
            "--params",
            "theta-nu,kappa",
            "--from",
            "1.1",
            "--to",
            "1.5",
            "--from2",
            "2",
            "--to2",
            "4",
            "--period",
            "1",
            "--tol",
            "1e-10",
            "--out",
        ])
        .arg(&out)
        .output()
        .expect("oneblock runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&out).expect("the curve");
    let rows: Vec<[f64; 2]> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            [f[3].parse().expect("θν"), f[4].parse().expect("κ")]
        })
        .collect();
    assert_eq!(rows.len(), fold.points.len());
    let mut mine: Vec<[f64; 2]> = fold.points.iter().map(|q| q.lambda).collect();
    let mut theirs = rows;
    for v in [&mut mine, &mut theirs] {
        v.sort_by(|a, b| a[0].total_cmp(&b[0]));
    }
    for (a, b) in mine.iter().zip(&theirs) {
        assert!(
            (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9,
            "{a:?} {b:?}"
        );
    }
}
