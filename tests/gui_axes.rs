//! Axes fit for print and a panel that fits, driven headless (egui_kittest):
//! every plot of every view, alone and in tiles, at 1280 × 800 and at text
//! size 1.5, shows at least five labelled ticks on each axis, read from the
//! text the frame actually painted; the angle unit switch relabels θ axes
//! in degrees and fractions of π; the side panel's last controls can be
//! scrolled to and used at text size 1.5; and the validity badge shows
//! outside the model's assumptions.
#![cfg(feature = "gui")]

use crate::window;

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

use oneblock::app::axes::AngleUnit;
use oneblock::app::settings::EventsPlot;
use oneblock::app::{Explorer, Layout, Recorder, Settings, ViewKind};
use oneblock::model::Params;
use window::{tick_labels, window_with_slips};

/// The window at 1280 × 800 with `settings` and a slip catalogue.
fn window_at(settings: Settings, rec: &Recorder) -> Harness<'static, Explorer> {
    window_with_slips(settings, rec, (1280.0, 800.0))
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
        let plot_left = oneblock::app::axes::plot_frames(&h.ctx)
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
