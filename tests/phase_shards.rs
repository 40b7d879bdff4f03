//! `oneblock phase` at any resolution (issue 56): a grid computed in 4
//! shards (`--shard K/N`) and joined (`--merge`) is the one-shot CSV bit
//! for bit below its `#` lines; bad shards and bad merges are one-line
//! usage errors; and cells seeded from their neighbours' cycles are
//! classed as the cell computed alone (the library call a 1 × 1 `phase`
//! run makes) in at least 99.5 % of a random sample.

use crate::cli_support::*;
use oneblock::SolverSettings;
use oneblock::model::Params;
use oneblock::sim::phase::{PhaseOptions, continue_cell};

/// A 40 × 70 grid (6 blocks of 32 × 32) across Fig. 4's flip, P2, chaos
/// and window region, at a cheap budget.
const GRID: [&str; 22] = [
    "phase",
    "--gamma",
    "6.5",
    "--nu",
    "1e-3",
    "--kappa-from",
    "8",
    "--kappa-to",
    "20",
    "--kappa-steps",
    "40",
    "--theta-nu-from",
    "0.8",
    "--theta-nu-to",
    "1.5",
    "--theta-nu-steps",
    "70",
    "--tol",
    "1e-8",
    "--transient",
    "120",
    "--keep=32",
];

/// The lines of `path` below its `#` lines.
fn body(path: &std::path::Path) -> Vec<String> {
    std::fs::read_to_string(path)
        .expect("a csv")
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(str::to_string)
        .collect()
}

#[test]
fn four_shards_merged_are_the_one_shot_grid() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let p = |name: &str| dir.path().join(name).to_string_lossy().to_string();
    let one = p("one.csv");
    assert_ok(&oneblock(&[&GRID[..], &["--out", &one]].concat()));
    let parts: Vec<String> = (1..=4).map(|k| p(&format!("part-{k}.csv"))).collect();
    for (k, part) in parts.iter().enumerate() {
        let shard = format!("{}/4", k + 1);
        let threads = if k % 2 == 0 { "1" } else { "2" };
        let o = oneblock(
            &[
                &GRID[..],
                &["--shard", &shard, "--threads", threads, "--out", part],
            ]
            .concat(),
        );
        assert_ok(&o);
    }
    // Given in any order.
    let all = p("all.csv");
    let png = p("all.png");
    let o = oneblock(&[
        "phase", "--merge", &parts[2], &parts[0], &parts[3], &parts[1], "--out", &all, "--png",
        &png,
    ]);
    assert_ok(&o);
    let (want, got) = (body(one.as_ref()), body(all.as_ref()));
    assert_eq!(want.len(), 1 + 40 * 70);
    assert_eq!(got, want);
    let bytes = std::fs::read(&png).expect("the png");
    assert_eq!(&bytes[1..4], b"PNG");

    // A part missing, a part twice, a file of no sharding: one line, exit 2.
    let x = p("x.csv");
    for bad in [
        vec![parts[0].as_str(), &parts[1], &parts[3]],
        vec![&parts[0], &parts[1], &parts[1], &parts[2], &parts[3]],
        vec![&parts[0], &parts[1], &parts[2], &one],
    ] {
        let args: Vec<String> = [&["phase", "--merge"][..], &bad, &["--out", &x]]
            .concat()
            .iter()
            .map(|s| s.to_string())
            .collect();
        assert_bad_input(&args, "--merge");
        assert!(!std::path::Path::new(&x).exists());
    }
}

#[test]
fn a_shard_out_of_range_is_a_one_line_usage_error() {
    for bad in ["0/4", "5/4", "3", "1/7", "a/b", "-1/2"] {
        let args: Vec<String> = [&GRID[..], &["--shard", bad, "--out", "-"]]
            .concat()
            .iter()
            .map(|s| s.to_string())
            .collect();
        assert_bad_input(&args, "--shard");
    }
}

/// A deterministic sample of `n` of `0..total` (a fixed LCG).
fn sample(total: usize, n: usize) -> Vec<usize> {
    let mut x: u64 = 56;
    let mut picked = std::collections::BTreeSet::new();
    while picked.len() < n {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        picked.insert((x >> 33) as usize % total);
    }
    picked.into_iter().collect()
}

#[test]
fn sampled_cells_are_classed_as_each_computed_alone() {
    // Fig. 4's ranges at 48 × 48, the command's default budget.
    let o = oneblock(&[
        "phase",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--kappa-from",
        "1",
        "--kappa-to",
        "42",
        "--kappa-steps",
        "48",
        "--theta-nu-steps",
        "48",
        "--out",
        "-",
    ]);
    assert_ok(&o);
    let (header, rows) = parse_csv(&stdout(&o));
    let class = header.iter().position(|h| h == "class").expect("class");
    let settings = SolverSettings::default();
    let opts = PhaseOptions::for_settings(&settings);
    let picked = sample(rows.len(), 400);
    let differ: Vec<String> = picked
        .iter()
        .filter_map(|&i| {
            let r = &rows[i];
            let (theta_nu, kappa) = (num(&r[0]), num(&r[1]));
            let params = Params {
                kappa,
                theta_nu,
                gamma: 6.5,
                nu: 1e-3,
                omega: 50.0,
            };
            // What a 1 × 1 `phase` run computes: no neighbour.
            let alone = continue_cell(params, settings, kappa, theta_nu, None, &opts, &|| false);
            let label = alone.class.label();
            (label != r[class]).then(|| format!("{theta_nu} {kappa}: {} alone {label}", r[class]))
        })
        .collect();
    // At least 99.5 %: at most 2 of 400.
    eprintln!(
        "{} of 400 sampled cells differ from the cell alone: {differ:?}",
        differ.len()
    );
    assert!(
        differ.len() <= 2,
        "{} of 400 differ: {differ:?}",
        differ.len()
    );
}
