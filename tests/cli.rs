//! The headless command line, run as a user runs it: the `oneblock` binary
//! with its flags, checked on its stdout, stderr, exit code and files.

use crate::cli_support;

use cli_support::*;

use oneblock::formats::SLIP_EVENT_COLUMNS;
use oneblock::jobs::{Shape, sweep_plan};
use oneblock::sim::{Column, Handover, SweepOptions, column_start, theta_nu_grid};
use oneblock::{Params, SolverSettings};

#[test]
fn map_json_reproduces_the_first_worked_example() {
    let o = run(&map_args(&["--theta", "0.5", "--json"]));
    assert_ok(&o);
    let text = stdout(&o);
    assert_eq!(
        text.trim_end().lines().count(),
        1,
        "one JSON object: {text}"
    );
    let v: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    let theta_next = v["theta_next"].as_f64().expect("theta_next");
    assert!((theta_next - 0.2037551562).abs() < 1e-9, "{theta_next}");
    assert!((v["slip_duration"].as_f64().expect("slip_duration") - 3.123143632).abs() < 1e-8);
    assert!((v["stick_duration"].as_f64().expect("stick_duration") - 101.7096366).abs() < 1e-6);
    assert!((v["stop_x"].as_f64().expect("stop_x") + 0.003275131363).abs() < 1e-10);
    assert!((v["stop_y"].as_f64().expect("stop_y") - 0.1167625165).abs() < 1e-9);
    for key in ["slip_distance", "peak_vr", "energy_released", "rhs_evals"] {
        assert!(
            v[key].as_f64().is_some_and(|x| x > 0.0),
            "{key}: {}",
            v[key]
        );
    }
    assert_eq!(v["restarted"], serde_json::Value::Bool(false));
    assert_eq!(v["regime"], "pure stick-slip");
}

#[test]
fn map_text_summary_shows_the_iterate() {
    let o = run(&map_args(&["--theta", "0.5"]));
    assert_ok(&o);
    let text = stdout(&o);
    let line = text
        .lines()
        .find(|l| l.starts_with("theta_next"))
        .expect("a theta_next line");
    let value = num(line.split_whitespace().nth(1).expect("a value"));
    assert!((value - 0.2037551562).abs() < 1e-9);
}

#[test]
fn orbit_rows_are_the_kept_events_and_continue_each_other() {
    let keep = 25;
    let o = run(&cmd_args(
        "orbit",
        &["--theta0", "0.5", "--transient", "5", "--keep", "25"],
    ));
    assert_ok(&o);
    let (header, rows) = parse_csv(&stdout(&o));
    assert_eq!(header, SLIP_EVENT_COLUMNS);
    assert_eq!(rows.len(), keep);
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name}"))
    };
    let (theta, next, restarted) = (col("theta"), col("theta_next"), col("restarted"));
    for w in rows.windows(2) {
        assert_eq!(w[0][restarted], "0");
        // Bit for bit: the next cycle starts exactly where this one ended.
        assert_eq!(num(&w[1][theta]), num(&w[0][next]));
    }
    // Onset times increase by the cycle's slip and stick durations.
    let (t0, slip, stick) = (
        col("onset_time"),
        col("slip_duration"),
        col("stick_duration"),
    );
    for w in rows.windows(2) {
        let dt = num(&w[1][t0]) - num(&w[0][t0]);
        let cycle = num(&w[0][slip]) + num(&w[0][stick]);
        assert!((dt - cycle).abs() < 1e-9 * cycle, "{dt} vs {cycle}");
    }
    let err = stderr(&o);
    assert!(err.contains("period:"), "{err}");
    assert!(err.contains("lyapunov exponent:"), "{err}");
}

