//! The command line under hostile input, as a user runs it: outputs never
//! clobbered through a link or by each other, failed writes reported, long
//! runs bounded in time and showing life, huge requests refused or bounded
//! in memory, presets everywhere, and results outside the model flagged.

#![allow(clippy::unwrap_used)]

mod cli_support;

use cli_support::*;
use std::path::Path;
use std::process::{Command, Output, Stdio};

/// No panic, no abort, no non-finite number anywhere in the output.
fn assert_sane(o: &Output) {
    let (out, err) = (stdout(o), stderr(o));
    assert!(
        !err.contains("panicked") && !err.contains("memory allocation"),
        "{err}"
    );
    for text in [&out, &err] {
        for word in text.split(|c: char| c == ',' || c.is_whitespace()) {
            assert!(
                !matches!(word, "inf" | "-inf" | "NaN"),
                "non-finite number in output: {text}"
            );
        }
    }
}

fn assert_bad_input(args: &[&str], flag: &str) {
    let o = oneblock(args);
    assert_sane(&o);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
    assert!(err.contains(flag), "{args:?} should name {flag}: {err}");
}

#[cfg(unix)]
#[test]
fn force_through_a_symlink_writes_the_target_and_keeps_the_link() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("real.csv");
    let link = dir.path().join("link.csv");
    std::fs::write(&target, "old").unwrap();
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let l = link.to_str().unwrap();
    let args = [&["trajectory"][..], &FIG3B, &["--out", l]].concat();
    let o = oneblock(&args);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--force"), "{}", stderr(&o));
    let o = oneblock(&[&args[..], &["--force"]].concat());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    let text = std::fs::read_to_string(&target).unwrap();
    // The new CSV: its provenance lines, then the header.
    assert!(text.starts_with("# oneblock "), "{text}");
    assert!(text.contains("\nt,x,y,u,w,phase\n"), "{text}");
}

#[test]
fn two_outputs_naming_one_file_are_refused_before_work() {
    let dir = tempfile::tempdir().unwrap();
    let same = dir.path().join("same.x");
    let s = same.to_str().unwrap();
    let alias = format!("{}/./same.x", dir.path().display());
    let phase = [
        "phase",
        "--preset",
        "fig4",
        "--kappa-from",
        "1",
        "--kappa-to",
        "2",
        "--kappa-steps",
        "2",
        "--theta-nu-steps",
        "2",
        "--force",
    ];
    assert_bad_input(
        &[&phase[..], &["--out", s, "--png", &alias]].concat(),
        "--png",
    );
    assert!(!same.exists(), "nothing written");
    assert_bad_input(&["work-precision", "--out", s, "--svg", s], "--svg");
}

#[test]
fn a_failed_or_closed_stdout_is_an_error() {
    let args = [&["map"][..], &FIG3B, &["--theta", "0.5"]].concat();
    if Path::new("/dev/full").exists() {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let o = Command::new(env!("CARGO_BIN_EXE_oneblock"))
            .args(&args)
            .stdout(full)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        assert!(stderr(&o).contains("stdout"), "{}", stderr(&o));
    }
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::process::CommandExt;
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_oneblock"));
        cmd.args(&args).stderr(Stdio::piped());
        // SAFETY: close(2) on descriptor 1 of the child only.
        unsafe {
            cmd.pre_exec(|| {
                libc::close(1);
                Ok(())
            });
        }
        let o = cmd.output().unwrap();
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        assert!(stderr(&o).contains("closed"), "{}", stderr(&o));
    }
}

#[test]
fn a_filter_that_matches_nothing_names_the_valid_values() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("wp.csv");
    let o = oneblock(&[
        "work-precision",
        "--only",
        "dp853",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("--only") && err.contains("dop853") && err.contains("euler"),
        "{err}"
    );
}

#[test]
fn the_issues_hostile_commands_are_answered() {
    let fig3b_sweep = ["--kappa", "18.95", "--gamma", "6.5", "--nu", "1e-3"];
    // Bounds, named flags, short numbers.
    for (args, flag) in [
        (vec!["gui", "--timeout", "1e300"], "--timeout"),
        (
            vec![
                "bench-worker",
                "--columns",
                "8",
                "--coarse",
                "4",
                "--transient",
                "18446744073709551615",
                "--keep",
                "1",
            ],
            "--transient",
        ),
        (
            vec![
                "bench-worker",
                "--transient",
                "9223372036854775807",
                "--keep",
                "9223372036854775809",
            ],
            "--transient",
        ),
        (vec!["bench-worker", "--columns", "1e15"], "--columns"),
        (vec!["bench-worker", "--threads", "1e15"], "--threads"),
        (
            vec!["bench-worker", "--transient", "1000000000000"],
            "--transient",
        ),
        (vec!["orbit", "--preset", "fig3b", "--keep", "-1"], "--keep"),
        (
            [
                &["bifurcation"][..],
                &fig3b_sweep,
                &["--theta-nu-from", "-1e308", "--theta-nu-to", "1e308"],
            ]
            .concat(),
            "--theta-nu-from",
        ),
        (
            vec![
                "phase",
                "--preset",
                "fig4",
                "--kappa-from",
                "1",
                "--kappa-to",
                "1e308",
                "--kappa-steps",
                "2",
                "--theta-nu-steps",
                "2",
            ],
            "--kappa-to",
        ),
        (
            vec![
                "phase",
                "--preset",
                "fig4",
                "--kappa-from",
                "1e308",
                "--kappa-to",
                "2",
                "--kappa-steps",
                "2",
                "--theta-nu-steps",
                "2",
            ],
            "--kappa-from",
        ),
        (
            vec![
                "phase",
                "--preset",
                "fig4",
                "--kappa-from",
                "1",
                "--kappa-to",
                "1e-300",
                "--kappa-steps",
                "2",
                "--theta-nu-steps",
                "2",
            ],
            "--kappa-to",
        ),
        (
            [
                &["trajectory"][..],
                &FIG3B,
                &["--events", "1000", "--spacing", "1e-6"],
            ]
            .concat(),
            "--spacing",
        ),
    ] {
        assert_bad_input(&args, flag);
        let err = stderr(&oneblock(&args));
        assert!(err.len() < 300, "short message: {err}");
    }
    let o = oneblock(&[
        "phase",
        "--preset",
        "fig4",
        "--kappa-from",
        "1e308",
        "--kappa-to",
        "2",
        "--kappa-steps",
        "2",
        "--theta-nu-steps",
        "2",
    ]);
    assert!(stderr(&o).contains("1e308"), "{}", stderr(&o));
}

