//! The side panel, driven headless through AccessKit (egui_kittest):
//! sliders, typed values (an invalid one in red and not sent), presets, the
//! regime badge and the smooth-lines switch, each checked against what the
//! window sends to a recording backend.
#![cfg(feature = "gui")]

use crate::window;

use eframe::egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

use oneblock::app::{Explorer, PRESETS, Recorder, Settings};
use oneblock::model::Params;
use window::{harness, last_sweep, last_trajectory};

#[test]
fn first_frame_starts_the_demo_jobs() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    let p = last_trajectory(&rec).expect("a trajectory was started");
    assert_eq!(p, Params::default());
    assert_eq!(
        (p.kappa, p.gamma, p.nu, p.theta_nu),
        (18.95, 6.5, 1e-3, 1.0)
    );
    assert!(last_sweep(&rec).is_some(), "a sweep was started");
}

#[test]
fn dragging_the_kappa_slider_sends_new_parameters() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    rec.clear();
    h.get_by_role_and_label(Role::Slider, "κ")
        .set_value_accesskit(30.0);
    h.run_steps(3);
    assert_eq!(h.state().settings.params.kappa, 30.0);
    let p = last_trajectory(&rec).expect("new trajectory");
    assert_eq!(p.kappa, 30.0);
    assert_eq!(p.gamma, 6.5);
    // κ is a sweep parameter: the diagram is recomputed too (after the debounce).
    let s = last_sweep(&rec).expect("new sweep");
    assert_eq!(s.kappa, 30.0);
}

#[test]
fn moving_theta_nu_only_restarts_the_orbit() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    rec.clear();
    h.get_by_role_and_label(Role::Slider, "θν")
        .set_value_accesskit(1.2);
    h.run_steps(4);
    assert_eq!(last_trajectory(&rec).map(|p| p.theta_nu), Some(1.2));
    assert!(
        last_sweep(&rec).is_none(),
        "θν is the diagram's x-axis: no new sweep"
    );
}

#[test]
fn a_preset_sets_every_parameter() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    rec.clear();
    let fig3a = &PRESETS[0];
    assert_eq!(fig3a.key, "fig3a");
    h.get_by_label(fig3a.label).click();
    h.run_steps(3);
    let want = Params {
        kappa: 50.0,
        gamma: 6.5,
        nu: 1e-4,
        theta_nu: 0.3,
        omega: 50.0,
    };
    assert_eq!(h.state().settings.params, want);
    assert_eq!(last_trajectory(&rec), Some(want));
    assert_eq!(last_sweep(&rec), Some(want));
    // The badge follows: κ = 50, γ = 6.5 is mixed with θc = 0.4090.
    assert!(h.query_by_label_contains("mixed: θc = 0.4090").is_some());
}

#[test]
fn an_invalid_kappa_is_shown_in_red_and_not_sent() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    rec.clear();
    let field = h.get_by_role_and_label(Role::TextInput, "κ value");
    field.focus();
    field.set_text_value_accesskit("-3");
    h.run_steps(3);
    let err = h
        .state()
        .controls
        .error(oneblock::app::controls::Field::Kappa);
    assert_eq!(err, Some("κ must be a finite number > 0"));
    assert!(h.query_by_label("κ must be a finite number > 0").is_some());
    assert_eq!(h.state().settings.params.kappa, 18.95);
    assert!(
        rec.commands().is_empty(),
        "nothing sent: {:?}",
        rec.commands()
    );

    // A valid value goes through.
    let field = h.get_by_role_and_label(Role::TextInput, "κ value");
    field.set_text_value_accesskit("25");
    h.run_steps(3);
    assert_eq!(
        h.state()
            .controls
            .error(oneblock::app::controls::Field::Kappa),
        None
    );
    assert_eq!(last_trajectory(&rec).map(|p| p.kappa), Some(25.0));
}

#[test]
fn the_regime_badge_follows_gamma_and_kappa() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    // Fig. 3b: γ² = 42.25 > max(1, 18.95).
    assert!(h.query_by_label_contains("pure stick-slip").is_some());
    // γ = 0.5 with κ = 3: γ² < min(1, κ).
    h.get_by_role_and_label(Role::Slider, "γ")
        .set_value_accesskit(0.5);
    h.run_steps(2);
    h.get_by_role_and_label(Role::Slider, "κ")
        .set_value_accesskit(3.0);
    h.run_steps(2);
    assert!(h.query_by_label_contains("pure creep").is_some());
    // γ = 6.5, κ = 50: mixed, θc = 0.4090 (docs/model.md).
    h.get_by_role_and_label(Role::Slider, "γ")
        .set_value_accesskit(6.5);
    h.get_by_role_and_label(Role::Slider, "κ")
        .set_value_accesskit(50.0);
    h.run_steps(2);
    assert!(h.query_by_label_contains("mixed: θc = 0.4090").is_some());
    // γ² between 1 and κ < 1: mixed as well (κ = 0.5, γ = 0.9).
    h.get_by_role_and_label(Role::Slider, "κ")
        .set_value_accesskit(0.5);
    h.get_by_role_and_label(Role::Slider, "γ")
        .set_value_accesskit(0.9);
    h.run_steps(2);
    assert!(h.query_by_label_contains("mixed: θc").is_some());
}

