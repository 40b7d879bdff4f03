//! "Find bifurcations" in the window, against the real worker's
//! continuation lane: the button runs the job over the diagram's θν range,
//! its branches are drawn over the diagram (stable solid, unstable dashed,
//! the doubling marked, also in the SVG export), the special-points table
//! shows the doubling to 9 significant digits and "Copy" puts its
//! `continue --points` line on the clipboard; a parameter change stops the
//! job and its late updates never reach the slot. Nothing of it is
//! computed on the UI thread: no continuation call lives in src/app/.
#![cfg(feature = "gui")]

use crate::window;
use oneblock::worker::Spec;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

use oneblock::app::bifurcation::Zoom;
use oneblock::app::branches::{csv_line, runs, sig9, special_rows};
use oneblock::app::jobs::{JobState, Jobs, Shown};
use oneblock::app::overlay;
use oneblock::app::settings::PhaseRange;
use oneblock::app::{Explorer, Layout, Recorder, Settings, ViewKind, preset};
use oneblock::sim::continuation::{ContParam, SpecialKind};
use oneblock::worker::{Command, Lane, Update};

fn fig3b_tab() -> Settings {
    let mut s = Settings {
        layout: Layout::Tabs,
        tab: ViewKind::Bifurcation,
        ..Settings::default()
    };
    s.params = preset("fig3b").expect("preset").params;
    s
}

/// A window whose Find bifurcations and Boundaries run on the real worker.
fn harness_on_worker(rec: &Recorder, settings: Settings) -> Harness<'static, Explorer> {
    window::harness_on_lanes(rec, settings, &[Lane::Continuation, Lane::Curves])
}

