//! Property tests of every command's argument parser and checks, driven in
//! this process (no binary spawned): any string given to any flag is either
//! accepted or refused as bad input (what the binary answers with exit
//! code 2), with one line of message, and never a panic.

#![allow(clippy::unwrap_used)]

use std::panic::{AssertUnwindSafe, catch_unwind};

use clap::Parser;
use oneblock::cli::{Cli, CliError, usage_line, validate};
use proptest::prelude::*;

fn cat<'a>(a: &[&'a str], b: &[&'a str]) -> Vec<&'a str> {
    [a, b].concat()
}

/// Each command with a valid command line and the flags that take a value.
// A table of command lines, one entry per subcommand: long, not complex
// (the 150-line rule is for src/).
#[allow(clippy::too_many_lines)]
fn commands(dir: &str) -> Vec<(Vec<String>, Vec<&'static str>)> {
    let out = format!("{dir}/out.csv");
    let png = format!("{dir}/out.png");
    let svg = format!("{dir}/out.svg");
    let model = [
        "--kappa",
        "18.95",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--theta-nu",
        "1.0",
    ];
    let model_flags = [
        "--kappa",
        "--gamma",
        "--nu",
        "--theta-nu",
        "--omega",
        "--preset",
        "--method",
        "--tol",
    ];
    let v = |xs: &[&str]| xs.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    vec![
        (
            v(&cat(&cat(&["map"], &model), &["--theta", "0.5"])),
            cat(&model_flags, &["--theta"]),
        ),
        (
            v(&cat(
                &cat(&["orbit"], &model),
                &["--transient", "10", "--keep", "5", "--out", &out],
            )),
            cat(
                &model_flags,
                &[
                    "--theta0",
                    "--transient",
                    "--keep",
                    "--out",
                    "--period-tol",
                    "--max-seconds",
                ],
            ),
        ),
        (
            v(&cat(
                &cat(&["trajectory"], &model),
                &["--events", "2", "--out", &out],
            )),
            cat(
                &model_flags,
                &[
                    "--theta0",
                    "--transient",
                    "--events",
                    "--spacing",
                    "--out",
                    "--max-seconds",
                ],
            ),
        ),
        (
            v(&[
                "bifurcation",
                "--kappa",
                "18.95",
                "--gamma",
                "6.5",
                "--nu",
                "1e-3",
                "--columns",
                "4",
                "--out",
                &out,
            ]),
            vec![
                "--kappa",
                "--gamma",
                "--nu",
                "--omega",
                "--preset",
                "--tol",
                "--theta-nu-from",
                "--theta-nu-to",
                "--columns",
                "--transient",
                "--keep",
                "--theta0",
                "--out",
                "--max-seconds",
            ],
        ),
        (
            v(&[
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
                "3",
                "--theta-nu-steps",
                "3",
                "--out",
                &out,
                "--png",
                &png,
            ]),
            vec![
                "--gamma",
                "--nu",
                "--omega",
                "--preset",
                "--kappa-from",
                "--kappa-to",
                "--kappa-steps",
                "--theta-nu-from",
                "--theta-nu-to",
                "--theta-nu-steps",
                "--transient",
                "--keep",
                "--period-tol",
                "--threads",
                "--out",
                "--png",
                "--max-seconds",
            ],
        ),
        (
            v(&["work-precision", "--out", &out, "--svg", &svg]),
            vec![
                "--preset",
                "--kappa",
                "--gamma",
                "--nu",
                "--theta-nu",
                "--omega",
                "--theta0",
                "--points",
                "--min-time-ms",
                "--only",
                "--out",
                "--svg",
                "--max-seconds",
            ],
        ),
        (
            v(&["bench-worker"]),
            vec![
                "--columns",
                "--coarse",
                "--transient",
                "--keep",
                "--tol",
                "--threads",
                "--repeats",
                "--latency-samples",
                "--phase",
            ],
        ),
        (
            v(&["gui"]),
            vec![
                "--preset",
                "--size",
                "--view",
                "--font-scale",
                "--timeout",
                "--tour-step",
            ],
        ),
    ]
}

/// Values a hostile user types: numbers of every size and form, and junk.
fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        any::<f64>().prop_map(|x| x.to_string()),
        any::<f64>().prop_map(|x| format!("{x:e}")),
        any::<i64>().prop_map(|x| x.to_string()),
        any::<u64>().prop_map(|x| x.to_string()),
        (-400i32..400).prop_map(|e| format!("1e{e}")),
        (-400i32..400).prop_map(|e| format!("-1e{e}")),
        prop::sample::select(vec![
            "NaN",
            "inf",
            "-inf",
            "",
            " ",
            "-",
            "--",
            "-1",
            "0",
            "1.5",
            "0x10",
            "1_000",
            "fig3b",
            "dp853",
            "dop853",
            "rk4",
            "1e3",
            "18446744073709551616",
            "1280x800",
            "0x0",
            "/",
            ".",
            "/dev/null",
            "/proc/self/x",
            "über",
            "∞",
        ])
        .prop_map(String::from),
        "\\PC{0,12}",
    ]
}

