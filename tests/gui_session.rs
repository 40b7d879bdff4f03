//! Sessions: a saved session reads back to identical settings and zoom; a
//! corrupt or partly wrong file gives one message naming what was wrong,
//! defaults for that, and keeps everything else as saved.
#![cfg(feature = "gui")]

use crate::window;

use oneblock::Params;
use oneblock::app::bifurcation::Zoom;
use oneblock::app::session::Session;
use oneblock::app::settings::{AccuracyMode, Layout, PhaseRange, Settings, ViewKind};
use oneblock::integrate::Method;

fn changed() -> Session {
    let mut s = Settings {
        params: Params {
            kappa: 50.0,
            gamma: 6.5,
            nu: 1e-4,
            theta_nu: 1.4,
            ..Params::default()
        },
        accuracy: AccuracyMode::Custom,
        method: Method::Rk4,
        step: 2e-4,
        layout: Layout::Tabs,
        tab: ViewKind::Events,
        font_scale: 1.5,
        preset: Some("intermittent".into()),
        columns: 123,
        ..Settings::default()
    };
    s.phase.zoom.push(PhaseRange {
        theta_nu: (1.0, 1.3),
        kappa: (10.0, 20.0),
    });
    Session {
        settings: s,
        bifurcation_zoom: vec![Zoom {
            theta_nu: (1.15, 1.35),
            theta: (0.2, 0.9),
        }],
        ..Session::default()
    }
}

#[test]
fn a_session_round_trip_restores_identical_settings() {
    let s = changed();
    let text = s.to_json();
    let back = Session::from_json(&text, "s.json");
    assert_eq!(back.message, None);
    assert_eq!(back.session, s);
    // Every field differs from the defaults where it was changed: the
    // round trip is not the defaults' by accident.
    assert_ne!(back.session.settings, Settings::default());
}

#[test]
fn a_corrupt_session_gives_one_message_and_defaults() {
    for text in ["{\"settings\": {\"params\": ", "[1, 2]", ""] {
        let l = Session::from_json(text, "bad.json");
        let m = l.message.expect("a message");
        assert!(m.contains("bad.json") && m.contains("default"), "{m}");
        assert_eq!(l.session.settings, Settings::default());
        assert!(l.session.bifurcation_zoom.is_empty());
    }
}

#[test]
fn bad_and_unknown_fields_are_named_and_the_rest_is_kept() {
    let good = changed();
    let mut v: serde_json::Value = serde_json::from_str(&good.to_json()).expect("json");
    v["settings"]["font_scale"] = serde_json::json!("big");
    v["settings"]["columns"] = serde_json::json!(5);
    v["settings"]["wobble"] = serde_json::json!(true);
    v["extra"] = serde_json::json!(1);
    let l = Session::from_json(&v.to_string(), "s.json");
    let m = l.message.expect("a message");
    assert_eq!(m.lines().count(), 1);
    for name in [
        "settings.font_scale",
        "diagram columns",
        "settings.wobble",
        "extra",
    ] {
        assert!(m.contains(name), "{m} should name {name}");
    }
    let d = Settings::default();
    let s = &l.session.settings;
    assert_eq!((s.font_scale, s.columns), (d.font_scale, d.columns));
    // Nothing else is lost.
    let g = &good.settings;
    assert_eq!(s.params, g.params);
    assert_eq!(
        (s.accuracy, s.method, s.step),
        (g.accuracy, g.method, g.step)
    );
    assert_eq!((s.layout, s.tab), (g.layout, g.tab));
    assert_eq!(s.phase, g.phase);
    assert_eq!(l.session.bifurcation_zoom, good.bifurcation_zoom);
}

/// The Events view states the laminar statistics of the events after the
/// transient: a synthetic run whose lengths are known, creep and stick-slip
/// by where each slip starts (κ = 50, γ = 6.5: creep for |θ| < 0.409).
#[test]
fn the_events_view_counts_the_laminar_phases_of_the_events_after_the_transient() {
    use egui_kittest::kittest::Queryable;
    use oneblock::app::Recorder;
    use oneblock::worker::Update;
    let rec = Recorder::new();
    let settings = Settings {
        layout: Layout::Tabs,
        tab: ViewKind::Events,
        params: oneblock::model::preset("intermittent").unwrap().params,
        ..Settings::default()
    };
    let mut h = window::harness(&rec, settings);
    h.run_steps(2);
    let g = window::trajectory_generation(&rec);
    // 40 events: the first 10 (a quarter, the transient) are left out;
    // then stick-slip slips (onset 0.6) with runs of 4, 6, 6 and 3 creep
    // slips (onset 0.1) between them, and a run cut by the window's end.
    let mut onsets = vec![0.1; 10];
    onsets.push(0.6);
    for l in [4, 6, 6, 3] {
        onsets.extend(std::iter::repeat_n(0.1, l));
        onsets.push(0.6);
    }
    onsets.extend(std::iter::repeat_n(0.1, 40 - onsets.len()));
    assert_eq!(onsets.len(), 40);
    for (i, th) in onsets.iter().enumerate() {
        let mut e = window::event(*th, *th, i as f64);
        e.onset_x = th.cos() / 50.0;
        e.slip_distance = if *th > 0.4 { 0.8 } else { 3e-3 };
        rec.push(Update::Slip {
            generation: g,
            event: e,
        });
    }
    h.run_steps(3);
    let label = "25 creep, 5 stick-slip · 4 laminar phases, mean laminar length 4.8";
    assert!(
        h.query_by_label_contains(label).is_some(),
        "no label containing {label:?}"
    );
}

