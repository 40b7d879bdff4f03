//! No input bricks a run: sessions that are not sessions (a FIFO, a
//! directory, invalid UTF-8, an unknown version) are refused in one line
//! before any window opens; failed work-precision settings are reported as
//! failed, never as NaN; long commands stop at --max-seconds and on Ctrl+C
//! with one line and nothing written; every error is one line that names
//! its flag, shortens long values and escapes control characters, with
//! exit 2 for what can be fixed before running and 1 for what failed
//! during it.

#![allow(clippy::unwrap_used)]

use crate::cli_support;

use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use cli_support::*;

/// Exactly one line on stderr, starting "error: ", with the exit code.
fn one_error_line(o: &Output, code: i32) -> String {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(code), "stderr: {err}");
    assert_eq!(err.lines().count(), 1, "not one line: {err:?}");
    assert!(err.starts_with("error: "), "{err}");
    assert!(!err.contains('\u{1b}'), "a raw escape character: {err:?}");
    err
}

fn gui_session(session: &std::path::Path, shot: &std::path::Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args(["gui", "--timeout", "5", "--session"])
        .arg(session)
        .arg("--screenshot")
        .arg(shot)
        // No display: a session refused must be refused before the window.
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .stdin(Stdio::null())
        .output()
        .unwrap()
}

// Sessions are the window's: a build without it says so instead.
#[cfg(feature = "gui")]
#[test]
fn sessions_that_are_not_sessions_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("shot.png");
    let folder = dir.path().join("a-folder");
    std::fs::create_dir(&folder).unwrap();
    let bad_utf8 = dir.path().join("latin1.json");
    std::fs::write(&bad_utf8, b"{\"settings\": {\"save_dir\": \"caf\xe9\"}}").unwrap();
    let mut cases = vec![(folder, "directory"), (bad_utf8, "UTF-8")];
    for v in ["99", "-1", "\"1\"", "1.5"] {
        let p = dir.path().join(format!("v{}.json", cases.len()));
        std::fs::write(
            &p,
            format!("{{\"oneblock_session\": {v}, \"settings\": {{}}}}"),
        )
        .unwrap();
        cases.push((p, "version"));
    }
    #[cfg(unix)]
    {
        let fifo = dir.path().join("fifo.json");
        let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
        assert!(made.success());
        cases.push((fifo, "not a regular file"));
    }
    for (path, why) in cases {
        let t0 = Instant::now();
        let o = gui_session(&path, &shot);
        let err = one_error_line(&o, 2);
        assert!(err.contains("--session") && err.contains(why), "{err}");
        // A FIFO with no writer is refused, not waited on.
        assert!(t0.elapsed() < Duration::from_secs(10), "{err}");
        assert!(!shot.exists());
    }
}

#[test]
fn a_missing_session_and_a_bad_size_name_their_flag() {
    let dir = tempfile::tempdir().unwrap();
    let o = gui_session(&dir.path().join("none.json"), &dir.path().join("s.png"));
    assert!(one_error_line(&o, 2).contains("--session"));
    let o = oneblock(&["gui", "--size", "-1280x800"]);
    let err = one_error_line(&o, 2);
    assert!(err.contains("--size") && err.contains("200x200"), "{err}");
}

