//! CSV exports from the window: the events and the phase grid are written
//! into the chosen folder in the command line's formats, under a fresh
//! name, with a note on the accuracy of an Auto trajectory.
#![cfg(feature = "gui")]

#[path = "common/window.rs"]
mod window;

mod common;
use common::xvfb::{have_xvfb, runtime_dir, under_xvfb};

use egui_kittest::kittest::Queryable;

use oneblock::app::{Recorder, Settings};
use oneblock::worker::Update;
use window::{event, feed_phase, harness, phase_jobs, phase_tab, wait_for_csv};

#[test]
fn export_writes_the_events_csv_into_the_chosen_folder() {
    let dir = tempfile::tempdir().expect("temp dir");
    let rec = Recorder::new();
    let settings = Settings {
        save_dir: dir.path().display().to_string(),
        ..Settings::default()
    };
    let mut h = harness(&rec, settings);
    h.run_steps(2);
    let g = window::trajectory_generation(&rec);
    for i in 0..3 {
        rec.push(Update::Slip {
            generation: g,
            event: event(0.5, 0.2, 103.0 * i as f64),
        });
    }
    h.run_steps(2);
    h.get_by_label("Export data").click();
    h.run_steps(2);
    h.get_by_label("Events CSV").click();
    // The file is written on a thread of its own.
    let path = wait_for_csv(&mut h, dir.path()).expect("an events CSV was written");
    // Under Auto the events come at the trajectory's accuracy: the window
    // says so, since the CSV cannot.
    h.run_steps(2);
    assert!(
        h.query_by_label_contains("computed at Auto's trajectory accuracy (dp54 tol 1e-5")
            .is_some()
    );
    let text = std::fs::read_to_string(&path).expect("read csv");
    // Where it came from: the program, the view, the model at the
    // trajectory's accuracy, and every setting as a session's JSON.
    let comments: Vec<&str> = text.lines().take_while(|l| l.starts_with('#')).collect();
    assert_eq!(comments.len(), 4, "{comments:?}");
    assert_eq!(comments[0], format!("# {}", oneblock::provenance::PROGRAM));
    assert_eq!(comments[1], "# view: events (the window)");
    assert!(
        comments[2].starts_with("# model: kappa = 18.95, gamma = 6.5, nu = 0.001, theta-nu = 1, ")
            && comments[2].ends_with("dp54 tol 1e-5"),
        "{}",
        comments[2]
    );
    let json = comments[3]
        .strip_prefix("# settings: window settings: ")
        .expect("the settings line");
    let back: Settings = serde_json::from_str(json).expect("the settings read back");
    assert_eq!(back.save_dir, dir.path().display().to_string());
    assert_eq!(back.params, Settings::default().params);
    // The csv crate reads past them to the header and the 3 rows.
    let mut r = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    assert_eq!(r.headers().expect("a header").len(), 16);
    assert_eq!(
        r.records()
            .filter(|x| x.as_ref().is_ok_and(|x| x.len() == 16))
            .count(),
        3
    );
    let mut lines = text.lines().skip(comments.len());
    // The command line's header, spelled out as `oneblock orbit` writes it.
    assert_eq!(
        lines.next(),
        Some(
            "theta,onset_x,onset_y,onset_time,accel_duration,slip_duration,stop_x,stop_y,\
slip_distance,peak_vr,energy_released,stick_duration,theta_next,restarted,rhs_evals,steps"
        )
    );
    assert_eq!(lines.count(), 3);
    assert!(
        path.file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with("oneblock-events-"))
    );
}

