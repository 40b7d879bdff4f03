//! Every example in the docs is run. docs/cli.md is the command line's
//! reference: it has a section for every subcommand naming every flag. In
//! every page of docs/ and in the README, each ` ```sh ` block followed by
//! ` ```text ` blocks is run (as one script, in an empty folder) and must
//! print what they show: a block's info string names the output
//! (`text stdout`, `text stderr` or `text FILE` for a file the commands
//! wrote), optionally `head` (its first lines) or `some` (these lines in
//! this order among others), and `exit=N` where the commands fail; `…`
//! stands for anything within a line (wall-clock times, this machine's
//! load). A ` ```sh ` block without output (setup) is not run.
//!
//! `UPDATE_DOCS=1 cargo test --release --test suite cli_docs::` rewrites the text
//! blocks from the binary's output (keeping a documented line with `…`
//! where it still matches), so that drift is fixed in one command.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::process::Command;

use clap::CommandFactory;
use oneblock::cli::Cli;

fn docs() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/cli.md")).unwrap()
}

#[test]
fn every_subcommand_and_flag_is_documented() {
    let docs = docs();
    let cli = Cli::command();
    for sub in cli.get_subcommands() {
        let name = sub.get_name();
        if name == "help" {
            continue;
        }
        let heading = format!("## `oneblock {name}`");
        let start = docs
            .find(&heading)
            .unwrap_or_else(|| panic!("docs/cli.md has no section {heading}"));
        let section = &docs[start..];
        let section = &section[..section[3..].find("\n## ").map_or(section.len(), |i| i + 3)];
        for arg in sub.get_arguments() {
            let Some(long) = arg.get_long() else { continue };
            if long == "help" {
                continue;
            }
            // A flag shared by several commands may be described once, in
            // "Common flags" or another section, and named in this one.
            assert!(
                section.contains(&format!("--{long}")) || docs.contains(&format!("`--{long}")),
                "docs/cli.md's section on {name} does not name --{long}"
            );
        }
    }
}

/// The pages whose examples are run: every page of docs/ and the README.
fn pages() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = vec![root.join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    docs.sort();
    out.extend(docs);
    out
}

/// Which output a ` ```text ` block shows, and how much of it.
#[derive(Debug, Clone, PartialEq)]
struct Shown {
    /// `stdout`, `stderr`, or a file the commands wrote.
    source: String,
    /// `exact`: every line; `head`: the first lines; `some`: these lines
    /// in this order among others.
    how: String,
}

/// An example: a ` ```sh ` block (run as one script in an empty folder,
/// `oneblock` being this build and `cargo run --release --` standing for
/// it) and the ` ```text ` blocks after it that show its output.
struct Example {
    page: String,
    script: String,
    /// The exit code the commands end with (`exit=N` on a block; 0 else).
    code: i32,
    blocks: Vec<Block>,
}

/// One shown output: where it is in the page (the lines between the
/// fences) and what it shows.
struct Block {
    shown: Shown,
    /// Index of the first line after the opening fence, and of the closing fence.
    start: usize,
    end: usize,
    expected: Vec<String>,
}

/// The info string of a ` ```text ` block: `text SOURCE [head|some] [exit=N]`.
fn parse_info(info: &str) -> Result<(Shown, Option<i32>), String> {
    let words: Vec<&str> = info.split_whitespace().collect();
    if words.first() != Some(&"text") || words.len() < 2 {
        return Err(format!(
            "'{info}': a text block says what it shows: text stdout|stderr|FILE [head|some] [exit=N]"
        ));
    }
    let mut how = "exact".to_string();
    let mut code = None;
    for w in &words[2..] {
        if let Some(n) = w.strip_prefix("exit=") {
            code = Some(n.parse().map_err(|_| format!("'{info}': exit=N"))?);
        } else if ["head", "some", "exact"].contains(w) {
            how = w.to_string();
        } else {
            return Err(format!("'{info}': unknown word {w}"));
        }
    }
    Ok((
        Shown {
            source: words[1].to_string(),
            how,
        },
        code,
    ))
}

