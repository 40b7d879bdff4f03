//! The window's Record → "θν played": a GIF of the return map as Play θν
//! shows it, written into the save folder by a thread of its own while the
//! window goes on (60 frames, 640×480); and the browser's way of making it
//! (`PlayRun` advanced a small budget at a time, as the page does between
//! its frames) gives the very bytes `figure --play` makes at once.
#![cfg(feature = "gui")]

use crate::window;

use std::time::Duration;

use egui_kittest::kittest::Queryable;
use oneblock::app::animation::{PlayRun, PlaySpan, play_gif};
use oneblock::app::figure::Figure;
use oneblock::app::{Layout, Recorder, Settings, ViewKind};
use window::harness;

/// Small jobs, so that each frame's orbit is quick.
fn small() -> Settings {
    Settings {
        columns: 24,
        sweep_transient: 60,
        sweep_keep: 20,
        trajectory_cycles: 30,
        ..Settings::default()
    }
}

#[test]
fn record_saves_a_gif_of_theta_nu_played() {
    let dir = tempfile::tempdir().expect("temp dir");
    let rec = Recorder::new();
    let settings = Settings {
        save_dir: dir.path().display().to_string(),
        layout: Layout::Tabs,
        tab: ViewKind::ReturnMap,
        ..small()
    };
    let mut h = harness(&rec, settings);
    h.run_steps(2);
    h.get_by_label("Record").click();
    h.run_steps(2);
    h.get_by_label("θν played").click();
    let mut gif = None;
    for _ in 0..6000 {
        h.step();
        gif = std::fs::read_dir(dir.path())
            .expect("read dir")
            .flatten()
            .map(|e| e.path())
            .find(|p| p.extension().is_some_and(|e| e == "gif"));
        if gif.is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let gif = gif.expect("a GIF was written within two minutes");
    let name = gif
        .file_name()
        .expect("a name")
        .to_string_lossy()
        .to_string();
    assert!(name.starts_with("oneblock-return-map-played-"), "{name}");
    assert_eq!(window::gif_size_and_frames(&gif), ((640, 480), 60));
}

#[test]
fn a_played_gif_made_in_pieces_is_the_gif_made_at_once() {
    let mut fig = Figure::record(ViewKind::ReturnMap, small());
    fig.size = eframe::egui::vec2(200.0, 150.0);
    // 40 frames: some come after the first chunk of 32, whose pixels the
    // palette is learnt from.
    let span = PlaySpan {
        from: 0.9,
        to: 1.3,
        frames: 40,
    };
    let whole = play_gif(fig.clone(), span).expect("a GIF");
    let one = PlaySpan { frames: 1, ..span };
    assert!(PlayRun::new(fig.clone(), one).is_err(), "one frame");
    let phase = Figure::record(ViewKind::Phase, small());
    assert!(PlayRun::new(phase, span).is_err(), "the phase view");
    let mut run = PlayRun::new(fig, span).expect("valid");
    let mut pieces = 0;
    let sliced = loop {
        pieces += 1;
        assert!(pieces < 1_000_000, "the recording never ends");
        if let Some(r) = run.advance(Duration::from_micros(200)) {
            break r.expect("a GIF");
        }
    };
    assert!(pieces > 40, "{pieces} pieces");
    // Each frame counts twice: gathered for the held axes and legend, then
    // drawn.
    assert_eq!(run.progress(), (80, 80));
    assert!(
        sliced == whole,
        "{} bytes against {}",
        sliced.len(),
        whole.len()
    );
}
