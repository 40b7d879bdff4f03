//! What the `figure` tests share: a session with small jobs, the command
//! run with no display of any kind, and a GIF read back as whole pictures.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use oneblock::app::Settings;
use oneblock::app::session::Session;

/// Fig. 3b's settings with small jobs (60 columns, short transients and
/// trajectories), so that a figure or a frame is quick.
pub fn small_settings() -> Settings {
    Settings {
        columns: 60,
        sweep_transient: 60,
        sweep_keep: 40,
        trajectory_cycles: 40,
        ..Settings::default()
    }
}

/// `settings` saved as a session `DIR/small.json`; its path.
pub fn session_of(dir: &Path, settings: Settings) -> PathBuf {
    let p = dir.join("small.json");
    let session = Session {
        settings,
        bifurcation_zoom: vec![],
        ..Session::default()
    };
    std::fs::write(&p, session.to_json()).expect("session");
    p
}

/// A session with small jobs ([`small_settings`]).
pub fn small_session(dir: &Path) -> PathBuf {
    session_of(dir, small_settings())
}

/// Runs `oneblock figure ARGS` with no display of any kind.
pub fn figure(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .arg("figure")
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run oneblock figure")
}

/// One frame as a whole picture: its delay (hundredths of a second) and
/// its RGBA pixels.
pub type Picture = (u16, Vec<u8>);

/// The frames of a GIF as whole pictures (RGBA), each frame's rectangle
/// drawn over the picture before it (the encoder stores only what
/// changed), with the picture's size and each frame's delay.
pub fn gif_frames(path: &Path) -> ((usize, usize), Vec<Picture>) {
    let file = std::fs::File::open(path).expect("gif written");
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d = opts.read_info(file).expect("a GIF");
    let (w, h) = (usize::from(d.width()), usize::from(d.height()));
    let mut canvas = vec![0u8; w * h * 4];
    let mut out = vec![];
    while let Some(f) = d.read_next_frame().expect("a frame") {
        let (fw, left, top) = (
            usize::from(f.width),
            usize::from(f.left),
            usize::from(f.top),
        );
        for (i, px) in f.buffer.chunks(4).enumerate() {
            let (x, y) = (left + i % fw, top + i / fw);
            if px[3] > 0 && x < w && y < h {
                canvas[(y * w + x) * 4..(y * w + x) * 4 + 4].copy_from_slice(px);
            }
        }
        out.push((f.delay, canvas.clone()));
    }
    ((w, h), out)
}