/// The examples of one page; an error names a text block that does not say
/// what it shows.
fn examples(page: &str, text: &str) -> Result<Vec<Example>, String> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out: Vec<Example> = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        if line == "```sh" {
            let mut script = String::new();
            i += 1;
            while lines[i] != "```" {
                let l = lines[i].replace("cargo run --release -- ", "oneblock ");
                script.push_str(&l);
                script.push('\n');
                i += 1;
            }
            out.push(Example {
                page: page.to_string(),
                script,
                code: 0,
                blocks: Vec::new(),
            });
        } else if let Some(info) = line.strip_prefix("```text") {
            let info = format!("text{info}");
            let (shown, code) = parse_info(&info).map_err(|e| format!("{page}:{}: {e}", i + 1))?;
            let end = (i + 1..lines.len()).find(|&k| lines[k] == "```").unwrap();
            let ex = out
                .last_mut()
                .ok_or_else(|| format!("{page}:{}: a text block before any sh block", i + 1))?;
            if let Some(c) = code {
                ex.code = c;
            }
            ex.blocks.push(Block {
                shown,
                start: i + 1,
                end,
                expected: lines[i + 1..end].iter().map(|s| s.to_string()).collect(),
            });
            i = end;
        } else if line.starts_with("```") && line.len() > 3 {
            // Another language's block (json, toml, ...): skip its body.
            i = (i + 1..lines.len())
                .find(|&k| lines[k] == "```")
                .unwrap_or(lines.len());
        }
        i += 1;
    }
    // A setup block (apt-get, cargo build) shows no output and is not run.
    out.retain(|e| !e.blocks.is_empty());
    Ok(out)
}

/// Whether `line` matches `pattern`, where `…` matches any characters.
fn matches(pattern: &str, line: &str) -> bool {
    let parts: Vec<&str> = pattern.split('…').collect();
    if parts.len() == 1 {
        return pattern == line;
    }
    let (first, last) = (parts[0], parts[parts.len() - 1]);
    if !line.starts_with(first)
        || line.len() < first.len() + last.len()
        || !line[first.len()..].ends_with(last)
    {
        return false;
    }
    let mut rest = &line[first.len()..line.len() - last.len()];
    for p in &parts[1..parts.len() - 1] {
        match rest.find(p) {
            Some(k) => rest = &rest[k + p.len()..],
            None => return false,
        }
    }
    true
}

/// What a block should say given the output `got`: the documented lines
/// where they still match (their `…` kept), the output's lines where they
/// do not. Equal to `expected` exactly when the docs are right.
fn regenerate(how: &str, expected: &[String], got: &[&str]) -> Vec<String> {
    let keep = |e: Option<&String>, g: &str| match e {
        Some(e) if matches(e, g) => e.clone(),
        _ => g.to_string(),
    };
    match how {
        "head" => got
            .iter()
            .take(expected.len().max(1))
            .enumerate()
            .map(|(k, g)| keep(expected.get(k), g))
            .collect(),
        "some" => {
            // Each documented line: kept where a line of the output (after
            // the previous one's) matches it, else the first output line
            // with the same first word (a `name  value` line).
            let mut from = 0;
            expected
                .iter()
                .map(|e| {
                    if let Some(k) = (from..got.len()).find(|&k| matches(e, got[k])) {
                        from = k + 1;
                        return e.clone();
                    }
                    let key = e.split_whitespace().next().unwrap_or("");
                    match (from..got.len()).find(|&k| got[k].split_whitespace().next() == Some(key))
                    {
                        Some(k) => {
                            from = k + 1;
                            got[k].to_string()
                        }
                        None => e.clone(),
                    }
                })
                .collect()
        }
        _ => got
            .iter()
            .enumerate()
            .map(|(k, g)| keep(expected.get(k), g))
            .collect(),
    }
}

/// Runs an example's script in an empty folder: (exit code, stdout,
/// stderr, the folder).
fn run(ex: &Example) -> (i32, String, String, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let bin = Path::new(env!("CARGO_BIN_EXE_oneblock"));
    let path = format!(
        "{}:{}",
        bin.parent().unwrap().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let o = Command::new("sh")
        .arg("-c")
        .arg(format!("set -e\n{}", ex.script))
        .env("PATH", path)
        .current_dir(dir.path())
        .output()
        .unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8(o.stdout).unwrap(),
        String::from_utf8(o.stderr).unwrap(),
        dir,
    )
}

