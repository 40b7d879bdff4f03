//! The Basins job and `oneblock figure --view basins`: at κ = 10, γ = 6.5,
//! ν = 1e-3 the fixed point and the P2 coexist near θν 1.38–1.41
//! (hysteresis). The job finds both, with basin fractions that sum with
//! the boundary's to 1, on one thread as on two; the figure's CSV names
//! them per column with one identity each along θν, and its SVG fills the
//! arc with both attractors' colours.
#![allow(clippy::unwrap_used)]

#[cfg(feature = "gui")]
use std::process::Command;

use oneblock::integrate::{Method, SolverSettings};
use oneblock::jobs::{Axis, BasinColumn, BasinsSpec, Spec, Update, run_collect};
use oneblock::model::Params;
use oneblock::sim::attractors::CellOptions;

/// A column as the CSV gives it: θν, each attractor's (track, label,
/// basin fraction), the boundary's fraction.
#[cfg(feature = "gui")]
type CsvColumn = (f64, Vec<(String, String, f64)>, f64);

fn spec(from: f64, to: f64, steps: usize) -> BasinsSpec {
    BasinsSpec {
        params: Params {
            kappa: 10.0,
            gamma: 6.5,
            nu: 1e-3,
            theta_nu: from,
            omega: 50.0,
        },
        settings: SolverSettings::adaptive(Method::Dop853, 1e-10),
        param: oneblock::sim::continuation::ContParam::ThetaNu,
        axis: Axis::new(from, to, steps),
        cells: CellOptions::column(),
    }
}

/// The job's columns, in grid order.
fn columns(spec: BasinsSpec, threads: usize) -> Vec<BasinColumn> {
    let ups = run_collect(Spec::Basins(spec), threads, |_| {}, || false).expect("completes");
    let mut cols: Vec<BasinColumn> = ups
        .into_iter()
        .filter_map(|u| match u {
            Update::Basins { column, .. } => Some(*column),
            _ => None,
        })
        .collect();
    cols.sort_by_key(|c| c.index);
    cols
}

#[test]
fn the_job_finds_the_fixed_point_and_the_p2_at_theta_nu_1_40() {
    let cols = columns(spec(1.40, 1.40, 1), 1);
    assert_eq!(cols.len(), 1);
    let f = cols[0].found.as_ref().expect("found");
    let mut periods: Vec<_> = f.attractors.iter().map(|a| a.period).collect();
    periods.sort();
    assert_eq!(periods, [Some(1), Some(2)]);
    let sum: f64 = f.attractors.iter().map(|a| a.basin_fraction).sum();
    assert!(
        (sum + f.boundary_fraction - 1.0).abs() < 1e-9,
        "{sum} + {}",
        f.boundary_fraction
    );
    assert!(f.attractors.iter().all(|a| a.basin_fraction > 0.2));
    // Every column, on two threads as on one, the same to the bit.
    let one = columns(spec(1.37, 1.42, 4), 1);
    let two = columns(spec(1.37, 1.42, 4), 2);
    assert_eq!(one, two);
    assert_eq!(
        one.iter().map(|c| c.index).collect::<Vec<_>>(),
        [0, 1, 2, 3]
    );
}

#[cfg(feature = "gui")]
/// Runs `oneblock figure --view basins` at the hysteresis, 25 columns over
/// θν 1.33 … 1.45, into `name` (a fresh temporary directory's).
fn figure(name: &str) -> String {
    let model = [
        "--view",
        "basins",
        "--kappa",
        "10",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--theta-nu-from",
        "1.33",
        "--theta-nu-to",
        "1.45",
        "--columns",
        "25",
    ];
    written(&model, name)
}

#[cfg(feature = "gui")]
/// What `oneblock figure ARGS --out NAME` writes (no display).
fn written(args: &[&str], name: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join(name);
    let o = Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .arg("figure")
        .args(args)
        .arg("--out")
        .arg(&out)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::read_to_string(&out).unwrap()
}

