//! The tour as a teacher opens it, through the binary in a real window
//! under Xvfb: `oneblock gui --tour-step N --layout FILE --screenshot` for
//! every step, at the projector setting the README gives (1024 × 768,
//! text ×1.5, the panel hidden) and at 1280 × 800. The layout the window
//! writes shows each view the step names at 200 × 150 points or more, its
//! plots whole (the λ strip where the step speaks of λ, the time series'
//! four) and the box over none of them. Skipped with a note where
//! `xvfb-run` is missing, except under CI.

#![cfg(feature = "gui")]
#![allow(clippy::unwrap_used)]

mod common;
use common::tour_layout::step_problems;
use common::xvfb::{have_xvfb, runtime_dir, under_xvfb};

use oneblock::app::layout_report::LayoutReport;
use oneblock::app::tour::STEPS;

/// Runs step `n` (1-based) at `size` with `extra` flags; its layout.
fn layout_of(dir: &std::path::Path, n: usize, size: &str, extra: &[&str]) -> LayoutReport {
    let xdg = runtime_dir(&dir.join("xdg"));
    let png = dir.join(format!("step{n}-{size}.png"));
    let json = dir.join(format!("step{n}-{size}.json"));
    let out = under_xvfb(400)
        .arg(env!("CARGO_BIN_EXE_oneblock"))
        .args([
            "gui",
            "--preset",
            "fig3b",
            "--size",
            size,
            "--timeout",
            "300",
        ])
        .args(["--tour-step", &n.to_string()])
        .args(extra)
        .arg("--screenshot")
        .arg(&png)
        .arg("--layout")
        .arg(&json)
        .env("XDG_RUNTIME_DIR", &xdg)
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "step {n} at {size}: {err}");
    assert!(err.contains("layout in"), "{err}");
    serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap()
}

#[test]
fn every_tour_step_shows_what_it_talks_about_at_the_projector_and_laptop_sizes() {
    if !have_xvfb("tour window test") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let projector = ["--font-scale", "1.5", "--hide-panel"];
    let mut bad = Vec::new();
    for (n, step) in STEPS.iter().enumerate() {
        for (size, wh, extra) in [
            ("1024x768", (1024.0, 768.0), &projector[..]),
            ("1280x800", (1280.0, 800.0), &[][..]),
        ] {
            let report = layout_of(dir.path(), n + 1, size, extra);
            for p in step_problems(&report, step, wh) {
                bad.push(format!("step {} at {size}: {p}", n + 1));
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// Without the tour the layout has no box; a layout file that exists is
/// never overwritten (the run refuses before the window opens).
#[test]
fn the_layout_without_the_tour_has_no_box_and_never_overwrites() {
    if !have_xvfb("tour window test") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let xdg = runtime_dir(&dir.path().join("xdg"));
    let (png, json) = (dir.path().join("w.png"), dir.path().join("w.json"));
    let run = || {
        under_xvfb(400)
            .arg(env!("CARGO_BIN_EXE_oneblock"))
            .args([
                "gui",
                "--preset",
                "fig3b",
                "--timeout",
                "300",
                "--screenshot",
            ])
            .arg(&png)
            .arg("--layout")
            .arg(&json)
            .env("XDG_RUNTIME_DIR", &xdg)
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .unwrap()
    };
    let out = run();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: LayoutReport =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(report.tour, None);
    assert!(
        report.views.iter().any(|v| v.view == "bifurcation"),
        "{report:?}"
    );
    std::fs::remove_file(&png).unwrap();
    let before = std::fs::read(&json).unwrap();
    let out = run();
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(std::fs::read(&json).unwrap(), before);
    assert!(!png.exists());
}