/// Steps the window until a label contains `text` (the view's threads
/// answer within seconds); false after about 60 s.
fn wait_for_label(
    h: &mut egui_kittest::Harness<'static, oneblock::app::Explorer>,
    text: &str,
) -> bool {
    use egui_kittest::kittest::Queryable;
    for _ in 0..1200 {
        h.step();
        if h.query_by_label_contains(text).is_some() {
            return true;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    false
}

/// The window's latest job of the kind `want` picks, as the recorder saw it
/// sent, run on the single-threaded host (the browser's) and its updates
/// handed back to the window as a backend would; false if none was sent.
fn answer(
    h: &mut egui_kittest::Harness<'static, oneblock::app::Explorer>,
    rec: &oneblock::app::Recorder,
    want: fn(&oneblock::jobs::Spec) -> bool,
) -> bool {
    use oneblock::jobs::{Local, Shape};
    use oneblock::worker::Command;
    for _ in 0..50 {
        h.step();
        let sent = rec.commands().into_iter().rev().find_map(|c| match c {
            Command::Run { generation, spec } if want(&spec) => Some((generation, spec)),
            _ => None,
        });
        if let Some((generation, spec)) = sent {
            for u in Local::start(spec, generation, Shape::default()).run_to_end(usize::MAX) {
                rec.push(u);
            }
            return true;
        }
    }
    false
}

/// The window asks for the channel passage, computed from f by a job of its
/// own, and shows it beside the mean laminar length (20.9 slips on the
/// intermittent preset, as `orbit --stats` gives), and its scan (a job too)
/// names the tangency it located by continuation and why the slope is not
/// −1/2; at the creep preset the scan finds no tangency and says so
/// instead of fitting.
#[test]
fn the_events_view_sets_the_channel_passage_beside_the_mean_and_fits_only_at_a_tangency() {
    use egui_kittest::kittest::Queryable;
    use oneblock::app::Recorder;
    use oneblock::app::settings::EventsPlot;
    use oneblock::worker::Update;
    for (preset, onsets, passage, verdict) in [
        ("intermittent", [0.1, 0.6], "channel passage 20.9", "ghost"),
        ("creep", [0.69, 0.7], "no open channel", "no tangency"),
    ] {
        let rec = Recorder::new();
        let settings = Settings {
            layout: Layout::Tabs,
            tab: ViewKind::Events,
            events_plot: EventsPlot::Scaling,
            params: oneblock::model::preset(preset).unwrap().params,
            ..Settings::default()
        };
        let mut h = window::harness(&rec, settings);
        h.run_steps(2);
        let g = window::trajectory_generation(&rec);
        for i in 0..40 {
            let th = onsets[usize::from(i % 5 == 0)];
            rec.push(Update::Slip {
                generation: g,
                event: window::event(th, th, f64::from(i)),
            });
        }
        use oneblock::jobs::Spec;
        assert!(answer(&mut h, &rec, |s| matches!(s, Spec::Passage(_))));
        assert!(wait_for_label(&mut h, passage), "{preset}: no {passage:?}");
        h.get_by_label("Laminar length vs distance to a tangency")
            .click();
        assert!(answer(&mut h, &rec, |s| matches!(s, Spec::Scan(_))));
        assert!(wait_for_label(&mut h, verdict), "{preset}: no {verdict:?}");
    }
}

#[test]
fn opening_a_session_in_the_window_replaces_settings_and_zoom_but_not_the_folder() {
    // What the browser's "Open session…" does with an uploaded file.
    use oneblock::app::{Explorer, Recorder};
    let mut app = Explorer::new(Box::new(Recorder::new()), Settings::default());
    app.settings.save_dir = "/my/figures".into();
    let s = changed();
    let loaded = Session::from_text(&s.to_json(), "s.json").expect("a current session");
    app.open_session(loaded);
    assert_eq!(app.settings.params, s.settings.params);
    assert_eq!(app.settings.tab, ViewKind::Events);
    assert_eq!(app.views.bifurcation.zoom, s.bifurcation_zoom);
    assert_eq!(app.settings.save_dir, "/my/figures");
    // A session of another version is refused with one line.
    let future = s
        .to_json()
        .replacen("\"oneblock_session\": 1", "\"oneblock_session\": 99", 1);
    assert_ne!(
        future,
        s.to_json(),
        "the version field is where the test expects it"
    );
    let e = Session::from_text(&future, "f.json").expect_err("refused");
    assert!(e.contains("version 99") && !e.contains('\n'), "{e}");
}