#[test]
fn a_long_transient_is_bounded_in_time_and_memory() {
    // 1e11 transient iterates per column: the old code allocated them all
    // (800 GB) before the first; now the column streams its transient and
    // --max-seconds stops the run with nothing written.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bif.csv");
    let o = oneblock(&[
        "bifurcation",
        "--preset",
        "chaos",
        "--theta-nu-from",
        "1.2",
        "--theta-nu-to",
        "1.25",
        "--columns",
        "2",
        "--transient",
        "1e11",
        "--keep",
        "1",
        "--max-seconds",
        "1.5",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_sane(&o);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("--max-seconds"), "{}", stderr(&o));
    assert!(!out.exists(), "nothing half-done is written");
    #[cfg(target_os = "linux")]
    {
        // The largest child this test binary has waited for so far.
        let mut ru: libc::rusage = unsafe { std::mem::zeroed() };
        // SAFETY: getrusage fills the struct it is given.
        assert_eq!(
            unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut ru) },
            0
        );
        let peak_mb = ru.ru_maxrss as f64 / 1024.0;
        assert!(peak_mb < 300.0, "peak RSS {peak_mb:.0} MB");
    }
}

#[test]
fn long_runs_show_life_off_a_terminal() {
    // stderr is a pipe here: a progress line every 5 s.
    let o = oneblock(&[
        "orbit",
        "--preset",
        "chaos",
        "--transient",
        "1e9",
        "--keep",
        "1",
        "--max-seconds",
        "6",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("orbit: ") && err.contains("iterates ("),
        "{err}"
    );
    assert!(o.stdout.is_empty(), "no half summary");
}

#[test]
fn presets_work_everywhere_and_flags_override_them() {
    let o = oneblock(&["map", "--preset", "fig3b", "--theta", "0.5", "--json"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    // docs/model.md's first worked example is Fig. 3b at θ = 0.5.
    assert!(
        (j["theta_next"].as_f64().unwrap() - 0.2037551562).abs() < 1e-9,
        "{j}"
    );
    let o = oneblock(&[
        "map",
        "--preset",
        "fig3b",
        "--kappa",
        "10",
        "--theta-nu",
        "1.2",
        "--theta",
        "1.0",
        "--json",
    ]);
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    // docs/model.md's fourth worked example: κ = 10, θν = 1.2 over Fig. 3b's γ, ν.
    assert!(
        (j["theta_next"].as_f64().unwrap() + 0.2667076065).abs() < 1e-9,
        "{j}"
    );
    assert_eq!(j["params"]["gamma"].as_f64(), Some(6.5));
    for args in [
        vec![
            "orbit",
            "--preset",
            "creep",
            "--transient",
            "5",
            "--keep",
            "3",
            "--json",
        ],
        vec!["trajectory", "--preset", "fig3a", "--events", "1"],
        vec![
            "bifurcation",
            "--preset",
            "fig3b",
            "--columns",
            "2",
            "--transient",
            "3",
            "--keep",
            "2",
        ],
        vec![
            "phase",
            "--preset",
            "fig4",
            "--kappa-from",
            "1",
            "--kappa-to",
            "2",
            "--kappa-steps",
            "2",
            "--theta-nu-steps",
            "2",
            "--transient",
            "5",
            "--keep",
            "16",
        ],
    ] {
        let o = oneblock(&args);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {}", stderr(&o));
        assert_sane(&o);
    }
    assert_bad_input(&["map", "--preset", "fig9", "--theta", "0.5"], "--preset");
    assert_bad_input(&["map", "--kappa", "1", "--theta", "0.5"], "--gamma");
}

#[test]
fn results_outside_the_model_are_flagged() {
    // ν = 0.1 is outside the slow-pulling assumption: computed, with a warning.
    let o = oneblock(&["map", "--preset", "fig3b", "--nu", "0.1", "--theta", "1"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("warning: nu = 0.1 is outside"),
        "{}",
        stderr(&o)
    );
    let o = oneblock(&[
        "map", "--preset", "fig3b", "--omega", "1e-6", "--theta", "1",
    ]);
    assert!(
        stderr(&o).contains("warning: omega = 1e-6 is below"),
        "{}",
        stderr(&o)
    );
    let o = oneblock(&["map", "--preset", "fig3b", "--theta", "1"]);
    assert!(
        stderr(&o).is_empty(),
        "the paper's point is inside: {}",
        stderr(&o)
    );
}

#[test]
fn counts_accept_exponents() {
    let o = oneblock(&[
        "orbit",
        "--preset",
        "fig3b",
        "--transient",
        "1e1",
        "--keep",
        "2e0",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(
        (j["transient"].as_u64(), j["keep"].as_u64()),
        (Some(10), Some(2))
    );
    assert_bad_input(&["orbit", "--preset", "fig3b", "--keep", "1.5"], "--keep");
}
