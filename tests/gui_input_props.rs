//! Property tests of the two parsers that read what the window did not
//! write itself this run: a session file (`gui --session`) and the saved
//! state (eframe's app.ron). Any input of the right shape, with arbitrary
//! numbers and lengths, either loads sanitised (every range drawable,
//! every list and string bounded, tiles the views that exist, each once)
//! or is refused in one line; never a hang, an abort or an allocation past
//! a bound. The window cases themselves (a session's and a saved state's
//! zoom of width 5e-324, 10,000 tiles, a 10 MB save folder) run through
//! the binary under Xvfb at the end.
#![cfg(feature = "gui")]
#![allow(clippy::unwrap_used)]

mod common;
use common::xvfb::{have_xvfb, runtime_dir, under_xvfb};

use std::collections::HashMap;
use std::time::{Duration, Instant};

use proptest::prelude::*;
use serde_json::{Value, json};

use oneblock::app::saved_state;
use oneblock::app::session::Session;
use oneblock::app::settings::{
    MAX_SAVE_DIR_LEN, MAX_ZOOM_LEVELS, PhaseRange, Settings, ViewKind, is_usable_range,
};

/// A float from every corner: ordinary, tiny, subnormal, huge, signed.
fn wild() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -10.0..10.0f64,
        1 => Just(0.0),
        1 => Just(5e-324),
        1 => Just(-5e-324),
        1 => Just(1e-310),
        1 => Just(1e308),
        1 => Just(-1e308),
        1 => Just(f64::MAX),
        1 => 0.0..1e-300f64,
    ]
}

fn wild_pair() -> impl Strategy<Value = (f64, f64)> {
    prop_oneof![
        (wild(), wild()),
        // A range whose width is at the edge of the bound.
        (wild(), 0.0..1e-10f64).prop_map(|(a, w)| (a, a + w)),
    ]
}

fn view_key() -> impl Strategy<Value = &'static str> {
    prop::sample::select(vec![
        "Plane",
        "Block",
        "Bifurcation",
        "ReturnMap",
        "Events",
        "Numerics",
        "Phase",
    ])
}

prop_compose! {
    /// A session of the right shape: settings with wild ranges, long
    /// lists and strings; a zoom stack of any length.
    fn session_json()(
        zoom in prop::collection::vec((wild_pair(), wild_pair()), 0..200),
        phase_zoom in prop::collection::vec((wild_pair(), wild_pair()), 0..200),
        range in (wild_pair(), wild_pair()),
        tiles in prop::collection::vec(view_key(), 0..3000),
        save_dir_len in prop_oneof![0..100usize, 4000..5000usize, Just(200_000usize)],
        version in prop_oneof![4 => Just(json!(1)), 1 => Just(json!(99)), 1 => Just(json!(-1)), 1 => Just(json!("x"))],
        preset in "[a-z\u{1b}\n]{0,12}",
        key in "[a-z\u{0}-\u{1f}]{1,8}",
    ) -> String {
        let zr = |((a, b), (c, d)): ((f64, f64), (f64, f64))| json!({"theta_nu": [a, b], "theta": [c, d]});
        let pr = |((a, b), (c, d)): ((f64, f64), (f64, f64))| json!({"theta_nu": [a, b], "kappa": [c, d]});
        let mut settings = json!({
            "tiled": tiles,
            "save_dir": "d".repeat(save_dir_len),
            "preset": preset,
            "phase": {"range": pr(range), "zoom": phase_zoom.into_iter().map(pr).collect::<Vec<_>>()},
        });
        settings[key.as_str()] = json!(1);
        json!({
            "oneblock_session": version,
            "settings": settings,
            "bifurcation_zoom": zoom.into_iter().map(zr).collect::<Vec<_>>(),
        })
        .to_string()
    }
}

