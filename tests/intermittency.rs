//! Intermittency statistics: laminar phases as runs of creep slips (by
//! where each slip starts, never by its size) on synthetic sequences whose
//! lengths are known; the log-log fit against a known power law; `oneblock
//! orbit --stats` on the paper's intermittent orbit checked slip by slip
//! against the creep criterion computed from each onset's position; the
//! creep channel's passage time against the measured mean laminar length;
//! and the tangency located by continuation.

use crate::cli_support;

use cli_support::*;
use oneblock::sim::intermittency::{
    Intermittency, Regime, laminar_lengths, length_counts, log_histogram, log_log_fit,
    supports_type_one,
};

/// Creep flags: a creep run cut by the window's start, then stick-slip
/// slips (two in a row after each phase, which enclose no phase) after the
/// given laminar lengths, then a creep run cut by the window's end.
fn synthetic(lengths: &[usize]) -> Vec<bool> {
    let mut s = vec![true; 7];
    s.push(false);
    for &l in lengths {
        s.extend(std::iter::repeat_n(true, l));
        s.extend([false, false]);
    }
    s.extend([true; 3]);
    s
}

/// Slip sizes for `creep`: small for creep, large for stick-slip.
fn sizes(creep: &[bool]) -> Vec<f64> {
    creep
        .iter()
        .enumerate()
        .map(|(i, c)| {
            if *c {
                3e-3 * (1.0 + 0.01 * i as f64)
            } else {
                0.7
            }
        })
        .collect()
}

fn stats(creep: &[bool]) -> Intermittency {
    Intermittency::of(creep, &sizes(creep))
}

#[test]
fn laminar_lengths_of_a_synthetic_sequence_are_the_known_ones() {
    let lengths = [12, 5, 40, 5, 3, 12, 12, 1];
    let s = synthetic(&lengths);
    let st = stats(&s);
    assert_eq!(st.laminar, lengths);
    assert_eq!(st.onsets.stick_slip, 2 * lengths.len() + 1);
    assert_eq!(st.onsets.creep, s.len() - st.onsets.stick_slip);
    let mean = lengths.iter().sum::<usize>() as f64 / lengths.len() as f64;
    assert!((st.mean_laminar.expect("mean") - mean).abs() < 1e-12);
    assert_eq!(
        length_counts(&st.laminar),
        vec![(1, 1), (3, 1), (5, 2), (12, 3), (40, 1)]
    );
    // The size histogram holds every slip once.
    assert_eq!(st.sizes.iter().map(|b| b.count).sum::<usize>(), s.len());
    // Sizes play no part: the same flags with every size equal give the
    // same phases.
    assert_eq!(Intermittency::of(&s, &vec![0.5; s.len()]).laminar, lengths);
    assert_eq!(laminar_lengths(&s), lengths);
}

