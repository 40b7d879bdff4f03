//! The map as a verified interpolant (`sim::MapInterpolant`): its error
//! against the direct map at points it was not built on, the location of a
//! jump of f, short orbits against integrated ones, and the statistics of
//! long orbits (Lyapunov exponent, invariant density) against integrated
//! orbits within their statistical errors.

#![allow(clippy::unwrap_used)]

use std::process::Command;

use oneblock::model::{exit_arc, wrap_angle};
use oneblock::numerics::sample::default_attractors;
use oneblock::sim::{
    InterpolantError, InterpolantOptions, MapInterpolant, OrbitOptions, cycles_in_lanes,
    orbit_interpolated,
};
use oneblock::{Params, Simulator, SolverSettings};

fn params(kappa: f64, nu: f64, theta_nu: f64) -> Params {
    Params {
        kappa,
        gamma: 6.5,
        nu,
        theta_nu,
        omega: 50.0,
    }
}

/// Fig. 3b's chaotic point and the intermittent point of the issue.
const FIG3B: (f64, f64, f64) = (18.95, 1e-3, 1.25);
const INTERMITTENT: (f64, f64, f64) = (50.0, 1e-4, 1.4);

fn sim_at((kappa, nu, theta_nu): (f64, f64, f64)) -> Simulator {
    Simulator::new(params(kappa, nu, theta_nu), SolverSettings::default()).unwrap()
}

fn opts(sim: &Simulator) -> InterpolantOptions {
    InterpolantOptions::for_settings(sim.settings())
}

/// The direct map at each θ, in lanes.
fn direct(sim: &Simulator, thetas: &[f64]) -> Vec<f64> {
    let tasks: Vec<_> = thetas.iter().map(|&t| (sim, t, 0.0)).collect();
    cycles_in_lanes(&tasks)
        .into_iter()
        .map(|r| r.unwrap().theta_next)
        .collect()
}

/// On each committed sample's parameter set (the default solver setting),
/// the interpolant over the sample's range reproduces the direct map to
/// 1e-10 at the sample's points, which it was not built on; its own check
/// reports the same bound. At most 1 % of the points may fall in a jump's
/// bracket (there `map` answers `None` and the caller integrates).
#[test]
fn error_is_within_1e_10_at_the_committed_sample() {
    for a in default_attractors() {
        let sim = Simulator::new(a.params, SolverSettings::default()).unwrap();
        let pts = a.fixed.unwrap();
        let lo = pts.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = pts.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let pad = 0.05 * (hi - lo);
        let interp = MapInterpolant::build(&sim, lo - pad, hi + pad, opts(&sim))
            .unwrap_or_else(|e| panic!("{}: {e}", a.name));
        let v = interp.verification();
        assert!(
            v.points >= 4 && v.max_map_error <= 1e-10,
            "{}: {v:?}",
            a.name
        );
        let exact = direct(&sim, pts);
        let mut worst: f64 = 0.0;
        let mut unanswered = 0;
        for (&t, &f) in pts.iter().zip(&exact) {
            match interp.map(t) {
                Some(g) => worst = worst.max(wrap_angle(g - f).abs()),
                None => unanswered += 1,
            }
        }
        assert!(worst <= 1e-10, "{}: max error {worst:e}", a.name);
        assert!(unanswered * 100 <= pts.len(), "{}: {unanswered}", a.name);
    }
}

/// At the intermittent point f jumps by about 2e-4 rad near θ = 0.62484
/// (the slip distance switches branch there; the steep but continuous
/// drop of 0.39 rad between θ = 0.625 and 0.63 is resolved by splitting).
/// The interpolant brackets the jump to within 1e-8 in θ, and the direct
/// map 1e-9 either side of the bracket confirms it: f changes by more than
/// 1e-5 rad across it, where its slope (≈ 7) would move it by 1e-7.
#[test]
fn a_jump_is_located_to_1e_8() {
    let sim = sim_at(INTERMITTENT);
    let interp = MapInterpolant::build(&sim, 0.6, 0.65, opts(&sim)).unwrap();
    let mut jumps = Vec::new();
    for (l, r) in interp.direct_stretches() {
        let f = direct(&sim, &[l - 1e-9, r + 1e-9]);
        let size = wrap_angle(f[0] - f[1]).abs();
        if r - l <= 1e-8 && size > 1e-5 {
            jumps.push((l, r, size));
        }
    }
    let &(l, r, size) = jumps.first().expect("a jump of f is bracketed to 1e-8");
    assert!(l > 0.6248 && r < 0.6249, "[{l}, {r}]: {size}");
    // Either side of the bracket the series answers, to 1e-10.
    let f = direct(&sim, &[l - 1e-7, r + 1e-7]);
    for (t, f) in [(l - 1e-7, f[0]), (r + 1e-7, f[1])] {
        if let Some(g) = interp.map(t) {
            assert!(wrap_angle(g - f).abs() <= 1e-10, "θ = {t}: {g} vs {f}");
        }
    }
    assert!(interp.map(l - 1e-7).is_some(), "no series left of the jump");
}

