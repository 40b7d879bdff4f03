//! A flip located to what is printed (issue 52, item 5). At κ = 19,
//! γ = 10, ν = 1e-3 the fixed point's first flip came out of `continue`
//! at θν = 1.0610506274 and 1.0610504862 from two starts, printed to 16
//! digits with m = −1 ± 1e-9, while the true flip is 1.0610507378: the
//! multiplier at the solver's tolerance 1e-10 is off by 6e-7 there
//! (dm/dθν ≈ 2.4). PDs are now located again on the multiplier at a
//! tighter tolerance: two starts agree within 1e-8 of each other and of a
//! bisection of `solve_cycle`'s multiplier at tol 1e-14, and the value is
//! printed to 10 significant digits. With the born cycles solved at that
//! tolerance too, the two flips the issue found "undecided" (κ = 2.5 near
//! θν 1.041, κ = 14 near 1.5226) are decided, each checked on its P2
//! solved by `cycle` on its own.
#![allow(clippy::unwrap_used)]

use crate::branch_birth::fixed_point_flip;
use crate::cli_support;

use cli_support::*;
use oneblock::model::Params;
use oneblock::sim::continuation::ContParam;

/// The first PD's printed θν from `continue` over [from, to] at κ = 19,
/// γ = 10, ν = 1e-3, and the text of its value cell.
fn first_pd(from: &str, to: &str) -> (f64, String) {
    let (o, _, rows) = continue_run(&[
        "--kappa",
        "19",
        "--gamma",
        "10",
        "--nu",
        "1e-3",
        "--theta-nu",
        from,
        "--param",
        "theta-nu",
        "--from",
        from,
        "--to",
        to,
        "--period",
        "1",
    ]);
    let pd = rows
        .iter()
        .find(|r| r[0] == "PD")
        .unwrap_or_else(|| panic!("{}", stderr(&o)));
    (num(&pd[3]), pd[3].clone())
}

#[test]
fn the_first_flip_at_kappa_19_gamma_10_agrees_from_two_starts_and_with_cycle() {
    let base = Params {
        kappa: 19.0,
        gamma: 10.0,
        nu: 1e-3,
        theta_nu: 1.06,
        ..Params::default()
    };
    let b = fixed_point_flip(base, ContParam::ThetaNu, [1.06, 1.062], 0.29);
    assert!((b - 1.0610507378).abs() < 2e-9, "{b}");
    let (a, a_text) = first_pd("1.0", "1.1");
    let (c, c_text) = first_pd("1.05", "1.08");
    assert!((a - c).abs() < 1e-8, "{a} vs {c}");
    for v in [a, c] {
        assert!((v - b).abs() < 1e-8, "{v} vs the bisection's {b}");
    }
    // Printed to 10 significant digits, not 16.
    for t in [a_text, c_text] {
        let digits = t.chars().filter(|ch| ch.is_ascii_digit()).count();
        assert!(digits <= 10, "{t}");
    }
}

/// The P2 through `seed` at θν by `oneblock cycle` at tol 1e-14 (as the
/// located flip): (minimal period, multiplier, half-width about θ*).
fn p2(kappa: &str, theta_nu: f64, seed: f64, centre: f64) -> (u64, f64, f64) {
    let (tn, th) = (format!("{theta_nu}"), format!("{seed}"));
    let args = [
        "cycle",
        "--preset",
        "fig4",
        "--kappa",
        kappa,
        "--theta-nu",
        &tn,
        "--period",
        "2",
        "--theta",
        &th,
        "--tol",
        "1e-14",
        "--json",
    ];
    let o = oneblock(&args);
    assert_ok(&o);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let pts: Vec<f64> = v["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let half = pts.iter().map(|p| (p - centre).abs()).fold(0.0, f64::max);
    (
        v["minimal_period"].as_u64().unwrap(),
        v["multiplier"].as_f64().unwrap(),
        half,
    )
}

/// The two flips issue 52 found "undecided" (κ = 2.5 near θν 1.041, κ = 14
/// near 1.5226, Fig. 4's γ and ν) are labelled supercritical with a
/// stable P2 below, and that P2, solved by `cycle` on its own 1e-8 below,
/// is stable with the predicted half-width (within 30 %).
#[test]
fn the_flips_once_undecided_are_supercritical_with_their_p2_below() {
    for (kappa, near) in [("2.5", 1.041), ("14", 1.5226)] {
        let dir = tempfile::tempdir().unwrap();
        let (out, pts) = (dir.path().join("b.csv"), dir.path().join("p.csv"));
        let args = [
            "continue",
            "--preset",
            "fig4",
            "--kappa",
            kappa,
            "--param",
            "theta-nu",
            "--from",
            "0.1",
            "--to",
            "1.55",
            "--period",
            "1",
            "--theta",
            "0.1",
            "--out",
            out.to_str().unwrap(),
            "--points",
            pts.to_str().unwrap(),
            "--json",
        ];
        let o = oneblock(&args);
        assert_ok(&o);
        let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
        let pd = v["branches"][0]["special"]
            .as_array()
            .unwrap()
            .iter()
            .find(|s| s["kind"] == "PD" && (s["value"].as_f64().unwrap() - near).abs() < 1e-3)
            .unwrap_or_else(|| panic!("no PD near {near} at kappa {kappa}: {v}"));
        assert_eq!(pd["criticality"], "supercritical", "{pd}");
        let nf = &pd["normal_form"];
        assert_eq!(nf["side"].as_f64().unwrap(), -1.0, "{pd}");
        let (b, theta) = (pd["value"].as_f64().unwrap(), pd["theta"].as_f64().unwrap());
        let amp = nf["amplitude"].as_f64().unwrap();
        let predicted = amp * 1e-8f64.sqrt();
        let (period, m, half) = p2(kappa, b - 1e-8, theta + predicted, theta);
        assert_eq!(period, 2, "kappa {kappa}");
        assert!(m.abs() < 1.0, "kappa {kappa}: m = {m}");
        assert!(
            (half / predicted - 1.0).abs() < 0.3,
            "kappa {kappa}: {half} vs {predicted}"
        );
    }
}
