//! The window really draws: `oneblock gui --preset fig3b --screenshot` under
//! Xvfb with the glow renderer (Mesa's software OpenGL), then the PNG is
//! checked: its size, several distinct colours, a plot area that is not
//! uniform. `.ci/run` installs Xvfb and Mesa; on a machine without
//! `xvfb-run` this test fails under CI (CI=true) and is skipped, with a
//! note, elsewhere.

#![cfg(feature = "gui")]
#![allow(clippy::unwrap_used)]

mod common;
use common::xvfb::{fig3b_window, have_xvfb};

use std::collections::HashSet;

#[test]
fn fig3b_screenshot_under_xvfb_is_a_real_picture() {
    if !have_xvfb("window test") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("fig3b.png");
    let out = fig3b_window(dir.path(), &[], &png);
    assert!(
        out.status.success(),
        "gui exited {:?}: {}",
        out.status.code(),
        String::from_utf8_lossy(&out.stderr)
    );

    let img = image::open(&png).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (1280, 800));
    let px = |x: u32, y: u32| img.get_pixel(x, y).0;
    let all: HashSet<[u8; 3]> = (0..800)
        .step_by(4)
        .flat_map(|y| (0..1280).step_by(4).map(move |x| (x, y)))
        .map(|(x, y)| px(x, y))
        .collect();
    assert!(
        all.len() >= 16,
        "only {} distinct colours: a blank window?",
        all.len()
    );
    // The views fill the right part of the window: not uniform there.
    let views: HashSet<[u8; 3]> = (100..760)
        .step_by(3)
        .flat_map(|y| (400..1260).step_by(3).map(move |x| (x, y)))
        .map(|(x, y)| px(x, y))
        .collect();
    assert!(
        views.len() >= 8,
        "view area nearly uniform ({} colours)",
        views.len()
    );
}