/// The first 10 iterates of a chaotic orbit (Fig. 3b) agree with direct
/// integration within 1e-8 (the per-iterate error, ~1e-12, grows by about
/// e^0.5 per iterate).
#[test]
fn first_ten_iterates_agree_with_direct_integration() {
    let sim = sim_at(FIG3B);
    let interp = MapInterpolant::build(&sim, 0.27, 0.52, opts(&sim)).unwrap();
    let (mut a, mut b) = (0.42, 0.42);
    for i in 0..10 {
        a = interp.map(a).unwrap();
        b = sim.map(b).unwrap();
        assert!(wrap_angle(a - b).abs() <= 1e-8, "iterate {i}: {a} vs {b}");
    }
}

/// Mean and standard error of the means of `batches` equal batches (the
/// iterates of a chaotic orbit are correlated; batch means of a few
/// thousand iterates are not, or much less).
fn batch_mean(xs: &[f64], batches: usize) -> (f64, f64) {
    let m = xs.len() / batches;
    let means: Vec<f64> = (0..batches)
        .map(|b| xs[b * m..(b + 1) * m].iter().sum::<f64>() / m as f64)
        .collect();
    let mean = means.iter().sum::<f64>() / batches as f64;
    let var = means.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (batches - 1) as f64;
    (mean, (var / batches as f64).sqrt())
}

/// The Lyapunov exponent and a 50-bin invariant density from 10⁶
/// interpolated iterates agree with those of 10⁵ integrated iterates within
/// 4 combined standard errors (batch means over 20 batches, which take the
/// correlation of the iterates into account), at Fig. 3b's chaotic point
/// and at the intermittent point.
#[test]
fn long_orbit_statistics_agree_with_direct_integration() {
    for point in [FIG3B, INTERMITTENT] {
        let sim = sim_at(point);
        let theta0 = point.2;
        let run = |keep| OrbitOptions {
            transient: 1000,
            keep,
            lyapunov: true,
            period_tol: 1e-9,
        };
        let io = orbit_interpolated(&sim, theta0, &run(1_000_000), opts(&sim), &|| false).unwrap();
        assert!(io.direct_iterates < 2000, "{:?}", io.direct_iterates);
        let it: Vec<f64> = io.orbit.events.iter().map(|e| e.theta).collect();
        // ln|f'| of each kept interpolated iterate, from the series (the
        // few integrated ones from their central difference).
        let il: Vec<f64> = it
            .iter()
            .map(|&t| match io.interpolant.event(t) {
                Some(e) => e.derivative.abs().ln(),
                None => {
                    let d = (sim.map(t + 1e-5).unwrap() - sim.map(t - 1e-5).unwrap()) / 2e-5;
                    d.abs().ln()
                }
            })
            .collect();
        // The integrated orbit in 20 batches of 5000 (each batch's exponent
        // is its own mean of ln|f'|).
        let mut theta = sim.orbit(theta0, &run(1), &|| false).unwrap().theta_last;
        let (mut dt, mut dl) = (Vec::new(), Vec::new());
        for _ in 0..20 {
            let mut o = run(5000);
            o.transient = 0;
            let orbit = sim.orbit(theta, &o, &|| false).unwrap();
            dt.extend(orbit.thetas());
            dl.push(orbit.lyapunov.unwrap());
            theta = orbit.theta_last;
        }
        let (li, ei) = batch_mean(&il, 20);
        let (ld, ed) = batch_mean(&dl, 20);
        let bound = 4.0 * ei.hypot(ed);
        assert!(
            (li - ld).abs() <= bound,
            "{point:?}: λ {li} ± {ei} vs {ld} ± {ed}"
        );
        assert!(ed < 0.05, "{point:?}: the direct exponent's error {ed}");

        let lo = dt.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = dt.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let bin = |t: f64| (((t - lo) / (hi - lo) * 50.0) as usize).min(49);
        let density = |xs: &[f64], batches: usize| -> Vec<(f64, f64)> {
            (0..50)
                .map(|k| {
                    let hits: Vec<f64> = xs.iter().map(|&t| f64::from(bin(t) == k)).collect();
                    batch_mean(&hits, batches)
                })
                .collect()
        };
        let (di, dd) = (density(&it, 20), density(&dt, 20));
        for k in 0..50 {
            let ((pi, si), (pd, sd)) = (di[k], dd[k]);
            // A bin the integrated orbit barely visits has a batch error of
            // 0: allow one visit in 5000 (the batch length) then.
            let bound = 4.0 * si.hypot(sd).max(2e-4);
            assert!(
                (pi - pd).abs() <= bound,
                "{point:?}: bin {k}: {pi} ± {si} vs {pd} ± {sd}"
            );
        }
    }
}