#[test]
fn only_varying_long_laminar_phases_are_called_intermittent() {
    let regime = |s: &[bool]| stats(s).regime();
    assert_eq!(
        regime(&synthetic(&[12, 1, 5, 40, 5, 3, 12, 12])),
        Regime::Intermittent
    );
    // Pure stick-slip: no creep at all; pure creep: no phase ends.
    assert_eq!(regime(&[false; 300]), Regime::NoCreep);
    assert_eq!(regime(&[true; 300]), Regime::NoStickSlip);
    let mut one = vec![true; 40];
    one[20] = false;
    assert_eq!(regime(&one), Regime::NoStickSlip);
    // Laminar lengths that repeat: periodic, whatever the lengths.
    assert_eq!(
        regime(&synthetic(&[4; 20])),
        Regime::Periodic { every: 1, first: 4 }
    );
    let alt: Vec<usize> = (0..20).map(|i| if i % 2 == 0 { 2 } else { 7 }).collect();
    assert_eq!(
        regime(&synthetic(&alt)),
        Regime::Periodic { every: 2, first: 2 }
    );
    // Stick-slip slips with one creep slip between them: an alternation.
    assert_eq!(
        regime(&synthetic(&[1, 1, 2, 1, 1, 1, 1, 1])),
        Regime::Alternating
    );
    assert_eq!(regime(&synthetic(&[30, 9])), Regime::TooFewPhases);
    // The summary line says it.
    assert!(
        stats(&[false; 30])
            .csv("slip_distance", "", &[])
            .contains("# not intermittent: every slip is stick-slip")
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

/// The intermittent preset's kept events and statistics at tol 1e-8.
fn intermittent_run(extra: &[&str]) -> (Vec<Vec<String>>, Vec<String>, String) {
    let dir = tempfile::tempdir().expect("temp dir");
    let (ev, st) = (dir.path().join("ev.csv"), dir.path().join("st.csv"));
    let (ev_s, st_s) = (ev.display().to_string(), st.display().to_string());
    let mut args = vec![
        "orbit",
        "--preset",
        "intermittent",
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
    ];
    args.extend_from_slice(extra);
    let o = oneblock(&args);
    assert_ok(&o);
    let (head, rows) = parse_csv(&std::fs::read_to_string(&ev).expect("events"));
    (rows, head, std::fs::read_to_string(&st).expect("stats"))
}

/// The lines of a statistics file after the `#` lines saying where it
/// came from (the program, command, model and flags).
fn own_lines(text: &str) -> impl Iterator<Item = &str> {
    let provenance = ["# oneblock ", "# command: ", "# model: ", "# settings: "];
    text.lines()
        .filter(move |l| !provenance.iter().any(|p| l.starts_with(p)))
}

/// The `#` line of `text` that starts with `start`.
fn hash_line<'a>(text: &'a str, start: &str) -> &'a str {
    text.lines()
        .find(|l| l.starts_with(start))
        .unwrap_or_else(|| panic!("no line starting {start:?} in\n{text}"))
}

/// The number after `word` in `line`.
fn after(line: &str, word: &str) -> f64 {
    let rest = line
        .split_once(word)
        .unwrap_or_else(|| panic!("no {word:?} in {line}"))
        .1;
    let tok: String = rest
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.' || *c == '-' || *c == 'e')
        .collect();
    tok.parse()
        .unwrap_or_else(|_| panic!("no number after {word:?} in {line}"))
}

/// Each kept slip is creep or stick-slip by the criterion computed here
/// from its onset's position (κ³x0² + y0² > γ², not from θ), the laminar
/// phases are that criterion's creep runs between stick-slip slips, the
/// intermittent orbit's sizes show that a size threshold would have told a
/// different story at the ends of the runs, and the channel passage stands
/// beside the mean laminar length, within 10 % (1.5 % here).
#[test]
fn orbit_stats_laminar_phases_are_runs_of_creep_slips() {
    let (rows, head, text) = intermittent_run(&[]);
    let col = |name: &str| head.iter().position(|h| h == name).expect(name);
    let (cx, cy, cd) = (col("onset_x"), col("onset_y"), col("slip_distance"));
    let (kappa, gamma): (f64, f64) = (50.0, 6.5);
    let a: Vec<f64> = rows
        .iter()
        .map(|r| kappa.powi(3) * num(&r[cx]).powi(2) + num(&r[cy]).powi(2))
        .collect();
    // No onset sits on the criterion's edge, where rounding could decide.
    assert!(a.iter().all(|a| (a - gamma * gamma).abs() > 1e-9));
    let creep: Vec<bool> = a.iter().map(|a| *a > gamma * gamma).collect();
    let n_creep = creep.iter().filter(|c| **c).count();
    // The runs, counted here.
    let mut expected = Vec::new();
    let mut run: Option<usize> = None;
    for &c in &creep {
        match (c, run.as_mut()) {
            (true, Some(n)) => *n += 1,
            (true, None) => {}
            (false, _) => {
                if let Some(n) = run.filter(|n| *n > 0) {
                    expected.push(n);
                }
                run = Some(0);
            }
        }
    }
    assert!(expected.len() > 40, "{} laminar phases", expected.len());
    // Some stick-slip slips are small (the first ones past θc, before the
    // re-injection): slips under a tenth of the largest that start on the
    // stick-slip arc.
    let max = rows.iter().map(|r| num(&r[cd])).fold(0.0, f64::max);
    let small_stick = rows
        .iter()
        .zip(&creep)
        .filter(|(r, c)| !**c && num(&r[cd]) < 0.1 * max)
        .count();
    assert!(small_stick > 40, "{small_stick} small stick-slip slips");
    let first = own_lines(&text).next().expect("a first line");
    assert!(
        first.starts_with(&format!(
            "# {n_creep} creep, {} stick-slip: by where",
            rows.len() - n_creep
        )),
        "{first}"
    );
    let mut from_file = Vec::new();
    for l in text.lines().filter(|l| l.starts_with("laminar_length,")) {
        let f: Vec<&str> = l.split(',').collect();
        let n: usize = f[1].parse().expect("length");
        let c: usize = f[3].parse().expect("count");
        from_file.extend(std::iter::repeat_n(n, c));
    }
    let mut sorted = expected.clone();
    sorted.sort_unstable();
    assert_eq!(from_file, sorted);
    assert!(text.contains("\n# intermittent\n"), "{text}");
    // The mean and the channel passage side by side.
    let mean = expected.iter().sum::<usize>() as f64 / expected.len() as f64;
    let line = hash_line(&text, "# mean laminar length");
    assert!(
        (after(line, "mean laminar length") - mean).abs() < 0.06,
        "{line}"
    );
    let pass = after(line, "channel passage");
    assert!(
        (pass / mean - 1.0).abs() <= 0.10,
        "channel passage {pass} against the mean laminar length {mean}"
    );
}

