//! `oneblock phase --png`: the picture is rasterised from SVG with the
//! committed font (labels with Greek letters and units, as in the window),
//! and `--png FILE.svg` writes the SVG itself.

#![allow(clippy::unwrap_used)]

use std::process::Command;

fn phase(dir: &std::path::Path, picture: &str) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args([
            "phase",
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
            "--png",
            picture,
        ])
        .current_dir(dir)
        .output()
        .unwrap()
}

#[test]
fn the_png_has_its_cells_and_its_labels() {
    let dir = tempfile::tempdir().unwrap();
    let o = phase(dir.path(), "p.png");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(dir.path().join("p.png")).unwrap().to_rgb8();
    // 3 columns of 200 px and 2 rows of 240 px, margins 100 + 150 and 20 + 70.
    assert_eq!(img.dimensions(), (850, 570));
    // The cells: the bottom-left one (θν = 0.5, κ = 2) is P2's green, the
    // top-right one (θν = 1.2, κ = 16) P4's purple (docs/cli.md's example).
    assert_eq!(img.get_pixel(200, 400).0, [82, 170, 84]);
    assert_eq!(img.get_pixel(650, 100).0, [150, 80, 180]);
    // The labels are set: dark pixels where the κ title (left margin) and
    // the θν title (below the axis) stand, none in the empty corner.
    let dark = |x0: u32, x1: u32, y0: u32, y1: u32| {
        (x0..x1)
            .flat_map(|x| (y0..y1).map(move |y| (x, y)))
            .filter(|&(x, y)| img.get_pixel(x, y).0.iter().all(|&c| c < 110))
            .count()
    };
    assert!(dark(10, 40, 150, 400) > 100, "no κ title");
    assert!(dark(250, 600, 540, 570) > 200, "no θν title");
    assert_eq!(dark(0, 90, 520, 570), 0, "ink in the empty corner");
}

#[test]
fn a_svg_name_writes_the_svg() {
    let dir = tempfile::tempdir().unwrap();
    let o = phase(dir.path(), "p.svg");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let svg = std::fs::read_to_string(dir.path().join("p.svg")).unwrap();
    assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
    assert!(svg.contains(">θν, pull direction [rad]</text>"), "{svg}");
    assert!(svg.contains(">κ = k_x/k_y, anisotropy</text>"));
    // 6 cells and 9 legend swatches, plus the page.
    assert_eq!(svg.matches("<rect ").count(), 1 + 6 + 9 + 9 + 1);
}
