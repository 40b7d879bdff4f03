//! The intermittency statistics from the interpolant's tabulated slip sizes
//! against those of directly integrated orbits, at Fig. 3a's intermittent
//! regime (κ = 50, γ = 6.5, ν = 1e-4, θν = 1.4): the mean laminar length
//! and the slip-size distribution agree within their statistical errors,
//! and `oneblock orbit --stats` says where its slip sizes came from.
#![allow(clippy::unwrap_used)]

use crate::common;
use common::fixture::preset;

use std::process::Command;

use oneblock::sim::intermittency::{Intermittency, creep_flags};
use oneblock::sim::{
    InterpolantOptions, OrbitOptions, Simulator, default_settings, orbit_interpolated,
};

const THETA_NU: f64 = 1.4;

fn sim() -> Simulator {
    Simulator::new(
        preset("fig3a").with_theta_nu(THETA_NU),
        default_settings(1e-10),
    )
    .unwrap()
}

fn opts(keep: usize) -> OrbitOptions {
    OrbitOptions {
        transient: 300,
        keep,
        lyapunov: false,
        period_tol: 1e-6,
    }
}

/// Per-batch fractions of `xs` in logarithmic bins between 1e-4 and 10:
/// (mean, standard error of the mean over the batches) for every bin.
fn log_histogram(xs: &[f64], bins: usize, batches: usize) -> Vec<(f64, f64)> {
    let per = xs.len() / batches;
    let (lo, hi) = (1e-4f64.ln(), 10f64.ln());
    let fractions: Vec<Vec<f64>> = xs
        .chunks(per)
        .take(batches)
        .map(|batch| {
            let mut h = vec![0.0; bins];
            for &x in batch {
                let k = ((x.ln() - lo) / (hi - lo) * bins as f64).floor();
                h[(k.max(0.0) as usize).min(bins - 1)] += 1.0 / per as f64;
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

/// 2·10⁵ kept events from the interpolant's tables against 2·10⁴
/// integrated ones: the mean laminar length within 4 combined standard
/// errors (batch means, so the correlation of successive phases counts),
/// and each of 25 logarithmic slip-size bins within 4 combined standard
/// errors (batch means over 20 batches), at least one event per batch.
#[test]
fn laminar_lengths_and_slip_sizes_agree_with_direct_integration() {
    let sim = sim();
    let direct = sim.orbit(THETA_NU, &opts(20_000), &|| false).unwrap();
    let interp = orbit_interpolated(
        &sim,
        THETA_NU,
        &opts(200_000),
        InterpolantOptions::for_settings(sim.settings()),
        &|| false,
    )
    .unwrap();
    let v = interp.interpolant.verification();
    assert!(v.max_map_error <= 1e-10, "{v:?}");
    // Nearly every event from the tables, not integrated.
    assert!(interp.direct_iterates < 2_000, "{}", interp.direct_iterates);

    let sizes = |o: &oneblock::sim::Orbit| -> Vec<f64> {
        o.events.iter().map(|e| e.slip_distance).collect()
    };
    let creep = |o: &oneblock::sim::Orbit| -> Vec<bool> {
        let p = sim.params();
        creep_flags(p.kappa, p.gamma, o.events.iter().map(|e| e.theta))
    };
    let (sd, si) = (sizes(&direct), sizes(&interp.orbit));
    let (a, b) = (
        Intermittency::of(&creep(&direct), &sd),
        Intermittency::of(&creep(&interp.orbit), &si),
    );
    assert!(a.laminar.len() > 200, "{} laminar phases", a.laminar.len());
    let (ma, ea) = (a.mean_laminar.unwrap(), a.mean_laminar_stderr.unwrap());
    let (mb, eb) = (b.mean_laminar.unwrap(), b.mean_laminar_stderr.unwrap());
    assert!(
        (ma - mb).abs() <= 4.0 * ea.hypot(eb),
        "mean laminar length {ma} ± {ea} (direct) vs {mb} ± {eb} (interpolant)"
    );

    let (bins, batches) = (25, 20);
    let (hd, hi) = (
        log_histogram(&sd, bins, batches),
        log_histogram(&si, bins, batches),
    );
    let floor = batches as f64 / sd.len() as f64;
    for (k, ((md, ed), (mi, ei))) in hd.iter().zip(&hi).enumerate() {
        let allowed = (4.0 * ed.hypot(*ei)).max(floor);
        assert!(
            (md - mi).abs() <= allowed,
            "bin {k}: {md} ± {ed} (direct) vs {mi} ± {ei} (interpolant)"
        );
    }
}

/// The statistics file's first line says whether the slip sizes were
/// integrated or taken from the interpolant's tables.
#[test]
fn orbit_stats_say_where_the_slip_sizes_came_from() {
    let dir = tempfile::tempdir().unwrap();
    for (map, says) in [
        ("interpolant", "slip sizes from the interpolant's tables"),
        ("direct", "slip sizes integrated"),
    ] {
        let st = dir.path().join(format!("{map}.csv"));
        let o = Command::new(env!("CARGO_BIN_EXE_oneblock"))
            .args([
                "orbit",
                "--kappa",
                "50",
                "--gamma",
                "6.5",
                "--nu",
                "1e-4",
                "--theta-nu",
                "1.4",
                "--transient",
                "300",
                "--keep",
                "600",
                "--no-lyapunov",
                "--map",
                map,
                "--stats",
            ])
            .arg(&st)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let text = std::fs::read_to_string(&st).unwrap();
        // After the creep/stick-slip counts, the laminar phases' line.
        // (past the program, command, model and flags lines)
        let first = text.lines().nth(5).unwrap();
        assert!(first.starts_with("# laminar phase"), "{first}");
        assert!(first.contains(says), "{first}");
    }
}
