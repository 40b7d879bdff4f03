//! Setup on a fresh machine: README.md, docs/gui.md and .ci/run use one
//! list of Debian packages (.ci/packages.txt), and `oneblock gui` without a
//! display says so in one line.

#![allow(clippy::unwrap_used)]

use std::path::Path;

fn read(rel: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)).unwrap()
}

/// The packages of .ci/packages.txt, in order.
fn package_list() -> Vec<String> {
    read(".ci/packages.txt")
        .lines()
        .map(|l| l.split('#').next().unwrap_or("").trim())
        .filter(|l| !l.is_empty())
        .map(str::to_string)
        .collect()
}

/// The packages of each `apt-get install` command of a page (its
/// continuation lines joined, options dropped).
fn apt_commands(page: &str) -> Vec<Vec<String>> {
    let joined = page.replace("\\\n", " ");
    joined
        .lines()
        .filter_map(|l| l.split_once("apt-get install").map(|(_, rest)| rest))
        .map(|rest| {
            rest.split_whitespace()
                .take_while(|w| !w.starts_with(['`', '>']) && *w != "&&" && *w != "#")
                .filter(|w| !w.starts_with('-'))
                .map(str::to_string)
                .collect()
        })
        .collect()
}

#[test]
fn the_docs_quote_the_one_package_list() {
    let list = package_list();
    for needed in [
        "build-essential",
        "libegl1",
        "libx11-xcb1",
        "libxkbcommon-x11-0",
        "xvfb",
    ] {
        assert!(
            list.iter().any(|p| p == needed),
            "{needed} is not in .ci/packages.txt"
        );
    }
    for page in ["README.md", "docs/gui.md"] {
        let cmds = apt_commands(&read(page));
        assert!(!cmds.is_empty(), "{page} has no apt-get install command");
        for c in cmds {
            assert_eq!(
                c, list,
                "{page}'s apt-get install differs from .ci/packages.txt"
            );
        }
    }
    let ci = read(".ci/run");
    assert!(
        ci.contains(".ci/packages.txt"),
        ".ci/run does not read .ci/packages.txt"
    );
    assert!(
        apt_commands(&ci)
            .iter()
            .all(|c| c.iter().all(|w| w.starts_with('"'))),
        ".ci/run names packages of its own"
    );
}

#[test]
fn the_readme_names_the_toolchain() {
    let readme = read("README.md");
    for needed in ["1.90", "rustup", "build-essential"] {
        assert!(
            readme.contains(needed),
            "README.md does not mention {needed}"
        );
    }
    let manifest = read("Cargo.toml");
    assert!(
        manifest.contains("rust-version = \"1.90\""),
        "README's Rust version is not Cargo.toml's"
    );
}

/// Without X11 or Wayland, `oneblock gui` fails with one line saying so
/// and naming xvfb-run, not the windowing library's error.
#[cfg(feature = "gui")]
#[test]
fn gui_without_a_display_says_so_in_one_line() {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args(["gui", "--preset", "fig3b"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let err = String::from_utf8(o.stderr).unwrap();
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("error: no display") && err.contains("xvfb-run"),
        "{err}"
    );
    assert!(!err.contains(".cargo") && !err.contains("winit"), "{err}");
    // Bad flags are still reported first, as usage errors.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args(["gui", "--font-scale", "9"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
}