/// The tangency nearest the intermittent preset: a fold located by
/// continuation, |m − 1| within the location accuracy, checked here by
/// solving the cycle on the window's side (a stable cycle of that period
/// near the fold's point) and finding none on the other. At each distance
/// from it the channel passage agrees with the mean laminar length within
/// 10 % (under 8 % measured); the creep runs do not lengthen as ε^(−1/2), and the verdict says
/// why instead of a bare slope.
#[test]
fn the_tangency_is_a_fold_located_by_continuation() {
    use oneblock::sim::continuation::M_ACCURACY;
    use oneblock::sim::intermittency::{Scaling, scaling};
    use oneblock::sim::{CycleOptions, Simulator, solve_cycle};
    use oneblock::{Method, SolverSettings};
    let p = oneblock::model::preset("intermittent")
        .expect("preset")
        .params;
    let settings = SolverSettings::adaptive(Method::Dop853, 1e-8);
    let sc = scaling(p, settings, &|| false).expect("scan");
    let Scaling::Fitted {
        tangency: t,
        points,
        fit,
    } = &sc
    else {
        panic!("no tangency near θν = 1.4: {}", sc.describe());
    };
    assert!((t.multiplier - 1.0).abs() <= M_ACCURACY, "{t:?}");
    assert!((t.theta_nu - p.theta_nu).abs() <= 0.05, "{t:?}");
    let side = (t.window - t.theta_nu).signum();
    let at = |d: f64| {
        let q = oneblock::Params {
            theta_nu: t.theta_nu + side * d,
            ..p
        };
        Simulator::new(q, settings).expect("sim")
    };
    // On the window's side, a stable cycle of the period next to the fold.
    let cyc = solve_cycle(
        &at(1e-5),
        t.theta,
        t.period,
        &CycleOptions::for_settings(&settings),
    )
    .expect("the window's cycle next to its fold");
    // The node's branch of the saddle-node: 0 < m < 1, its point near the
    // fold's (m − 1 grows as the square root of the distance: 0.61 here).
    assert!(cyc.multiplier > 0.0 && cyc.multiplier < 1.0, "{cyc:?}");
    assert!((cyc.points[0] - t.theta).abs() < 1e-3, "{cyc:?}");
    // On the other side, no cycle from the fold's point converges there.
    let gone = solve_cycle(
        &at(-1e-4),
        t.theta,
        t.period,
        &CycleOptions::for_settings(&settings),
    );
    assert!(
        gone.as_ref().is_err()
            || gone
                .as_ref()
                .is_ok_and(|c| (c.points[0] - t.theta).abs() > 1e-3),
        "{gone:?}"
    );
    assert!(points.len() >= 5, "{points:?}");
    for q in points {
        let (m, pass) = (q.mean.expect("a mean"), q.passage.expect("a passage"));
        assert!(
            (pass / m - 1.0).abs() <= 0.10,
            "at ε = {}: channel passage {pass} against mean {m}",
            q.eps
        );
    }
    let (slope, _) = fit.expect("a fit");
    assert!(slope.abs() < 0.2, "{slope}");
    assert!(!sc.supports_type_one());
    let words = sc.describe();
    assert!(
        words.contains("not -1/2") && words.contains("ghost"),
        "{words}"
    );
}