#[test]
fn orbit_json_summary_reports_period_and_lyapunov() {
    // θν = 1 at κ = 18.95: a stable fixed point (period 1, λ < 0).
    let o = run(&cmd_args(
        "orbit",
        &[
            "--theta0",
            "0.5",
            "--transient",
            "100",
            "--keep",
            "20",
            "--json",
        ],
    ));
    assert_ok(&o);
    let text = stdout(&o);
    assert_eq!(
        text.trim_end().lines().count(),
        1,
        "only the JSON summary: {text}"
    );
    let v: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    assert_eq!(v["period"], 1);
    assert_eq!(v["keep"], 20);
    // A periodic orbit's exponent is its solved cycle's ln|multiplier|/p:
    // exact, so no standard error.
    let l = v["lyapunov"].as_f64().expect("lyapunov");
    let m = v["cycle"]["multiplier"].as_f64().expect("the solved cycle");
    assert!(
        l < 0.0 && (l - m.abs().ln()).abs() < 1e-12,
        "{l} vs ln|{m}|"
    );
    assert!(v["lyapunov_stderr"].is_null());

    // θν = 1.25: the chaotic attractor of the benchmark (λ > 0).
    let mut args = cmd_args("orbit", &["--transient", "100", "--keep", "300", "--json"]);
    let i = args.iter().position(|a| a == "--theta-nu").expect("flag") + 1;
    args[i] = "1.25".into();
    let o = run(&args);
    assert_ok(&o);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("valid JSON");
    assert_eq!(v["period"], "aperiodic");
    let (l, e) = (
        v["lyapunov"].as_f64().expect("lyapunov"),
        v["lyapunov_stderr"].as_f64().expect("stderr"),
    );
    assert!(l - 3.0 * e > 0.0, "lyapunov {l} ± {e}");
}

#[test]
fn trajectory_phases_follow_the_cycle_and_time_runs_forward() {
    let events = 3;
    let o = run(&cmd_args(
        "trajectory",
        &[
            "--theta0",
            "0.5",
            "--events",
            "3",
            "--spacing",
            "0.05",
            "--out",
            "-",
        ],
    ));
    assert_ok(&o);
    let (header, rows) = parse_csv(&stdout(&o));
    assert_eq!(header, ["t", "x", "y", "u", "w", "phase"]);
    // Starts at the onset θ0 = 0.5 on C, at rest relative to the surface.
    assert_eq!(num(&rows[0][0]), 0.0);
    assert!((num(&rows[0][1]) - 0.5f64.cos() / 18.95).abs() < 1e-15);
    assert!((num(&rows[0][2]) - 0.5f64.sin()).abs() < 1e-15);
    assert!((num(&rows[0][3]) - 1e-3 * 1f64.cos()).abs() < 1e-15);

    // Collapse runs of one phase: each cycle is accel, decel, stick.
    let mut runs: Vec<(&str, usize)> = Vec::new();
    for r in &rows {
        match runs.last_mut() {
            Some((p, n)) if *p == r[5] => *n += 1,
            _ => runs.push((&r[5], 1)),
        }
    }
    let phases: Vec<&str> = runs.iter().map(|(p, _)| *p).collect();
    assert_eq!(phases, ["accel", "decel", "stick"].repeat(events));
    for (p, n) in &runs {
        if *p == "stick" {
            assert_eq!(*n, 2, "a stick phase is recorded by its two ends");
        }
    }
    let t: Vec<f64> = rows.iter().map(|r| num(&r[0])).collect();
    assert!(t.windows(2).all(|w| w[1] >= w[0]), "time goes backwards");
    // During slips, samples are at most the spacing apart.
    for (w, r) in t.windows(2).zip(rows.windows(2)) {
        if r[0][5] != "stick" && r[1][5] != "stick" {
            assert!(w[1] - w[0] <= 0.05 + 1e-12, "{} -> {}", w[0], w[1]);
        }
    }
    assert!(stderr(&o).contains("3 cycle(s)"));
}