/// What every loaded settings must satisfy, whatever the file held.
fn assert_sane(s: &Settings) {
    assert!(!s.tiled.is_empty() && s.tiled.len() <= ViewKind::ALL.len());
    for (i, v) in s.tiled.iter().enumerate() {
        assert!(!s.tiled[..i].contains(v), "a repeated tile");
    }
    assert!(s.save_dir.len() <= MAX_SAVE_DIR_LEN);
    assert!(
        s.preset
            .as_deref()
            .is_none_or(|k| oneblock::app::preset(k).is_some())
    );
    let ok = |r: &PhaseRange| r.is_valid();
    assert!(ok(&s.phase.range));
    assert!(s.phase.zoom.iter().all(ok) && s.phase.zoom.len() <= MAX_ZOOM_LEVELS);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn any_session_loads_sanitised_or_is_refused_in_one_line(text in session_json()) {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("s.json");
        std::fs::write(&p, &text).unwrap();
        let t0 = Instant::now();
        match Session::read(&p) {
            Err(e) => {
                prop_assert_eq!(e.lines().count(), 1);
                prop_assert!(e.contains("version"), "{}", e);
                prop_assert!(!e.contains('\u{1b}'), "a raw escape: {:?}", e);
            }
            Ok(l) => {
                let (settings, _) = l.session.settings.clone().sanitised();
                assert_sane(&settings);
                prop_assert!(l.session.bifurcation_zoom.len() <= MAX_ZOOM_LEVELS);
                for z in &l.session.bifurcation_zoom {
                    prop_assert!(is_usable_range(z.theta_nu) && is_usable_range(z.theta));
                }
                if let Some(m) = &l.message {
                    prop_assert_eq!(m.lines().count(), 1);
                    prop_assert!(!m.chars().any(char::is_control), "{:?}", m);
                    prop_assert!(m.len() < 2000, "{} bytes", m.len());
                }
            }
        }
        prop_assert!(t0.elapsed() < Duration::from_secs(5));
    }

    /// The saved state: the same settings written as eframe writes them
    /// (RON inside RON), or mangled. Either set aside with one line, or
    /// parsed and then sanitised to sane settings.
    #[test]
    fn any_saved_state_is_used_sanitised_or_set_aside(
        text in session_json(),
        cut in 0usize..4000,
        mangle in any::<bool>(),
    ) {
        let v: Value = serde_json::from_str(&text).unwrap();
        // Settings from the session's parser (the same shape), then as RON.
        let settings = Session::from_json(&text, "x").session.settings;
        let mut inner = ron::to_string(&settings).unwrap();
        // The raw wild fields too, which the session parser dropped.
        if let Some(t) = v["settings"]["tiled"].as_array() {
            let tiles: Vec<String> = t.iter().filter_map(|x| x.as_str().map(str::to_string)).collect();
            inner = inner.replacen("tiled:[", &format!("tiled:[{}", tiles.iter().map(|t| format!("{t},")).collect::<String>()), 1);
        }
        if mangle {
            inner.truncate(cut.min(inner.len()));
        }
        let kv: HashMap<String, String> = [("app".to_string(), inner)].into();
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("app.ron");
        std::fs::write(&p, ron::to_string(&kv).unwrap()).unwrap();
        let t0 = Instant::now();
        match saved_state::check(&p) {
            Some(m) => {
                prop_assert_eq!(m.lines().count(), 1);
                prop_assert!(m.contains("set aside"), "{}", m);
                prop_assert!(!p.exists());
            }
            None => {
                let kv: HashMap<String, String> =
                    ron::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
                let s: Settings = ron::from_str(&kv["app"]).unwrap();
                assert_sane(&s.sanitised().0);
            }
        }
        prop_assert!(t0.elapsed() < Duration::from_secs(5));
    }
}

/// The cases, through the parsers: a zoom of width 5e-324 and
/// 10,000 tiles load sanitised, at once; a 10 MB save folder in the saved
/// state is set aside.
#[test]
fn the_reported_bricking_inputs_load_sanitised() {
    let text = json!({
        "oneblock_session": 1,
        "settings": {"tiled": vec!["Plane"; 10_000], "save_dir": "d".repeat(100_000),
                     "phase": {"zoom": [{"theta_nu": [0, 5e-324], "kappa": [1, 1]}]}},
        "bifurcation_zoom": [{"theta_nu": [0, 5e-324], "theta": [0, 5e-324]}],
    })
    .to_string();
    let l = Session::from_json(&text, "s.json");
    assert!(l.session.bifurcation_zoom.is_empty());
    let s = &l.session.settings;
    assert_eq!(s.tiled, vec![ViewKind::Plane]);
    assert!(s.phase.zoom.is_empty());
    assert_eq!(s.save_dir, Settings::default().save_dir);
    let m = l.message.unwrap();
    for name in ["bifurcation_zoom", "tiles", "save folder", "phase grid"] {
        assert!(m.contains(name), "{name}: {m}");
    }

    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("app.ron");
    let big = Settings {
        save_dir: "d".repeat(10_000_000),
        ..Settings::default()
    };
    let kv: HashMap<String, String> = [("app".to_string(), ron::to_string(&big).unwrap())].into();
    std::fs::write(&p, ron::to_string(&kv).unwrap()).unwrap();
    let m = saved_state::check(&p).unwrap();
    assert!(m.contains("set aside") && m.contains("bytes"), "{m}");
}

