//! docs/cli.md's ranges are `--help`'s: for every flag of every command,
//! the ranges its help states (`[a, b]`, `(a, b]`, `a to b`) and those its
//! row in docs/cli.md states (the same forms, and `a ≤ X ≤ b`) are the
//! same set. A default's own bounds (`[default: …]`, the last column) and
//! a variable's domain (`θν ∈ [0, π/2]`) are not the flag's range and are
//! left out on both sides.

#![allow(clippy::unwrap_used)]

use crate::cli_support;

use std::collections::{BTreeMap, BTreeSet};

use cli_support::*;

const COMMANDS: [&str; 10] = [
    "map",
    "orbit",
    "cycle",
    "continue",
    "trajectory",
    "bifurcation",
    "phase",
    "work-precision",
    "bench-worker",
    "gui",
];

/// A bound as written: a number, π or π/2.
fn bound(s: &str) -> Option<f64> {
    match s {
        "π" => Some(std::f64::consts::PI),
        "π/2" => Some(std::f64::consts::FRAC_PI_2),
        _ if s.starts_with(|c: char| c.is_ascii_digit() || c == '-') => s.parse().ok(),
        _ => None,
    }
}

/// `text` without the spans that open with `open` and end at the first
/// `close` after it.
fn without(text: &str, open: &str, close: &[char]) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find(open) {
        out.push_str(&rest[..i]);
        let after = &rest[i + open.len()..];
        match after.find(close) {
            Some(j) => rest = &after[j + 1..],
            None => rest = "",
        }
    }
    out.push_str(rest);
    out
}

/// The ranges stated in `text`, as (lo, hi) written to 6 digits.
fn ranges(text: &str) -> BTreeSet<String> {
    let text = without(text, "[default:", &[']']);
    let text = without(&text, "∈ [", &[']', ')']);
    let text = without(&text, "∈ (", &[']', ')']);
    let mut out = BTreeSet::new();
    let mut add = |a: f64, b: f64| {
        out.insert(format!("{a:.6e}..{b:.6e}"));
    };
    // [a, b], (a, b], [a, b), (a, b), not after a letter or digit ("8(5,3)").
    let chars: Vec<char> = text.chars().collect();
    for (i, &c) in chars.iter().enumerate() {
        if !(c == '[' || c == '(') || (i > 0 && chars[i - 1].is_alphanumeric()) {
            continue;
        }
        let Some(len) = chars[i + 1..].iter().position(|&c| c == ']' || c == ')') else {
            continue;
        };
        let inner: String = chars[i + 1..i + 1 + len].iter().collect();
        if let Some((a, b)) = inner.split_once(',')
            && let (Some(a), Some(b)) = (bound(a.trim()), bound(b.trim()))
        {
            add(a, b);
        }
    }
    // "a to b", "a ≤ X ≤ b", "a < X ≤ b".
    let words: Vec<&str> = text
        .split_whitespace()
        .map(|w| w.trim_matches(|c: char| matches!(c, ',' | ';' | ':' | '(' | ')' | '.')))
        .collect();
    for w in words.windows(3) {
        if w[1] == "to"
            && let (Some(a), Some(b)) = (bound(w[0]), bound(w[2]))
        {
            add(a, b);
        }
    }
    for w in words.windows(5) {
        if matches!(w[1], "≤" | "<")
            && w[3] == "≤"
            && let (Some(a), Some(b)) = (bound(w[0]), bound(w[4]))
        {
            add(a, b);
        }
    }
    out
}

/// Each flag's help text (its line and the indented lines after it).
fn help_flags(cmd: &str) -> BTreeMap<String, String> {
    let o = oneblock(&[cmd, "--help"]);
    assert_ok(&o);
    let mut flags = BTreeMap::new();
    let mut current: Option<String> = None;
    for line in stdout(&o).lines() {
        let t = line.trim_start();
        let t = t.strip_prefix("-h, ").unwrap_or(t);
        if line.starts_with("  ") && t.starts_with("--") {
            let name = t.split([' ', '<']).next().unwrap().to_string();
            flags.insert(name.clone(), t.to_string());
            current = Some(name);
        } else if let Some(f) = &current
            && line.starts_with("          ")
        {
            let entry = flags.get_mut(f).unwrap();
            entry.push(' ');
            entry.push_str(line.trim());
        } else {
            current = None;
        }
    }
    flags
}

/// The table rows of `section` (and the common flags') naming `flag` in
/// their first cell, without their last (default) cell.
fn doc_rows(docs: &str, cmd: &str, flag: &str) -> Option<String> {
    let section = |title: &str| {
        docs.split("\n## ")
            .find(|s| s.starts_with(title))
            .unwrap_or("")
            .to_string()
    };
    let mut text = section(&format!("`oneblock {cmd}`"));
    if cmd != "bench-worker" && cmd != "gui" {
        text.push('\n');
        text.push_str(&section("Common flags"));
    }
    let rows: Vec<String> = text
        .lines()
        .filter(|l| l.starts_with("| "))
        .filter(|l| {
            let first = l.split('|').nth(1).unwrap_or("");
            first.contains(&format!("`{flag} ")) || first.contains(&format!("`{flag}`"))
        })
        .map(|l| {
            let cells: Vec<&str> = l.split('|').collect();
            cells[..cells.len().saturating_sub(2)].join("|")
        })
        .collect();
    (!rows.is_empty()).then(|| rows.join("\n"))
}

#[test]
fn docs_ranges_match_help() {
    let docs =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/cli.md")).unwrap();
    let mut wrong = Vec::new();
    let mut compared = 0;
    for cmd in COMMANDS {
        for (flag, help) in help_flags(cmd) {
            let in_help = ranges(&help);
            match doc_rows(&docs, cmd, &flag) {
                Some(row) => {
                    compared += 1;
                    let in_docs = ranges(&row);
                    if in_help != in_docs {
                        wrong.push(format!(
                            "{cmd} {flag}: --help {in_help:?}, docs/cli.md {in_docs:?}"
                        ));
                    }
                }
                None if !in_help.is_empty() => {
                    wrong.push(format!(
                        "{cmd} {flag}: --help {in_help:?}, no row in docs/cli.md"
                    ));
                }
                None => {}
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    // The comparison is not vacuous: most flags have a row.
    assert!(compared > 80, "only {compared} flags compared");
}

#[test]
fn the_range_reader_reads_every_form() {
    let r = ranges(
        "x in [1e-6, 1e6], (0, 1e7] seconds, 1 to 64, 0 ≤ N ≤ 1e5, 0 < S ≤ 2 [default: within [1e-9, 1e-3]] θν ∈ [0, π/2] 8(5,3)",
    );
    assert_eq!(r.len(), 5, "{r:?}");
    assert!(r.contains(&format!("{:.6e}..{:.6e}", 1e-6, 1e6)));
    assert!(r.contains(&format!("{:.6e}..{:.6e}", 0.0, 2.0)));
}
