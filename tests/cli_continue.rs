//! `oneblock continue` on the command line: a run stopped by
//! `--max-seconds` or failing mid-way writes what it has and says where
//! it stopped; progress lines name each located point; one `--curve` run
//! writes every arm of a boundary; bad values of its flags are refused.

#![allow(clippy::unwrap_used)]

use crate::cli_support;

use cli_support::*;

fn fig4(out: &str, points: &str, more: &[&str]) -> Vec<String> {
    with(
        &[
            "continue", "--preset", "fig4", "--param", "theta-nu", "--from", "0.1", "--to", "1.55",
            "--period", "1", "--out", out, "--points", points,
        ],
        more,
    )
}

/// The value after "at theta-nu = " in `text`.
fn stopped_at(text: &str) -> f64 {
    let rest = text
        .rsplit("at theta-nu = ")
        .next()
        .unwrap_or_else(|| panic!("no position in {text}"));
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == 'e'))
        .unwrap_or(rest.len());
    num(&rest[..end])
}

#[test]
fn max_seconds_writes_what_was_computed_and_says_where_it_stopped() {
    let dir = tempfile::tempdir().unwrap();
    let (out, pts) = (dir.path().join("b.csv"), dir.path().join("p.csv"));
    let args = fig4(
        out.to_str().unwrap(),
        pts.to_str().unwrap(),
        // The seed given: the attractor search at --from (50 ms) is under
        // the same limit and would stop first, writing nothing.
        &["--max-seconds", "0.001", "--theta", "0.06"],
    );
    let o = run(&args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    let last = err.trim_end().lines().last().unwrap();
    assert!(
        last.starts_with("error: continue: stopped by --max-seconds = 0.001")
            && last.contains("written"),
        "{err}"
    );
    let at = stopped_at(last);
    // The branch file ends where the message says, short of --to.
    let (_, rows) = parse_csv(&std::fs::read_to_string(&out).unwrap());
    assert!(!rows.is_empty());
    assert_eq!(num(&rows[0][0]), 0.1);
    assert_eq!(num(&rows[rows.len() - 1][0]), at);
    assert!(at < 1.55, "{at}");
    let (_, specials) = parse_csv(&std::fs::read_to_string(&pts).unwrap());
    let end = specials.last().unwrap();
    assert_eq!((end[0].as_str(), num(&end[3])), ("end", at));
}

#[test]
fn a_branch_failing_mid_way_writes_its_points_and_says_where_and_why() {
    // κ = 1.212: past its doubling the fixed point's multiplier grows to
    // ~−1e3 within 0.006 in θν, next to a near-jump of f, and the
    // corrector gives up there.
    let dir = tempfile::tempdir().unwrap();
    let (out, pts) = (dir.path().join("b.csv"), dir.path().join("p.csv"));
    let args = fig4(
        out.to_str().unwrap(),
        pts.to_str().unwrap(),
        &["--kappa", "1.212"],
    );
    let o = run(&args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    let last = err.trim_end().lines().last().unwrap();
    assert!(
        last.contains("the P1 branch failed: ") && last.contains("written"),
        "{err}"
    );
    let at = stopped_at(last);
    assert!(at > 0.8 && at < 1.55, "{at}");
    let (_, rows) = parse_csv(&std::fs::read_to_string(&out).unwrap());
    assert_eq!(num(&rows[rows.len() - 1][0]), at);
    assert!(rows.len() > 10);
    let (_, specials) = parse_csv(&std::fs::read_to_string(&pts).unwrap());
    let kinds: Vec<&str> = specials.iter().map(|r| r[0].as_str()).collect();
    assert_eq!(kinds, ["PD", "end"]);
    assert!(num(&specials[0][3]) < at);
}

#[test]
fn a_progress_line_names_each_located_point_as_it_is_found() {
    let dir = tempfile::tempdir().unwrap();
    let (out, pts) = (dir.path().join("b.csv"), dir.path().join("p.csv"));
    let o = run(&fig4(out.to_str().unwrap(), pts.to_str().unwrap(), &[]));
    assert_ok(&o);
    let err = stderr(&o);
    let lines: Vec<f64> = err
        .lines()
        .filter(|l| l.starts_with("continue: PD of the P1 branch at theta-nu = "))
        .map(stopped_at)
        .collect();
    let (_, specials) = parse_csv(&std::fs::read_to_string(&pts).unwrap());
    let located: Vec<f64> = specials
        .iter()
        .filter(|r| r[0] == "PD")
        .map(|r| num(&r[3]))
        .collect();
    assert_eq!(located.len(), 2, "{err}");
    assert_eq!(lines, located, "{err}");
    // They come before the summary.
    let first_summary = err.find("P1 branch in theta-nu").unwrap();
    assert!(err.find("continue: PD of").unwrap() < first_summary);
}

#[test]
fn one_curve_run_writes_both_arms_of_the_fp_to_p2_boundary() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("pd1.csv");
    let args = with(
        &[
            "continue",
            "--preset",
            "fig4",
            "--curve",
            "pd",
            "--params",
            "theta-nu,kappa",
            "--from",
            "0.1",
            "--to",
            "1.55",
            "--from2",
            "1",
            "--to2",
            "42",
            "--period",
            "1",
        ],
        &["--out", out.to_str().unwrap()],
    );
    let o = run(&args);
    assert_ok(&o);
    let (header, rows) = parse_csv(&std::fs::read_to_string(&out).unwrap());
    assert_eq!(
        header,
        [
            "curve",
            "kind",
            "period",
            "theta_nu",
            "kappa",
            "theta",
            "multiplier"
        ]
    );
    let arms: std::collections::BTreeSet<&str> = rows.iter().map(|r| r[0].as_str()).collect();
    assert!(!arms.is_empty() && arms.len() <= 2, "{arms:?}");
    let kappa: Vec<f64> = rows.iter().map(|r| num(&r[4])).collect();
    let theta_nu: Vec<f64> = rows.iter().map(|r| num(&r[3])).collect();
    for r in &rows {
        assert!((num(&r[6]) + 1.0).abs() <= 1e-6, "{r:?}");
        assert!(
            num(&r[3]) >= 0.1 - 0.05 && num(&r[3]) <= 1.55 + 0.05,
            "{r:?}"
        );
    }
    // From the top of the box down to κ ≈ 1.21, on both sides of the
    // κ = 16 doublings (θν = 1.04 and 1.54).
    let (lo, hi) = kappa
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &k| {
            (a.min(k), b.max(k))
        });
    assert!(lo < 1.215 && lo > 1.2, "{lo}");
    assert!(hi >= 42.0 - 1.0, "{hi}");
    let at_16: Vec<f64> = rows
        .windows(2)
        .filter(|w| w[0][0] == w[1][0])
        .filter(|w| (num(&w[0][4]) - 16.0) * (num(&w[1][4]) - 16.0) <= 0.0)
        .map(|w| num(&w[0][3]))
        .collect();
    assert!(at_16.iter().any(|x| (x - 1.0438).abs() < 0.01), "{at_16:?}");
    assert!(at_16.iter().any(|x| (x - 1.5358).abs() < 0.01), "{at_16:?}");
    assert!(theta_nu.iter().any(|&x| x < 0.4));
    let err = stderr(&o);
    assert!(err.contains("pd curve 0 of P1"), "{err}");
}