#[test]
fn bifurcation_equals_the_windows_sweep_plan_recomputed_by_the_core() {
    let (from, to, columns, transient, keep) = (0.9, 1.3, 9, 20, 10);
    let o = oneblock(&[
        "bifurcation",
        "--kappa",
        "18.95",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--theta-nu-from",
        "0.9",
        "--theta-nu-to",
        "1.3",
        "--columns",
        "9",
        "--transient",
        "20",
        "--keep",
        "10",
        "--out",
        "-",
    ]);
    assert_ok(&o);
    let (header, rows) = parse_csv(&stdout(&o));
    assert_eq!(header, ["theta_nu", "theta", "lyapunov", "lyapunov_stderr"]);
    assert_eq!(rows.len(), columns * keep);
    let got: Vec<(f64, f64)> = rows.iter().map(|r| (num(&r[0]), num(&r[1]))).collect();

    // The window's sweep plan, each column recomputed with the core alone
    // from the neighbour the plan names.
    let params = Params {
        kappa: 18.95,
        gamma: 6.5,
        nu: 1e-3,
        theta_nu: from,
        omega: 50.0,
    };
    let settings = SolverSettings::default();
    let grid = theta_nu_grid(from, to, columns);
    let opts = SweepOptions {
        transient,
        keep,
        map: oneblock::sim::MapChoice::Auto,
    };
    let shape = Shape::default();
    let mut last: Vec<Option<Handover>> = vec![None; columns];
    let mut cols: Vec<Vec<(f64, f64)>> = vec![Vec::new(); columns];
    for p in sweep_plan(columns, shape.coarse_columns, shape.chains) {
        let neighbour = p.parent.and_then(|q| last[q]);
        let start = column_start(params.kappa, grid[p.index], neighbour.map(|h| h.theta));
        let slow = neighbour.and_then(|h| h.slow_period);
        let col = Column::run_from(params, settings, grid[p.index], start, slow, &opts, &|| {
            false
        });
        assert!(col.error.is_none());
        last[p.index] = col.handover();
        cols[p.index] = col.thetas.iter().map(|&th| (col.theta_nu, th)).collect();
    }
    let want: Vec<(f64, f64)> = cols.concat();
    assert_eq!(got, want, "bit for bit");
    let err = stderr(&o);
    // No progress bar when stderr is not a terminal: just the summary.
    assert!(!err.contains('\u{1b}') && !err.contains('\r'), "{err:?}");
    assert_eq!(err.lines().count(), 2, "{err}");
    assert!(
        err.contains("iterates integrated") && err.contains(" thread(s)"),
        "{err}"
    );
}

#[test]
fn negative_angles_parse_and_follow_the_reflection_symmetry() {
    // y → −y maps (θ, θν) to (−θ, −θν): f(−θ; −θν) = −f(θ; θν), written
    // with a leading minus and an exponent, as a user may type them.
    let args = set(
        map_args(&["--theta", "-5e-1", "--json"]),
        "--theta-nu",
        "-1e0",
    );
    let o = run(&args);
    assert_ok(&o);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("valid JSON");
    let theta_next = v["theta_next"].as_f64().expect("theta_next");
    assert!((theta_next + 0.2037551562).abs() < 1e-9, "{theta_next}");
}

#[test]
fn bifurcation_reports_failed_columns_and_goes_on() {
    // Euler with h = 0.2 cannot resolve the stop at θν = π/2 (the core
    // reports "step too large" rather than a wrong value); the other
    // columns still run.
    let (columns, keep) = (3, 2);
    let o = oneblock(&[
        "bifurcation",
        "--kappa",
        "18.95",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--method",
        "euler",
        "--step",
        "0.2",
        "--columns",
        "3",
        "--transient",
        "2",
        "--keep",
        "2",
    ]);
    assert_ok(&o);
    let err = stderr(&o);
    let warnings: Vec<&str> = err.lines().filter(|l| l.starts_with("warning:")).collect();
    assert!(!warnings.is_empty(), "{err}");
    assert!(!err.contains("panicked"));
    let (_, rows) = parse_csv(&stdout(&o));
    let mut per_column = std::collections::BTreeMap::new();
    for r in &rows {
        *per_column.entry(r[0].clone()).or_insert(0) += 1;
    }
    let grid = theta_nu_grid(0.0, std::f64::consts::FRAC_PI_2, columns);
    let short: Vec<f64> = grid
        .iter()
        .copied()
        .filter(|tn| per_column.get(&tn.to_string()).copied().unwrap_or(0) < keep)
        .collect();
    // One warning per short column, naming its θν and the reason.
    assert_eq!(warnings.len(), short.len(), "{err}");
    for tn in short {
        let w = warnings
            .iter()
            .find(|w| w.contains(&format!("theta-nu = {tn} ")))
            .unwrap_or_else(|| panic!("no warning for theta-nu = {tn}: {err}"));
        assert!(w.contains("too large"), "{w}");
    }
}

