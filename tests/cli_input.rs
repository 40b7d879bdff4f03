//! Bad input and output files on the command line: every refusal names its
//! flag on one line with exit code 2, and no existing file is lost.

use crate::cli_support;

use std::path::Path;
use std::time::{Duration, Instant};

use cli_support::*;
use oneblock::formats::SLIP_EVENT_COLUMNS;

#[test]
fn bad_input_names_the_flag_and_exits_with_2() {
    let map = map_args(&["--theta", "0.5"]);
    for (flag, values) in [
        ("--kappa", &["NaN", "inf", "0", "-1"][..]),
        ("--gamma", &["-0.5", "NaN"]),
        ("--nu", &["0", "-1e-3", "inf"]),
        ("--theta-nu", &["NaN", "-inf"]),
        ("--theta", &["2.5", "NaN", "inf"]),
    ] {
        for v in values {
            assert_bad_input(&set(map.clone(), flag, v), flag);
        }
    }
    let extra = [
        (&["--omega", "0"][..], "--omega"),
        (&["--omega", "NaN"], "--omega"),
        (&["--tol", "1e-15"], "--tol"),
        (&["--tol", "0.1"], "--tol"),
        (&["--tol", "NaN"], "--tol"),
        (&["--method", "rk45x"], "--method"),
        (&["--method", "rk4", "--step", "0"], "--step"),
        (&["--method", "euler", "--step", "NaN"], "--step"),
        (&["--method", "rk4", "--tol", "1e-8"], "--tol"),
    ];
    for (more, flag) in extra {
        assert_bad_input(
            &with(&map.iter().map(String::as_str).collect::<Vec<_>>(), more),
            flag,
        );
    }

    let orbit = cmd_args(
        "orbit",
        &["--theta0", "0.5", "--transient", "1", "--keep", "2"],
    );
    assert_bad_input(&set(orbit.clone(), "--theta0", "-2"), "--theta0");
    assert_bad_input(&set(orbit.clone(), "--keep", "0"), "--keep");
    assert_bad_input(
        &set(orbit.clone(), "--transient", "18446744073709551615"),
        "--transient",
    );
    assert_bad_input(&set(orbit.clone(), "--kappa", "NaN"), "--kappa");
    assert_bad_input(
        &with(
            &orbit.iter().map(String::as_str).collect::<Vec<_>>(),
            &["--period-tol", "0"],
        ),
        "--period-tol",
    );
    assert_bad_input(
        &with(
            &orbit.iter().map(String::as_str).collect::<Vec<_>>(),
            &["--json", "--out", "-"],
        ),
        "--out",
    );

    // work-precision's θ₀ is checked as orbit's: on the exit arc of the
    // attractor given, and refused without one.
    let wp = |extra: &[&str]| {
        let mut a = vec!["work-precision", "--out", "-", "--theta0", "1e308"];
        a.extend_from_slice(extra);
        a.into_iter().map(String::from).collect::<Vec<_>>()
    };
    assert_bad_input(&wp(&[]), "--theta0");
    assert_bad_input(&wp(&["--preset", "fig3b"]), "--theta0");

    let traj = cmd_args("trajectory", &["--theta0", "0.5", "--events", "1"]);
    assert_bad_input(&set(traj.clone(), "--events", "0"), "--events");
    assert_bad_input(&set(traj.clone(), "--theta0", "3"), "--theta0");
    for v in ["0", "-0.1", "NaN", "1e-9"] {
        assert_bad_input(
            &with(
                &traj.iter().map(String::as_str).collect::<Vec<_>>(),
                &["--spacing", v],
            ),
            "--spacing",
        );
    }

    let bif: Vec<String> = [
        "bifurcation",
        "--kappa",
        "18.95",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--theta-nu-from",
        "0",
        "--theta-nu-to",
        "1.5",
        "--columns",
        "2",
        "--transient",
        "1",
        "--keep",
        "1",
    ]
    .map(String::from)
    .to_vec();
    assert_bad_input(&set(bif.clone(), "--columns", "0"), "--columns");
    assert_bad_input(&set(bif.clone(), "--keep", "0"), "--keep");
    assert_bad_input(&set(bif.clone(), "--columns", "1000000000000"), "--columns");
    assert_bad_input(
        &set(set(bif.clone(), "--columns", "1000"), "--keep", "1000000"),
        "--keep",
    );
    assert_bad_input(
        &set(bif.clone(), "--transient", "1000000000000000"),
        "--transient",
    );
    assert_bad_input(
        &set(bif.clone(), "--theta-nu-from", "NaN"),
        "--theta-nu-from",
    );
    assert_bad_input(&set(bif.clone(), "--theta-nu-to", "inf"), "--theta-nu-to");
    assert_bad_input(&set(bif.clone(), "--nu", "0"), "--nu");
    assert_bad_input(&set(bif.clone(), "--gamma", "-1"), "--gamma");
    assert_bad_input(&set(bif.clone(), "--kappa", "-inf"), "--kappa");
}