#[cfg(feature = "gui")]
#[test]
fn the_csv_names_two_attractors_per_middle_column_with_one_identity_each() {
    let csv = figure("basins.csv");
    let mut lines = csv.lines();
    let head = lines.next().unwrap();
    assert!(head.starts_with("# oneblock "), "{head}");
    // Then where it came from: the command line, the model, the flags.
    let mut lines = lines.skip_while(|l| !l.starts_with("# model: "));
    let model = lines.next().unwrap();
    assert!(
        model.contains("kappa = 10") && model.contains("25 columns"),
        "{model}"
    );
    let mut lines = lines.skip_while(|l| l.starts_with('#'));
    assert_eq!(
        lines.next().unwrap(),
        "theta_nu,attractor,label,period,basin_fraction,multiplier,lyapunov,verdict,colour"
    );
    // Per θν: (track, label, fraction) of each attractor, and the boundary.
    let mut cols: Vec<CsvColumn> = Vec::new();
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        let tn: f64 = f[0].parse().unwrap();
        if cols.last().is_none_or(|c| c.0 != tn) {
            cols.push((tn, Vec::new(), 0.0));
        }
        let c = cols.last_mut().unwrap();
        match f[2] {
            "boundary" => c.2 = f[4].parse().unwrap(),
            "failed" => panic!("a column failed: {l}"),
            label => c.1.push((f[1].into(), label.into(), f[4].parse().unwrap())),
        }
    }
    assert_eq!(cols.len(), 25);
    for (tn, atts, boundary) in &cols {
        let sum: f64 = atts.iter().map(|a| a.2).sum::<f64>() + boundary;
        assert!((sum - 1.0).abs() < 1e-9, "θν {tn}: fractions sum to {sum}");
    }
    let both: Vec<_> = cols.iter().filter(|c| c.1.len() == 2).collect();
    assert!(
        both.len() >= 3,
        "{} columns with two attractors",
        both.len()
    );
    // The fixed point beside the large P2 over 1.37 … 1.42; below 1.371 a
    // second, small P2 beside it (the seeded diagram's 1.364 … 1.3708).
    let mut with_p1 = Vec::new();
    for c in &both {
        let (tn, atts, _) = c;
        assert!((1.36..=1.42).contains(tn), "two attractors at θν {tn}");
        let mut labels: Vec<_> = atts.iter().map(|a| a.1.as_str()).collect();
        labels.sort();
        if labels == ["P1", "P2"] {
            assert!(*tn >= 1.37, "θν {tn}");
            with_p1.push(*c);
        } else {
            assert_eq!(labels, ["P2", "P2"], "θν {tn}");
            assert_ne!(atts[0].0, atts[1].0, "θν {tn}: two tracks");
            assert!(*tn < 1.371, "θν {tn}");
        }
    }
    assert!(
        with_p1.len() >= 3,
        "{} columns with P1 and P2",
        with_p1.len()
    );
    // One identity per attractor along θν: P2's track at the left end is
    // P2's where it coexists with P1, and P1's there is P1's at the right.
    let track = |c: &CsvColumn, label: &str| c.1.iter().find(|a| a.1 == label).map(|a| a.0.clone());
    let (first, last, mid) = (&cols[0], &cols[24], with_p1[0]);
    assert_eq!(track(first, "P2"), track(mid, "P2"));
    assert_eq!(track(last, "P1"), track(mid, "P1"));
    assert_ne!(track(mid, "P1"), track(mid, "P2"));
    // The small P2 halves into the fixed point: one track (issue 54),
    // two in all.
    let small = cols
        .iter()
        .find(|c| c.1.len() == 2 && c.1.iter().all(|a| a.1 == "P2"))
        .map(|c| {
            c.1.iter()
                .find(|a| a.0 != track(first, "P2").unwrap())
                .unwrap()
                .0
                .clone()
        });
    assert_eq!(
        small,
        track(mid, "P1"),
        "the small P2 goes on as the fixed point"
    );
    let mut all: Vec<&String> = cols.iter().flat_map(|c| c.1.iter().map(|a| &a.0)).collect();
    all.sort();
    all.dedup();
    assert_eq!(all.len(), 2, "tracks {all:?}");
}