/// An interval off the exit arc is refused, saying where the arc is; a
/// piece budget too small for a jump is refused with the reason.
#[test]
fn refusals_say_why() {
    let sim = sim_at(FIG3B);
    let p = sim.params();
    let (psi, half) = exit_arc(p.kappa, p.theta_nu);
    let e =
        MapInterpolant::build(&sim, psi + half + 0.1, psi + half + 0.2, opts(&sim)).unwrap_err();
    assert!(matches!(e, InterpolantError::OffArc { .. }), "{e}");
    assert!(e.to_string().contains("not on the exit arc"), "{e}");
    let e = MapInterpolant::build(&sim, 0.5, 0.4, opts(&sim)).unwrap_err();
    assert!(matches!(e, InterpolantError::OffArc { .. }), "{e}");

    let sim = sim_at(INTERMITTENT);
    let tight = InterpolantOptions {
        max_pieces: 2,
        ..opts(&sim)
    };
    let e = MapInterpolant::build(&sim, 0.6, 0.65, tight).unwrap_err();
    assert!(matches!(e, InterpolantError::Unresolved { .. }), "{e}");
    assert!(e.to_string().contains("within 2 pieces"), "{e}");
}

fn oneblock(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args(args)
        .output()
        .unwrap()
}

/// `orbit --map`: the summary names the map used, with the interpolant's
/// measured error; a bad value is one line naming the flag, exit 2.
#[test]
fn orbit_says_which_map_it_used() {
    let base = [
        "orbit",
        "--kappa",
        "18.95",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--theta-nu",
        "1.25",
        "--transient",
        "400",
        "--keep",
        "50",
        "--json",
    ];
    let json = |extra: &str| {
        let mut a = base.to_vec();
        a.extend(["--map", extra]);
        let o = oneblock(&a);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        v
    };
    let i = json("interpolant");
    assert_eq!(i["map"]["method"], "interpolant");
    assert!(i["map"]["max_map_error"].as_f64().unwrap() <= 1e-10);
    let d = json("direct");
    assert_eq!(d["map"]["method"], "direct");
    // A short run chooses the direct map by itself.
    assert_eq!(json("auto")["map"]["method"], "direct");
    assert_eq!(i["keep"], 50);
    assert!(i["map"]["direct_iterates"].as_u64().unwrap() >= 300);

    let mut bad = base.to_vec();
    bad.extend(["--map", "spline"]);
    let o = oneblock(&bad);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("--map"), "{err}");
}

/// Where the map cannot be resolved within the piece budget (κ = 3,
/// θν = 1.1257: rough near θ = 1.064), `orbit --map interpolant` says so
/// and integrates every iterate: the same orbit as `--map direct`, never a
/// worse one.
#[test]
fn orbit_says_so_and_integrates_when_the_interpolant_is_refused() {
    let run = |map: &str| {
        let o = oneblock(&[
            "orbit",
            "--kappa",
            "3",
            "--gamma",
            "6.5",
            "--nu",
            "1e-3",
            "--theta-nu",
            "1.1257373675363425",
            "--transient",
            "300",
            "--keep",
            "100",
            "--json",
            "--map",
            map,
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    let tried = run("interpolant");
    assert_eq!(tried["map"]["method"], "direct");
    let why = tried["map"]["interpolant_refused"].as_str().unwrap();
    assert!(why.contains("could not be resolved"), "{why}");
    let direct = run("direct");
    for key in ["period", "lyapunov", "lyapunov_stderr", "keep"] {
        assert_eq!(tried[key], direct[key], "{key}");
    }
}
