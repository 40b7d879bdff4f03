//! Sessions that keep results, through the path the user takes: Find
//! bifurcations, Save session, then Open session… in a fresh window. The
//! branches, their special points and their status line come back drawn
//! with no job sent, bound to the session's parameters, so a κ change
//! clears them as it clears computed ones (and a θν change, the diagram's
//! axis, does not). A session whose branches are corrupt opens with one
//! message and without them; a file that cannot be read changes nothing.
//! `figure` draws a session's branches without computing them again.
#![cfg(feature = "gui")]

use crate::window;

use std::path::{Path, PathBuf};

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

use oneblock::app::bifurcation::Zoom;
use oneblock::app::branches::BranchData;
use oneblock::app::figure::{Figure, Overlays, compute};
use oneblock::app::jobs::JobState;
use oneblock::app::open_session::PATH_LABEL;
use oneblock::app::session::{Results, Session};
use oneblock::app::session_results::{Kept, MAX_BRANCH_POINTS};
use oneblock::app::svg_render::Look;
use oneblock::app::{Explorer, Layout, Recorder, Settings, ViewKind, preset};
use oneblock::jobs::{Local, Shape, Spec};
use oneblock::sim::continuation::{
    Branch, BranchPoint, ContParam, SpecialKind, SpecialPoint, Stop,
};
use oneblock::worker::Command;

fn fig3b_tab(dir: &Path) -> Settings {
    Settings {
        layout: Layout::Tabs,
        tab: ViewKind::Bifurcation,
        params: preset("fig3b").expect("preset").params,
        save_dir: dir.display().to_string(),
        ..Settings::default()
    }
}

/// Find bifurcation jobs the window sent.
fn branch_jobs(rec: &Recorder) -> usize {
    rec.commands()
        .iter()
        .filter(|c| {
            matches!(
                c,
                Command::Run {
                    spec: Spec::Branches(_),
                    ..
                }
            )
        })
        .count()
}

/// Runs the Find bifurcations job the window sent on this thread and hands
/// its updates back as the worker would.
fn answer_branches(h: &mut Harness<'static, Explorer>, rec: &Recorder) {
    let (generation, spec) = rec
        .commands()
        .into_iter()
        .find_map(|c| match c {
            Command::Run {
                generation,
                spec: spec @ Spec::Branches(_),
            } => Some((generation, spec)),
            _ => None,
        })
        .expect("the job was sent");
    for u in Local::start(spec, generation, Shape::default()).run_to_end(usize::MAX) {
        rec.push(u);
    }
    h.run_steps(3);
}

