//! The counts the docs state, against the code: "11 kinds of job",
//! "10 worker lanes", "9 views", "6 continued chains", "3 slip lanes".
//! Prose once said "six lanes" where there were 8, "seven jobs" where
//! there were 9 and "8 chains" where there were 6. Every sentence in
//! README.md, docs/ and the sources that states one of these counts is
//! read and checked; each count must be stated at least once.

use std::path::{Path, PathBuf};

use oneblock::jobs::{Kind, Lane, Shape};
use oneblock::sim::LANES;

const WORDS: [&str; 13] = [
    "zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten",
    "eleven", "twelve",
];

/// The number a word or numeral says, if it says one.
fn number(w: &str) -> Option<usize> {
    let w = w.to_lowercase();
    w.parse()
        .ok()
        .or_else(|| WORDS.iter().position(|&x| x == w))
}

/// Every file the counts may be stated in.
fn texts() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = vec![root.join("README.md")];
    let mut dirs = vec![root.join("docs"), root.join("src")];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).expect("readable").flatten() {
            let p = e.path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|x| x == "md" || x == "rs") {
                out.push(p);
            }
        }
    }
    out
}

/// Each (file, number) that states `phrase` ("N phrase", the text's line
/// breaks and comment markers read as spaces).
fn stated(phrase: &str) -> Vec<(String, usize)> {
    let mut found = Vec::new();
    for p in texts() {
        let text = std::fs::read_to_string(&p).expect("utf-8");
        let words: Vec<&str> = text
            .split(|c: char| c.is_whitespace() || c == '/' || c == '*' || c == '(' || c == '`')
            .filter(|w| !w.is_empty())
            .collect();
        let want: Vec<&str> = phrase.split(' ').collect();
        for i in 1..words.len().saturating_sub(want.len() - 1) {
            let here = &words[i..i + want.len()];
            let same = here
                .iter()
                .zip(&want)
                .all(|(a, b)| a.trim_end_matches([',', '.', ';', ':', ')']) == *b);
            if same && let Some(n) = number(words[i - 1]) {
                found.push((p.display().to_string(), n));
            }
        }
    }
    found
}

fn check(phrase: &str, count: usize) {
    let found = stated(phrase);
    assert!(!found.is_empty(), "no text states the {phrase}");
    for (file, n) in found {
        assert_eq!(n, count, "{file} says {n} {phrase}; the code has {count}");
    }
}

#[test]
fn the_docs_state_the_job_tables_counts() {
    check("kinds of job", Kind::COUNT);
    check("worker lanes", Lane::ALL.len());
}

#[test]
fn the_docs_state_the_chains_and_slip_lanes_of_a_diagram() {
    check("continued chains", Shape::default().chains);
    check("slip lanes", LANES);
}

#[cfg(feature = "gui")]
#[test]
fn the_docs_state_the_number_of_views() {
    check("views", oneblock::app::ViewKind::ALL.len());
}