/// Steps the window until "Find bifurcations" has ended (at most ~60 s).
fn until_settled(h: &mut Harness<'static, Explorer>) {
    for _ in 0..3000 {
        h.step();
        if h.state().jobs.branches_settled() {
            h.run_steps(2);
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    panic!("Find bifurcations did not end");
}

fn copied(h: &Harness<'static, Explorer>) -> Vec<String> {
    h.output()
        .platform_output
        .commands
        .iter()
        .filter_map(|c| match c {
            egui::OutputCommand::CopyText(t) => Some(t.clone()),
            _ => None,
        })
        .collect()
}

#[test]
fn find_bifurcations_draws_the_branches_and_lists_the_doubling() {
    let rec = Recorder::new();
    let mut h = harness_on_worker(&rec, fig3b_tab());
    // The diagram zoomed to θν ∈ [1.0, 1.2]: the job runs over that.
    h.state_mut().views.bifurcation.zoom.push(Zoom {
        theta_nu: (1.0, 1.2),
        theta: (0.0, 1.0),
    });
    h.run_steps(2);
    h.get_by_label("Find bifurcations").click();
    h.step();
    let spec = rec
        .commands()
        .into_iter()
        .find_map(|c| match c {
            Command::Run {
                spec: Spec::Branches(spec),
                ..
            } => Some(spec),
            _ => None,
        })
        .expect("the job was sent");
    assert_eq!((spec.from, spec.to), (1.0, 1.2));
    assert_eq!(spec.param, ContParam::ThetaNu);
    assert_eq!(spec.params.kappa, 18.95);
    until_settled(&mut h);
    let jobs = &h.state().jobs;
    assert_eq!(jobs.branches.state, JobState::Done);
    let data = jobs.branches.data.clone();
    // The fixed point, stable then (dashed) unstable, and the P2 level.
    let p1 = &data.branches[0];
    assert_eq!(p1.period, 1);
    let r = runs(p1);
    assert!(r.iter().any(|r| r.stable) && r.iter().any(|r| !r.stable));
    assert!(data.branches.iter().any(|b| b.period == 2));
    let pd = p1
        .of_kind(SpecialKind::PeriodDoubling)
        .next()
        .expect("a doubling")
        .clone();
    assert!(pd.lambda > 1.0 && pd.lambda < 1.2 && (pd.multiplier + 1.0).abs() < 1e-6);
    // Its legend, of what is drawn (no kind of point the branches lack),
    // and the status line says why it stopped.
    for name in [overlay::STABLE, overlay::UNSTABLE, "PD"] {
        assert!(h.query_by_label(name).is_some(), "legend {name}");
    }
    for (kind, name) in [(SpecialKind::Fold, "fold"), (SpecialKind::Border, "border")] {
        if !data
            .branches
            .iter()
            .any(|b| b.of_kind(kind).next().is_some())
        {
            assert!(
                h.query_by_label(name).is_none(),
                "legend {name}: none drawn"
            );
        }
    }
    assert!(
        h.query_by_label_contains("bifurcations: ").is_some()
            && h.query_by_label_contains("stopped").is_some(),
        "the status line tells why it stopped"
    );

    // Hovering the doubling's marker tells it to 9 digits.
    let t = h
        .state()
        .views
        .bifurcation
        .transform
        .expect("the diagram was drawn");
    let at = t.position_from_point(&egui_plot::PlotPoint::new(pd.lambda, pd.theta));
    h.hover_at(at);
    h.run_steps(3);
    let value = sig9(pd.lambda);
    // 9 significant digits, trailing zeros dropped (1.08957190 → 1.0895719).
    assert!(
        value.chars().filter(char::is_ascii_digit).count() <= 9
            && (value.parse::<f64>().unwrap() - pd.lambda).abs() <= 5e-9 * pd.lambda.abs(),
        "{value}"
    );
    assert!(
        h.query_by_label_contains(&format!("θν = {value}"))
            .is_some(),
        "the hover names θν = {value}"
    );
    h.remove_cursor();

    // The table: the PD row to 9 digits; Copy puts its CSV line out.
    h.get_by_label_contains("Special points").click();
    h.run_steps(2);
    assert!(
        h.query_by_label(&value).is_some(),
        "the PD row shows {value}"
    );
    assert!(h.query_by_label(&sig9(pd.theta)).is_some());
    let first_copy = h
        .query_all_by_label("Copy")
        .next()
        .expect("a Copy button per row");
    first_copy.click();
    h.step();
    let line = csv_line(ContParam::ThetaNu, special_rows(&data)[0]);
    assert_eq!(copied(&h), vec![line.clone()]);
    let cells: Vec<&str> = line.split(',').collect();
    assert_eq!(&cells[..3], ["PD", "1", "theta-nu"]);
    assert_eq!(cells[3].parse::<f64>().expect("value"), pd.lambda);
    assert_eq!(cells[4].parse::<f64>().expect("theta"), pd.theta);
    h.get_by_label("Copy all").click();
    h.step();
    let all = copied(&h);
    assert_eq!(all.len(), 1);
    assert!(all[0].starts_with("kind,period,parameter,value,theta,multiplier,criticality\n"));
    assert!(all[0].contains(&line));

    // The SVG export draws the same series: the branches' and the PD's
    // colours are series of the diagram's plot.
    let svg = svg_of(&h, ViewKind::Bifurcation);
    let key = |c: egui::Color32| {
        format!(
            "bifurcation:{:x}{:x}{:x}",
            c.r() >> 5,
            c.g() >> 5,
            c.b() >> 5
        )
    };
    let pd_colour = overlay::marker(SpecialKind::PeriodDoubling).0.color;
    for c in [overlay::BRANCH, pd_colour] {
        assert!(
            svg.contains(&format!("data-series=\"{}\"", key(c))),
            "{} in the SVG",
            key(c)
        );
    }
}

/// Drags a box across the diagram (the plot right of the side panel).
fn drag_zoom_box(h: &mut Harness<'static, Explorer>) {
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
}

/// What the window shows of a Find bifurcations result: its branches, its
/// special points' table and its status line.
fn branches_shown(h: &Harness<'static, Explorer>) -> [bool; 3] {
    [
        !h.state().jobs.branches.data.branches.is_empty(),
        h.query_by_label_contains("Special points (").is_some(),
        h.query_by_label_contains("bifurcations: ").is_some(),
    ]
}

/// As a user would: Find bifurcations on Fig. 3b, drag a zoom box, change
/// κ. The κ = 18.95 branches, their special points and their status line
/// are gone from the new diagram, and stay gone after a preset change.
#[test]
fn find_bifurcations_then_a_zoom_then_kappa_leaves_nothing_of_the_old_branches() {
    let rec = Recorder::new();
    let mut h = harness_on_worker(&rec, fig3b_tab());
    h.run_steps(2);
    h.get_by_label("Find bifurcations").click();
    h.step();
    until_settled(&mut h);
    assert_eq!(branches_shown(&h), [true; 3], "the result is shown");
    drag_zoom_box(&mut h);
    assert_eq!(h.state().views.bifurcation.zoom.len(), 1, "zoomed");
    assert_eq!(branches_shown(&h), [true; 3], "a zoom keeps the result");
    h.state_mut().settings.params.kappa = 16.0;
    h.run_steps(3);
    assert_eq!(branches_shown(&h), [false; 3], "κ changed");
    assert!(h.state().views.bifurcation.zoom.is_empty(), "the zoom too");
    h.state_mut().settings.params = preset("fig3a").expect("preset").params;
    h.run_steps(3);
    assert_eq!(branches_shown(&h), [false; 3], "a preset later");
}

#[test]
fn a_parameter_change_stops_the_job_and_drops_what_it_sends_later() {
    let rec = Recorder::new();
    let mut jobs = Jobs::new(Box::new(rec.clone()));
    let mut s = fig3b_tab();
    let shown = Shown {
        now: 0.0,
        sweep_zoom: Some((1.0, 1.2)),
        phase: false,
    };
    jobs.sync(&s, shown);
    jobs.find_bifurcations(&s, (1.0, 1.2));
    let g = jobs.branches.generation;
    assert_eq!(jobs.branches.state, JobState::Running);
    // θν is the diagram's axis: moving it changes nothing.
    s.params.theta_nu = 1.1;
    jobs.sync(&s, shown);
    assert_eq!(jobs.branches.generation, g);
    // A zoom stops a running job but keeps what it found.
    jobs.apply(Update::Summary {
        generation: g,
        lane: Lane::Continuation,
        text: "following the cascade".into(),
    });
    let zoomed = Shown {
        sweep_zoom: Some((1.05, 1.15)),
        ..shown
    };
    jobs.sync(&s, zoomed);
    assert_eq!(jobs.branches.state, JobState::Cancelled);
    assert_eq!(
        jobs.branches.summary.as_deref(),
        Some("stopped: the θν range changed")
    );
    assert_eq!(jobs.branches.data.range, (1.0, 1.2));
    // Started again; κ changes: cancelled on its lane, its result gone.
    jobs.find_bifurcations(&s, (1.0, 1.2));
    let g = jobs.branches.generation;
    rec.clear();
    s.params.kappa = 16.0;
    jobs.sync(&s, shown);
    assert!(rec.commands().iter().any(|c| matches!(
        c,
        Command::Cancel {
            lane: Some(Lane::Continuation),
            ..
        }
    )));
    assert_eq!(jobs.branches.state, JobState::Cancelled);
    let late = Update::Summary {
        generation: g,
        lane: Lane::Continuation,
        text: "1 PD".into(),
    };
    assert!(!jobs.apply(late), "a stale update is dropped");
    assert!(jobs.branches.data.branches.is_empty());
    assert_eq!(
        jobs.branches.summary.as_deref(),
        Some("stopped: the parameters changed")
    );
}

#[test]
fn boundaries_draw_the_doubling_curves_over_the_phase_diagram() {
    let rec = Recorder::new();
    let mut s = Settings {
        layout: Layout::Tabs,
        tab: ViewKind::Phase,
        ..Settings::default()
    };
    s.params = preset("fig4").expect("preset").params;
    s.phase.range = PhaseRange {
        theta_nu: (0.1, 1.55),
        kappa: (10.0, 22.0),
    };
    let mut h = harness_on_worker(&rec, s);
    h.run_steps(2);
    let before = svg_of(&h, ViewKind::Phase);
    let white = "data-series=\"phase:777\"";
    assert!(!before.contains(white), "no curve before Boundaries");
    h.get_by_label("Boundaries").click();
    h.step();
    let spec = rec
        .commands()
        .into_iter()
        .find_map(|c| match c {
            Command::Run {
                spec: Spec::Curves(spec),
                ..
            } => Some(spec),
            _ => None,
        })
        .expect("the job was sent");
    assert_eq!((spec.theta_nu, spec.kappa), ((0.1, 1.55), (10.0, 22.0)));
    assert_eq!(
        spec.params.kappa, 16.0,
        "from the doublings at the slider's κ"
    );
    for _ in 0..3000 {
        h.step();
        let c = &h.state().jobs.curves;
        if c.issued() && c.state != JobState::Running {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    h.run_steps(2);
    let jobs = &h.state().jobs;
    assert_eq!(jobs.curves.state, JobState::Done);
    let periods: Vec<usize> = jobs.curves.data.curves.iter().map(|c| c.period).collect();
    assert!(periods.contains(&1) && periods.contains(&2), "{periods:?}");
    // The view and the status bar say what was found.
    assert_eq!(h.query_all_by_label_contains("boundaries: ").count(), 2);
    // Drawn, also in the SVG: the curves' white line is a series now.
    assert!(svg_of(&h, ViewKind::Phase).contains(white));
    // γ changes: the curves belonged to the old γ.
    h.state_mut().settings.params.gamma = 6.0;
    h.run_steps(2);
    assert!(h.state().jobs.curves.data.curves.is_empty());
}

fn svg_of(h: &Harness<'static, Explorer>, v: ViewKind) -> String {
    oneblock::app::svg_render::render_svg(
        &[v],
        &h.state().settings,
        &h.state().jobs,
        &h.state().views.bifurcation.zoom,
        egui::vec2(900.0, 650.0),
        false,
    )
}

/// The UI thread never continues a branch: no continuation entry point is
/// called anywhere in the window's code.
#[test]
fn no_continuation_runs_in_the_window() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/app");
    let mut stack = vec![root];
    let mut checked = 0;
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).expect("src/app").flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
                continue;
            }
            let text = std::fs::read_to_string(&p).expect("source");
            checked += 1;
            for call in [
                "continue_branch(",
                "cascade(",
                "cascade_reporting(",
                "continue_curve(",
                "solve_cycle(",
            ] {
                assert!(!text.contains(call), "{} calls {call}", p.display());
            }
        }
    }
    assert!(checked > 20);
}
