//! Running the `oneblock` binary as a user does, for the command-line tests.

#![allow(dead_code)]

use std::process::{Command, Output};

/// docs/model.md's first worked example.
pub const FIG3B: [&str; 8] = [
    "--kappa",
    "18.95",
    "--gamma",
    "6.5",
    "--nu",
    "1e-3",
    "--theta-nu",
    "1.0",
];

pub fn oneblock(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args(args)
        .output()
        .expect("the oneblock binary runs")
}

pub fn with(base: &[&str], more: &[&str]) -> Vec<String> {
    base.iter().chain(more).map(|s| s.to_string()).collect()
}

pub fn run(args: &[String]) -> Output {
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    oneblock(&refs)
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).expect("stdout is UTF-8")
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8(o.stderr.clone()).expect("stderr is UTF-8")
}

pub fn assert_ok(o: &Output) {
    assert!(
        o.status.success(),
        "exit {:?}, stderr:\n{}",
        o.status.code(),
        stderr(o)
    );
}

/// Parses a CSV with a header into (header, rows of cells), past the `#`
/// lines saying where it came from.
pub fn parse_csv(text: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header = lines
        .next()
        .expect("a header line")
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

pub fn num(cell: &str) -> f64 {
    cell.parse()
        .unwrap_or_else(|e| panic!("'{cell}' is not a number: {e}"))
}

pub fn map_args(more: &[&str]) -> Vec<String> {
    with(
        &with(&["map"], &FIG3B)
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
        more,
    )
}

pub fn cmd_args(cmd: &str, more: &[&str]) -> Vec<String> {
    with(
        &with(&[cmd], &FIG3B)
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
        more,
    )
}

/// Exit code 2, one line on stderr naming `flag`, no panic.
pub fn assert_bad_input(args: &[String], flag: &str) {
    let o = run(args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: stderr {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
    assert!(err.contains(flag), "{args:?} should name {flag}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(o.stdout.is_empty(), "{args:?}: nothing on stdout");
}

/// Replaces the value of `flag` in `args`.
pub fn set(mut args: Vec<String>, flag: &str, value: &str) -> Vec<String> {
    let i = args
        .iter()
        .position(|a| a == flag)
        .unwrap_or_else(|| panic!("no {flag}"));
    args[i + 1] = value.to_string();
    args
}

/// A `continue` run with `args` (no `--out`, `--points`) writing its branch
/// and its special points into a temporary folder: (the run, branch rows,
/// special-point rows), after checking it succeeded.
pub fn continue_run(args: &[&str]) -> (Output, Vec<Vec<String>>, Vec<Vec<String>>) {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let (out, pts) = (dir.path().join("b.csv"), dir.path().join("p.csv"));
    let mut all: Vec<String> = vec!["continue".into()];
    all.extend(args.iter().map(|s| s.to_string()));
    for (flag, path) in [("--out", &out), ("--points", &pts)] {
        all.push(flag.into());
        all.push(path.to_str().expect("a UTF-8 path").into());
    }
    let o = run(&all);
    assert_ok(&o);
    let read =
        |p: &std::path::Path| parse_csv(&std::fs::read_to_string(p).expect("the CSV it wrote")).1;
    let (branch, points) = (read(&out), read(&pts));
    (o, branch, points)
}

/// The largest resident size of any child waited for, in KB: a test that
/// reads it runs in a binary of its own (the suite's children are many).
#[cfg(target_os = "linux")]
pub fn children_peak_kb() -> i64 {
    // SAFETY: getrusage fills the plain C struct it is given.
    unsafe {
        let mut u: libc::rusage = std::mem::zeroed();
        assert_eq!(libc::getrusage(libc::RUSAGE_CHILDREN, &mut u), 0);
        u.ru_maxrss
    }
}
