//! Seeded diagrams and grids (docs/attractors.md), through the commands:
//! every attractor at each column or cell from the exit arc's cell graph,
//! checked against direct orbits from seeds spread over the arc (an
//! independent count: full integrated orbits, periods from their
//! iterates).

#![allow(clippy::unwrap_used)]

use crate::cli_support;

use crate::common::seeded::{self, Ended};

use std::collections::BTreeSet;

use cli_support::*;
use oneblock::model::{Params, wrap_angle};
use oneblock::sim::Period;

fn params(kappa: f64, theta_nu: f64) -> Params {
    Params {
        kappa,
        gamma: 6.5,
        nu: 1e-3,
        theta_nu,
        omega: 50.0,
    }
}

/// What direct orbits reach: each distinct cycle's points, `None` for an
/// orbit on no period.
type Reached = Vec<Option<Vec<f64>>>;

/// The distinct attractors the orbits `ended` on: each a cycle's points
/// (sorted), or `None` for an orbit that settles on no period.
fn distinct(ended: &[Ended]) -> Reached {
    let mut found: Reached = Vec::new();
    for e in ended {
        let reached = match e.period {
            Period::Periodic(q) => {
                let mut pts = e.kept[e.kept.len() - q..].to_vec();
                pts.sort_by(f64::total_cmp);
                Some(pts)
            }
            Period::Aperiodic => None,
        };
        let same = |a: &Option<Vec<f64>>| match (a, &reached) {
            (Some(a), Some(b)) => {
                a.len() == b.len() && a.iter().zip(b).all(|(x, y)| wrap_angle(x - y).abs() < 1e-4)
            }
            (None, None) => true,
            _ => false,
        };
        if !found.iter().any(same) {
            found.push(reached);
        }
    }
    found
}

/// What direct orbits from `n` seeds reach at `p`.
fn direct(p: Params, n: usize) -> Reached {
    distinct(&seeded::orbits(p, n))
}

/// What direct orbits from 32 seeds reach at a column of the κ = 10 range
/// (the reference both seeded tests and the phase job's share).
fn kappa10_direct(tn: f64) -> Reached {
    distinct(seeded::kappa10_at(tn))
}

/// The seeded diagram's CSV rows (θν, θ, attractor); the followed
/// attractor's rows (label 0) carry the column's λ, the others none.
fn seeded_rows(args: &[&str]) -> Vec<(f64, f64, u8)> {
    let o = oneblock(args);
    assert_ok(&o);
    let out = stdout(&o);
    // The provenance lines (`#`) first, then the header.
    let mut lines = out.lines().skip_while(|l| l.starts_with('#'));
    assert_eq!(
        lines.next(),
        Some("theta_nu,theta,lyapunov,lyapunov_stderr,attractor")
    );
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let label: u8 = f[4].parse().unwrap();
            assert!(
                label == 0 || f[2].is_empty(),
                "λ on the followed attractor's rows only: {l}"
            );
            (f[0].parse().unwrap(), f[1].parse().unwrap(), label)
        })
        .collect()
}

/// κ = 10 over the hysteresis range: each column's attractors are those
/// direct orbits from 32 seeds end on, and the multistable columns fill
/// the range (1.364, where the small P2 is born, to the P2's fold at
/// 1.4202) and nothing outside it.
#[test]
fn the_seeded_diagram_shows_every_branch_direct_orbits_reach() {
    let rows = seeded_rows(&[
        "bifurcation",
        "--kappa",
        "10",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--theta-nu-from",
        "1.33",
        "--theta-nu-to",
        "1.45",
        "--columns",
        "13",
        "--keep",
        "24",
        "--seeds",
        "1",
    ]);
    let mut columns: Vec<f64> = rows.iter().map(|r| r.0).collect();
    columns.dedup();
    assert_eq!(columns.len(), 13);
    let mut multistable = vec![];
    for tn in columns {
        let labels: BTreeSet<u8> = rows.iter().filter(|r| r.0 == tn).map(|r| r.2).collect();
        let found = kappa10_direct(tn);
        assert_eq!(labels.len(), found.len(), "theta-nu {tn}: {found:?}");
        if labels.len() > 1 {
            multistable.push(tn);
        }
        // Every labelled point is a point of a cycle the orbits reached.
        for r in rows.iter().filter(|r| r.0 == tn) {
            let on = |c: &Option<Vec<f64>>| {
                c.as_ref()
                    .is_some_and(|c| c.iter().any(|x| wrap_angle(x - r.1).abs() < 1e-5))
            };
            assert!(
                found.iter().any(on),
                "theta-nu {tn}: {r:?} in none of {found:?}"
            );
        }
    }
    assert!(
        multistable.iter().all(|&t| (1.364..1.4202).contains(&t)),
        "{multistable:?}"
    );
    assert!(multistable.len() >= 4, "{multistable:?}");
}