/// `gui` under Xvfb, with `home` as HOME and XDG_DATA_HOME under it.
fn gui_in(home: &std::path::Path, args: &[&std::ffi::OsStr]) -> std::process::Output {
    let xdg = runtime_dir(&home.join("runtime"));
    under_xvfb(300)
        .arg(env!("CARGO_BIN_EXE_oneblock"))
        .arg("gui")
        .args(args)
        .env("HOME", home)
        .env("XDG_DATA_HOME", home.join("data"))
        .env("XDG_RUNTIME_DIR", &xdg)
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap()
}

/// The window cases: a session and a saved state holding a zoom of width
/// 5e-324, 10,000 tiles and (the saved state) a 10 MB save folder. Each
/// run renders its screenshot within --timeout; the saved state is set
/// aside or sanitised, never bricking the launch.
#[test]
fn bricking_sessions_and_saved_states_render_under_xvfb() {
    if !have_xvfb("window cases") {
        return;
    }
    let home = tempfile::tempdir().unwrap();
    let session = home.path().join("s.json");
    std::fs::write(
        &session,
        json!({
            "oneblock_session": 1,
            "settings": {"layout": "Tabs", "tab": "Bifurcation", "tiled": vec!["Plane"; 10_000],
                         "phase": {"zoom": [{"theta_nu": [0, 5e-324], "kappa": [1, 1]}]}},
            "bifurcation_zoom": [{"theta_nu": [0, 5e-324], "theta": [0, 5e-324]}],
        })
        .to_string(),
    )
    .unwrap();
    let shot = home.path().join("s.png");
    let o = gui_in(
        home.path(),
        &[
            "--timeout".as_ref(),
            "120".as_ref(),
            "--session".as_ref(),
            session.as_os_str(),
            "--screenshot".as_ref(),
            shot.as_os_str(),
        ],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(shot.exists());

    // The saved state: a 10 MB save folder is set aside.
    let data = home.path().join("data").join("oneblock");
    std::fs::create_dir_all(&data).unwrap();
    let state = data.join("app.ron");
    let big = Settings {
        save_dir: "d".repeat(10_000_000),
        ..Settings::default()
    };
    let kv: HashMap<String, String> = [("app".to_string(), ron::to_string(&big).unwrap())].into();
    std::fs::write(&state, ron::to_string(&kv).unwrap()).unwrap();
    let shot = home.path().join("state.png");
    let o = gui_in(
        home.path(),
        &[
            "--timeout".as_ref(),
            "120".as_ref(),
            "--saved-state".as_ref(),
            "--screenshot".as_ref(),
            shot.as_os_str(),
        ],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("set aside"), "{err}");
    assert!(!state.exists() && data.join("app.ron.unusable-1").exists());

    // And 10,000 tiles with a zoom of width 5e-324: sanitised, rendered.
    let mut s = Settings {
        tiled: vec![ViewKind::Plane; 10_000],
        ..Settings::default()
    };
    s.phase.zoom = vec![PhaseRange {
        theta_nu: (0.0, 5e-324),
        kappa: (1.0, 1.0),
    }];
    let kv: HashMap<String, String> = [("app".to_string(), ron::to_string(&s).unwrap())].into();
    std::fs::write(&state, ron::to_string(&kv).unwrap()).unwrap();
    let shot = home.path().join("tiles.png");
    let o = gui_in(
        home.path(),
        &[
            "--timeout".as_ref(),
            "120".as_ref(),
            "--saved-state".as_ref(),
            "--screenshot".as_ref(),
            shot.as_os_str(),
        ],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(shot.exists());
}

/// A frame that stalls cannot keep a scripted run alive: the watchdog
/// ends it within --timeout and its grace, with one line naming the flag
/// and exit 1 (the first frame here sleeps for an hour).
#[test]
fn timeout_bounds_a_run_whose_frame_stalls() {
    if !have_xvfb("stalled-frame case") {
        return;
    }
    let home = tempfile::tempdir().unwrap();
    let shot = home.path().join("shot.png");
    let started = std::time::Instant::now();
    let o = gui_in(
        home.path(),
        &[
            "--screenshot".as_ref(),
            shot.as_os_str(),
            "--timeout".as_ref(),
            "1".as_ref(),
            "--stall-first-frame".as_ref(),
        ],
    );
    let took = started.elapsed();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("--timeout"), "{err}");
    assert!(!shot.exists());
    // The hour-long frame is cut at 1 s + the grace (2 s with the test's
    // stall: no picture is due), and the start.
    assert!(took < std::time::Duration::from_secs(60), "{took:?}");
}
