//! The bifurcation view's zoom: a box drawn on the diagram recomputes that
//! θν range at full resolution, and Back returns to the whole range.
#![cfg(feature = "gui")]

#[path = "common/window.rs"]
mod window;

use eframe::egui;
use egui_kittest::kittest::Queryable;
use oneblock::worker::Spec;

use oneblock::app::{Recorder, Settings, ViewKind};
use oneblock::worker::Command;
use window::harness;

#[test]
fn a_box_drawn_on_the_diagram_recomputes_that_range() {
    let rec = Recorder::new();
    let settings = Settings {
        layout: oneblock::app::Layout::Tabs,
        tab: ViewKind::Bifurcation,
        ..Settings::default()
    };
    let mut h = harness(&rec, settings);
    h.run_steps(2);
    let full = rec
        .commands()
        .into_iter()
        .find_map(|c| match c {
            Command::Run {
                spec: Spec::Sweep(spec),
                ..
            } => Some((spec.axis.from, spec.axis.to)),
            _ => None,
        })
        .expect("first sweep");
    assert_eq!(full, (0.0, std::f64::consts::FRAC_PI_2));
    rec.clear();
    // Drag across the middle of the plot (the central area right of the panel).
    let (a, b) = (egui::pos2(700.0, 400.0), egui::pos2(950.0, 600.0));
    h.hover_at(a);
    h.step();
    h.drag_at(a);
    h.step();
    for i in 1..=5 {
        h.hover_at(a + (b - a) * (i as f32 / 5.0));
        h.step();
    }
    h.drop_at(b);
    h.run_steps(3);
    let zoomed = rec
        .commands()
        .into_iter()
        .find_map(|c| match c {
            Command::Run {
                spec: Spec::Sweep(spec),
                ..
            } => Some((spec.axis.from, spec.axis.to, spec.params)),
            _ => None,
        })
        .expect("a zoom recomputes the diagram");
    assert!(
        zoomed.0 > full.0 && zoomed.1 < full.1 && zoomed.0 < zoomed.1,
        "{zoomed:?}"
    );
    assert_eq!(zoomed.2.kappa, 18.95);
    assert_eq!(h.state().views.bifurcation.zoom.len(), 1);
    // Back returns to the whole range.
    rec.clear();
    h.get_by_label("Back").click();
    h.run_steps(3);
    let back = rec.commands().into_iter().find_map(|c| match c {
        Command::Run {
            spec: Spec::Sweep(spec),
            ..
        } => Some((spec.axis.from, spec.axis.to)),
        _ => None,
    });
    assert_eq!(back, Some(full));
}
