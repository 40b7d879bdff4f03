//! Axes fit for print and a panel that fits, driven headless (egui_kittest):
//! every plot of every view, alone and in tiles, at 1280 × 800 and at text
//! size 1.5, shows at least five labelled ticks on each axis, read from the
//! text the frame actually painted; the angle unit switch relabels θ axes
//! in degrees and fractions of π; the side panel's last controls can be
//! scrolled to and used at text size 1.5; and the validity badge shows
//! outside the model's assumptions.
#![cfg(feature = "gui")]

#[path = "common/window.rs"]
mod window;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use oneblock::worker::Spec;

use oneblock::app::axes::{AngleUnit, plot_frames};
use oneblock::app::settings::EventsPlot;
use oneblock::app::{Explorer, Layout, Recorder, Settings, ViewKind};
use oneblock::model::Params;
use oneblock::worker::{Command, Update};
use window::{event, harness};

/// Every text the last frame painted, with where.
fn painted_texts(h: &Harness<'static, Explorer>) -> Vec<(String, egui::Rect)> {
    fn walk(s: &egui::Shape, out: &mut Vec<(String, egui::Rect)>) {
        match s {
            egui::Shape::Text(t) => {
                out.push((t.galley.text().to_string(), t.visual_bounding_rect()))
            }
            egui::Shape::Vec(v) => v.iter().for_each(|s| walk(s, out)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    for cs in &h.output().shapes {
        walk(&cs.shape, &mut out);
    }
    out
}

/// Whether `t` reads as a tick label: a number, possibly in degrees or a
/// multiple or fraction of π.
fn is_tick(t: &str) -> bool {
    let t = t.trim_end_matches('°');
    if t.parse::<f64>().is_ok() {
        return true;
    }
    // "π", "-π/2", "3π/8", "0.38π"
    let t = t.trim_start_matches('-');
    match t.split_once('π') {
        Some((num, rest)) => {
            (num.is_empty() || num.parse::<f64>().is_ok())
                && (rest.is_empty()
                    || rest
                        .strip_prefix('/')
                        .is_some_and(|d| d.parse::<u32>().is_ok()))
        }
        None => false,
    }
}

/// The tick labels under the x axis and left of the y axis of each plot
/// drawn in the last frame: (plot, x labels, y labels).
fn tick_labels(h: &Harness<'static, Explorer>) -> Vec<(&'static str, Vec<String>, Vec<String>)> {
    let texts = painted_texts(h);
    let line = h.ctx.global_style().text_styles[&egui::TextStyle::Body].size;
    plot_frames(&h.ctx)
        .into_iter()
        .map(|(name, f)| {
            let xs = texts
                .iter()
                .filter(|(t, r)| {
                    is_tick(t)
                        && r.center().x >= f.left() - 1.0
                        && r.center().x <= f.right() + 1.0
                        && r.top() >= f.bottom() - 1.0
                        && r.top() <= f.bottom() + 2.0 * line
                })
                .map(|(t, _)| t.clone())
                .collect();
            let ys = texts
                .iter()
                .filter(|(t, r)| {
                    is_tick(t)
                        && r.center().y >= f.top() - 1.0
                        && r.center().y <= f.bottom() + 1.0
                        && r.right() <= f.left() + 1.0
                        && r.right() >= f.left() - 12.0 * line
                })
                .map(|(t, _)| t.clone())
                .collect();
            (name, xs, ys)
        })
        .collect()
}

/// The window at 1280 × 800 with `settings`, after a catalogue of 300
/// slips of varied sizes has arrived (as a running window has one).
fn window_at(settings: Settings, rec: &Recorder) -> Harness<'static, Explorer> {
    let mut h = harness(rec, settings);
    h.set_size(egui::vec2(1280.0, 800.0));
    h.run_steps(2);
    if let Some(generation) = rec.commands().into_iter().find_map(|c| match c {
        Command::Run {
            generation,
            spec: Spec::Trajectory(..),
        } => Some(generation),
        _ => None,
    }) {
        for i in 0..300 {
            let mut e = event(0.5, 0.2, 103.0 * i as f64);
            e.slip_distance = 0.2 + 0.7 * ((i * 37) % 100) as f64 / 100.0;
            rec.push(Update::Slip {
                generation,
                event: e,
            });
        }
    }
    h.run_steps(4);
    h
}

fn check_ticks(h: &Harness<'static, Explorer>, what: &str, want_plots: usize) {
    let labels = tick_labels(h);
    assert!(
        labels.len() >= want_plots,
        "{what}: {} plots drawn, expected {want_plots}",
        labels.len()
    );
    for (name, xs, ys) in labels {
        // The time series' four plots share one time axis, labelled under
        // the last (time-series-energy) only.
        let shared_x = matches!(name, "time-series-x" | "time-series-y" | "time-series-vr");
        assert!(
            xs.len() >= 5 || shared_x && xs.is_empty(),
            "{what}, {name}: x tick labels {xs:?}"
        );
        assert!(ys.len() >= 5, "{what}, {name}: y tick labels {ys:?}");
    }
}

#[test]
fn every_plot_has_five_labelled_ticks_per_axis_alone_and_in_tiles() {
    for scale in [1.0, 1.5] {
        for v in ViewKind::ALL {
            let plots = match v {
                ViewKind::Block => 0,
                // Side by side where there is room for them (text ×1),
                // one at a time where there is not.
                ViewKind::Events if scale == 1.0 => 3,
                _ => 1,
            };
            let rec = Recorder::new();
            let h = window_at(
                Settings {
                    layout: Layout::Tabs,
                    tab: v,
                    font_scale: scale,
                    ..Settings::default()
                },
                &rec,
            );
            check_ticks(&h, &format!("{} at text ×{scale}", v.key()), plots);
        }
        // Plane, bifurcation, return map and the events tile, which is too
        // narrow for its plots side by side and shows one at a time: each
        // in turn.
        for plot in [EventsPlot::Series, EventsPlot::Sizes, EventsPlot::Laminar] {
            let rec = Recorder::new();
            let h = window_at(
                Settings {
                    layout: Layout::Tiles,
                    font_scale: scale,
                    events_plot: plot,
                    ..Settings::default()
                },
                &rec,
            );
            check_ticks(&h, &format!("tiles at text ×{scale}, events {plot:?}"), 4);
        }
    }
}

#[test]
fn angle_axes_follow_the_chosen_unit() {
    let labels_of = |unit: AngleUnit| {
        let rec = Recorder::new();
        let h = window_at(
            Settings {
                layout: Layout::Tabs,
                tab: ViewKind::Bifurcation,
                angle_unit: unit,
                ..Settings::default()
            },
            &rec,
        );
        let (_, xs, _) = tick_labels(&h)
            .into_iter()
            .find(|(n, ..)| *n == "bifurcation")
            .expect("the diagram was drawn");
        xs
    };
    let deg = labels_of(AngleUnit::Degrees);
    assert!(
        deg.len() >= 5 && deg.iter().all(|t| t.ends_with('°')),
        "{deg:?}"
    );
    assert!(deg.contains(&"40°".to_string()), "{deg:?}");
    let pi = labels_of(AngleUnit::PiFractions);
    assert!(
        pi.contains(&"π/4".to_string()) && pi.contains(&"π/2".to_string()),
        "{pi:?}"
    );
    let rad = labels_of(AngleUnit::Radians);
    assert!(rad.contains(&"1.0".to_string()), "{rad:?}");
}

#[test]
fn the_side_panel_is_reachable_at_1280x800_and_text_size_1_5() {
    for scale in [1.0, 1.5] {
        let rec = Recorder::new();
        let mut h = window_at(
            Settings {
                layout: Layout::Tabs,
                tab: ViewKind::Plane,
                font_scale: scale,
                params: Params {
                    kappa: 30.0,
                    ..Params::default()
                },
                ..Settings::default()
            },
            &rec,
        );
        let plot_left = plot_frames(&h.ctx)
            .iter()
            .map(|(_, r)| r.left())
            .fold(f32::INFINITY, f32::min);
        for label in [
            "Restart orbit",
            "Reset to defaults",
            "Save screenshot",
            "dark background",
        ] {
            h.get_by_label(label).scroll_to_me();
            h.run_steps(3);
            let r = h.get_by_label(label).rect();
            assert!(
                r.top() >= 0.0 && r.bottom() <= 800.0 && r.left() >= 0.0 && r.right() <= plot_left,
                "text ×{scale}: '{label}' at {r:?} is not wholly inside the panel (plots from x = {plot_left})"
            );
        }
        // And it works from there: the reset brings κ back.
        h.get_by_label("Reset to defaults").click();
        h.run_steps(3);
        assert_eq!(h.state().settings.params.kappa, Params::default().kappa);
    }
}

#[test]
fn the_validity_badge_shows_outside_the_model() {
    let rec = Recorder::new();
    let mut h = window_at(Settings::default(), &rec);
    let badges = |h: &Harness<'static, Explorer>| {
        h.query_all_by_label_contains("Outside the model's validity")
            .count()
    };
    assert_eq!(badges(&h), 0, "no badge for the paper's parameters");
    h.state_mut().settings.params.nu = 0.1;
    h.run_steps(3);
    // In the top bar, and over the side panel with the reason.
    assert_eq!(badges(&h), 2);
    assert!(
        h.query_all_by_label_contains("nu = 0.1 is outside the model's slow-pulling assumption")
            .count()
            >= 1,
        "the badge says why"
    );
}
