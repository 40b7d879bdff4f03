//! Every CSV a command writes begins with `#` lines saying where it came
//! from: the program and its version, the command line as run, the
//! model's parameters with the solver's accuracy (a preset's values
//! written out), and every flag's value, defaults included. The csv crate
//! reads past them (`comment(Some(b'#'))`) to the same header and rows.

use crate::cli_support;

use cli_support::{assert_ok, run};

/// The `#` lines of `text`, and its header and rows as the csv crate
/// reads them when told that `#` starts a comment (every row as wide as
/// the header).
fn read(text: &str) -> (Vec<&str>, Vec<String>, Vec<csv::StringRecord>) {
    let comments: Vec<&str> = text.lines().take_while(|l| l.starts_with('#')).collect();
    let mut r = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let header: Vec<String> = r
        .headers()
        .expect("a header row")
        .iter()
        .map(str::to_string)
        .collect();
    let rows: Vec<csv::StringRecord> = r.records().map(|x| x.expect("a row")).collect();
    for row in &rows {
        assert_eq!(row.len(), header.len(), "{row:?} under {header:?}");
    }
    (comments, header, rows)
}

/// Checks the `#` lines of a CSV written by `oneblock ARGS`: the program,
/// the command line, the model (with `model` in it), the flags (with
/// `flag` in them).
fn check_header(comments: &[&str], args: &[String], model: &str, flag: &str) {
    assert_eq!(comments.len(), 4, "{comments:?}");
    assert_eq!(
        comments[0],
        format!("# oneblock {}", env!("CARGO_PKG_VERSION"))
    );
    assert_eq!(
        comments[1],
        format!("# command: oneblock {}", args.join(" "))
    );
    assert!(
        comments[2].starts_with("# model: ") && comments[2].contains(model),
        "{} should name {model}",
        comments[2]
    );
    assert!(
        comments[3].starts_with("# settings: --") && comments[3].contains(flag),
        "{} should hold {flag}",
        comments[3]
    );
}

fn args(s: &str) -> Vec<String> {
    s.split_whitespace().map(str::to_string).collect()
}

#[test]
fn every_command_csv_on_stdout_begins_with_where_it_came_from() {
    // (command line, what the model line names, a flag's default that the
    // settings line spells out, a column of the header).
    let cases = [
        (
            "orbit --preset fig3b --transient 50 --keep 20 --out -",
            // fig3b's κ, written out though only the preset was given.
            "kappa = 18.95, gamma = 6.5",
            "--map=auto",
            "slip_distance",
        ),
        (
            "bifurcation --preset fig3b --columns 3 --transient 50 --keep 2 --out -",
            "dop853 tol 1e-10",
            "--seeds=0",
            "lyapunov",
        ),
        (
            "phase --preset fig4 --kappa-from 2 --kappa-to 16 --kappa-steps 2 \
             --theta-nu-from 0.5 --theta-nu-to 1.2 --theta-nu-steps 2 --out -",
            "vary over the grid",
            "--keep=128",
            "class",
        ),
        (
            "trajectory --preset fig3b --transient 5 --events 2 --out -",
            // fig3b's θν, with κ, γ, ν and Ω.
            "kappa = 18.95, gamma = 6.5, nu = 0.001, theta-nu = 1, omega = 50",
            "--spacing=",
            "phase",
        ),
        (
            "continue --preset fig3b --param theta-nu --from 1.0 --to 1.05 --period 1 --out -",
            "kappa = 18.95",
            "--param=theta-nu",
            "multiplier",
        ),
    ];
    for (line, model, flag, column) in cases {
        let a = args(line);
        let o = run(&a);
        assert_ok(&o);
        let text = String::from_utf8(o.stdout).expect("utf-8");
        let (comments, header, rows) = read(&text);
        check_header(&comments, &a, model, flag);
        assert!(comments[2].starts_with("# model: kappa = "), "{line}");
        assert!(header.iter().any(|h| h == column), "{line}: {header:?}");
        assert!(!rows.is_empty(), "{line}: no rows");
    }
}

#[test]
fn csv_files_and_second_outputs_carry_the_lines_too() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = |n: &str| dir.path().join(n).display().to_string();
    let cases = [
        (
            format!(
                "continue --preset fig3b --param theta-nu --from 1.0 --to 1.2 --period 1 --out {} --points {}",
                file("branch.csv"),
                file("points.csv")
            ),
            vec!["branch.csv", "points.csv"],
        ),
        (
            format!(
                "orbit --preset intermittent --tol 1e-8 --transient 100 --keep 300 --no-lyapunov --stats {}",
                file("stats.csv")
            ),
            vec!["stats.csv"],
        ),
        (
            format!(
                "work-precision --preset fig3b --points 2 --min-time-ms 0 --only dop853 --out {}",
                file("wp.csv")
            ),
            vec!["wp.csv"],
        ),
    ];
    for (line, files) in cases {
        let a = args(&line);
        assert_ok(&run(&a));
        for f in files {
            let text = std::fs::read_to_string(dir.path().join(f)).expect("written");
            let comments: Vec<&str> = text.lines().take_while(|l| l.starts_with('#')).collect();
            // The provenance first; a command's own notes may follow.
            check_header(&comments[..4], &a, "", "--");
            let (_, header, _) = read(&text);
            assert!(header.len() > 1, "{f}: {header:?}");
        }
    }
}

#[test]
fn a_value_with_a_newline_keeps_every_comment_on_its_line() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("a\nb.csv");
    let a = vec![
        "orbit".to_string(),
        "--preset".into(),
        "fig3b".into(),
        "--transient".into(),
        "5".into(),
        "--keep".into(),
        "3".into(),
        "--out".into(),
        out.display().to_string(),
    ];
    assert_ok(&run(&a));
    let text = std::fs::read_to_string(&out).expect("written");
    let (comments, header, rows) = read(&text);
    assert_eq!(comments.len(), 4, "{comments:?}");
    assert!(
        comments[1].contains("'") && comments[1].contains("a\\nb.csv"),
        "{}",
        comments[1]
    );
    assert_eq!(header[0], "theta");
    assert_eq!(rows.len(), 3);
}