#[cfg(feature = "gui")]
#[test]
fn the_svg_fills_the_arc_with_both_attractors_colours() {
    let svg = figure("basins.svg");
    // The palette's first two colours: the P2 found first, then the P1.
    for c in ["#1f77b4", "#ff7f0e"] {
        let n = svg.matches(&format!("fill=\"{c}\"")).count();
        assert!(n >= 10, "{c}: {n} fills");
    }
    for word in ["P1", "P2", "basin boundary", "basin fraction"] {
        assert!(svg.contains(word), "{word}");
    }
}

#[cfg(feature = "gui")]
/// The return map's figure with its basins band and a chaotic attractor's
/// density, from the cell graph at the figure's parameters.
fn return_map_svg(model: &[&str]) -> String {
    let args: Vec<&str> = ["--view", "return-map"]
        .iter()
        .chain(model)
        .copied()
        .collect();
    written(&args, "map.svg")
}

#[cfg(feature = "gui")]
#[test]
fn the_return_map_shades_the_basins_and_draws_the_density() {
    let svg = return_map_svg(&["--preset", "chaos"]);
    assert!(svg.contains("basin: chaotic"), "no basin legend");
    assert!(svg.contains("invariant density"), "no density legend");
    let svg = return_map_svg(&[
        "--kappa",
        "10",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--theta-nu",
        "1.365",
    ]);
    // Two P2 cycles coexist here (the large one and the small one born at
    // 1.36398), both within the map's view: two entries, two colours. (At
    // 1.40 the view holds the fixed point alone, and the legend names only
    // what is drawn.)
    assert_eq!(svg.matches("basin: P2").count(), 2, "two P2 basins");
    assert!(!svg.contains("invariant density"));
    // Both attractors' colours (the band's stretches).
    for c in ["#1f77b4", "#ff7f0e"] {
        assert!(svg.contains(c), "{c}");
    }
}

/// Fig. 3b's Basins figure follows three tracks over θν (the cascade into
/// chaos, the P3 window born in a fold out of that chaos, and the chaos
/// that halves into the fixed point at the right end): each has its own
/// colour, in the CSV and in the picture drawn by the same command.
#[cfg(feature = "gui")]
#[test]
fn no_two_identities_share_a_colour_at_fig3b() {
    let dir = tempfile::tempdir().unwrap();
    let (csv, png) = (dir.path().join("b.csv"), dir.path().join("b.png"));
    for out in [&csv, &png] {
        let o = crate::cli_support::oneblock(&[
            "figure",
            "--view",
            "basins",
            "--preset",
            "fig3b",
            "--out",
            out.to_str().unwrap(),
        ]);
        crate::cli_support::assert_ok(&o);
    }
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut colour_of = std::collections::BTreeMap::new();
    for l in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let f: Vec<&str> = l.split(',').collect();
        let (id, label, colour) = (f[1], f[2], *f.last().unwrap());
        if label == "failed" {
            continue;
        }
        assert!(
            colour.len() == 7 && colour.starts_with('#'),
            "colour '{colour}' in {l}"
        );
        let prev = colour_of.insert(id.to_string(), colour.to_string());
        assert!(
            prev.is_none_or(|p| p == colour),
            "{id} drawn in two colours"
        );
    }
    // The tracks and the boundary's grey.
    assert!(colour_of.len() >= 4, "{colour_of:?}");
    let distinct: std::collections::HashSet<&String> = colour_of.values().collect();
    assert_eq!(distinct.len(), colour_of.len(), "shared: {colour_of:?}");
    // Each identity's colour is painted in the picture.
    let img = image::open(&png).unwrap().to_rgb8();
    let painted: std::collections::HashSet<[u8; 3]> = img.pixels().map(|p| p.0).collect();
    for (id, c) in &colour_of {
        let rgb = [1, 3, 5].map(|i| u8::from_str_radix(&c[i..i + 2], 16).unwrap());
        assert!(
            painted.contains(&rgb),
            "identity '{id}' ({c}) not in the picture"
        );
    }
}