/// Where no periodic window's cycle folds within reach, nothing is fitted
/// and the file says so in words (the pure-creep preset: its fixed point
/// is followed and never folds).
#[test]
fn without_a_tangency_nothing_is_fitted() {
    let dir = tempfile::tempdir().expect("temp dir");
    let st = dir.path().join("st.csv");
    let st_s = st.display().to_string();
    let o = oneblock(&[
        "orbit",
        "--preset",
        "creep",
        "--transient",
        "200",
        "--keep",
        "300",
        "--no-lyapunov",
        "--stats",
        &st_s,
        "--scaling",
    ]);
    assert_ok(&o);
    let text = std::fs::read_to_string(&st).expect("stats");
    let line = hash_line(&text, "# type-I scaling");
    assert!(
        line.contains("no tangency") && line.contains("not fitted"),
        "{line}"
    );
    assert!(!text.contains("slope"), "{text}");
    assert_bad_input(
        &cmd_args("orbit", &["--keep", "10", "--scaling"]),
        "--scaling",
    );
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
    let first = own_lines(&text).next().expect("a first line");
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

/// Pure creep has no laminar phase (no stick-slip slip ends one) and the
/// channel is closed by its fixed point; pure stick-slip has no creep.
#[test]
fn pure_regimes_have_no_laminar_phases() {
    for (preset, verdict, channel) in [
        (
            "creep",
            "# not intermittent: every slip is creep",
            "no open channel",
        ),
        (
            "chaos",
            "# not intermittent: every slip is stick-slip",
            "no creep slip",
        ),
    ] {
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
        assert!(text.contains(verdict), "{preset}: {text}");
        assert!(text.contains(channel), "{preset}: {text}");
        assert!(!text.contains("\nlaminar_length,"), "{preset}: {text}");
    }
}

/// The channel passage in pieces (`PassageRun`, what a host on a slice of
/// time runs): one map evaluation per call, a cancel between two stops it
/// at once, and its answer is `passage`'s, the intermittent preset's open
/// channel of about 21 slips.
#[test]
fn the_channel_passage_runs_one_map_evaluation_at_a_time() {
    use oneblock::sim::intermittency::channel::{
        CELLS, ENTRIES, MAX_RETURN, Passage, PassageRun, passage,
    };
    use oneblock::sim::{Simulator, default_settings};
    use std::cell::Cell;
    let params = oneblock::model::preset("intermittent")
        .expect("a preset")
        .params;
    let sim = Simulator::new(params, default_settings(1e-8)).expect("valid");
    let near = 0.1;
    let whole = passage(&sim, near, &|| false).expect("computed");
    assert!(
        matches!(&whole, Passage::Open(c) if (20.0..22.0).contains(&c.mean)),
        "{whole:?}"
    );
    // Counted: every evaluation polls the cancel once, first.
    let polls = Cell::new(0);
    let count = || {
        polls.set(polls.get() + 1);
        false
    };
    let mut run = PassageRun::new(&sim, near);
    let mut calls = 0;
    let stepped = loop {
        calls += 1;
        if let Some(r) = run.advance(&sim, &count) {
            break r.expect("computed");
        }
        assert_eq!(polls.get(), calls, "one evaluation per call");
    };
    assert_eq!(stepped, whole);
    assert!(
        calls > CELLS && calls <= CELLS + ENTRIES * (MAX_RETURN + 1),
        "{calls}"
    );
    // Cancelled after 100 evaluations: the 101st call says so.
    let mut run = PassageRun::new(&sim, near);
    let n = Cell::new(0);
    let stop = || {
        n.set(n.get() + 1);
        n.get() > 100
    };
    for _ in 0..100 {
        assert!(run.advance(&sim, &stop).is_none());
    }
    assert!(matches!(
        run.advance(&sim, &stop),
        Some(Err(oneblock::sim::SimError::Cancelled))
    ));
}
