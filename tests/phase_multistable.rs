//! The phase view's job with seeds (docs/attractors.md): at κ = 10,
//! γ = 6.5, ν = 1e-3 the grid's multistable cells lie in the hysteresis
//! range (θν from the fixed point's second flip, 1.364, to the P2 branch's
//! fold, 1.4202), and the attractors it lists for each (the window's click
//! list) are those direct orbits from 32 seeds spread over the arc end on,
//! each cycle then solved by Newton: an independent run.

#![allow(clippy::unwrap_used)]

use crate::common::seeded;

use oneblock::jobs::{Axis, PhaseSpec, PhaseTuning, Spec, Update, run_collect};
use oneblock::model::Params;
use oneblock::sim::{CycleOptions, Period, Simulator, default_settings, solve_cycle};
use oneblock::worker::{GridCell, MAX_LISTED};

/// A cycle direct orbits reached: its period and multiplier (Newton).
#[derive(Debug)]
struct Reached {
    period: Option<usize>,
    multiplier: Option<f64>,
}

/// The distinct attractors the orbits from 32 seeds at a θν of the κ = 10
/// range end on (an aperiodic end has no period), each cycle solved by
/// Newton from the orbit's last onset.
fn attractors_default(theta_nu: f64) -> Option<Vec<Reached>> {
    let settings = default_settings(1e-10);
    let sim = Simulator::new(params(theta_nu), settings).ok()?;
    let mut found: Vec<Reached> = Vec::new();
    for e in seeded::kappa10_at(theta_nu) {
        let r = match e.period {
            Period::Periodic(q) => {
                let c = solve_cycle(
                    &sim,
                    e.theta_last,
                    q,
                    &CycleOptions::for_settings(&settings),
                )
                .ok()?;
                Reached {
                    period: Some(c.minimal_period),
                    multiplier: Some(c.multiplier),
                }
            }
            Period::Aperiodic => Reached {
                period: None,
                multiplier: None,
            },
        };
        let same = |a: &Reached| {
            a.period == r.period
                && match (a.multiplier, r.multiplier) {
                    (Some(x), Some(y)) => (x - y).abs() < 1e-6,
                    _ => true,
                }
        };
        if !found.iter().any(same) {
            found.push(r);
        }
    }
    Some(found)
}

fn params(theta_nu: f64) -> Params {
    seeded::kappa10_params(theta_nu)
}

/// The window's phase job over θν = 1.33 … 1.45 at κ = 10, with 8 seeds
/// and the lists on, as the view starts it.
fn grid() -> Vec<GridCell> {
    let spec = PhaseSpec {
        params: params(0.0),
        settings: default_settings(1e-10),
        theta_nu: Axis::new(1.33, 1.45, 13),
        kappa: Axis::new(10.0, 10.0, 1),
        transient: 400,
        keep: 128,
        tuning: PhaseTuning {
            seeds: 8,
            list_attractors: true,
            ..PhaseTuning::default()
        },
    };
    let ups = run_collect(Spec::Phase(spec), 2, |_| {}, || false).expect("completes");
    let mut cells: Vec<GridCell> = ups
        .into_iter()
        .flat_map(|u| match u {
            Update::PhaseCells { cells, .. } => cells,
            _ => Vec::new(),
        })
        .collect();
    cells.sort_by_key(|c| c.column);
    cells
}

#[test]
fn the_phase_jobs_multistable_cells_list_the_attractors_that_attractors_finds() {
    let cells = grid();
    assert_eq!(cells.len(), 13);
    let mut multistable = vec![];
    for gc in &cells {
        let (tn, n) = (gc.cell.theta_nu, gc.cell.attractors.unwrap());
        if n < 2 {
            assert!(gc.listed.is_empty(), "theta-nu {tn}: {:?}", gc.listed);
            continue;
        }
        multistable.push(tn);
        // Independently: full orbits from 32 other seeds, cycles by Newton.
        let found = attractors_default(tn).unwrap();
        assert!(found.len() >= 2, "theta-nu {tn}: {found:?}");
        assert_eq!(
            gc.listed.len(),
            found.len().min(MAX_LISTED),
            "theta-nu {tn}"
        );
        let mut periods: Vec<Option<usize>> = gc.listed.iter().map(|a| a.period).collect();
        let mut want: Vec<Option<usize>> = found.iter().map(|a| a.period).collect();
        periods.sort();
        want.sort();
        assert_eq!(periods, want, "theta-nu {tn}");
        // Between the P2 branch's lower fold (1.364) and the fixed point's
        // second flip (1.3708) the two are P2 cycles; above it, the fixed
        // point and the P2.
        if tn > 1.3708 {
            assert_eq!(periods, vec![Some(1), Some(2)], "theta-nu {tn}");
        }
        for a in &gc.listed {
            // The same cycle has the same multiplier (both solved by Newton).
            let m = a.multiplier.unwrap();
            assert!(
                found
                    .iter()
                    .any(|f| f.period == a.period && (f.multiplier.unwrap() - m).abs() < 1e-5),
                "theta-nu {tn}: {a:?} is not among {found:?}"
            );
            assert!(m.abs() < 1.0, "an attractor: |m| < 1, {m}");
            assert!(a.basin_fraction > 0.0, "theta-nu {tn}: {a:?}");
        }
        let total: f64 = gc.listed.iter().map(|a| a.basin_fraction).sum();
        assert!(total <= 1.0 + 1e-12, "theta-nu {tn}: {total}");
    }
    assert!(
        multistable.iter().all(|&t| (1.364..1.4202).contains(&t)),
        "{multistable:?}"
    );
    assert!(multistable.len() >= 4, "{multistable:?}");
}