/// The file with extension `ext` in `dir`, waiting for a writer thread.
fn wait_for_file(h: &mut Harness<'static, Explorer>, dir: &Path, ext: &str) -> PathBuf {
    for _ in 0..200 {
        h.step();
        let found = std::fs::read_dir(dir)
            .expect("read dir")
            .flatten()
            .map(|e| e.path())
            .find(|p| p.extension().is_some_and(|e| e == ext));
        if let Some(p) = found {
            return p;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    panic!("no .{ext} file in {}", dir.display());
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

/// Opens the session at `path` through Open session… (the modal's path
/// field and its Open button).
fn open_through_the_modal(h: &mut Harness<'static, Explorer>, path: &Path) {
    h.get_by_label("Open session…").click();
    h.run_steps(2);
    let field = h.get_by_role_and_label(eframe::egui::accesskit::Role::TextInput, PATH_LABEL);
    field.focus();
    field.set_text_value_accesskit(&path.display().to_string());
    h.run_steps(2);
    h.get_by_label("Open").click();
    h.run_steps(3);
}

#[test]
fn a_session_keeps_the_branches_and_reopens_them_without_a_job_until_kappa_changes() {
    let dir = tempfile::tempdir().expect("tempdir");
    let rec = Recorder::new();
    let mut h = window::harness(&rec, fig3b_tab(dir.path()));
    h.state_mut().views.bifurcation.zoom.push(Zoom {
        theta_nu: (1.0, 1.2),
        theta: (0.0, 1.0),
    });
    h.run_steps(2);
    h.get_by_label("Find bifurcations").click();
    h.step();
    answer_branches(&mut h, &rec);
    let computed = h.state().jobs.branches.clone();
    assert_eq!(computed.state, JobState::Done);
    assert!(
        computed.data.branches[0]
            .of_kind(SpecialKind::PeriodDoubling)
            .next()
            .is_some(),
        "a doubling was found"
    );
    h.get_by_label("Save session").click();
    let saved = wait_for_file(&mut h, dir.path(), "json");
    let bytes = std::fs::metadata(&saved).expect("saved").len();
    assert!(bytes < 1 << 20, "{bytes} bytes");

    // A fresh window opens it: the same branches, points and status line,
    // drawn, and no job asked for them.
    let rec2 = Recorder::new();
    let mut h2 = window::harness(&rec2, Settings::default());
    h2.run_steps(2);
    open_through_the_modal(&mut h2, &saved);
    let back = &h2.state().jobs.branches;
    assert_eq!(back.data, computed.data, "the same branches");
    assert_eq!(back.summary, computed.summary, "the same status line");
    assert_eq!(h2.state().settings.params, computed_params());
    assert_eq!(h2.state().views.bifurcation.zoom.len(), 1);
    assert!(h2.state().open_dialog.is_none(), "the modal closed");
    assert_eq!(branches_shown(&h2), [true; 3], "drawn as computed");
    h2.run_steps(5);
    assert_eq!(branch_jobs(&rec2), 0, "no Find bifurcations job");

    // θν is the diagram's axis: they stay. κ: they are cleared.
    h2.state_mut().settings.params.theta_nu = 1.1;
    h2.run_steps(3);
    assert_eq!(branches_shown(&h2), [true; 3], "θν keeps them");
    h2.state_mut().settings.params.kappa = 16.0;
    h2.run_steps(3);
    assert_eq!(branches_shown(&h2), [false; 3], "κ clears them");
    assert!(h2.state().jobs.branches.bound.is_none());
    assert_eq!(branch_jobs(&rec2), 0, "and nothing is recomputed");
}

fn computed_params() -> oneblock::Params {
    preset("fig3b").expect("preset").params
}

/// A small branch of fig3b's θν, with a doubling.
fn a_branch() -> Branch {
    let point = |lambda: f64, theta: f64, multiplier: f64| BranchPoint {
        lambda,
        points: vec![theta],
        multiplier,
        stable: multiplier.abs() < 1.0,
        minimal_period: 1,
    };
    Branch {
        param: oneblock::sim::continuation::ContParam::ThetaNu,
        period: 1,
        points: vec![
            point(1.0, 0.3, -0.5),
            point(1.1, 0.4, -1.0),
            point(1.2, 0.5, -1.4),
        ],
        special: vec![SpecialPoint {
            kind: SpecialKind::PeriodDoubling,
            period: 1,
            lambda: 1.1,
            theta: 0.4,
            multiplier: -1.0,
            note: String::new(),
            flip: None,
        }],
        stop: Stop::Reached,
        map_evals: 40,
    }
}

fn a_session_with(branches: Vec<Branch>) -> Session {
    Session {
        settings: fig3b_tab(Path::new(".")),
        bifurcation_zoom: Vec::new(),
        results: Results {
            branches: Some(Kept {
                data: BranchData {
                    param: Some(ContParam::ThetaNu),
                    range: (1.0, 1.2),
                    branches,
                    doublings: Vec::new(),
                },
                summary: Some("1 PD, 0 fold".into()),
            }),
            curves: None,
        },
    }
}

#[test]
fn corrupt_branches_are_dropped_with_one_message_and_the_rest_is_kept() {
    let good = a_session_with(vec![a_branch()]);
    let back = Session::from_json(&good.to_json(), "s.json");
    assert_eq!(back.message, None);
    assert_eq!(back.session, good, "a clean round trip");

    let mut nan = a_branch();
    nan.points[1].lambda = f64::NAN;
    let mut long = a_branch();
    long.points = vec![long.points[0].clone(); MAX_BRANCH_POINTS + 1];
    let many = a_session_with(vec![a_branch(); 65]).to_json();
    for (text, why) in [
        (a_session_with(vec![nan]).to_json(), "unreadable"),
        (a_session_with(vec![long]).to_json(), "over 5000 points"),
        (many, "over 64 branches"),
    ] {
        let l = Session::from_json(&text, "bad.json");
        let m = l.message.expect("a message");
        assert_eq!(m.lines().count(), 1, "{m}");
        assert!(
            m.contains("bad.json") && m.contains("branches") && m.contains(why),
            "{m}"
        );
        assert_eq!(l.session.results, Results::default(), "{m}");
        assert_eq!(l.session.settings, good.settings, "the rest is kept");
    }
    // An older session (no results) is clean.
    let mut v: serde_json::Value = serde_json::from_str(&good.to_json()).expect("json");
    v.as_object_mut().expect("object").remove("branches");
    let old = Session::from_json(&v.to_string(), "old.json");
    assert_eq!(
        (old.message, old.session.results),
        (None, Results::default())
    );
}

#[test]
fn opening_a_corrupt_or_unreadable_session_in_the_window_says_so() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut nan = a_branch();
    nan.special[0].theta = f64::INFINITY;
    let bad = dir.path().join("oneblock-session-bad.json");
    std::fs::write(&bad, a_session_with(vec![nan]).to_json()).expect("write");
    let rec = Recorder::new();
    let mut h = window::harness(&rec, Settings::default());
    h.run_steps(2);
    open_through_the_modal(&mut h, &bad);
    assert_eq!(h.state().settings.params, computed_params(), "opened");
    assert!(h.state().jobs.branches.data.branches.is_empty());
    assert!(
        h.query_by_label_contains("dropped branches").is_some(),
        "the toast names what was dropped"
    );

    // A folder is no session: the modal says why and nothing changes.
    let before = h.state().settings.clone();
    open_through_the_modal(&mut h, dir.path());
    assert!(
        h.query_by_label_contains("it is a directory").is_some(),
        "the reason is shown"
    );
    assert!(h.state().open_dialog.is_some(), "the modal stays open");
    assert_eq!(h.state().settings, before);
    h.get_by_label("Cancel").click();
    h.run_steps(2);
    assert!(h.state().open_dialog.is_none());
}

#[test]
fn a_figure_draws_the_branches_a_session_kept_without_computing_them() {
    let session = a_session_with(vec![a_branch()]);
    let mut fig = Figure {
        view: ViewKind::Bifurcation,
        settings: session.settings.clone(),
        zoom: Vec::new(),
        theta_nu: None,
        theta: None,
        size: eframe::egui::vec2(640.0, 480.0),
        crosshair: false,
        look: Look::default(),
        overlays: Overlays {
            branches: true,
            boundaries: false,
        },
        session: Some(session.clone()),
    };
    fig.settings.columns = 40;
    let jobs = compute(&fig).expect("computed");
    let kept = session.results.branches.expect("kept");
    assert_eq!(
        jobs.branches.data, kept.data,
        "the session's, not recomputed"
    );
    // Other parameters than the session's: its branches are not drawn.
    fig.overlays.branches = false;
    fig.settings.params.kappa = 16.0;
    let jobs = compute(&fig).expect("computed");
    assert!(jobs.branches.data.branches.is_empty());
}

/// A session the window could not read back (over its bound) is saved
/// without its results, saying so, rather than as a file it would refuse.
#[test]
fn a_session_too_large_to_read_back_is_saved_without_its_results() {
    let mut b = a_branch();
    b.period = 8;
    let mut p = b.points[0].clone();
    p.points = vec![0.123_456_789_012_345_6; 8];
    p.minimal_period = 8;
    b.points = vec![p; 4000];
    let big = a_session_with(vec![b; 20]);
    let (text, note) = big.to_file_text();
    let note = note.expect("a note");
    assert!(note.contains("saved without them"), "{note}");
    let back = Session::from_json(&text, "s.json");
    assert_eq!(back.message, None);
    assert_eq!(back.session.results, Results::default());
    assert_eq!(back.session.settings, big.settings);
    // A session of ordinary size is written whole.
    let small = a_session_with(vec![a_branch()]);
    assert_eq!(small.to_file_text(), (small.to_json(), None));
}

/// Boundaries' curves are kept too, and cleared by a γ change (the phase
/// diagram's axes, θν and κ, keep them).
#[test]
fn a_session_keeps_the_boundary_curves_until_gamma_changes() {
    use oneblock::app::branches::CurveData;
    use oneblock::sim::continuation::{Curve, CurveKind, CurvePoint, GeneralisedFlip};
    let point = |t: f64, k: f64| CurvePoint {
        lambda: [t, k],
        theta: 0.4,
        multiplier: -1.0,
    };
    let curve = Curve {
        kind: CurveKind::PeriodDoubling,
        period: 1,
        params: [ContParam::ThetaNu, ContParam::Kappa],
        points: vec![point(1.0, 12.0), point(1.1, 14.0), point(1.2, 16.0)],
        ends: ["the box".into(), "the box".into()],
        map_evals: 30,
        generalised_flips: vec![GeneralisedFlip {
            lambda: [1.05, 13.0],
            coefficients: [1.0, -2.0],
        }],
    };
    let mut session = a_session_with(vec![a_branch()]);
    session.settings.tab = ViewKind::Phase;
    session.results.curves = Some(Kept {
        data: CurveData {
            curves: vec![curve],
        },
        summary: Some("1 PD curve".into()),
    });
    let text = session.to_json();
    let loaded = Session::from_text(&text, "s.json").expect("a session");
    assert_eq!(loaded.session, session);
    let rec = Recorder::new();
    let mut h = window::harness(&rec, Settings::default());
    h.run_steps(2);
    h.state_mut().open_session(loaded);
    h.run_steps(3);
    let kept = session.results.curves.as_ref().expect("curves");
    assert_eq!(h.state().jobs.curves.data, kept.data);
    // The phase view and the status bar say what was found.
    assert_eq!(
        h.query_all_by_label_contains("boundaries: 1 PD curve")
            .count(),
        2
    );
    h.state_mut().settings.params.kappa = 13.0;
    h.state_mut().settings.params.theta_nu = 1.0;
    h.run_steps(3);
    assert_eq!(h.state().jobs.curves.data, kept.data, "the axes keep them");
    h.state_mut().settings.params.gamma = 6.0;
    h.run_steps(3);
    assert!(
        h.state().jobs.curves.data.curves.is_empty(),
        "γ clears them"
    );
    let curve_jobs = rec
        .commands()
        .iter()
        .filter(|c| {
            matches!(
                c,
                Command::Run {
                    spec: Spec::Curves(_),
                    ..
                }
            )
        })
        .count();
    assert_eq!(curve_jobs, 0, "nothing was computed");
}