#[test]
fn export_writes_the_phase_grid_as_oneblock_phase_does() {
    let dir = tempfile::tempdir().expect("temp dir");
    let rec = Recorder::new();
    let settings = Settings {
        save_dir: dir.path().display().to_string(),
        ..phase_tab()
    };
    let mut h = harness(&rec, settings);
    h.run_steps(2);
    let job = phase_jobs(&rec)[0];
    feed_phase(&rec, &job);
    h.run_steps(2);
    h.get_by_label("Export data").click();
    h.run_steps(2);
    h.get_by_label("Phase diagram CSV (oneblock phase)").click();
    let path = wait_for_csv(&mut h, dir.path()).expect("a phase CSV was written");
    assert!(
        path.file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with("oneblock-phase-"))
    );
    let text = std::fs::read_to_string(&path).expect("read csv");
    let (comments, lines): (Vec<&str>, Vec<&str>) = text.lines().partition(|l| l.starts_with('#'));
    assert_eq!(comments[1], "# view: phase (the window)");
    // θν and κ are the grid's axes: the model line leaves θν out.
    assert!(
        comments[2].starts_with("# model: kappa = ") && !comments[2].contains("theta-nu"),
        "{}",
        comments[2]
    );
    assert_eq!(
        lines[0],
        "theta_nu,kappa,period,lyapunov,regime,iterates,class,lyapunov_stderr"
    );
    assert_eq!(lines.len(), 901);
    // Rows of increasing κ, each along increasing θν.
    assert_eq!(lines[1], "0,1,1,-0.2,,40,FP,");
    assert!(lines[900].starts_with("1.5707963267948966,42,0,0.3,,40,chaos,0.05"));
}

/// `oneblock gui --session S --screenshot out.svg` under Xvfb for every
/// view (a session with small grids, so that it is quick and also checks
/// that a session renders headless): each SVG parses, labels its axes with
/// at least five numeric ticks written as text, and has the series the
/// view draws.
#[test]
fn every_view_exports_an_svg_with_text_ticks_and_its_series() {
    use oneblock::app::ViewKind;
    use oneblock::app::session::Session;
    use oneblock::app::settings::Layout;
    if !have_xvfb("SVG window test") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let xdg = runtime_dir(&dir.path().join("xdg"));
    // The fewest series each view draws on the Fig. 3b orbit, and the
    // fewest numeric tick labels (the block view is a picture, not a plot).
    let expect = [
        (ViewKind::Plane, 2, 10),
        (ViewKind::Block, 1, 0),
        (ViewKind::Bifurcation, 1, 10),
        (ViewKind::ReturnMap, 2, 10),
        (ViewKind::Events, 2, 10),
        (ViewKind::Numerics, 1, 10),
        (ViewKind::Phase, 1, 10),
    ];
    for (v, min_series, min_ticks) in expect {
        let mut s = Settings {
            layout: Layout::Tabs,
            tab: v,
            columns: 60,
            sweep_transient: 60,
            sweep_keep: 40,
            trajectory_cycles: 40,
            ..Settings::default()
        };
        s.phase.theta_nu_steps = 6;
        s.phase.kappa_steps = 6;
        let session = dir.path().join(format!("{}.json", v.key()));
        std::fs::write(
            &session,
            Session {
                settings: s,
                bifurcation_zoom: vec![],
                ..Session::default()
            }
            .to_json(),
        )
        .expect("session");
        let svg = dir.path().join(format!("{}.svg", v.key()));
        let out = under_xvfb(400)
            .arg(env!("CARGO_BIN_EXE_oneblock"))
            .args(["gui", "--timeout", "300", "--session"])
            .arg(&session)
            .arg("--screenshot")
            .arg(&svg)
            .env("XDG_RUNTIME_DIR", &xdg)
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .expect("run");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{}: {err}", v.key());
        assert!(!err.contains("warning: session"), "{err}");
        let text = std::fs::read_to_string(&svg).expect("svg");
        let (texts, series) = parse_svg(&text);
        let numeric = texts
            .iter()
            .filter(|t| t.replace('−', "-").trim().parse::<f64>().is_ok())
            .count();
        eprintln!("{}: {numeric} numeric labels, series {series:?}", v.key());
        if let Some(keep) = std::env::var_os("ONEBLOCK_KEEP_SVG") {
            std::fs::copy(
                &svg,
                std::path::Path::new(&keep).join(format!("{}.svg", v.key())),
            )
            .expect("keep the SVG");
        }
        assert!(
            numeric >= min_ticks,
            "{}: {numeric} numeric tick labels in {texts:?}",
            v.key()
        );
        assert!(series.len() >= min_series, "{}: series {series:?}", v.key());
        if matches!(v, ViewKind::Plane | ViewKind::Events) {
            same_series_as_the_png(&text, &session, dir.path(), &xdg, v.key());
        }
    }
}