/// Pure creep (issue 38): where f hugs the diagonal the seeds' orbits did
/// not arrive in their budget and every column was called multistable.
#[test]
fn a_seeded_pure_creep_diagram_has_no_multistable_column() {
    let o = oneblock(&[
        "bifurcation",
        "--kappa",
        "22.2",
        "--gamma",
        "0.5",
        "--nu",
        "1e-3",
        "--theta-nu-from",
        "0.1",
        "--theta-nu-to",
        "1.2",
        "--columns",
        "23",
        "--seeds",
        "16",
    ]);
    assert_ok(&o);
    let out = stdout(&o);
    let labels: BTreeSet<&str> = out
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap())
        .collect();
    assert_eq!(labels, BTreeSet::from(["0"]));
    assert!(
        stderr(&o).contains("every column has one attractor"),
        "{}",
        stderr(&o)
    );
}

/// Fig. 3b's windows in seeded columns: the P10 at 1.2345, the P8 at 1.245
/// and the P14 at 1.23617 alone (the saddle beside each holds orbits for
/// thousands of iterates: a seed still on it was a second attractor), as
/// direct orbits from 16 seeds all end on the one cycle.
#[test]
fn inside_fig3b_windows_a_seeded_column_has_its_cycle_alone() {
    for (tn, period) in [(1.2345, 10), (1.245, 8), (1.2361655303598935, 14)] {
        let t = tn.to_string();
        let rows = seeded_rows(&[
            "bifurcation",
            "--preset",
            "fig3b",
            "--theta-nu-from",
            &t,
            "--theta-nu-to",
            &t,
            "--columns",
            "1",
            "--transient",
            "2000",
            "--keep",
            "64",
            "--seeds",
            "1",
        ]);
        assert!(rows.iter().all(|r| r.2 == 0), "θν {tn}: a second attractor");
        let found = direct(params(18.95, tn), 16);
        assert_eq!(found.len(), 1, "θν {tn}: {found:?}");
        assert_eq!(found[0].as_ref().map(Vec::len), Some(period), "θν {tn}");
    }
}

/// The seeded phase grid counts, cell by cell, the attractors direct
/// orbits from 32 seeds reach.
#[test]
fn the_seeded_phase_grid_counts_what_direct_orbits_reach() {
    let o = oneblock(&[
        "phase",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--kappa-from",
        "10",
        "--kappa-to",
        "10",
        "--kappa-steps",
        "1",
        "--theta-nu-from",
        "1.33",
        "--theta-nu-to",
        "1.45",
        "--theta-nu-steps",
        "13",
        "--seeds",
        "1",
    ]);
    assert_ok(&o);
    let out = stdout(&o);
    let mut lines = out.lines().skip_while(|l| l.starts_with('#'));
    let header = lines.next().unwrap();
    assert!(header.ends_with(",attractors"), "{header}");
    let mut multistable = vec![];
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        let tn: f64 = f[0].parse().unwrap();
        let n: usize = f.last().unwrap().parse().unwrap();
        let found = kappa10_direct(tn);
        assert_eq!(n, found.len(), "theta-nu {tn}: {found:?}");
        if n > 1 {
            multistable.push(tn);
        }
    }
    assert!(
        multistable.iter().all(|&t| (1.364..1.4202).contains(&t)),
        "{multistable:?}"
    );
    assert!(multistable.len() >= 4, "{multistable:?}");
    assert!(stderr(&o).contains("multistable"), "{}", stderr(&o));
}

/// A seeded run whose cell graph cannot be built (RK4 at step 0.18 cannot
/// resolve the slips of the whole exit arc, though it runs the followed
/// orbits) says so column by column and cell by cell, and its summary
/// counts only what the graph counted (issue 40: failed seeds were
/// dropped and the rest called one attractor).
#[test]
fn an_uncounted_seeded_column_or_cell_is_named_not_called_single() {
    let o = oneblock(&[
        "bifurcation",
        "--kappa",
        "20",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--method",
        "rk4",
        "--step",
        "0.18",
        "--theta-nu-from",
        "1",
        "--theta-nu-to",
        "1.5",
        "--columns",
        "6",
        "--seeds",
        "1",
    ]);
    assert_ok(&o);
    let err = stderr(&o);
    let uncounted = err.matches("its other attractors not counted").count();
    let failed = err.matches("failed after").count();
    assert!(uncounted >= 1 && failed >= 1, "{err}");
    assert!(!err.contains("every column has one attractor"), "{err}");
    assert!(
        err.contains(&format!("{failed} failed, {uncounted} not counted")),
        "{err}"
    );

    let o = oneblock(&[
        "phase",
        "--method",
        "rk4",
        "--step",
        "0.18",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--kappa-from",
        "10",
        "--kappa-to",
        "40",
        "--kappa-steps",
        "4",
        "--theta-nu-from",
        "0.5",
        "--theta-nu-to",
        "1.4",
        "--theta-nu-steps",
        "3",
        "--seeds",
        "1",
    ]);
    assert_ok(&o);
    let err = stderr(&o);
    let out = stdout(&o);
    // A cell that ran (a class, not "failed") without a count.
    let ran_uncounted = out
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .filter(|l| !l.contains(",failed,") && l.ends_with(','))
        .count();
    assert!(ran_uncounted >= 1, "{out}");
    assert!(err.contains("its attractors not counted"), "{err}");
    let counted = out
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .filter(|l| !l.ends_with(','))
        .count();
    assert!(
        err.contains(&format!(" of {counted} cell(s) multistable")),
        "{err}"
    );
    assert!(
        err.contains(&format!("{ran_uncounted} not counted")),
        "{err}"
    );
}
