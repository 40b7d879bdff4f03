//! The real window under Xvfb: whether `xvfb-run` is here (CI installs it,
//! so there its absence fails), a private runtime folder, and the command
//! the window runs under.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Whether `xvfb-run` is here. Under CI (CI set) its absence fails the
/// test; elsewhere `what` is skipped with a note.
pub fn have_xvfb(what: &str) -> bool {
    let here = Command::new("sh")
        .args(["-c", "command -v xvfb-run"])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    if !here {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI must install xvfb (see .ci/run)"
        );
        eprintln!("note: xvfb-run not found; {what} skipped (apt-get install xvfb xauth)");
    }
    here
}

/// The folder `path`, made private to its owner as XDG_RUNTIME_DIR must
/// be; `path` again.
pub fn runtime_dir(path: &Path) -> PathBuf {
    std::fs::create_dir_all(path).expect("runtime dir");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o700)).expect("mode");
    }
    path.to_path_buf()
}

/// `timeout SECONDS xvfb-run -a` on a 1600×1000 screen: the program and
/// its arguments follow.
pub fn under_xvfb(seconds: u32) -> Command {
    let mut c = Command::new("timeout");
    c.arg(seconds.to_string())
        .args(["xvfb-run", "-a", "-s", "-screen 0 1600x1000x24"]);
    c
}

/// `oneblock gui` at Fig. 3b, 1280×800, under Xvfb (a private runtime
/// folder in `dir`, no Wayland), with `extra` flags, its screenshot to
/// `png`: how it ended, which the caller checks.
pub fn fig3b_window(dir: &Path, extra: &[&str], png: &Path) -> Output {
    let xdg = runtime_dir(&dir.join("xdg"));
    under_xvfb(400)
        .arg(env!("CARGO_BIN_EXE_oneblock"))
        .args([
            "gui",
            "--preset",
            "fig3b",
            "--size",
            "1280x800",
            "--timeout",
            "300",
        ])
        .args(extra)
        .arg("--screenshot")
        .arg(png)
        .env("XDG_RUNTIME_DIR", &xdg)
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run oneblock gui")
}
