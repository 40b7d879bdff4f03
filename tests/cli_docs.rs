//! docs/cli.md is the command line's reference: it has a section for every
//! subcommand naming every flag, and each example whose output it shows
//! (a ` ```text stdout ` or ` ```text stderr ` block after a ` ```sh `
//! block) prints exactly that, `…` standing for anything within a line
//! (wall-clock times, this machine's load).

#![allow(clippy::unwrap_used)]

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

/// An example: the shell command (continuations joined), which stream,
/// and the lines it prints.
struct Example {
    command: String,
    stream: String,
    expected: Vec<String>,
}

fn examples(docs: &str) -> Vec<Example> {
    let lines: Vec<&str> = docs.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        if lines[i] == "```sh" {
            let mut cmd = String::new();
            i += 1;
            while lines[i] != "```" {
                cmd.push_str(lines[i].trim_end_matches('\\').trim());
                cmd.push(' ');
                i += 1;
            }
            // The output block, if any: the next fenced block.
            let next = (i + 1..lines.len()).find(|&j| lines[j].starts_with("```"));
            if let Some(j) = next
                && let Some(stream) = lines[j].strip_prefix("```text ")
            {
                let end = (j + 1..lines.len()).find(|&k| lines[k] == "```").unwrap();
                out.push(Example {
                    command: cmd.trim().to_string(),
                    stream: stream.trim().to_string(),
                    expected: lines[j + 1..end].iter().map(|s| s.to_string()).collect(),
                });
                i = end;
            }
        }
        i += 1;
    }
    out
}

/// Whether `line` matches `pattern`, where `…` matches any characters.
fn matches(pattern: &str, line: &str) -> bool {
    let parts: Vec<&str> = pattern.split('…').collect();
    if parts.len() == 1 {
        return pattern == line;
    }
    let (first, last) = (parts[0], parts[parts.len() - 1]);
    if !line.starts_with(first) || !line[first.len()..].ends_with(last) {
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

#[test]
fn the_examples_print_what_the_docs_show() {
    let docs = docs();
    let examples = examples(&docs);
    assert!(examples.len() >= 6, "found {} examples", examples.len());
    let dir = tempfile::tempdir().unwrap();
    for ex in examples {
        let words: Vec<&str> = ex.command.split_whitespace().collect();
        assert_eq!(words[0], "oneblock", "{}", ex.command);
        let o = Command::new(env!("CARGO_BIN_EXE_oneblock"))
            .args(&words[1..])
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{}: {}",
            ex.command,
            String::from_utf8_lossy(&o.stderr)
        );
        let text = String::from_utf8(if ex.stream == "stderr" {
            o.stderr
        } else {
            o.stdout
        })
        .unwrap();
        let got: Vec<&str> = text.lines().collect();
        assert_eq!(
            got.len(),
            ex.expected.len(),
            "{}: printed\n{text}\nexpected\n{}",
            ex.command,
            ex.expected.join("\n")
        );
        for (g, e) in got.iter().zip(&ex.expected) {
            assert!(
                matches(e, g),
                "{}:\n printed  {g}\n expected {e}",
                ex.command
            );
        }
        // Each example starts from an empty folder.
        for f in std::fs::read_dir(dir.path()).unwrap() {
            std::fs::remove_file(f.unwrap().path()).unwrap();
        }
    }
}

#[test]
fn the_wildcard_matches_as_documented() {
    assert!(matches("a … s, b", "a 1.5 s, b"));
    assert!(matches("…", "anything"));
    assert!(!matches("a … s", "b 1 s"));
    assert!(matches("x", "x") && !matches("x", "y"));
}
