//! Intermittency statistics: laminar lengths on synthetic sequences whose
//! lengths are known, the log-log fit against a known power law, and
//! `oneblock orbit --stats` on the paper's intermittent orbit checked
//! against its own events CSV.

mod cli_support;

use cli_support::*;
use oneblock::sim::intermittency::{
    Intermittency, LARGE_FRACTION, Regime, laminar_lengths, length_counts, log_histogram,
    log_log_fit, supports_type_one,
};

/// A sequence of creep slips (sizes around 3e-3) broken by large slips
/// (around 0.7) after the given laminar lengths, with a creep run before
/// the first and after the last large slip that must not be counted.
fn synthetic(lengths: &[usize]) -> Vec<f64> {
    let mut s: Vec<f64> = (0..7).map(|i| 2.5e-3 + 1e-5 * i as f64).collect();
    s.push(0.8);
    for (k, &l) in lengths.iter().enumerate() {
        s.extend((0..l).map(|i| 3e-3 * (1.0 + 0.01 * i as f64)));
        s.push(0.6 + 0.01 * k as f64);
    }
    s.extend([3e-3, 4e-3, 5e-3]);
    s
}

#[test]
fn laminar_lengths_of_a_synthetic_sequence_are_the_known_ones() {
    let lengths = [12, 0, 5, 40, 5, 3, 12, 12];
    let s = synthetic(&lengths);
    let st = Intermittency::of(&s, None).expect("stats");
    assert_eq!(st.laminar, lengths);
    assert_eq!(st.large, lengths.len() + 1);
    assert_eq!(st.creep, s.len() - st.large);
    assert!((st.threshold - LARGE_FRACTION * 0.8).abs() < 1e-15);
    let mean = lengths.iter().sum::<usize>() as f64 / lengths.len() as f64;
    assert!((st.mean_laminar.expect("mean") - mean).abs() < 1e-12);
    assert_eq!(
        length_counts(&st.laminar),
        vec![(0, 1), (3, 1), (5, 2), (12, 3), (40, 1)]
    );
    // The size histogram holds every slip once.
    assert_eq!(st.sizes.iter().map(|b| b.count).sum::<usize>(), s.len());
    // A threshold above every creep slip and below every large one gives
    // the same lengths, whatever its value.
    for t in [0.01, 0.1, 0.5] {
        assert_eq!(laminar_lengths(&s, t), lengths, "threshold {t}");
    }
}

#[test]
fn a_sequence_without_large_slips_has_no_laminar_phase() {
    let s = vec![3e-3; 50];
    let st = Intermittency::of(&s, None).expect("stats");
    // Every slip is "large" relative to itself: phases of length 0, which
    // is what a creep fixed point is (no re-injection to count).
    assert!(st.laminar.iter().all(|&l| l == 0));
    assert!(Intermittency::of(&[0.0, 0.0], None).is_none());
}

#[test]
fn only_varying_long_laminar_phases_are_called_intermittent() {
    let regime = |s: &[f64]| Intermittency::of(s, None).expect("stats").regime();
    // Varied lengths, mean 11: intermittent.
    assert_eq!(
        regime(&synthetic(&[12, 0, 5, 40, 5, 3, 12, 12])),
        Regime::Intermittent
    );
    // A stick-slip orbit: every slip large (the sizes of a chaotic one
    // vary by a factor below 4), so no creep at all.
    let chaotic: Vec<f64> = (0..300)
        .map(|i| 0.3 + 0.5 * ((i * 37) % 100) as f64 / 100.0)
        .collect();
    assert_eq!(regime(&chaotic), Regime::NoCreep);
    // A periodic orbit with 4 creep slips per large one, and one whose
    // laminar lengths alternate 2, 7: periodic, whatever the lengths.
    assert_eq!(
        regime(&synthetic(&[4; 20])),
        Regime::Periodic { every: 1, first: 4 }
    );
    let alt: Vec<usize> = (0..20).map(|i| if i % 2 == 0 { 2 } else { 7 }).collect();
    assert_eq!(
        regime(&synthetic(&alt)),
        Regime::Periodic { every: 2, first: 2 }
    );
    // Large slips with one creep slip between them: an alternation.
    assert_eq!(
        regime(&synthetic(&[1, 1, 0, 1, 2, 1, 1, 0])),
        Regime::Alternating
    );
    // Two complete phases only.
    assert_eq!(regime(&synthetic(&[30, 9])), Regime::TooFewPhases);
    // One large slip in a long creep: nothing to measure.
    let mut creep = vec![3e-3; 40];
    creep[20] = 0.7;
    assert_eq!(regime(&creep), Regime::NoLargeSlips);
    // The summary line says it.
    assert!(
        Intermittency::of(&chaotic, None)
            .expect("stats")
            .csv("slip_distance")
            .contains("# not intermittent: every slip is large")
    );
}