#[test]
fn the_examples_print_what_the_docs_show() {
    let update = std::env::var_os("UPDATE_DOCS").is_some_and(|v| v == "1");
    let mut failures = Vec::new();
    let mut count = 0;
    for page in pages() {
        let name = page
            .strip_prefix(env!("CARGO_MANIFEST_DIR"))
            .unwrap()
            .display()
            .to_string();
        let text = std::fs::read_to_string(&page).unwrap();
        let exs = examples(&name, &text).unwrap_or_else(|e| panic!("{e}"));
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        // Blocks are rewritten from the page's end so that earlier indices hold.
        let mut rewrites: Vec<(usize, usize, Vec<String>)> = Vec::new();
        for ex in &exs {
            // The window's drawing (figure, gui) is not in a build without
            // the gui feature; those examples run in the default build.
            let windowed = ["oneblock figure", "oneblock gui"];
            if !cfg!(feature = "gui") && windowed.iter().any(|w| ex.script.contains(w)) {
                continue;
            }
            count += 1;
            let (code, stdout, stderr, dir) = run(ex);
            if code != ex.code {
                failures.push(format!(
                    "{}: `{}` exited with {code}, not {}: {stderr}",
                    ex.page,
                    ex.script.trim(),
                    ex.code
                ));
                continue;
            }
            for b in &ex.blocks {
                let file;
                let out = match b.shown.source.as_str() {
                    "stdout" => &stdout,
                    "stderr" => &stderr,
                    f => {
                        file = std::fs::read_to_string(dir.path().join(f)).unwrap_or_default();
                        &file
                    }
                };
                let got: Vec<&str> = out.lines().collect();
                let want = regenerate(&b.shown.how, &b.expected, &got);
                if want != b.expected {
                    if update {
                        rewrites.push((b.start, b.end, want));
                    } else {
                        failures.push(format!(
                            "{}:{}: `{}` {} ({}) differs; shown\n{}\nprinted\n{}",
                            ex.page,
                            b.start,
                            ex.script.trim(),
                            b.shown.source,
                            b.shown.how,
                            b.expected.join("\n"),
                            // As much as the block would show, and a little more.
                            got[..got.len().min(b.expected.len() + 3)].join("\n")
                        ));
                    }
                }
            }
        }
        if update && !rewrites.is_empty() {
            rewrites.sort_by_key(|r| std::cmp::Reverse(r.0));
            for (start, end, want) in rewrites {
                lines.splice(start..end, want);
            }
            let mut new = lines.join("\n");
            new.push('\n');
            std::fs::write(&page, new).unwrap();
            eprintln!("UPDATE_DOCS: rewrote {name}");
        }
    }
    assert!(count >= 12, "found only {count} examples");
    assert!(
        failures.is_empty(),
        "{} example(s) differ from the docs (UPDATE_DOCS=1 cargo test --release --test suite cli_docs:: rewrites the text blocks):\n\n{}",
        failures.len(),
        failures.join("\n\n")
    );
}

#[test]
fn the_wildcard_matches_as_documented() {
    assert!(matches("a … s, b", "a 1.5 s, b"));
    assert!(matches("…", "anything"));
    assert!(!matches("a … s", "b 1 s"));
    assert!(matches("x", "x") && !matches("x", "y"));
    assert!(matches("a…b", "ab") && !matches("a…a", "a"));
}

#[test]
fn regeneration_keeps_matching_patterns_and_replaces_drift() {
    let e = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    assert_eq!(
        regenerate("exact", &e(&["t … s", "m 0.7"]), &["t 1.2 s", "m 0.8", "x"]),
        e(&["t … s", "m 0.8", "x"])
    );
    assert_eq!(
        regenerate("head", &e(&["a,b"]), &["a,c", "1,2"]),
        e(&["a,c"])
    );
    assert_eq!(
        regenerate(
            "some",
            &e(&["theta 0.2", "steps …"]),
            &["x 1", "theta 0.3", "steps 9"]
        ),
        e(&["theta 0.3", "steps …"])
    );
}
