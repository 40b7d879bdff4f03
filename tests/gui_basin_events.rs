//! The Basins view's events (issue 54): at κ = 10 over θν 1.35–1.43 the
//! window, on the real worker's Basins lane, marks exactly the events the
//! command line prints for the same columns, with the same values, and a
//! hover over an event's mark or over a basin explains it in one sentence.
#![cfg(feature = "gui")]
#![allow(clippy::unwrap_used)]

use crate::cli_support::*;
use crate::window;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use serde_json::Value;

use oneblock::app::basin_events::event_sentence;
use oneblock::app::{Explorer, Layout, Recorder, Settings, ViewKind, preset};
use oneblock::worker::Lane;

/// The Basins tab at the hysteresis preset, over θν 1.35–1.43 in 48
/// columns.
fn hysteresis_basins() -> Settings {
    let mut s = Settings {
        layout: Layout::Tabs,
        tab: ViewKind::Basins,
        ..Settings::default()
    };
    s.params = preset("hysteresis").expect("preset").params;
    s.basins.columns = 48;
    s.basins.zoom = vec![(1.35, 1.43)];
    s
}

/// Steps the window until the Basins job has sent its events (~90 s at most).
fn until_events(h: &mut Harness<'static, Explorer>) {
    for _ in 0..4500 {
        h.step();
        if h.state().jobs.basins.data.events.is_some() {
            h.run_steps(3);
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    panic!("the Basins job sent no events");
}

/// The events `attractors --param` prints over θν 1.35–1.43 at the
/// hysteresis preset in 48 columns, and its JSON.
fn cli_events() -> Value {
    let o = oneblock(&[
        "attractors",
        "--preset",
        "hysteresis",
        "--param",
        "theta-nu",
        "--from",
        "1.35",
        "--to",
        "1.43",
        "--columns",
        "48",
        "--json",
    ]);
    assert_ok(&o);
    serde_json::from_str(&stdout(&o)).unwrap()
}

/// The window's events are the command line's: the same causes, the
/// same values to 1e-12.
fn assert_same_events(window: &[oneblock::sim::attractors::events::Event], cli: &[Value]) {
    assert_eq!(window.len(), cli.len(), "{window:?}\n{cli:?}");
    for (w, c) in window.iter().zip(cli) {
        assert_eq!(w.cause.name(), c["cause"], "{w:?}");
        let v = c["value"].as_f64().unwrap();
        assert!((w.value - v).abs() <= 1e-12 * v.abs(), "{} vs {v}", w.value);
    }
}

#[test]
fn the_window_marks_the_events_the_command_line_prints_and_explains_them() {
    let rec = Recorder::new();
    let mut h = window::harness_on_lanes(&rec, hysteresis_basins(), &[Lane::Basins]);
    until_events(&mut h);
    let d = h.state().jobs.basins.data.clone();
    let events = d.events.clone().expect("events");
    // The command line over the same columns.
    let j = cli_events();
    let cli = j["events"].as_array().unwrap();
    assert_eq!(cli.len(), 3, "{cli:?}");
    assert_same_events(&events.events, cli);
    assert_eq!(d.ids.tracks.len(), j["tracks"].as_array().unwrap().len());
    // Each event's mark is in the legend, and hovering its line on the
    // basins plot shows its sentence.
    assert!(h.query_by_label("fold").is_some() && h.query_by_label("flip").is_some());
    let frame = oneblock::app::axes::plot_frames(&h.ctx)
        .into_iter()
        .find(|(n, _)| *n == "basins")
        .expect("the basins plot was drawn")
        .1;
    let n = d.columns.len() as f64;
    let half = (d.to - d.from) / (n - 1.0) / 2.0;
    let (x0, x1) = (d.from - half, d.to + half);
    let fold = &events.events[2];
    let x = frame.left() + frame.width() * ((fold.value - x0) / (x1 - x0)) as f32;
    h.hover_at(egui::pos2(x, frame.center().y));
    h.run_steps(3);
    let sentence = event_sentence(fold, &d);
    assert!(
        sentence.starts_with("fold at θν = 1.420231535"),
        "{sentence}"
    );
    assert!(
        window::painted_texts(&h)
            .iter()
            .any(|(t, _)| t.contains("fold at θν = 1.420231535")),
        "the hover shows the fold's sentence"
    );
    // A basin well away from any event: the large P2's, at θν ≈ 1.39,
    // with its death and smallest kick.
    let x = frame.left() + frame.width() * ((1.39 - x0) / (x1 - x0)) as f32;
    let theta = 0.255; // a point of the large P2 cycle
    let y0 = d
        .columns
        .iter()
        .flatten()
        .filter_map(|c| c.found.as_ref().ok())
        .map(|f| f.basins[0].from)
        .fold(f64::INFINITY, f64::min);
    let y1 = d
        .columns
        .iter()
        .flatten()
        .filter_map(|c| c.found.as_ref().ok())
        .map(|f| f.basins.last().unwrap().to)
        .fold(f64::NEG_INFINITY, f64::max);
    let y = frame.bottom() - frame.height() * ((theta - y0) / (y1 - y0)) as f32;
    h.hover_at(egui::pos2(x, y));
    h.run_steps(3);
    // The tooltip's rows, joined (it wraps).
    let texts: Vec<String> = window::painted_texts(&h).into_iter().map(|t| t.0).collect();
    let all = texts.join("");
    let start = "P2, from the range's start, dies at θν = 1.420231535 in a fold; basin here";
    let at = all.find(start).unwrap_or_else(|| panic!("{texts:?}"));
    assert!(all[at..].contains("smallest kick"), "{texts:?}");
}

/// The bifurcation diagram's "births & deaths" toggle: over its zoomed θν
/// range the Basins job runs with the Basins view not shown, and the
/// diagram marks the same events the command line prints for that range,
/// with the legend naming them and a hover giving the sentence.
#[test]
fn the_bifurcation_diagram_marks_the_same_births_and_deaths() {
    use oneblock::app::bifurcation::Zoom;
    let rec = Recorder::new();
    let mut s = hysteresis_basins();
    s.tab = ViewKind::Bifurcation;
    s.basins.columns = 48;
    s.basins.zoom.clear();
    let mut h = window::harness_on_lanes(&rec, s, &[Lane::Basins, Lane::Sweep]);
    h.state_mut().views.bifurcation.zoom.push(Zoom {
        theta_nu: (1.35, 1.43),
        theta: (0.0, 1.0),
    });
    h.run_steps(2);
    assert!(h.state().jobs.basins.data.events.is_none());
    h.get_by_label("births & deaths").click();
    h.run_steps(2);
    until_events(&mut h);
    let d = h.state().jobs.basins.data.clone();
    assert_eq!((d.from, d.to), (1.35, 1.43), "over the diagram's range");
    let events = d.events.clone().expect("events");
    let j = cli_events();
    assert_same_events(&events.events, j["events"].as_array().unwrap());
    // The legend names the causes; a hover on the fold's line reads it.
    h.run_steps(3);
    assert!(h.query_by_label("fold").is_some() && h.query_by_label("flip").is_some());
    let t = h
        .state()
        .views
        .bifurcation
        .transform
        .expect("the diagram was drawn");
    let fold = &events.events[2];
    let at = t.position_from_point(&egui_plot::PlotPoint::new(fold.value, 0.5));
    h.hover_at(at);
    h.run_steps(3);
    assert!(
        window::painted_texts(&h)
            .iter()
            .any(|(t, _)| t.contains("fold at θν = 1.420231535")),
        "the hover shows the fold's sentence"
    );
}
