//! A cascade switches only onto the cycle born at the doubling (issue 38):
//! at κ = 3, γ = 6.5, ν = 1e-3 the P2's doubling at θν ≈ 1.12484 gives
//! birth to a P4 that loses stability 4e-5 further on; the cascade used
//! to follow another P4 (doubling at 1.2393, δ = 6.5). Checked through
//! `oneblock continue --cascade` against the born P4 followed
//! independently with `oneblock cycle` and bisected on m = −1.

#![allow(clippy::unwrap_used)]

use crate::cli_support;

use cli_support::*;

const MODEL: [&str; 6] = ["--kappa", "3", "--gamma", "6.5", "--nu", "1e-3"];

/// The P4 through the seed at θν: (multiplier, points), or `None` where
/// Newton finds none of minimal period 4.
fn p4(theta_nu: f64, seed: f64) -> Option<(f64, Vec<f64>)> {
    let (tn, th) = (format!("{theta_nu}"), format!("{seed}"));
    let mut args = vec!["cycle"];
    args.extend(MODEL);
    args.extend(["--theta-nu", &tn, "--period", "4", "--theta", &th, "--json"]);
    let o = oneblock(&args);
    if !o.status.success() {
        return None;
    }
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    if v["minimal_period"].as_u64() != Some(4) {
        return None;
    }
    let pts = v["points"].as_array().unwrap();
    let pts: Vec<f64> = pts.iter().map(|x| x.as_f64().unwrap()).collect();
    Some((v["multiplier"].as_f64().unwrap(), pts))
}

/// The point of `pts` nearest θ.
fn nearest(pts: &[f64], theta: f64) -> f64 {
    let d = |x: &f64| (x - theta).abs();
    *pts.iter().min_by(|a, b| d(a).total_cmp(&d(b))).unwrap()
}

#[test]
fn kappa_3s_p4_doubles_where_the_p4_born_at_1_12484_loses_stability() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b.csv");
    let mut args = vec!["continue"];
    args.extend(MODEL);
    args.extend([
        "--param",
        "theta-nu",
        "--from",
        "1.0",
        "--to",
        "1.3",
        "--period",
        "2",
        "--cascade",
        "--json",
        "--out",
    ]);
    args.push(out.to_str().unwrap());
    let o = oneblock(&args);
    assert_ok(&o);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let doublings = v["cascade"]["doublings"].as_array().unwrap();
    assert!(doublings.len() >= 2, "{}", v["cascade"]);
    let (b1, b2) = (&doublings[0], &doublings[1]);
    assert_eq!(b1["period"], 2, "{b1}");
    assert_eq!(b2["period"], 4, "{b2}");
    let star = b1["value"].as_f64().unwrap();
    assert!((star - 1.12484).abs() < 1e-5, "{b1}");
    let b2 = b2["value"].as_f64().unwrap();

    // Independently: the P4 born there, stable just past the P2's
    // doubling, followed in θν by Newton from its last points and bisected
    // on m = −1.
    let theta_star = b1["theta"].as_f64().unwrap();
    let mut lo = star + 1e-5;
    let (m, pts) = p4(lo, theta_star - 1e-4).unwrap();
    assert!(m.abs() < 1.0, "born stable: m = {m}");
    let mut seed = nearest(&pts, theta_star);
    assert!((seed - theta_star).abs() < 1e-3, "{pts:?}");
    // Out in steps of 1e-5 until it is unstable.
    let mut hi = lo;
    loop {
        hi += 1e-5;
        assert!(hi < star + 1e-3, "the born P4 stayed stable");
        let (m, pts) = p4(hi, seed).unwrap();
        if m < -1.0 {
            break;
        }
        (lo, seed) = (hi, nearest(&pts, seed));
    }
    for _ in 0..30 {
        let mid = 0.5 * (lo + hi);
        let (m, pts) = p4(mid, seed).unwrap();
        if m < -1.0 {
            hi = mid;
        } else {
            (lo, seed) = (mid, nearest(&pts, seed));
        }
    }
    let loses = 0.5 * (lo + hi);
    assert!(
        (b2 - loses).abs() < 1e-8,
        "the cascade's P4 doubles at {b2}, the P4 born at {star} loses stability at {loses}"
    );
    // Not the other P4, which doubles near 1.2393.
    assert!(b2 - star < 1e-3, "{b2}");
}
