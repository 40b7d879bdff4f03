//! The bifurcation view's zoom: a box drawn on the diagram recomputes that
//! θν range at full resolution, and Back returns to the whole range; a
//! pinch zooms too; seeded columns the cell graph could not count are
//! named, not shown as one attractor.
#![cfg(feature = "gui")]

use crate::window;

use eframe::egui;
use egui_kittest::kittest::Queryable;
use oneblock::worker::Spec;

use oneblock::app::{Recorder, Settings, ViewKind};
use oneblock::worker::Command;
use window::harness;

/// The diagram as the one tab, at the defaults.
fn diagram_tab() -> Settings {
    Settings {
        layout: oneblock::app::Layout::Tabs,
        tab: ViewKind::Bifurcation,
        ..Settings::default()
    }
}

#[test]
fn a_box_drawn_on_the_diagram_recomputes_that_range() {
    let rec = Recorder::new();
    let mut h = harness(&rec, diagram_tab());
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

/// Touches `ids` at `pos` in `phase` (a finger each).
fn touch(
    h: &mut egui_kittest::Harness<'_, oneblock::app::Explorer>,
    fingers: &[(u64, egui::Pos2)],
    phase: egui::TouchPhase,
) {
    for &(id, pos) in fingers {
        h.input_mut().events.push(egui::Event::Touch {
            device_id: egui::TouchDeviceId(1),
            id: egui::TouchId(id),
            phase,
            pos,
            force: None,
        });
    }
}

/// Two fingers spread apart on the diagram (a phone's pinch) zoom into a
/// box about their centre, recomputed as a drawn box is; pinched together,
/// they go back a level.
#[test]
fn a_pinch_on_the_diagram_zooms_about_its_centre_and_a_pinch_out_goes_back() {
    let rec = Recorder::new();
    let mut h = harness(&rec, diagram_tab());
    h.run_steps(2);
    let t = h
        .state()
        .views
        .bifurcation
        .transform
        .expect("the diagram is drawn");
    let centre = egui::pos2(800.0, 450.0);
    let at_centre = t.value_from_position(centre);
    rec.clear();
    // Fingers 40 px either side of the centre, spread to 160 px: scale 4.
    let fingers = |d: f32| {
        [
            (1, centre - egui::vec2(d, 0.0)),
            (2, centre + egui::vec2(d, 0.0)),
        ]
    };
    // A backend moves the pointer with the first touch (egui starts a
    // gesture where the pointer is).
    h.hover_at(centre);
    h.step();
    touch(&mut h, &fingers(40.0), egui::TouchPhase::Start);
    h.step();
    for d in [60.0, 90.0, 120.0, 160.0] {
        touch(&mut h, &fingers(d), egui::TouchPhase::Move);
        h.step();
    }
    assert!(
        rec.commands().iter().all(|c| !matches!(
            c,
            Command::Run {
                spec: Spec::Sweep(_),
                ..
            }
        )),
        "nothing is recomputed while the fingers move"
    );
    touch(&mut h, &fingers(160.0), egui::TouchPhase::End);
    h.run_steps(3);
    let zoomed = rec
        .commands()
        .into_iter()
        .find_map(|c| match c {
            Command::Run {
                spec: Spec::Sweep(spec),
                ..
            } => Some((spec.axis.from, spec.axis.to)),
            _ => None,
        })
        .expect("a pinch recomputes the diagram");
    let [x0, _] = t.bounds().min();
    let [x1, _] = t.bounds().max();
    let width = zoomed.1 - zoomed.0;
    assert!(
        (width - (x1 - x0) / 4.0).abs() < 0.02 * width,
        "{zoomed:?} of {x0}..{x1}"
    );
    let mid = (zoomed.0 + zoomed.1) / 2.0;
    assert!(
        (mid - at_centre.x).abs() < 0.02 * width,
        "{mid} against {}",
        at_centre.x
    );
    assert_eq!(h.state().views.bifurcation.zoom.len(), 1);
    // Pinched together: back to the whole range.
    rec.clear();
    touch(&mut h, &fingers(160.0), egui::TouchPhase::Start);
    h.step();
    for d in [120.0, 80.0, 40.0] {
        touch(&mut h, &fingers(d), egui::TouchPhase::Move);
        h.step();
    }
    touch(&mut h, &fingers(40.0), egui::TouchPhase::End);
    h.run_steps(3);
    assert!(h.state().views.bifurcation.zoom.is_empty());
}

/// A seeded column whose attractors the cell graph could not count is
/// named over the diagram ("1 not counted": one of the columns, the
/// others counted; its θν and why on hover), never taken for a column
/// with one attractor.
#[test]
fn a_seeded_column_that_could_not_be_counted_is_named_over_the_diagram() {
    use oneblock::worker::{Lane, Outcome, Update};
    let rec = Recorder::new();
    let settings = Settings {
        sweep_seeds: 4,
        ..diagram_tab()
    };
    let mut h = harness(&rec, settings);
    h.run_steps(2);
    let (generation, axis) = rec
        .commands()
        .into_iter()
        .find_map(|c| match c {
            Command::Run {
                generation,
                spec: Spec::Sweep(spec),
            } => Some((generation, spec.axis)),
            _ => None,
        })
        .expect("the sweep");
    let why = "the exit arc's map failed at a cell edge";
    for index in 0..axis.steps {
        let value = axis.from + (axis.to - axis.from) * index as f64 / (axis.steps - 1) as f64;
        rec.push(Update::Column {
            generation,
            index,
            value,
            thetas: vec![0.3, 0.31],
            coarse: false,
            rhs_evals: 100,
            map: Default::default(),
            lyapunov: None,
            attractor: vec![0, 0],
            uncounted: (index == 7).then(|| why.to_string()),
        });
    }
    rec.push(Update::Finished {
        generation,
        lane: Lane::Sweep,
        outcome: Outcome::Completed,
    });
    h.run_steps(3);
    let label = h.get_by_label("1 not counted");
    label.hover();
    h.run_steps(8);
    let seventh = axis.from + (axis.to - axis.from) * 7.0 / (axis.steps - 1) as f64;
    let line = format!("θν = {seventh:.4}: {why}");
    assert!(
        h.query_by_label_contains(&line).is_some(),
        "the hover names the column: {line}"
    );
}