#[test]
fn sizes_equal_to_one_percent_fill_one_bin() {
    // A periodic orbit's slips still converging in their sixth digit.
    let xs: Vec<f64> = (0..100).map(|i| 0.1 * (1.0 + 1e-6 * i as f64)).collect();
    let b = log_histogram(&xs, 30);
    assert_eq!(b.len(), 1);
    assert_eq!(b[0].count, 100);
    assert!(b[0].lo < 0.1 && b[0].hi > 0.1 * (1.0 + 1e-4));
    // Two sizes 2 % apart are told apart.
    let two: Vec<f64> = (0..100)
        .map(|i| if i % 2 == 0 { 0.1 } else { 0.102 })
        .collect();
    let b = log_histogram(&two, 30);
    assert_eq!(b.iter().filter(|b| b.count > 0).count(), 2);
}

#[test]
fn the_log_log_fit_recovers_a_known_exponent() {
    let pts: Vec<(f64, f64)> = [1e-4, 3e-4, 1e-3, 3e-3, 1e-2]
        .iter()
        .map(|&e: &f64| (e, 2.0 * e.powf(-0.5)))
        .collect();
    let (slope, intercept) = log_log_fit(&pts).expect("fit");
    assert!((slope + 0.5).abs() < 1e-12, "{slope}");
    assert!((intercept - 2f64.log10()).abs() < 1e-12);
    assert!(supports_type_one(slope));
    let steep: Vec<(f64, f64)> = pts.iter().map(|&(e, _)| (e, e.powf(-1.0))).collect();
    let (s2, _) = log_log_fit(&steep).expect("fit");
    assert!(!supports_type_one(s2));
    assert!(log_log_fit(&pts[..2]).is_none());
}

#[test]
fn orbit_stats_agree_with_the_orbits_own_events() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (ev, st) = (dir.path().join("ev.csv"), dir.path().join("st.csv"));
    let (ev_s, st_s) = (ev.display().to_string(), st.display().to_string());
    let o = oneblock(&[
        "orbit",
        "--kappa",
        "50",
        "--gamma",
        "6.5",
        "--nu",
        "1e-4",
        "--theta-nu",
        "1.4",
        "--tol",
        "1e-8",
        "--transient",
        "200",
        "--keep",
        "1500",
        "--no-lyapunov",
        "--out",
        &ev_s,
        "--stats",
        &st_s,
    ]);
    assert_ok(&o);
    let (head, rows) = parse_csv(&std::fs::read_to_string(&ev).expect("events"));
    let col = head
        .iter()
        .position(|h| h == "slip_distance")
        .expect("slip_distance column");
    let sizes: Vec<f64> = rows.iter().map(|r| num(&r[col])).collect();
    // The intermittent orbit's sizes are bimodal: creep slips of a few
    // thousandths (growing to below a tenth before a re-injection), large
    // slips of more than half a unit.
    let max = sizes.iter().copied().fold(0.0, f64::max);
    assert!(max > 0.5, "{max}");
    let large: Vec<usize> = (0..sizes.len())
        .filter(|&i| sizes[i] >= 0.25 * max)
        .collect();
    assert!(large.len() > 20, "{} large slips", large.len());
    // No slip lies near the threshold (0.25 of the largest), so which
    // slips are large does not hang on rounding: the orbit is a
    // pseudo-orbit, and an odd slip between the modes may occur.
    assert!(
        sizes.iter().all(|&s| (s / max - 0.25).abs() > 0.05),
        "a slip size lies within 0.05·max of the threshold"
    );
    let expected: Vec<usize> = large.windows(2).map(|w| w[1] - w[0] - 1).collect();
    let text = std::fs::read_to_string(&st).expect("stats");
    let mut lines = text.lines();
    // The mixed regime: slips of both kinds by where they start.
    let onsets = lines.next().expect("the onset line");
    assert!(
        onsets.contains(" creep, ") && onsets.contains(" stick-slip: by where"),
        "{onsets}"
    );
    assert!(lines.next().is_some_and(|l| l.starts_with("# large slip")));
    assert_eq!(lines.next(), Some("# intermittent"));
    assert_eq!(lines.next(), Some("statistic,lo,hi,count"));
    let mut from_file = Vec::new();
    let mut binned = 0;
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        match f[0] {
            "laminar_length" => {
                let n: usize = f[1].parse().expect("length");
                let c: usize = f[3].parse().expect("count");
                from_file.extend(std::iter::repeat_n(n, c));
            }
            "slip_size" => binned += f[3].parse::<usize>().expect("count"),
            other => panic!("unexpected statistic {other}"),
        }
    }
    let mut sorted = expected.clone();
    sorted.sort_unstable();
    assert_eq!(from_file, sorted);
    assert_eq!(binned, sizes.len());
    // Creep phases of the intermittent orbit last tens of iterates.
    let mean = expected.iter().sum::<usize>() as f64 / expected.len() as f64;
    assert!((10.0..60.0).contains(&mean), "mean laminar length {mean}");
}