#[test]
fn unwritable_output_is_refused_before_any_work() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let missing = dir.path().join("no/such/folder/out.csv");
    let missing = missing.to_str().expect("UTF-8 path");
    // A run long enough that simulating first would be noticed.
    let start = Instant::now();
    assert_bad_input(
        &[
            "bifurcation",
            "--kappa",
            "18.95",
            "--gamma",
            "6.5",
            "--nu",
            "1e-3",
            "--columns",
            "100000",
            "--transient",
            "100000",
            "--keep",
            "10",
            "--out",
            missing,
        ]
        .map(String::from),
        "--out",
    );
    assert!(start.elapsed() < Duration::from_secs(5));
    let traj = cmd_args("trajectory", &["--events", "100000", "--out", missing]);
    assert_bad_input(&traj, "--out");
    let folder = dir.path().to_str().expect("UTF-8 path");
    assert_bad_input(
        &cmd_args("orbit", &["--keep", "1", "--out", folder]),
        "--out",
    );
}

#[test]
fn existing_output_is_kept_unless_forced() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("orbit.csv");
    std::fs::write(&path, "keep me\n").expect("write");
    let p = path.to_str().expect("UTF-8 path");
    let args = cmd_args("orbit", &["--transient", "2", "--keep", "3", "--out", p]);
    assert_bad_input(&args, "--out");
    assert!(stderr(&run(&args)).contains("--force"));
    assert_eq!(std::fs::read_to_string(&path).expect("read"), "keep me\n");

    let forced = with(
        &args.iter().map(String::as_str).collect::<Vec<_>>(),
        &["--force"],
    );
    let o = run(&forced);
    assert_ok(&o);
    assert!(o.stdout.is_empty(), "the CSV went to the file");
    let (header, rows) = parse_csv(&std::fs::read_to_string(&path).expect("read"));
    assert_eq!(header, SLIP_EVENT_COLUMNS);
    assert_eq!(rows.len(), 3);
    // No temporary files left beside it.
    assert_eq!(std::fs::read_dir(dir.path()).expect("list").count(), 1);

    // A new file is written without --force.
    let fresh = dir.path().join("path.csv");
    let o = run(&cmd_args(
        "trajectory",
        &["--out", fresh.to_str().expect("UTF-8 path")],
    ));
    assert_ok(&o);
    assert!(Path::new(&fresh).exists());
}

#[test]
fn dash_writes_to_stdout() {
    for cmd in ["orbit", "trajectory"] {
        let o = run(&cmd_args(cmd, &["--out", "-"]));
        assert_ok(&o);
        assert!(stdout(&o).lines().count() > 2, "{cmd}");
        assert!(!Path::new("-").exists(), "no file called '-'");
    }
    let o = oneblock(&[
        "bifurcation",
        "--kappa",
        "3",
        "--gamma",
        "0.5",
        "--nu",
        "1e-3",
        "--columns",
        "2",
        "--transient",
        "1",
        "--keep",
        "2",
        "--out",
        "-",
    ]);
    assert_ok(&o);
    let rows = stdout(&o).lines().filter(|l| !l.starts_with('#')).count();
    assert_eq!(rows, 1 + 2 * 2);
}

/// A flag given without its value (at the end of the line, or followed by
/// another flag) is named with what it expects, on one line: its values,
/// else the first sentence of its help (it was `--out: unknown value '':
/// expected one of`, with nothing after).
#[test]
fn a_flag_without_its_value_says_what_it_expects() {
    for (args, want) in [
        (
            &["orbit", "--preset", "fig3b", "--out"][..],
            "error: --out needs a value: CSV file of the kept events",
        ),
        (
            &["orbit", "--preset", "fig3b", "--method"],
            "error: --method needs a value: one of dp54, dop853, rk4, euler",
        ),
        (
            &["figure", "--view", "phase", "--out"],
            "error: --out needs a value: Where the figure goes (see",
        ),
        (
            &[
                "bifurcation",
                "--preset",
                "fig3b",
                "--out",
                "x.csv",
                "--columns",
            ],
            "error: --columns needs a value: Number of values, evenly spaced (in log10 of the value for kappa, nu and omega, which span decades), ends included (1 to 1e6) (see",
        ),
    ] {
        let o = oneblock(args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with(want), "{args:?}: {err}");
        assert!(!err.contains("unknown value ''"), "{err}");
    }
}

/// `bifurcation --param`'s range: each bad end is one line naming its flag
/// and what it must be (exit 2), before any work.
#[test]
fn a_bad_range_of_the_varied_parameter_names_its_flag() {
    let base = ["bifurcation", "--preset", "fig3b", "--out", "-"];
    for (more, want) in [
        (
            &["--param", "kappa", "--from", "0", "--to", "5"][..],
            "error: --from = 0 is out of range: kappa must be positive (its axis is logarithmic)",
        ),
        (
            &["--param", "gamma", "--from", "1", "--to", "2e5"],
            "error: --to = 200000: gamma is out of range: must lie in [0.1, 1e4]",
        ),
        (
            &["--param", "theta-nu", "--from", "0", "--to", "2000"],
            "error: --to = 2000 is out of range: theta-nu must lie in [-1000, 1000] radians",
        ),
        (
            &["--param", "omega", "--to", "5"],
            "error: the following required arguments were not provided: --from",
        ),
        (
            &["--param", "nu"],
            "error: --from and --to: required with --param nu",
        ),
    ] {
        let args: Vec<&str> = base.iter().chain(more).copied().collect();
        let o = oneblock(&args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with(want), "{args:?}: {err}");
    }
}
