//! A P2 branch followed back into the doubling it was born in (issue 52,
//! item 7). It used to report a "fold" at the fixed point's doubling and
//! walk back as the same cycle with its halves swapped (in θν), or to
//! cross onto the fixed point and write it as a P2 to the end of the
//! range with "0 PD" (in κ, on the command line and in the window's Find
//! bifurcations). Now the branch ends at the fixed point's doubling,
//! located on the fixed point, with no fold and no P2 row whose points
//! coincide; the doubling is checked against a bisection of the fixed
//! point's multiplier from `solve_cycle` alone at tol 1e-14. The same
//! for a P4 that merges back into its P2 (κ = 7, γ = 4): it ends at the
//! tip with no fold reported just before it.
#![allow(clippy::unwrap_used)]

use crate::cli_support;
use crate::common;

use cli_support::*;
use common::jobs::{fig3b, spawn};
use common::until_finished;
use oneblock::model::Params;
use oneblock::sim::continuation::{ContParam, SpecialKind, SpecialPoint};
use oneblock::sim::{CycleOptions, Simulator, default_settings, solve_cycle};
use oneblock::worker::{CascadeFrom, Command, ContinuationSpec, Lane, Outcome, Update};

/// λ where the fixed point through `seed` has the multiplier −1 (from
/// `solve_cycle` alone, DOP853 at tol 1e-14, where m is good to ~1e-9) in
/// `param` between `lo` and `hi`, by bisection.
pub fn fixed_point_flip(
    base: Params,
    param: ContParam,
    [mut lo, mut hi]: [f64; 2],
    seed: f64,
) -> f64 {
    let settings = default_settings(1e-14);
    let opts = CycleOptions::for_settings(&settings);
    let mut seed = seed;
    let mut m_at = |v: f64| {
        let sim = Simulator::new(param.set(&base, v), settings).unwrap();
        let c = solve_cycle(&sim, seed, 1, &opts).unwrap();
        seed = c.points[0];
        c.multiplier + 1.0
    };
    let f_lo = m_at(lo);
    assert!(f_lo * m_at(hi) < 0.0, "no flip in [{lo}, {hi}]");
    while hi - lo > 1e-11 * hi.abs().max(1.0) {
        let mid = 0.5 * (lo + hi);
        if m_at(mid) * f_lo > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Runs `continue` on Fig. 3b's P2 and returns (stderr, branch rows,
/// special-point rows).
fn p2_run(more: &[&str]) -> (String, Vec<Vec<String>>, Vec<Vec<String>>) {
    let mut args = vec!["--preset", "fig3b", "--period", "2"];
    args.extend_from_slice(more);
    let (o, branch, points) = continue_run(&args);
    (stderr(&o), branch, points)
}

/// No fold, every row a P2 with distinct halves, and the last special
/// point the end at the fixed point's doubling `b`, listed as a P1 PD.
fn ends_at_its_birth(err: &str, rows: &[Vec<String>], specials: &[Vec<String>], b: f64, tol: f64) {
    assert!(specials.iter().all(|r| r[0] != "fold"), "{err}");
    for r in rows {
        let (t1, t2) = (num(&r[2]), num(&r[3]));
        assert!(
            (t1 - t2).abs() > 1e-6,
            "a P2 row whose points coincide: {r:?}\n{err}"
        );
    }
    let pd: Vec<_> = specials.iter().filter(|r| r[0] == "PD").collect();
    assert_eq!(pd.len(), 1, "{err}");
    assert_eq!(pd[0][1], "1", "the fixed point's doubling: {err}");
    let end = specials.last().unwrap();
    assert_eq!(end[0], "end", "{err}");
    for at in [num(&pd[0][3]), num(&end[3])] {
        assert!((at - b).abs() < tol, "{at} vs the bisection's {b}\n{err}");
    }
    assert!(err.contains("it met the P1 cycle it is born from"), "{err}");
}

#[test]
fn a_p2_followed_down_in_theta_nu_ends_at_the_fixed_points_doubling() {
    let b = fixed_point_flip(fig3b(1.0), ContParam::ThetaNu, [1.08, 1.10], 0.42);
    assert!((b - 1.0895719).abs() < 1e-7, "{b}");
    let (err, rows, pts) = p2_run(&[
        "--theta-nu",
        "1.15",
        "--param",
        "theta-nu",
        "--from",
        "1.15",
        "--to",
        "1.0",
    ]);
    ends_at_its_birth(&err, &rows, &pts, b, 1e-8);
    // It never went below the doubling (no P2 exists there).
    assert!(rows.iter().all(|r| num(&r[0]) > b), "{err}");
}

#[test]
fn a_p2_followed_up_in_kappa_ends_at_the_fixed_points_doubling() {
    let b = fixed_point_flip(fig3b(1.1), ContParam::Kappa, [19.7, 19.9], 0.42);
    assert!((b - 19.8018).abs() < 1e-4, "{b}");
    let (err, rows, pts) = p2_run(&[
        "--theta-nu",
        "1.1",
        "--param",
        "kappa",
        "--from",
        "18.95",
        "--to",
        "30",
    ]);
    ends_at_its_birth(&err, &rows, &pts, b, 2e-7);
    assert!(rows.iter().all(|r| num(&r[0]) < b), "{err}");
}

#[test]
fn find_bifurcations_in_kappa_lists_the_doubling_the_p2_is_born_in() {
    let b = fixed_point_flip(fig3b(1.1), ContParam::Kappa, [19.7, 19.9], 0.42);
    let (w, _) = spawn(64, 1, 8);
    let spec = ContinuationSpec {
        params: fig3b(1.1),
        settings: default_settings(1e-10),
        param: ContParam::Kappa,
        from: 18.95,
        to: 30.0,
        max_period: 32,
        cycle: None,
        cascade: CascadeFrom::Branch,
        curves: None,
    };
    assert!(w.send(Command::run(1, spec)));
    let (ups, outcome) = until_finished(&w, 1, Lane::Continuation);
    assert_eq!(outcome, Outcome::Completed, "{ups:?}");
    let specials: Vec<&SpecialPoint> = ups
        .iter()
        .filter_map(|u| match u {
            Update::Special { point, .. } => Some(point),
            _ => None,
        })
        .collect();
    let pd: Vec<_> = specials
        .iter()
        .filter(|s| s.kind == SpecialKind::PeriodDoubling)
        .collect();
    assert_eq!(pd.len(), 1, "{specials:?}");
    assert_eq!(pd[0].period, 1);
    assert!((pd[0].lambda - b).abs() < 1e-7, "{} vs {b}", pd[0].lambda);
    assert!(specials.iter().all(|s| s.kind != SpecialKind::Fold));
    let summary: Vec<&String> = ups
        .iter()
        .filter_map(|u| match u {
            Update::Summary { text, .. } => Some(text),
            _ => None,
        })
        .collect();
    assert!(
        summary.iter().any(|t| t.starts_with("1 PD, 0 fold")),
        "{summary:?}"
    );
    for u in &ups {
        if let Update::Branch { branch, .. } = u {
            assert_eq!(branch.period, 2);
            assert!(branch.points.iter().all(|p| p.minimal_period == 2));
            assert!(branch.points.iter().all(|p| p.lambda < b));
        }
    }
}

#[test]
fn the_p4_of_a_bubble_ends_where_it_merges_with_no_fold_before() {
    // κ = 7, γ = 4: the P4 born at the P2's first doubling (θν 1.1144538)
    // merges back into the P2 at that one's second doubling, 1.2942936
    // (tools/reference_map.py's P2 multiplier passes −1 there, and its P4
    // half-width is 0.79·√(b − θν) at 5.7e-7 below it). Near that tip the
    // P4's m → +1 like 20.5·(b − θν), so m's error put m = +1 1.3e-8
    // before the tip: a "fold" was reported there.
    let (o, rows, pts) = continue_run(&[
        "--kappa",
        "7",
        "--gamma",
        "4",
        "--nu",
        "1e-3",
        "--param",
        "theta-nu",
        "--from",
        "0.8",
        "--to",
        "1.6",
        "--period",
        "1",
        "--cascade",
    ]);
    let err = stderr(&o);
    assert!(pts.iter().all(|r| r[0] != "fold"), "{err}");
    let end = pts.last().unwrap();
    assert_eq!((end[0].as_str(), end[1].as_str()), ("end", "4"), "{err}");
    let pd: Vec<_> = pts.iter().filter(|r| r[0] == "PD" && r[1] == "2").collect();
    assert_eq!(pd.len(), 2, "{err}");
    for at in [num(&pd[1][3]), num(&end[3])] {
        assert!((at - 1.2942936).abs() < 1e-6, "{at}\n{err}");
    }
    for r in rows.iter().filter(|r| r[1] == "4") {
        assert!((num(&r[2]) - num(&r[4])).abs() > 1e-6, "{r:?}\n{err}");
    }
}