#[test]
fn bad_values_of_the_run_flags_name_the_flag_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let (out, pts) = (dir.path().join("b.csv"), dir.path().join("p.csv"));
    let base = fig4(
        out.to_str().unwrap(),
        pts.to_str().unwrap(),
        &["--max-seconds", "10"],
    );
    for bad in ["0", "-1", "NaN", "inf", "1e8"] {
        assert_bad_input(&set(base.clone(), "--max-seconds", bad), "--max-seconds");
    }
    // An empty range, named by the flag that makes it empty.
    assert_bad_input(&set(base.clone(), "--to", "0.1"), "--to");
    // A period out of 1…64, an unknown parameter.
    for p in ["0", "65", "-1", "x"] {
        assert_bad_input(&set(base.clone(), "--period", p), "--period");
    }
    assert_bad_input(&set(base.clone(), "--param", "sigma"), "--param");
    // A start not on a cycle: off the exit arc, or on no 2-cycle near it.
    let refs: Vec<&str> = base.iter().map(String::as_str).collect();
    assert_bad_input(&with(&refs, &["--theta", "3.0"]), "--theta");
    assert_bad_input(
        &set(with(&refs, &["--theta", "0.05"]), "--period", "2"),
        "--theta",
    );
    assert!(!out.exists() && !pts.exists(), "nothing written");
}

#[test]
fn the_cascade_prints_its_doublings_and_ratios_that_follow_from_them() {
    let dir = tempfile::tempdir().unwrap();
    let (out, pts) = (dir.path().join("c.csv"), dir.path().join("p.csv"));
    let args = with(
        &[
            "continue",
            "--preset",
            "fig3b",
            "--param",
            "theta-nu",
            "--from",
            "1.0",
            "--to",
            "1.6",
            "--period",
            "1",
            "--cascade",
        ],
        &[
            "--out",
            out.to_str().unwrap(),
            "--points",
            pts.to_str().unwrap(),
        ],
    );
    let o = run(&args);
    assert_ok(&o);
    let err = stderr(&o);
    // The table: "  n  period  b_n  gap  delta", after the "cascade:" line.
    let table: Vec<Vec<&str>> = err
        .lines()
        .skip_while(|l| !l.starts_with("cascade: "))
        .skip(2)
        .take_while(|l| l.starts_with("  ") && !l.contains("Feigenbaum"))
        .map(|l| l.split_whitespace().collect())
        .collect();
    assert!(table.len() >= 4, "{err}");
    let periods: Vec<usize> = table.iter().map(|r| r[1].parse().unwrap()).collect();
    let expected: Vec<usize> = (0..table.len()).map(|i| 1 << i).collect();
    assert_eq!(periods, expected);
    // The doublings are the PD rows of points.csv, one per level.
    let (_, specials) = parse_csv(&std::fs::read_to_string(&pts).unwrap());
    let pds: Vec<f64> = specials
        .iter()
        .filter(|r| r[0] == "PD")
        .map(|r| num(&r[3]))
        .collect();
    let b: Vec<f64> = table.iter().map(|r| num(r[2])).collect();
    assert_eq!(pds.len(), b.len());
    for (x, y) in pds.iter().zip(&b) {
        assert!((x - y).abs() < 1e-14, "{x} vs {y}");
    }
    // δₙ recomputed from the printed bₙ, and the last near Feigenbaum's.
    for (i, row) in table.iter().enumerate().skip(2) {
        let delta = (b[i - 1] - b[i - 2]) / (b[i] - b[i - 1]);
        assert!((num(row[4]) - delta).abs() < 1e-4, "{row:?} vs {delta}");
    }
    let last = (b[b.len() - 2] - b[b.len() - 3]) / (b[b.len() - 1] - b[b.len() - 2]);
    assert!((last - 4.6692).abs() < 0.1, "{b:?}");
}

