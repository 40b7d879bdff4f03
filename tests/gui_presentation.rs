//! The lecture hall (issue 41), driven headless (egui_kittest): the side
//! panel hides and comes back (H, the top bar's Panel) and the choice is a
//! setting; its width comes back when projector mode is switched off; a
//! view's Fill makes it fill the window and Esc brings the layout back; and
//! the tour, walked with the arrow keys through every step at a
//! projector's 1024 × 768 (text ×1.5, the panel hidden, as the README
//! gives it) and at 1280 × 800, shows each view the step names at 200 ×
//! 150 points or more with its plots whole, keeps its box off every plot
//! and draws the λ strip where the step speaks of it; End tour gives back
//! the settings from before it.
#![cfg(feature = "gui")]

use crate::window;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

use crate::common::tour_layout::step_problems;
use oneblock::app::axes::plot_frames;
use oneblock::app::bifurcation::Zoom;
use oneblock::app::tour::STEPS;
use oneblock::app::{Explorer, Layout, Recorder, Settings, ViewKind};
use window::harness;

fn at(size: (f32, f32), settings: Settings, rec: &Recorder) -> Harness<'static, Explorer> {
    let mut h = harness(rec, settings);
    h.set_size(egui::vec2(size.0, size.1));
    h.run_steps(3);
    h
}

#[test]
fn the_panel_hides_and_the_views_take_its_width() {
    let rec = Recorder::new();
    let mut h = at(
        (1280.0, 800.0),
        Settings {
            layout: Layout::Tabs,
            tab: ViewKind::Bifurcation,
            ..Settings::default()
        },
        &rec,
    );
    let shown = h.state().view_rect(ViewKind::Bifurcation).expect("drawn");
    let panel = h.state().panel_rect;
    assert!(panel.width() >= 250.0, "{panel:?}");
    h.key_press(egui::Key::H);
    h.run_steps(3);
    assert!(h.state().settings.hide_panel);
    let hidden = h.state().view_rect(ViewKind::Bifurcation).expect("drawn");
    // The diagram has the panel's former width (its frame and margins
    // aside).
    assert!(
        hidden.width() >= shown.width() + panel.width() - 12.0,
        "{shown:?} then {hidden:?} (panel {panel:?})"
    );
    let plot = plot_frames(&h.ctx)
        .into_iter()
        .find(|(n, _)| *n == "bifurcation")
        .expect("the diagram");
    assert!(plot.1.left() < 150.0, "{plot:?}");
    // Remembered: the setting is saved with the others.
    let json = serde_json::to_string(&h.state().settings).expect("serialises");
    let back: Settings = serde_json::from_str(&json).expect("reads back");
    assert!(back.hide_panel);
    // The top bar's Panel shows it again.
    h.get_by_label("Panel").click();
    h.run_steps(3);
    assert!(!h.state().settings.hide_panel);
    assert!(h.state().panel_rect.width() >= 250.0);
}

#[test]
fn the_panel_width_comes_back_when_projector_mode_is_switched_off() {
    let rec = Recorder::new();
    let mut h = at((1024.0, 768.0), Settings::default(), &rec);
    let normal = h.state().panel_rect.width();
    let projector = "projector: large text, thick lines, high contrast";
    h.get_by_label(projector).scroll_to_me();
    h.run_steps(2);
    h.get_by_label(projector).click_accesskit();
    h.run_steps(4);
    assert!(h.state().settings.projector);
    let wide = h.state().panel_rect.width();
    // Never more than a third of a projector's 1024 points.
    assert!(wide <= 1024.0 / 3.0 + 1.0, "projector panel {wide}");
    h.get_by_label(projector).scroll_to_me();
    h.run_steps(2);
    h.get_by_label(projector).click_accesskit();
    h.run_steps(10);
    assert!(!h.state().settings.projector);
    let back = h.state().panel_rect.width();
    assert!((back - normal).abs() < 1.0, "normal {normal}, after {back}");
}

#[test]
fn fill_makes_one_view_fill_the_window_and_escape_brings_the_layout_back() {
    let rec = Recorder::new();
    let mut h = at((1280.0, 800.0), Settings::default(), &rec);
    let tile = h.state().view_rect(ViewKind::ReturnMap).expect("a tile");
    // The third Fill is the return map's (plane, bifurcation, return map).
    let fills = h.query_all_by_label("Fill").collect::<Vec<_>>();
    assert_eq!(fills.len(), 4);
    let pos = fills
        .iter()
        .position(|n| tile.contains(n.rect().center()))
        .expect("the return map's Fill");
    fills[pos].click();
    h.run_steps(3);
    let s = &h.state().settings;
    assert_eq!(
        (s.layout, s.tab, s.hide_panel),
        (Layout::Tabs, ViewKind::ReturnMap, true)
    );
    let full = h.state().view_rect(ViewKind::ReturnMap).expect("drawn");
    assert!(full.width() > 1240.0 && full.height() > 650.0, "{full:?}");
    h.key_press(egui::Key::Escape);
    h.run_steps(3);
    let s = &h.state().settings;
    assert_eq!((s.layout, s.hide_panel), (Layout::Tiles, false));
}

