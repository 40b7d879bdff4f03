//! Bifurcation columns with thousands of points: the worker's sweep job
//! takes an unsettled column's thousands of kept points (5000) from the map's verified
//! interpolant (bitwise what the core's column gives with `MapChoice::Auto`),
//! and their distribution is the directly integrated column's: the same
//! period for a periodic column, the same extent and histogram (within
//! statistical error) for a chaotic one.
#![allow(clippy::unwrap_used)]

use crate::common;
use common::jobs::spawn;
use common::until_finished;

use oneblock::Params;
use oneblock::sim::interpolant::MapUsed;
use oneblock::sim::{Column, MapChoice, SweepOptions, default_settings, settled_period};
use oneblock::worker::Lane;
use oneblock::worker::{Axis, Command, Outcome, SweepSpec, Update};

const TRANSIENT: usize = 300;
/// The fewest kept points for which `Auto` builds the interpolant.
const KEEP: usize = MapChoice::AUTO_COLUMN_KEEP;

fn params(kappa: f64, theta_nu: f64) -> Params {
    Params {
        kappa,
        gamma: 6.5,
        nu: 1e-3,
        theta_nu,
        omega: 50.0,
    }
}

/// The worker's one-column sweep at (κ, θν), from θ = θν.
fn worker_column(generation: u64, kappa: f64, theta_nu: f64) -> Vec<f64> {
    let (w, _) = spawn(256, 1, 1);
    let cmd = Command::run(
        generation,
        SweepSpec {
            params: params(kappa, theta_nu),
            settings: default_settings(1e-10),
            param: oneblock::sim::continuation::ContParam::ThetaNu,
            axis: Axis::new(theta_nu, theta_nu, 1),
            transient: TRANSIENT,
            keep: KEEP,
            map: MapChoice::Auto,
            theta0: None,
            seeds: 0,
        },
    );
    assert!(w.send(cmd));
    let (ups, outcome) = until_finished(&w, generation, Lane::Sweep);
    assert_eq!(outcome, Outcome::Completed);
    let cols: Vec<Vec<f64>> = ups
        .into_iter()
        .filter_map(|u| match u {
            Update::Column { thetas, .. } => Some(thetas),
            _ => None,
        })
        .collect();
    assert_eq!(cols.len(), 1);
    cols.into_iter().next().unwrap()
}

/// The core's column at (κ, θν) from θ = θν.
fn core_column(kappa: f64, theta_nu: f64, map: MapChoice) -> Column {
    let opts = SweepOptions {
        transient: TRANSIENT,
        keep: KEEP,
        map,
    };
    Column::run(
        params(kappa, theta_nu),
        default_settings(1e-10),
        theta_nu,
        theta_nu,
        &opts,
        &|| false,
    )
}

/// The worker's column is the core's `Auto` column, which was taken from
/// the interpolant (checked to 1e-10); returns it with the direct column.
fn columns(generation: u64, kappa: f64, theta_nu: f64) -> (Vec<f64>, Vec<f64>) {
    let worker = worker_column(generation, kappa, theta_nu);
    let auto = core_column(kappa, theta_nu, MapChoice::Auto);
    assert_eq!(worker, auto.thetas);
    match &auto.map {
        MapUsed::Interpolant(s) => assert!(s.max_map_error <= 1e-10, "{s:?}"),
        other => panic!("the column did not use the interpolant: {other:?}"),
    }
    let direct = core_column(kappa, theta_nu, MapChoice::Direct);
    assert_eq!(direct.map, MapUsed::Direct);
    assert_eq!((worker.len(), direct.thetas.len()), (KEEP, KEEP));
    (worker, direct.thetas)
}

/// κ = 23, θν = 1.2043 approaches its period-4 cycle so slowly that the
/// column has not settled after its transient: the interpolated points
/// settle on the same period-4 cycle as the integrated ones.
#[test]
fn a_slow_periodic_column_has_the_same_period() {
    let (interp, direct) = columns(1, 23.0, 1.2042771838760873);
    assert_eq!(settled_period(&direct, 1e-6), Some(4));
    assert_eq!(settled_period(&interp, 1e-6), Some(4));
    let cycle = |xs: &[f64]| {
        let mut c = xs[xs.len() - 4..].to_vec();
        c.sort_by(f64::total_cmp);
        c
    };
    for (a, b) in cycle(&interp).iter().zip(cycle(&direct)) {
        assert!((a - b).abs() < 1e-6, "{a} vs {b}");
    }
}

/// Per-batch fractions of `xs` in each of `bins` equal bins over [lo, hi]:
/// (mean, standard error of the mean over the batches) for every bin.
fn histogram(xs: &[f64], lo: f64, hi: f64, bins: usize, batches: usize) -> Vec<(f64, f64)> {
    let per = xs.len() / batches;
    let fractions: Vec<Vec<f64>> = xs
        .chunks(per)
        .take(batches)
        .map(|batch| {
            let mut h = vec![0.0; bins];
            for &x in batch {
                let k = (((x - lo) / (hi - lo)) * bins as f64) as usize;
                h[k.min(bins - 1)] += 1.0 / per as f64;
            }
            h
        })
        .collect();
    (0..bins)
        .map(|k| {
            let m = fractions.iter().map(|h| h[k]).sum::<f64>() / batches as f64;
            let var =
                fractions.iter().map(|h| (h[k] - m).powi(2)).sum::<f64>() / (batches - 1) as f64;
            (m, (var / batches as f64).sqrt())
        })
        .collect()
}

/// Fig. 3b's chaotic column (θν = 1.25): the interpolated and the
/// integrated points are different pseudo-orbits of the same attractor. Its
/// ends are sharp (images of the map's turning point), so the extremes of
/// 5000 points agree within 1e-6 (measured: 1.1e-7 and 2.8e-8 apart, on an
/// attractor 0.2 wide; with 2000 points they were 2e-6 and 8e-6 apart,
/// the spacing of the samples there). The 20-bin histograms agree within
/// 4 combined standard errors (batch means over 10 batches, which take the
/// correlation of successive points into account), with a floor of one
/// point per batch.
#[test]
fn a_chaotic_column_has_the_same_distribution() {
    let (interp, direct) = columns(2, 18.95, 1.25);
    let lo = direct.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = direct.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    assert!(hi - lo > 0.1, "not chaotic: [{lo}, {hi}]");
    let imin = interp.iter().copied().fold(f64::INFINITY, f64::min);
    let imax = interp.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    assert!((imin - lo).abs() < 1e-6, "{imin} vs {lo}");
    assert!((imax - hi).abs() < 1e-6, "{imax} vs {hi}");
    let (batches, bins) = (10, 20);
    let hi_ = hi + 1e-9;
    let a = histogram(&interp, lo, hi_, bins, batches);
    let b = histogram(&direct, lo, hi_, bins, batches);
    let floor = batches as f64 / interp.len() as f64;
    for (k, ((ma, sa), (mb, sb))) in a.iter().zip(&b).enumerate() {
        let allowed = (4.0 * sa.hypot(*sb)).max(floor);
        assert!(
            (ma - mb).abs() <= allowed,
            "bin {k}: {ma} ± {sa} vs {mb} ± {sb}"
        );
    }
}