#[test]
fn orbit_json_with_a_file_splits_data_and_summary() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("events.csv");
    let o = run(&cmd_args(
        "orbit",
        &[
            "--transient",
            "3",
            "--keep",
            "4",
            "--json",
            "--no-lyapunov",
            "--out",
            path.to_str().expect("UTF-8 path"),
        ],
    ));
    assert_ok(&o);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("valid JSON");
    assert_eq!(v["keep"], 4);
    assert!(v["lyapunov"].is_null());
    let (_, rows) = parse_csv(&std::fs::read_to_string(&path).expect("read"));
    assert_eq!(rows.len(), 4);
    // The summary's last onset continues the orbit: it is the last row's θ'
    // (to an ulp: serde_json's default float parser is not exact).
    let theta_last = v["theta_last"].as_f64().expect("theta_last");
    assert!((theta_last - num(&rows[3][12])).abs() <= 4.0 * f64::EPSILON);
    assert!(stderr(&o).is_empty(), "{}", stderr(&o));
}

#[test]
fn bifurcation_writes_each_columns_lyapunov_exponent() {
    // Fig. 3b at θν = 0.9 (a stable fixed point) and 1.25 (chaos).
    let o = oneblock(&[
        "bifurcation",
        "--preset",
        "fig3b",
        "--theta-nu-from",
        "0.9",
        "--theta-nu-to",
        "1.25",
        "--columns",
        "2",
        "--transient",
        "200",
        "--keep",
        "64",
    ]);
    assert_ok(&o);
    let (header, rows) = parse_csv(&stdout(&o));
    assert_eq!(header, ["theta_nu", "theta", "lyapunov", "lyapunov_stderr"]);
    let column = |tn: &str| -> Vec<&Vec<String>> { rows.iter().filter(|r| r[0] == tn).collect() };
    let (fixed, chaos) = (column("0.9"), column("1.25"));
    assert_eq!((fixed.len(), chaos.len()), (64, 64));
    for c in [&fixed, &chaos] {
        assert!(
            c.iter().all(|r| r[2] == c[0][2] && r[3] == c[0][3]),
            "one λ a column"
        );
    }
    // The fixed point: λ = ln|f'(θ*)| exactly, no error bar; f' here from
    // the central difference of `oneblock map` about the kept onset.
    assert_eq!(fixed[0][3], "");
    let lambda = num(&fixed[0][2]);
    let th = num(&fixed[0][1]);
    let next = |theta: f64| {
        let o = run(&[
            "map",
            "--preset",
            "fig3b",
            "--theta-nu",
            "0.9",
            "--tol",
            "1e-12",
            "--theta",
            &theta.to_string(),
            "--json",
        ]
        .map(String::from));
        assert_ok(&o);
        let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON");
        v["theta_next"].as_f64().expect("theta_next")
    };
    let h = 1e-5;
    let slope = (next(th + h) - next(th - h)) / (2.0 * h);
    assert!(
        lambda < 0.0 && (lambda - slope.abs().ln()).abs() < 1e-4,
        "{lambda} vs ln|{slope}|"
    );
    // Chaos: positive, beyond twice its standard error.
    let (l, se) = (num(&chaos[0][2]), num(&chaos[0][3]));
    assert!(l > 2.0 * se && se > 0.0, "{l} ± {se}");
}
