//! A flip's criticality is confirmed on its born cycle (issue 38, item 5):
//! at κ = 1.5, γ = 6.5, ν = 1e-3 the fixed point's first flip
//! (θν ≈ 0.395657) was labelled supercritical, because the coefficient's
//! ±0.01 stencil crosses a jump of f; on its stable side lies an unstable
//! P2 (`oneblock cycle … --period 2 --theta 0.30092` at θν = 0.39564736
//! gives m = 1.00337), so it is subcritical. Checked through `oneblock
//! continue` and, independently, `oneblock cycle`.

#![allow(clippy::unwrap_used)]

use crate::cli_support;

use cli_support::*;

/// The PD lines of `continue` on the P1 branch at κ over θν ∈ [from, to].
fn pd_lines(kappa: &str, from: &str, to: &str) -> Vec<String> {
    pd_lines_of(kappa, from, to, "1")
}

/// The PD lines of `continue` on the branch of the attractor's `period`
/// cycle at κ over θν ∈ [from, to].
fn pd_lines_of(kappa: &str, from: &str, to: &str, period: &str) -> Vec<String> {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b.csv");
    let o = oneblock(&[
        "continue",
        "--kappa",
        kappa,
        "--gamma",
        "6.5",
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
        period,
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_ok(&o);
    stderr(&o)
        .lines()
        .chain(stdout(&o).lines())
        .filter(|l| l.trim_start().starts_with("PD "))
        .map(str::to_string)
        .collect()
}

/// The number after `key = ` in a line.
fn number(line: &str, key: &str) -> f64 {
    let at = line.find(&format!("{key} = ")).unwrap() + key.len() + 3;
    line[at..]
        .split_whitespace()
        .next()
        .unwrap()
        .trim_end_matches([',', ';'])
        .parse()
        .unwrap()
}

#[test]
fn kappa_1_5s_first_flip_is_subcritical_with_its_unstable_p2_below() {
    let lines = pd_lines("1.5", "0.3", "0.45");
    assert_eq!(lines.len(), 1, "{lines:?}");
    let pd = &lines[0];
    assert!(
        pd.contains("subcritical: an unstable P2 cycle below"),
        "{pd}"
    );
    let (star, theta) = (number(pd, "theta-nu"), number(pd, "theta"));
    let amplitude: f64 = pd
        .split("half-width ")
        .nth(1)
        .unwrap()
        .split('*')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    // Independently: the P2 a distance below the flip, by `cycle`.
    let delta = 1e-5;
    let at = format!("{}", star - delta);
    let seed = format!("{}", theta + amplitude * delta.sqrt());
    let o = oneblock(&[
        "cycle",
        "--kappa",
        "1.5",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--theta-nu",
        &at,
        "--period",
        "2",
        "--theta",
        &seed,
        "--json",
    ]);
    assert_ok(&o);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let m = v["multiplier"].as_f64().unwrap();
    assert!(
        m > 1.0,
        "the P2 next to a subcritical flip is unstable: {v}"
    );
    let pts: Vec<f64> = v["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert_eq!(pts.len(), 2, "{v}");
    let half = 0.5 * (pts[0] - pts[1]).abs();
    let predicted = amplitude * delta.sqrt();
    assert!(
        (half - predicted).abs() < 0.3 * predicted,
        "{half} against {predicted}"
    );
}

#[test]
fn every_labelled_flip_is_confirmed_by_its_born_cycle() {
    let mut labelled = 0;
    for kappa in ["1.5", "2", "2.5", "3", "10", "14", "18.95", "50"] {
        for pd in pd_lines(kappa, "0.1", "1.55") {
            if pd.contains("supercritical") || pd.contains("subcritical") {
                assert!(
                    pd.contains("; confirmed: the P2 cycle")
                        || pd.contains("; set by the P2 cycle"),
                    "kappa {kappa}: {pd}"
                );
                labelled += 1;
            } else {
                assert!(pd.contains("undecided criticality"), "{pd}");
                assert!(pd.contains("no P2 cycle found"), "{pd}");
            }
        }
    }
    assert!(labelled >= 12, "{labelled}");
}

/// At κ = 3 the coefficient's ±0.01/p stencil reached across the steep
/// part of f (f' from 5 to 170 within 0.003 at the P2's θ = 0.97885):
/// three of the fixed point's flips and the P2's flip at θν = 1.12484 came
/// out undecided (c = 8.6e8 ± 8.6e8 there). With the stencil inside f^p's
/// smooth piece, each is labelled and confirmed by its born cycle.
#[test]
fn kappa_3s_flips_are_labelled_and_confirmed() {
    let labelled = |pd: &str| {
        !pd.contains("undecided")
            && (pd.contains("; confirmed: the P") || pd.contains("; set by the P"))
    };
    let p1 = pd_lines("3", "0.1", "1.55");
    assert_eq!(p1.len(), 4, "{p1:?}");
    for pd in &p1 {
        assert!(labelled(pd), "{pd}");
    }
    let p2 = pd_lines_of("3", "1.0", "1.13", "2");
    let flip = p2
        .iter()
        .find(|l| (number(l, "theta-nu") - 1.12484).abs() < 1e-4)
        .unwrap_or_else(|| panic!("{p2:?}"));
    assert!(labelled(flip), "{flip}");
    assert!(
        flip.contains("supercritical: a stable P4 cycle above"),
        "{flip}"
    );
}