#[test]
fn phase_draws_the_curves_of_a_continue_run_over_its_picture() {
    let dir = tempfile::tempdir().unwrap();
    let curve = dir.path().join("pd.csv");
    // A diagonal from (0.15, 2) to (0.95, 19) in the curve CSV's format,
    // over four cells that are all FP (blue, so the white line shows).
    let mut text = String::from("curve,kind,period,theta_nu,kappa,theta,multiplier\n");
    for i in 0..=20 {
        let f = i as f64 / 20.0;
        text.push_str(&format!(
            "0,pd,1,{},{},0.4,-1\n",
            0.15 + 0.8 * f,
            2.0 + 17.0 * f
        ));
    }
    std::fs::write(&curve, text).unwrap();
    let phase = |png: &std::path::Path, more: &[&str]| {
        let args = with(
            &[
                "phase",
                "--gamma",
                "6.5",
                "--nu",
                "1e-3",
                "--kappa-from",
                "1",
                "--kappa-to",
                "20",
                "--kappa-steps",
                "2",
                "--theta-nu-from",
                "0.1",
                "--theta-nu-to",
                "1.0",
                "--theta-nu-steps",
                "2",
                "--png",
                png.to_str().unwrap(),
            ],
            more,
        );
        run(&args)
    };
    let (plain, drawn) = (dir.path().join("a.png"), dir.path().join("b.png"));
    assert_ok(&phase(&plain, &[]));
    assert_ok(&phase(&drawn, &["--boundaries", curve.to_str().unwrap()]));
    let a = image::open(&plain).unwrap().to_rgb8();
    let b = image::open(&drawn).unwrap().to_rgb8();
    assert_eq!(a.dimensions(), b.dimensions());
    // The curve is drawn in its own style, white on a dark halo, over the
    // plot of FP's blue cells (whose box the legend's rows above may
    // shift): (near) white pixels inside that box are the curve's, and
    // there are none without it.
    let whitened = |img: &image::RgbImage| -> Vec<(u32, u32)> {
        // The plot's rows and columns: those mostly blue (not the
        // legend's swatch).
        let (w, h) = img.dimensions();
        let blue = |x: u32, y: u32| img.get_pixel(x, y).0 == [49, 104, 181];
        let rows: Vec<u32> = (0..h)
            .filter(|&y| (0..w).filter(|&x| blue(x, y)).count() > w as usize / 2)
            .collect();
        let cols: Vec<u32> = (0..w)
            .filter(|&x| (0..h).filter(|&y| blue(x, y)).count() > h as usize / 2)
            .collect();
        let (x0, x1) = (cols[0], cols[cols.len() - 1]);
        let (y0, y1) = (rows[0], rows[rows.len() - 1]);
        img.enumerate_pixels()
            .filter(|(x, y, p)| {
                (x0 + 3..x1 - 3).contains(x)
                    && (y0 + 3..y1 - 3).contains(y)
                    && p.0.iter().all(|&c| c >= 235)
            })
            .map(|(x, y, _)| (x, y))
            .collect()
    };
    assert!(
        whitened(&a).is_empty(),
        "white inside the plot without a curve"
    );
    let whitened = whitened(&b);
    assert!(whitened.len() > 300, "{}", whitened.len());
    let (xs, ys): (Vec<u32>, Vec<u32>) = whitened.iter().copied().unzip();
    let span = |v: &[u32]| v.iter().max().unwrap() - v.iter().min().unwrap();
    assert!(
        span(&xs) > 400 && span(&ys) > 300,
        "{} {}",
        span(&xs),
        span(&ys)
    );
    let left = whitened.iter().min_by_key(|p| p.0).unwrap();
    let right = whitened.iter().max_by_key(|p| p.0).unwrap();
    assert!(
        right.1 < left.1,
        "image y grows downwards: {left:?} {right:?}"
    );
    // A file without the theta_nu and kappa columns is refused, naming
    // the flag.
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "a,b\n1,2\n").unwrap();
    let o = phase(
        &dir.path().join("c.png"),
        &["--boundaries", bad.to_str().unwrap()],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--boundaries"), "{}", stderr(&o));
}