/// Parses and checks `argv` as the binary does; returns the exit code it
/// would give before any work (0 when it would go on to run).
fn exit_code(argv: &[String]) -> Result<i32, String> {
    let full: Vec<String> = std::iter::once("oneblock".to_string())
        .chain(argv.iter().cloned())
        .collect();
    let r = catch_unwind(AssertUnwindSafe(|| match Cli::try_parse_from(&full) {
        Err(e) => {
            let line = usage_line(&e);
            if line.lines().count() != 1 {
                return Err(format!("parser message is not one line: {line:?}"));
            }
            Ok(2)
        }
        Ok(cli) => match validate(&cli) {
            Ok(()) => Ok(0),
            Err(CliError::Usage(m)) => {
                if m.lines().count() != 1 || !m.contains("--") {
                    return Err(format!("message does not name a flag on one line: {m:?}"));
                }
                if m.len() > 400 {
                    return Err(format!("message too long: {m}"));
                }
                Ok(2)
            }
            Err(CliError::Failed(m)) => Err(format!("a check failed as a run would: {m}")),
        },
    }));
    r.map_err(|_| format!("panicked on {argv:?}"))?
}

fn with_value(base: &[String], flag: &str, value: &str) -> Vec<String> {
    let mut argv = base.to_vec();
    match argv.iter().position(|a| a == flag) {
        Some(i) => argv[i + 1] = value.to_string(),
        None => {
            argv.push(flag.to_string());
            argv.push(value.to_string());
        }
    }
    argv
}

#[test]
fn the_valid_command_lines_pass_their_checks() {
    let dir = tempfile::tempdir().unwrap();
    for (argv, _) in commands(dir.path().to_str().unwrap()) {
        assert_eq!(exit_code(&argv), Ok(0), "{argv:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 600, .. ProptestConfig::default() })]
    #[test]
    fn any_value_for_any_flag_is_accepted_or_bad_input(
        which in 0usize..8,
        flag_pick in any::<prop::sample::Index>(),
        v in value(),
        v2 in value(),
        second in any::<bool>(),
    ) {
        let dir = tempfile::tempdir().unwrap();
        let cmds = commands(dir.path().to_str().unwrap());
        let (base, flags) = &cmds[which];
        let flag = flag_pick.get(flags);
        let mut argv = with_value(base, flag, &v);
        if second {
            // Two flags at once: combinations (transient × keep, from × to).
            let other = flags[(flag_pick.index(flags.len()) + 1) % flags.len()];
            argv = with_value(&argv, other, &v2);
        }
        let code = exit_code(&argv);
        prop_assert!(matches!(code, Ok(0) | Ok(2)), "{argv:?}: {code:?}");
    }
}