#[test]
fn orbit_stats_refuses_stdout_and_the_out_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let f = dir.path().join("x.csv").display().to_string();
    let base = cmd_args("orbit", &["--keep", "10"]);
    let mut a = base.clone();
    a.extend(["--stats".into(), "-".into()]);
    assert_bad_input(&a, "--stats");
    let mut b = base;
    b.extend(["--out".into(), f.clone(), "--stats".into(), f]);
    assert_bad_input(&b, "--stats");
}

#[test]
fn the_intermittent_window_has_a_lower_end_and_its_laminar_phases_shorten_there() {
    use oneblock::sim::intermittency::{CRITICAL_RESOLUTION, scaling};
    use oneblock::{Method, SolverSettings};
    let p = oneblock::model::preset("intermittent")
        .expect("preset")
        .params;
    let sc = scaling(p, SolverSettings::adaptive(Method::Dop853, 1e-8), &|| false)
        .expect("scan")
        .expect("θν = 1.4 is intermittent, with a lower end within 0.4");
    // Measured with `oneblock orbit --stats` at tol 1e-8: mean laminar
    // length 0.69 at θν = 1.245, 1.76 at 1.247, 4.85 at 1.25 (≥ 2 is
    // intermittent here).
    assert!(
        (1.245 - CRITICAL_RESOLUTION..1.25 + CRITICAL_RESOLUTION).contains(&sc.theta_nu_c),
        "{}",
        sc.theta_nu_c
    );
    assert!(sc.points.len() >= 5, "{:?}", sc.points);
    // Here the phases get shorter towards θν_c, not longer as in type-I
    // intermittency: the fitted slope is positive and −1/2 is not claimed.
    let (slope, _) = sc.fit.expect("fit");
    assert!(slope > 0.0, "{slope} from {:?}", sc.points);
    assert!(!sc.supports_type_one());
}

/// `orbit --stats`'s first line for `preset`: (creep, stick-slip) by
/// where each slip starts.
fn onset_counts(preset: &str) -> (usize, usize) {
    let dir = tempfile::tempdir().expect("temp dir");
    let st = dir.path().join("st.csv");
    let st_s = st.display().to_string();
    let o = oneblock(&[
        "orbit",
        "--preset",
        preset,
        "--transient",
        "200",
        "--keep",
        "300",
        "--no-lyapunov",
        "--stats",
        &st_s,
    ]);
    assert_ok(&o);
    let text = std::fs::read_to_string(&st).expect("stats");
    let first = text.lines().next().expect("a first line");
    let words: Vec<&str> = first.trim_start_matches("# ").split_whitespace().collect();
    assert_eq!(words[1], "creep,", "{first}");
    assert_eq!(words[3], "stick-slip:", "{first}");
    let n = |w: &str| w.parse::<usize>().expect("a count");
    (n(words[0]), n(words[2]))
}

/// Issue 28: creep and stick-slip by the model's criterion (γ² < A(θ) at
/// the onset), not by size: the pure-creep preset and Fig. 3a's creep
/// fixed point have only creep, the chaos preset (pure stick-slip) none.
#[test]
fn creep_is_where_the_slip_starts() {
    assert_eq!(onset_counts("creep"), (300, 0));
    assert_eq!(onset_counts("fig3a"), (300, 0));
    assert_eq!(onset_counts("chaos"), (0, 300));
}