/// `gui --tour-step` takes a step of the tour, 1 to 7, and `--layout` a
/// new file beside `--screenshot`: anything else is one line naming the
/// flag (and the range), exit 2, before any window opens.
#[test]
fn a_tour_step_out_of_range_and_a_layout_without_a_picture_name_their_flag() {
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("s.png");
    let shot = shot.to_str().unwrap();
    for n in ["0", "8", "-1", "2.5", "many"] {
        let o = oneblock(&["gui", "--tour-step", n, "--screenshot", shot]);
        let err = one_error_line(&o, 2);
        assert!(err.contains("--tour-step"), "{n}: {err}");
        if matches!(n, "0" | "8") {
            assert!(err.contains("[1, 7]"), "{n}: {err}");
        }
    }
    let o = oneblock(&["gui", "--tour-step", "2", "--view", "plane"]);
    assert!(one_error_line(&o, 2).contains("--tour-step"));
    let layout = dir.path().join("l.json");
    let layout = layout.to_str().unwrap();
    let o = oneblock(&["gui", "--layout", layout]);
    let err = one_error_line(&o, 2);
    assert!(
        err.contains("--layout") && err.contains("--screenshot"),
        "{err}"
    );
    std::fs::write(layout, "kept").unwrap();
    let o = oneblock(&["gui", "--screenshot", shot, "--layout", layout]);
    let err = one_error_line(&o, 2);
    assert!(
        err.contains("--layout") && err.contains("already exists"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(layout).unwrap(), "kept");
    assert!(!std::path::Path::new(shot).exists());
}

#[test]
fn long_and_control_character_values_are_shortened_and_escaped() {
    let long = "x".repeat(5000);
    let o = run(&with(
        &["orbit", "--preset", "fig3b", "--out", "-", "--map"],
        &[&long],
    ));
    let err = one_error_line(&o, 2);
    assert!(
        err.contains("--map") && err.len() < 300,
        "{} bytes",
        err.len()
    );
    // A path with a newline and an escape sequence: one line, escaped.
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("no\nsuch\u{1b}[31m/x.csv");
    let o = Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args(["trajectory", "--preset", "fig3b", "--events", "2", "--out"])
        .arg(&bad)
        .output()
        .unwrap();
    let err = one_error_line(&o, 2);
    assert!(err.contains("--out") && err.contains("\\n"), "{err}");
}

#[test]
fn work_precision_names_theta0_with_a_short_number() {
    let o = oneblock(&[
        "work-precision",
        "--preset",
        "intermittent",
        "--theta0",
        "1e308",
        "--out",
        "-",
    ]);
    let err = one_error_line(&o, 2);
    assert!(err.contains("--theta0") && err.contains("1e308"), "{err}");
    assert!(err.len() < 300, "{err}");
}

/// `work-precision` with one point and no repeats: every setting that
/// fails is reported as failed (its `failed` column equal to `points`,
/// its measurements empty, and in the summary), never as NaN.
#[test]
fn failed_work_precision_settings_are_reported_not_nan() {
    let o = oneblock(&[
        "work-precision",
        "--preset",
        "intermittent",
        "--points",
        "1",
        "--min-time-ms",
        "0",
        "--only",
        "rk4",
        "--out",
        "-",
    ]);
    assert_ok(&o);
    let out = stdout(&o);
    assert!(!out.contains("NaN") && !out.contains("inf"), "{out}");
    let body: String = out
        .lines()
        .filter(|l| !l.starts_with('#'))
        .collect::<Vec<_>>()
        .join("\n");
    let (header, rows) = parse_csv(&body);
    let col = |n: &str| header.iter().position(|h| h == n).unwrap();
    let (points, failed, max_error) = (col("points"), col("failed"), col("max_error"));
    let mut n_failed = 0;
    for r in &rows {
        if r[failed] == r[points] {
            n_failed += 1;
            assert!(r[max_error].is_empty(), "{r:?}");
        } else {
            assert!(num(&r[max_error]).is_finite(), "{r:?}");
        }
    }
    // RK4 at step 0.1 cannot resolve this slip: at least that one fails,
    // and the summary says how many did.
    assert!(n_failed >= 1, "{out}");
    let err = stderr(&o);
    assert!(
        err.contains(&format!("({n_failed} failed on every point")),
        "{err}"
    );
}

/// The slow cycle of the issue: stopped by --max-seconds, one line, exit 1,
/// nothing on stdout; a bad --max-seconds is refused (exit 2).
#[test]
fn cycle_and_bench_worker_stop_at_max_seconds() {
    let slow = [
        "cycle",
        "--kappa",
        "1e-6",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--theta-nu",
        "1",
        "--period",
        "64",
        "--theta",
        "1",
    ];
    let t0 = Instant::now();
    let o = run(&with(&slow, &["--max-seconds", "1"]));
    if o.status.success() {
        // A machine fast enough to finish in a second: nothing to stop.
        return;
    }
    let err = one_error_line(&o, 1);
    assert!(err.contains("--max-seconds") && err.contains("nothing was written"));
    assert!(o.stdout.is_empty());
    assert!(t0.elapsed() < Duration::from_secs(10));
    let o = run(&with(&slow, &["--max-seconds", "0"]));
    assert!(one_error_line(&o, 2).contains("--max-seconds"));

    let t0 = Instant::now();
    let o = oneblock(&["bench-worker", "--repeats", "100", "--max-seconds", "0.5"]);
    let err = one_error_line(&o, 1);
    assert!(err.contains("--max-seconds"), "{err}");
    assert!(o.stdout.is_empty(), "{}", stdout(&o));
    assert!(t0.elapsed() < Duration::from_secs(10));
}

/// Ctrl+C (SIGINT) stops `cycle` cleanly: exit 1, one line, nothing
/// written.
#[cfg(unix)]
#[test]
fn ctrl_c_stops_cycle_with_one_line() {
    let child = Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args([
            "cycle",
            "--kappa",
            "1e-6",
            "--gamma",
            "6.5",
            "--nu",
            "1e-3",
            "--theta-nu",
            "1",
            "--period",
            "64",
            "--theta",
            "1",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let o = child.wait_with_output().unwrap();
    if o.status.success() {
        return; // finished before the signal
    }
    let err = one_error_line(&o, 1);
    assert!(err.contains("Ctrl+C") && err.contains("nothing was written"));
    assert!(o.stdout.is_empty());
}

#[test]
fn two_null_outputs_are_allowed_and_write_failures_name_their_flag() {
    let o = oneblock(&[
        "orbit",
        "--preset",
        "fig3b",
        "--transient",
        "2",
        "--keep",
        "3",
        "--out",
        "/dev/null",
        "--stats",
        "/dev/null",
    ]);
    assert_ok(&o);
    if std::path::Path::new("/dev/full").exists() {
        // A write that fails during the run: exit 1, the flag named.
        let o = oneblock(&[
            "orbit",
            "--preset",
            "fig3b",
            "--transient",
            "2",
            "--keep",
            "3",
            "--out",
            "/dev/null",
            "--stats",
            "/dev/full",
        ]);
        let err = one_error_line(&o, 1);
        assert!(err.contains("--stats"), "{err}");
    }
}

/// `continue --param theta-nu` needs no --theta-nu: --from and --to set
/// it (an empty range is then the first thing refused, by its flag).
#[test]
fn the_varied_parameter_needs_no_flag_of_its_own() {
    let o = oneblock(&[
        "continue", "--kappa", "18.95", "--gamma", "6.5", "--nu", "1e-3", "--param", "theta-nu",
        "--from", "1.07", "--to", "1.07", "--period", "1", "--out", "-",
    ]);
    let err = one_error_line(&o, 2);
    assert!(err.contains("--to") && err.contains("empty"), "{err}");
    // Another model flag left out is still required, by name.
    let o = oneblock(&[
        "continue", "--gamma", "6.5", "--nu", "1e-3", "--param", "theta-nu", "--from", "1.07",
        "--to", "1.11", "--period", "1", "--out", "-",
    ]);
    assert!(one_error_line(&o, 2).contains("--kappa"));
}

/// `trajectory --events`' bound is what the 2e6-sample cap allows: a cycle
/// records at least 5 samples, however coarse the spacing (measured here),
/// so 400000 cycles fit and more are refused up front, naming --events.
#[test]
fn trajectory_events_range_is_what_the_sample_cap_allows() {
    let o = oneblock(&[
        "trajectory",
        "--preset",
        "fig3b",
        "--events",
        "20",
        "--spacing",
        "1e6",
        "--out",
        "-",
    ]);
    assert_ok(&o);
    let rows = stdout(&o).lines().filter(|l| !l.starts_with('#')).count() - 1;
    let per_cycle = rows as f64 / 20.0;
    assert!((5.0..6.0).contains(&per_cycle), "{rows} rows for 20 cycles");
    assert!(400_000.0 * per_cycle <= 2.0e6 + 400_000.0);
    let o = oneblock(&[
        "trajectory",
        "--preset",
        "fig3b",
        "--events",
        "400001",
        "--out",
        "-",
    ]);
    let err = one_error_line(&o, 2);
    assert!(err.contains("--events") && err.contains("400000"), "{err}");
}

/// A session whose keys hold control characters (an escape sequence), read
/// where no window can open: the warning about them is escaped and folded
/// into the error's one line.
#[cfg(feature = "gui")]
#[test]
fn a_warning_then_an_error_is_one_escaped_line() {
    let dir = tempfile::tempdir().unwrap();
    let s = dir.path().join("s.json");
    std::fs::write(
        &s,
        "{\"oneblock_session\": 1, \"settings\": {\"\\u001b[31mred\": 1}, \"x\\ny\": 2}",
    )
    .unwrap();
    let o = gui_session(&s, &dir.path().join("shot.png"));
    let err = stderr(&o);
    assert!(!o.status.success());
    assert_eq!(err.lines().count(), 1, "{err:?}");
    assert!(!err.contains('\u{1b}'), "{err:?}");
    assert!(
        err.contains("\\u{1b}[31mred") && err.contains("x\\ny"),
        "{err}"
    );
}

/// The attractor search before a branch (no --theta) is bounded too: a
/// limit shorter than the search stops it, one line, exit 1, no file.
#[test]
fn continues_attractor_search_stops_at_max_seconds() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b.csv");
    let o = Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args([
            "continue",
            "--preset",
            "fig4",
            "--param",
            "theta-nu",
            "--from",
            "0.1",
            "--to",
            "1.55",
            "--period",
            "1",
            "--max-seconds",
            "0.0001",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    let err = one_error_line(&o, 1);
    assert!(
        err.contains("--max-seconds") && err.contains("nothing was written"),
        "{err}"
    );
    assert!(!out.exists());
}

/// An output in a folder where no file can be made is found before any
/// work, by trying to make one: a read-only file system refuses even root,
/// whose permission bits say yes. /proc stands in for a read-only mount
/// (it accepts no new files); the run is long enough that finding the
/// problem afterwards would take seconds, not milliseconds.
#[test]
fn an_output_where_no_file_can_be_made_is_refused_before_the_run() {
    if !std::path::Path::new("/proc/self").exists() {
        eprintln!("note: no /proc here; skipped");
        return;
    }
    let started = Instant::now();
    let o = oneblock(&[
        "bifurcation",
        "--preset",
        "fig3b",
        "--columns",
        "400",
        "--transient",
        "2000",
        "--keep",
        "500",
        "--out",
        "/proc/oneblock-out.csv",
    ]);
    let err = one_error_line(&o, 2);
    assert!(err.contains("--out"), "{err}");
    assert!(
        started.elapsed() < Duration::from_secs(5),
        "refused only after {:?}",
        started.elapsed()
    );
}

/// `attractors` is bounded like every long command: a limit shorter than
/// its search stops it with one line, exit 1, and nothing on stdout.
#[test]
fn attractors_stops_at_max_seconds() {
    // RK4 at a step of 1e-4 takes tens of seconds for Fig. 3b's 64 seeds
    // (every preset's seeds at the default accuracy now finish within the
    // first 50 ms the limit is polled at).
    let o = oneblock(&[
        "attractors",
        "--preset",
        "fig3b",
        "--method",
        "rk4",
        "--step",
        "1e-4",
        "--max-seconds",
        "0.001",
    ]);
    let err = one_error_line(&o, 1);
    assert!(err.contains("--max-seconds"), "{err}");
    assert!(o.stdout.is_empty());
}

/// `figure` is bounded too (a large phase grid takes a while): one line,
/// exit 1, no file.
#[cfg(feature = "gui")]
#[test]
fn figure_stops_at_max_seconds() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("phase.svg");
    let o = oneblock(&[
        "figure",
        "--view",
        "phase",
        "--kappa-steps",
        "60",
        "--theta-nu-steps",
        "60",
        "--max-seconds",
        "0.001",
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = one_error_line(&o, 1);
    assert!(err.contains("--max-seconds"), "{err}");
    assert!(!out.exists());
}
