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

/// A display that goes away ends the window with one line and exit 1:
/// the window runs under Xvfb until its server is killed (as Ctrl+C in the
/// terminal of an `xvfb-run` does), and must not crash on its way out (it
/// did: a segmentation fault, exit 139, after Xlib's own line).
#[test]
fn a_display_that_goes_away_ends_the_window_with_one_line_and_exit_1() {
    if !have_xvfb("display-loss test") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let xdg = common::xvfb::runtime_dir(&dir.path().join("xdg"));
    // The shell runs inside xvfb-run: it knows its server by $DISPLAY, and
    // finds it in /proc (a fresh Debian has no pkill).
    let script = r#"
        "$0" gui --preset fig3b --size 800x600 2>"$1" &
        G=$!
        sleep 8
        for p in /proc/[0-9]*; do
            if tr '\0' ' ' < "$p/cmdline" 2>/dev/null | grep -q "Xvfb $DISPLAY "; then
                kill -KILL "${p#/proc/}"
            fi
        done
        wait $G
        echo "exit=$?"
    "#;
    let err = dir.path().join("stderr.txt");
    let out = common::xvfb::under_xvfb(120)
        .args(["sh", "-c", script, env!("CARGO_BIN_EXE_oneblock")])
        .arg(&err)
        .env("XDG_RUNTIME_DIR", &xdg)
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&out.stdout);
    let stderr = std::fs::read_to_string(&err).unwrap();
    assert!(said.contains("exit=1"), "{said} / {stderr}");
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{stderr}");
    assert!(
        lines[0].starts_with("error: gui: the display went away"),
        "{stderr}"
    );
}
