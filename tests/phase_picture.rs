//! `oneblock phase --png`: the grid just computed drawn by `oneblock
//! figure`'s code (issue 57, "one engine"): the same picture as `figure
//! --view phase` over the same grid, its cells in the classes' colours at
//! the size and resolution asked for, and `--boundaries` curves each in a
//! style and legend entry of its own.

#![allow(clippy::unwrap_used)]

use std::path::Path;
use std::process::{Command, Output};

/// The grid of docs/cli.md's example: Fig. 4's γ and ν, θν 0.5 … 1.2 in 3
/// columns, κ 2 … 16 in 2 rows.
const GRID: [&str; 14] = [
    "--preset",
    "fig4",
    "--kappa-from",
    "2",
    "--kappa-to",
    "16",
    "--kappa-steps",
    "2",
    "--theta-nu-from",
    "0.5",
    "--theta-nu-to",
    "1.2",
    "--theta-nu-steps",
    "3",
];

fn oneblock(dir: &Path, args: &[&str]) -> Output {
    let o = Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

/// `phase` over [`GRID`] with `more` flags.
fn phase(dir: &Path, more: &[&str]) -> Output {
    oneblock(dir, &[&["phase"], &GRID[..], more].concat())
}

#[test]
fn phase_png_and_figure_view_phase_are_the_same_picture() {
    let dir = tempfile::tempdir().unwrap();
    phase(dir.path(), &["--png", "a.png", "--size", "500x360"]);
    oneblock(
        dir.path(),
        &[
            &["figure", "--view", "phase"],
            &GRID[..],
            &["--size", "500x360", "--out", "b.png"],
        ]
        .concat(),
    );
    let a = image::open(dir.path().join("a.png")).unwrap().to_rgba8();
    let b = image::open(dir.path().join("b.png")).unwrap().to_rgba8();
    // 500 × 360 points at figure's two pixels a point.
    assert_eq!(a.dimensions(), (1000, 720));
    assert_eq!(b.dimensions(), a.dimensions());
    let differ = a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
    assert_eq!(differ, 0, "{differ} pixels differ");
}

/// The plot area of an SVG: the x, y, width and height of the grid's
/// image (the cells, one texel each).
fn cells_rect(svg: &str) -> [f64; 4] {
    let at = svg.find("<image ").expect("the cells' image");
    let tag = &svg[at..at + svg[at..].find("/>").unwrap()];
    let attr = |k: &str| -> f64 {
        let from = tag.find(&format!(" {k}=\"")).unwrap() + k.len() + 3;
        tag[from..from + tag[from..].find('"').unwrap()]
            .parse()
            .unwrap()
    };
    [attr("x"), attr("y"), attr("width"), attr("height")]
}

#[test]
fn the_picture_has_its_cells_and_the_figures_words_at_the_size_asked_for() {
    let dir = tempfile::tempdir().unwrap();
    phase(dir.path(), &["--png", "p.svg", "--size", "500x360"]);
    phase(
        dir.path(),
        &["--png", "p.png", "--size", "500x360", "--dpi", "72"],
    );
    let svg = std::fs::read_to_string(dir.path().join("p.svg")).unwrap();
    // The figure's words: units in parentheses, the classes as the
    // window names them, only the classes drawn.
    assert!(svg.contains(">θν, pull direction (rad)</text>"), "{svg}");
    assert!(svg.contains(">κ = k_x/k_y, anisotropy</text>"));
    assert!(!svg.contains("[rad]") && !svg.contains("CHAOS"));
    assert!(svg.contains(">P2</text>") && svg.contains(">P4</text>"));
    assert!(!svg.contains(">undecided</text>") && !svg.contains(">failed</text>"));
    // At 72 dpi a point is a pixel.
    let img = image::open(dir.path().join("p.png")).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (500, 360));
    // The cells (docs/cli.md's example): the bottom-left one (θν = 0.5,
    // κ = 2) is P2's green, the top-right one (θν = 1.2, κ = 16) P4's
    // purple, each at its cell's centre.
    let [x, y, w, h] = cells_rect(&svg);
    let at = |col: f64, row_from_top: f64| {
        let px = x + w * (col + 0.5) / 3.0;
        let py = y + h * (row_from_top + 0.5) / 2.0;
        img.get_pixel(px as u32, py as u32).0
    };
    let near = |p: [u8; 3], q: [u8; 3]| p.iter().zip(q).all(|(a, b)| a.abs_diff(b) <= 2);
    assert!(near(at(0.0, 1.0), [82, 170, 84]), "{:?}", at(0.0, 1.0));
    assert!(near(at(2.0, 0.0), [150, 80, 180]), "{:?}", at(2.0, 0.0));
}

#[test]
fn each_boundary_curve_has_its_own_style_and_legend_entry() {
    let dir = tempfile::tempdir().unwrap();
    // Two curves in `continue --curve --out`'s format (its `#` lines
    // first): FP to P2 rising across the grid, P2 to P4 falling.
    let mut text = String::from(
        "# oneblock 0.1.0\n# command: oneblock continue --curve pd\n\
         curve,kind,period,theta_nu,kappa,theta,multiplier\n",
    );
    for i in 0..=10 {
        let f = f64::from(i) / 10.0;
        text.push_str(&format!(
            "0,pd,1,{},{},0.4,-1\n",
            0.5 + 0.7 * f,
            3.0 + 12.0 * f
        ));
    }
    for i in 0..=10 {
        let f = f64::from(i) / 10.0;
        text.push_str(&format!(
            "1,pd,2,{},{},0.4,-1\n",
            0.5 + 0.7 * f,
            15.0 - 12.0 * f
        ));
    }
    std::fs::write(dir.path().join("curves.csv"), text).unwrap();
    phase(
        dir.path(),
        &["--png", "c.svg", "--boundaries", "curves.csv"],
    );
    let svg = std::fs::read_to_string(dir.path().join("c.svg")).unwrap();
    // Each drawn in its colour (white, cyan) on the dark halo, as series
    // of the phase plot.
    let series = |colour: &str| {
        svg.lines()
            .filter(|l| {
                l.contains("data-series=\"phase:") && l.contains(&format!("stroke=\"{colour}\""))
            })
            .count()
    };
    assert!(series("#ffffff") > 0, "no white FP to P2 curve");
    assert!(series("#00e5ff") > 0, "no cyan P2 to P4 curve");
    // Two legend entries, one each, and none for a fold not drawn.
    assert_eq!(svg.matches(">FP to P2</text>").count(), 1);
    assert_eq!(svg.matches(">P2 to P4</text>").count(), 1);
    assert!(!svg.contains("fold of"));
    // The legend's keys are the lines as drawn: both colours outside the
    // plot too (the keys stand above it).
    let key = |colour: &str| {
        svg.lines()
            .any(|l| !l.contains("data-series") && l.contains(&format!("stroke=\"{colour}\"")))
    };
    assert!(key("#ffffff") && key("#00e5ff"), "the legend's keys");
}