/// Walks the tour with → at `size` and text `scale` (the side panel
/// `hidden` or not), checking each step's layout as `gui --layout` reports
/// it ([`step_problems`]).
fn walk_tour(size: (f32, f32), scale: f32, hidden: bool) {
    let rec = Recorder::new();
    let mut h = at(
        size,
        Settings {
            font_scale: scale,
            hide_panel: hidden,
            ..Settings::default()
        },
        &rec,
    );
    h.get_by_label("Tour").click();
    for (i, step) in STEPS.iter().enumerate() {
        h.run_steps(5);
        let what = format!(
            "{size:?} text ×{scale}, panel hidden {hidden}, step {} ({})",
            i + 1,
            step.title
        );
        assert_eq!(h.state().tour.step, Some(i), "{what}");
        let bad = step_problems(&h.state().layout_report(), step, size);
        assert!(bad.is_empty(), "{what}: {}", bad.join("; "));
        h.key_press(egui::Key::ArrowRight);
    }
    // Back one step with ←; past the end it stays on the last.
    h.run_steps(3);
    assert_eq!(h.state().tour.step, Some(STEPS.len() - 1));
    h.key_press(egui::Key::ArrowLeft);
    h.run_steps(3);
    assert_eq!(h.state().tour.step, Some(STEPS.len() - 2));
}

#[test]
fn the_tour_box_covers_no_plot_of_its_step_and_the_strip_shows_where_spoken_of() {
    // The projector setting the README gives, a laptop's window, and
    // large text there with the panel hidden.
    walk_tour((1024.0, 768.0), 1.5, true);
    walk_tour((1280.0, 800.0), 1.0, false);
    walk_tour((1280.0, 800.0), 1.5, true);
}

/// End tour gives back the parameters, views and layout from before the
/// tour: the session saved before it and the one after are the same.
#[test]
fn end_tour_gives_back_the_settings_from_before_the_tour() {
    let rec = Recorder::new();
    let mine = Settings {
        layout: Layout::Tabs,
        tab: ViewKind::Basins,
        tiled: vec![ViewKind::Block, ViewKind::Numerics],
        map_difference: true,
        ..Settings::default()
    };
    let mut h = at((1280.0, 800.0), mine, &rec);
    h.state_mut().settings.params.theta_nu = 0.9;
    let zoom = Zoom {
        theta_nu: (1.2, 1.3),
        theta: (0.1, 0.5),
    };
    h.state_mut().views.bifurcation.zoom.push(zoom);
    h.run_steps(2);
    let before = h.state().settings.clone();
    h.get_by_label("Tour").click();
    h.run_steps(3);
    for _ in 0..3 {
        h.get_by_label("Next").click();
        h.run_steps(3);
    }
    assert_ne!(h.state().settings, before);
    assert!(
        h.state().views.bifurcation.zoom.is_empty(),
        "a step's parameters clear the zoom"
    );
    h.get_by_label("End tour").click();
    h.run_steps(3);
    assert_eq!(h.state().tour.step, None);
    assert_eq!(h.state().settings, before);
    assert_eq!(h.state().views.bifurcation.zoom, [zoom], "the zoom is back");
    assert!(h.state().view_rect(ViewKind::Basins).is_some());
}

#[test]
fn the_tour_box_can_be_moved() {
    let rec = Recorder::new();
    let mut h = at((1280.0, 800.0), Settings::default(), &rec);
    h.get_by_label("Tour").click();
    h.run_steps(5);
    let before = h.state().tour.box_rect.expect("drawn");
    // Drag it by its title up by 200 points.
    let grip = before.center_top() + egui::vec2(0.0, 10.0);
    h.drag_at(grip);
    h.run_steps(1);
    h.hover_at(grip - egui::vec2(0.0, 200.0));
    h.run_steps(1);
    h.drop_at(grip - egui::vec2(0.0, 200.0));
    h.run_steps(3);
    let after = h.state().tour.box_rect.expect("drawn");
    assert!(
        (before.top() - after.top() - 200.0).abs() < 2.0,
        "{before:?} then {after:?}"
    );
}