#[test]
fn smooth_lines_follow_the_switch_and_auto_drops_them_on_software_gl() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    let feathering = |h: &Harness<'static, Explorer>| h.ctx.tessellation_options(|o| o.feathering);
    // A GPU (or unknown renderer): Auto means anti-aliased.
    assert_eq!(h.state().settings.smooth_lines, None);
    assert!(h.query_by_label("Auto (on)").is_some());
    assert!(feathering(&h));
    h.get_by_label("off").click();
    h.run_steps(2);
    assert_eq!(h.state().settings.smooth_lines, Some(false));
    assert!(!feathering(&h));
    // Software OpenGL: Auto turns them off, and says why.
    h.state_mut().set_software_gl(true);
    h.run_steps(1);
    h.get_by_label("Auto (off: software GL)").click();
    h.run_steps(2);
    assert_eq!(h.state().settings.smooth_lines, None);
    assert!(h.query_by_label("Auto (off: software GL)").is_some());
    assert!(!feathering(&h));
    h.get_by_label("on").click();
    h.run_steps(2);
    assert!(feathering(&h));
}

/// The Tour button starts the tour on its first step; Next and Previous walk
/// it, each step setting its parameters and tiles, and the window sends
/// the new parameters to the worker as for a preset; End tour closes it.
#[test]
fn the_tour_walks_the_papers_story_in_the_window() {
    use oneblock::app::tour::STEPS;
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    let check = |h: &Harness<'static, Explorer>, i: usize| {
        let s = &h.state().settings;
        let step = &STEPS[i];
        let p = oneblock::app::preset(step.preset).expect("preset").params;
        assert_eq!(s.params, p.with_theta_nu(step.theta_nu), "{}", step.title);
        assert_eq!(s.tiled.as_slice(), step.views, "{}", step.title);
        assert_eq!(h.state().tour.step, Some(i));
    };
    h.get_by_label("Tour").click();
    h.run_steps(6);
    check(&h, 0);
    assert!(h.query_by_label_contains("Tour 1/7: Creep").is_some());
    h.get_by_label("Next").click();
    h.run_steps(6);
    check(&h, 1);
    h.get_by_label("Next").click();
    h.run_steps(6);
    check(&h, 2);
    h.get_by_label("Previous").click();
    h.run_steps(6);
    check(&h, 1);
    // The second step's parameters reach the worker.
    h.run_steps(30);
    let t = last_trajectory(&rec).expect("a trajectory was asked for");
    assert_eq!(t.theta_nu, STEPS[1].theta_nu);
    h.get_by_label("End tour").click();
    h.run_steps(6);
    assert_eq!(h.state().tour.step, None);
}

/// A view's "?" opens its paragraph on a click (a tap, where nothing
/// hovers) and a click outside closes it.
#[test]
fn a_click_on_the_question_mark_pins_the_views_paragraph_until_a_click_outside() {
    use oneblock::app::help::view_help;
    use oneblock::app::{Layout, ViewKind};
    let rec = Recorder::new();
    let settings = Settings {
        layout: Layout::Tabs,
        tab: ViewKind::ReturnMap,
        ..Settings::default()
    };
    let mut h = harness(&rec, settings);
    h.run_steps(2);
    let paragraph = view_help(ViewKind::ReturnMap);
    let shown = |h: &Harness<'static, Explorer>| h.query_all_by_label(paragraph).count();
    assert_eq!(shown(&h), 0, "closed at first");
    h.get_by_label("?").click();
    h.run_steps(3);
    assert!(shown(&h) >= 1, "a click opens the paragraph");
    // It stays open over the next frames (a popup, not a tooltip that
    // needs the pointer to stay).
    h.run_steps(5);
    assert!(shown(&h) >= 1, "the paragraph stays open");
    // A click elsewhere: the return map's f(θ) − θ switch.
    h.get_by_label("f(θ) − θ").click();
    h.run_steps(3);
    assert_eq!(shown(&h), 0, "a click outside closes it");
}