/// The PNG of the same session shows every series colour of the SVG: the
/// two pictures draw the same series.
fn same_series_as_the_png(
    svg: &str,
    session: &std::path::Path,
    dir: &std::path::Path,
    xdg: &std::path::Path,
    key: &str,
) {
    let png = dir.join(format!("{key}.png"));
    let out = under_xvfb(400)
        .arg(env!("CARGO_BIN_EXE_oneblock"))
        .args(["gui", "--timeout", "300", "--session"])
        .arg(session)
        .arg("--screenshot")
        .arg(&png)
        .env("XDG_RUNTIME_DIR", xdg)
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run");
    assert!(
        out.status.success(),
        "{key}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let img = image::open(&png).expect("png").to_rgb8();
    let colours = series_colours(svg);
    assert!(!colours.is_empty(), "{key}: no series colours");
    let found: Vec<[u8; 3]> = colours
        .iter()
        .copied()
        .filter(|c| {
            img.pixels().any(|p| {
                p.0.iter()
                    .zip(c)
                    .all(|(a, b)| (i32::from(*a) - i32::from(*b)).abs() <= 12)
            })
        })
        .collect();
    assert_eq!(
        found, colours,
        "{key}: series colours of the SVG in the PNG"
    );
}

/// The distinct opaque colours (`#rrggbb` fill or stroke) of the SVG's
/// series, images aside.
fn series_colours(svg: &str) -> Vec<[u8; 3]> {
    use quick_xml::events::Event;
    let mut r = quick_xml::Reader::from_str(svg);
    let mut out = std::collections::BTreeSet::new();
    loop {
        match r.read_event().expect("parses") {
            Event::Start(e) | Event::Empty(e) => {
                let attrs: Vec<(Vec<u8>, String)> = e
                    .attributes()
                    .flatten()
                    .map(|a| {
                        (
                            a.key.as_ref().to_vec(),
                            String::from_utf8_lossy(&a.value).to_string(),
                        )
                    })
                    .collect();
                let get = |k: &[u8]| attrs.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone());
                if get(b"class").as_deref() != Some("series") || e.name().as_ref() == b"image" {
                    continue;
                }
                let pairs: [(&[u8], &[u8]); 2] =
                    [(b"fill", b"fill-opacity"), (b"stroke", b"stroke-opacity")];
                for (paint, opacity) in pairs {
                    if let Some(c) = get(paint).filter(|c| c.len() == 7 && c.starts_with('#'))
                        && get(opacity).is_none()
                    {
                        let h = |i: usize| u8::from_str_radix(&c[i..i + 2], 16).expect("hex");
                        out.insert([h(1), h(3), h(5)]);
                    }
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    out.into_iter().collect()
}

/// The texts and the distinct series (`data-series`) of an SVG, which must
/// parse as XML to the end.
fn parse_svg(text: &str) -> (Vec<String>, std::collections::BTreeSet<String>) {
    use quick_xml::events::Event;
    let mut r = quick_xml::Reader::from_str(text);
    let (mut texts, mut series) = (Vec::new(), std::collections::BTreeSet::new());
    let mut in_text = false;
    let mut root = false;
    loop {
        match r.read_event().expect("the SVG parses") {
            Event::Start(e) | Event::Empty(e) => {
                root |= e.name().as_ref() == b"svg";
                in_text = e.name().as_ref() == b"text";
                for a in e.attributes().flatten() {
                    if a.key.as_ref() == b"data-series" {
                        series.insert(String::from_utf8_lossy(&a.value).to_string());
                    }
                }
            }
            Event::Text(t) if in_text => {
                texts.push(String::from_utf8_lossy(t.as_ref()).to_string());
            }
            Event::End(_) => in_text = false,
            Event::Eof => break,
            _ => {}
        }
    }
    assert!(root, "no <svg> element");
    (texts, series)
}

/// Waits for a file ending in `ext` in `dir` (written on a thread).
fn wait_for_ext(
    h: &mut egui_kittest::Harness<'static, oneblock::app::Explorer>,
    dir: &std::path::Path,
    ext: &str,
) -> Option<std::path::PathBuf> {
    for _ in 0..200 {
        h.step();
        let found = std::fs::read_dir(dir)
            .expect("read dir")
            .flatten()
            .map(|e| e.path())
            .find(|p| p.extension().is_some_and(|e| e == ext));
        if found.is_some() {
            return found;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    None
}

/// The panel's SVG button writes a vector picture of the tiles, with the
/// events the window was sent; Save session writes a file that reads back
/// to the window's settings.
#[test]
fn the_window_saves_an_svg_of_the_tiles_and_a_session() {
    use oneblock::app::session::Session;
    let dir = tempfile::tempdir().expect("temp dir");
    let rec = Recorder::new();
    let settings = Settings {
        save_dir: dir.path().display().to_string(),
        ..Settings::default()
    };
    let mut h = harness(&rec, settings);
    h.run_steps(2);
    let g = window::trajectory_generation(&rec);
    for i in 0..30 {
        rec.push(Update::Slip {
            generation: g,
            event: event(0.5, 0.2, 103.0 * i as f64),
        });
    }
    h.run_steps(2);
    h.query_all_by_label("SVG")
        .next()
        .expect("an SVG button")
        .click();
    let svg = wait_for_ext(&mut h, dir.path(), "svg").expect("an SVG was written");
    assert!(
        svg.file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with("oneblock-window-"))
    );
    let text = std::fs::read_to_string(&svg).expect("svg");
    let (texts, series) = parse_svg(&text);
    // The four default tiles' titles, as text.
    for t in ["Plane (x, y)", "Bifurcation", "Return map", "Events"] {
        assert!(texts.iter().any(|x| x == t), "{t} missing in {texts:?}");
    }
    // The events' series and distributions are there.
    assert!(
        series.iter().any(|s| s.starts_with("events_series:")),
        "{series:?}"
    );

    h.get_by_label("Save session").click();
    let json = wait_for_ext(&mut h, dir.path(), "json").expect("a session was written");
    let back = Session::from_json(&std::fs::read_to_string(&json).expect("json"), "s");
    assert_eq!(back.message, None);
    assert_eq!(back.session.settings, h.state().settings);
}

/// Record on the plane's tile (at half speed) writes an animated GIF of
/// 120 frames into the save folder, made on a thread of its own while the
/// window goes on.
#[test]
fn record_saves_an_animated_gif_of_the_plane() {
    let dir = tempfile::tempdir().expect("temp dir");
    let rec = Recorder::new();
    let settings = Settings {
        save_dir: dir.path().display().to_string(),
        trajectory_cycles: 40,
        ..Settings::default()
    };
    let mut h = harness(&rec, settings);
    h.run_steps(2);
    h.query_all_by_label("Record")
        .next()
        .expect("a Record menu on the plane's tile")
        .click();
    h.run_steps(2);
    h.get_by_label("Half speed").click();
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
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let gif = gif.expect("a GIF was written within two minutes");
    assert!(
        gif.file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with("oneblock-plane-"))
    );
    assert_eq!(window::gif_size_and_frames(&gif), ((640, 480), 120));
}

/// The browser's Record: the same GIF made in pieces (the view's data a
/// budget at a time, then a frame per piece, as the page makes it between
/// its frames), byte for byte what `figure --frames` and the desktop's
/// Record make; 40 frames, so some come after the first chunk of 32 whose
/// pixels the palette is learnt from.
#[test]
fn a_gif_made_in_pieces_is_the_gif_made_at_once() {
    use oneblock::app::ViewKind;
    use oneblock::app::animation::{GifRun, gif};
    use oneblock::app::figure::Figure;
    let fig = Figure {
        view: ViewKind::Plane,
        settings: Settings {
            trajectory_cycles: 30,
            ..Settings::default()
        },
        zoom: Vec::new(),
        theta_nu: None,
        theta: None,
        size: eframe::egui::vec2(200.0, 150.0),
        crosshair: false,
        look: Default::default(),
        overlays: Default::default(),
        session: None,
    };
    let whole = gif(&fig, 40, 0.5).expect("a GIF");
    assert!(GifRun::new(fig.clone(), 0, 0.5).is_err(), "no frames");
    assert!(GifRun::new(fig.clone(), 40, 2.0).is_err(), "too fast");
    let mut run = GifRun::new(fig, 40, 0.5).expect("valid");
    let mut pieces = 0;
    let sliced = loop {
        pieces += 1;
        assert!(pieces < 100_000, "the recording never ends");
        if let Some(r) = run.advance(std::time::Duration::from_micros(200)) {
            break r.expect("a GIF");
        }
    };
    assert!(pieces > 40 + 32, "{pieces} pieces");
    assert_eq!(run.progress(), (40, 40));
    assert!(
        sliced == whole,
        "{} bytes against {}",
        sliced.len(),
        whole.len()
    );
}