/// A tile too small for its controls (the projector: 1024 × 768, text
/// 1.5, the panel hidden, four tiles) folds them into its title row's
/// "Controls" menu, where they work; the same tiles at 1280 × 800 and
/// text 1 keep them above the plot.
#[test]
fn a_small_tile_folds_its_controls_into_a_menu_that_works() {
    let tiles = vec![
        ViewKind::Plane,
        ViewKind::Bifurcation,
        ViewKind::ReturnMap,
        ViewKind::Events,
    ];
    let rec = Recorder::new();
    let roomy = Settings {
        layout: Layout::Tiles,
        tiled: tiles.clone(),
        ..Settings::default()
    };
    let h = at((1280.0, 800.0), roomy, &rec);
    assert!(
        h.query_by_label("every attractor").is_some(),
        "shown above the plot"
    );
    assert!(h.query_by_label("Controls").is_none());

    let rec = Recorder::new();
    let projector = Settings {
        layout: Layout::Tiles,
        tiled: tiles,
        projector: true,
        font_scale: 1.5,
        hide_panel: true,
        ..Settings::default()
    };
    let mut h = at((1024.0, 768.0), projector, &rec);
    assert!(h.query_by_label("every attractor").is_none(), "folded away");
    h.get_by_label("Controls").click();
    h.run_steps(3);
    h.get_by_label("every attractor").click();
    h.run_steps(3);
    assert_eq!(
        h.state().settings.sweep_seeds,
        1,
        "the menu's check box works"
    );
}

/// On a phone (390 × 844) the top bar has the tour; each step shows one of
/// its views at a time, the whole width, with the box under it (over no
/// plot), and the box's chooser switches the view.
#[test]
fn the_phone_has_the_tour_one_view_at_a_time_with_the_box_below() {
    let rec = Recorder::new();
    let mut h = at((390.0, 844.0), Settings::default(), &rec);
    h.get_by_label("Tour").click();
    h.run_steps(5);
    assert_eq!(h.state().tour.step, Some(0));
    for (k, &v) in STEPS[0].views.iter().enumerate() {
        if k > 0 {
            h.get_by_label(v.tab_title()).click();
            h.run_steps(4);
        }
        let shown: Vec<ViewKind> = ViewKind::ALL
            .into_iter()
            .filter(|&w| h.state().view_rect(w).is_some())
            .collect();
        assert_eq!(shown, [v], "one view at a time");
        let rect = h.state().view_rect(v).expect("drawn");
        let tour = h.state().tour.box_rect.expect("the box");
        assert!(rect.width() >= 350.0, "{v:?} in {rect:?}");
        assert!(rect.height() >= 300.0, "{v:?} in {rect:?}");
        assert!(
            tour.top() >= rect.bottom() - 1.0,
            "box {tour:?} under {rect:?}"
        );
        assert!(tour.right() <= 391.0, "box {tour:?} on the screen");
        for (name, plot) in plot_frames(&h.ctx) {
            assert!(!plot.intersects(tour), "box {tour:?} over {name} {plot:?}");
        }
    }
    h.get_by_label("End tour").click();
    h.run_steps(3);
    assert_eq!(h.state().tour.step, None);
}

/// A toast (here a session's refused value, at a phone's width and at the
/// desktop's) is painted in the status bar, over no plot, and the views
/// keep their rectangles while it shows.
#[test]
fn a_toast_is_in_the_status_bar_over_no_plot() {
    for size in [(390.0, 844.0), (1280.0, 800.0)] {
        let rec = Recorder::new();
        let mut h = at(size, Settings::default(), &rec);
        let before: Vec<_> = ViewKind::ALL
            .into_iter()
            .filter_map(|v| h.state().view_rect(v))
            .collect();
        let text = "session s.json: invalid parameters (defaults used)";
        h.state_mut().shots.toast(text.into(), true, 0.0);
        h.run_steps(3);
        let after: Vec<_> = ViewKind::ALL
            .into_iter()
            .filter_map(|v| h.state().view_rect(v))
            .collect();
        assert_eq!(before, after, "at {size:?} the views moved");
        let bar = h.state().status_rect;
        let shown: Vec<egui::Rect> = window::painted_texts(&h)
            .into_iter()
            .filter(|(t, _)| t.starts_with("session s.json"))
            .map(|(_, r)| r)
            .collect();
        assert!(!shown.is_empty(), "at {size:?} the toast is not painted");
        for r in shown {
            assert!(
                bar.expand(1.0).contains_rect(r),
                "at {size:?}: {r:?} outside {bar:?}"
            );
            for (name, plot) in plot_frames(&h.ctx) {
                assert!(!plot.intersects(r), "at {size:?} over {name}");
            }
        }
    }
}
