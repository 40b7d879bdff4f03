//! The phase-diagram view: a grid runs only while the view is shown (or
//! after Compute), γ recomputes it and κ, θν do not, Stop keeps it stopped;
//! the cells are drawn and described on hover, a click moves θν and κ there,
//! and a box recomputes that range at full resolution; with seeds the
//! multistable cells are marked (a legend entry) and a click lists their
//! attractors; the doubling curves' generalised flips are marked and listed.
#![cfg(feature = "gui")]

use crate::window;

use eframe::egui::accesskit::Role;
use egui_kittest::kittest::{NodeT, Queryable};
use oneblock::worker::Spec;

use oneblock::app::jobs::JobState;
use oneblock::app::phase_attractors::multistable_centres;
use oneblock::app::{Recorder, Settings, ViewKind};
use oneblock::sim::continuation::{ContParam, Curve, CurveKind, CurvePoint, GeneralisedFlip};
use oneblock::sim::theta_nu_grid;
use oneblock::worker::Update;
use oneblock::worker::{Command, Lane, ListedAttractor, Outcome};
use window::{
    feed_phase, feed_phase_with, harness, last_trajectory, phase_cancels, phase_cell_pos,
    phase_jobs, phase_tab,
};

#[test]
fn the_phase_diagram_is_computed_only_while_its_view_is_shown() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(3);
    assert!(phase_jobs(&rec).is_empty(), "not shown: no grid");
    // Shown as a tab: the paper's grid at the sliders' γ, ν, Ω.
    h.state_mut().settings.layout = oneblock::app::Layout::Tabs;
    h.state_mut().settings.tab = ViewKind::Phase;
    h.run_steps(2);
    let jobs = phase_jobs(&rec);
    assert_eq!(jobs.len(), 1);
    let j = jobs[0];
    assert_eq!(j.theta_nu, (0.0, std::f64::consts::FRAC_PI_2, 30));
    assert_eq!(j.kappa, (1.0, 42.0, 30));
    assert_eq!(
        (j.params.gamma, j.params.nu, j.params.omega),
        (6.5, 1e-3, 50.0)
    );
    assert!(h.query_by_label_contains("0/900 cells").is_some());
    // Hidden while running: stopped; shown again: started afresh.
    h.state_mut().settings.tab = ViewKind::Plane;
    h.run_steps(2);
    assert_eq!(phase_cancels(&rec), 1);
    assert_eq!(phase_jobs(&rec).len(), 1);
    h.state_mut().settings.tab = ViewKind::Phase;
    h.run_steps(2);
    let jobs = phase_jobs(&rec);
    assert_eq!(jobs.len(), 2);
    assert!(jobs[1].generation > jobs[0].generation);
    // Moving κ or θν only moves the cross-hair; γ recomputes the grid.
    rec.clear();
    h.state_mut().settings.params.kappa = 30.0;
    h.state_mut().settings.params.theta_nu = 0.4;
    let ctx = h.ctx.clone();
    h.state_mut().flush(&ctx);
    h.run_steps(2);
    assert!(phase_jobs(&rec).is_empty());
    h.state_mut().settings.params.gamma = 6.0;
    h.run_steps(1);
    let ctx = h.ctx.clone();
    h.state_mut().flush(&ctx);
    h.run_steps(1);
    let jobs = phase_jobs(&rec);
    assert_eq!(jobs.len(), 1);
    assert_eq!(jobs[0].params.gamma, 6.0);
    // Stop: stays stopped.
    rec.clear();
    h.get_by_label("Stop").click();
    h.run_steps(2);
    let ctx = h.ctx.clone();
    h.state_mut().flush(&ctx);
    h.run_steps(2);
    assert_eq!(phase_cancels(&rec), 1);
    assert!(phase_jobs(&rec).is_empty());
    assert!(h.query_by_label_contains("stopped").is_some());
    h.get_by_label("Compute").click();
    h.run_steps(2);
    assert_eq!(phase_jobs(&rec).len(), 1);
}

#[test]
fn the_phase_view_draws_the_cells_and_a_click_sets_theta_nu_and_kappa() {
    let rec = Recorder::new();
    let mut h = harness(&rec, phase_tab());
    h.run_steps(2);
    let job = phase_jobs(&rec)[0];
    // A stale batch (an older generation) is dropped.
    rec.push(Update::PhaseCells {
        generation: 0,
        cells: vec![],
        coarse: true,
    });
    feed_phase(&rec, &job);
    h.run_steps(3);
    {
        let j = &h.state().jobs;
        assert_eq!(j.phase.data.filled, 900);
        assert_eq!(j.phase.state, JobState::Done);
        assert_eq!(j.stale_dropped, 1);
    }
    assert!(h.query_by_label_contains("900/900 cells · done").is_some());
    // The legend names every class.
    for name in ["FP", "P2", "P6+", "chaos", "undecided", "failed"] {
        assert!(h.query_by_label(name).is_some(), "legend {name}");
    }

    // Click the cell at row 20, column 7.
    rec.clear();
    let (row, column) = (20, 7);
    let pos = phase_cell_pos(&h, &job, row, column);
    h.hover_at(pos);
    h.run_steps(3);
    // Hovering tells the cell (θν = 7·(π/2)/29, κ = 1 + 20·41/29: FP here).
    assert!(
        h.query_by_label_contains("θν = 0.3792, κ = 29.2759")
            .is_some(),
        "the hovered cell is described"
    );
    assert!(h.query_by_label_contains("FP (fixed point)").is_some());
    assert!(h.query_by_label_contains("40 iterates").is_some());
    h.drag_at(pos);
    h.step();
    h.drop_at(pos);
    h.run_steps(3);
    let want_tn = theta_nu_grid(0.0, std::f64::consts::FRAC_PI_2, 30)[column];
    let want_k = theta_nu_grid(1.0, 42.0, 30)[row];
    let p = h.state().settings.params;
    assert_eq!((p.theta_nu, p.kappa), (want_tn, want_k));
    assert!(
        h.state().settings.phase.zoom.is_empty(),
        "a click is not a zoom"
    );
    // The sliders show it and the orbit restarts there.
    let slider = |s: &str| {
        h.get_by_role_and_label(Role::Slider, s)
            .accesskit_node()
            .numeric_value()
    };
    assert_eq!(slider("κ"), Some(want_k));
    assert_eq!(slider("θν"), Some(want_tn));
    let t = last_trajectory(&rec).expect("the orbit restarts at the cell");
    assert_eq!((t.theta_nu, t.kappa), (want_tn, want_k));
    // κ and θν are the grid's axes: no new grid.
    assert!(phase_jobs(&rec).is_empty());
}

#[test]
fn a_box_on_the_phase_diagram_recomputes_that_range_and_back_restores_it() {
    let rec = Recorder::new();
    let mut h = harness(&rec, phase_tab());
    h.run_steps(2);
    let full = phase_jobs(&rec)[0];
    feed_phase(&rec, &full);
    h.run_steps(3);
    rec.clear();
    let (a, b) = (
        phase_cell_pos(&h, &full, 5, 4),
        phase_cell_pos(&h, &full, 22, 25),
    );
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
    let jobs = phase_jobs(&rec);
    assert_eq!(jobs.len(), 1, "a zoom recomputes at once");
    let z = jobs[0];
    let tns = theta_nu_grid(0.0, std::f64::consts::FRAC_PI_2, 30);
    let ks = theta_nu_grid(1.0, 42.0, 30);
    let near = |x: f64, y: f64, tol: f64| (x - y).abs() < tol;
    assert!(
        near(z.theta_nu.0, tns[4], 0.01) && near(z.theta_nu.1, tns[25], 0.01),
        "{z:?}"
    );
    assert!(
        near(z.kappa.0, ks[5], 0.2) && near(z.kappa.1, ks[22], 0.2),
        "{z:?}"
    );
    // At full resolution, not a magnified picture.
    assert_eq!((z.theta_nu.2, z.kappa.2), (30, 30));
    assert_eq!(h.state().settings.phase.zoom.len(), 1);
    // The view now shows the zoomed grid, computing.
    assert_eq!(h.state().jobs.phase.data.kappa, (z.kappa.0, z.kappa.1));
    // Back returns to the whole range.
    rec.clear();
    h.get_by_label("Back").click();
    h.run_steps(3);
    let jobs = phase_jobs(&rec);
    assert_eq!(jobs.len(), 1);
    assert_eq!(
        (jobs[0].theta_nu, jobs[0].kappa),
        (full.theta_nu, full.kappa)
    );
    assert!(h.state().settings.phase.zoom.is_empty());
}

/// The seeds and lists the phase commands sent asked for, in order.
fn seeds_sent(rec: &Recorder) -> Vec<(usize, bool)> {
    rec.commands()
        .into_iter()
        .filter_map(|c| match c {
            Command::Run {
                spec: Spec::Phase(spec),
                ..
            } => Some((spec.tuning.seeds, spec.tuning.list_attractors)),
            _ => None,
        })
        .collect()
}

#[test]
fn with_seeds_multistable_cells_are_marked_and_a_click_lists_their_attractors() {
    let rec = Recorder::new();
    let mut s = phase_tab();
    s.phase.seeds = 8;
    let mut h = harness(&rec, s);
    h.run_steps(2);
    // The grid counts each cell's attractors and lists a multistable one's.
    assert_eq!(seeds_sent(&rec), vec![(8, true)]);
    let job = phase_jobs(&rec)[0];
    let (row, column) = (20, 7);
    let fp = ListedAttractor {
        period: Some(1),
        multiplier: Some(-0.6),
        lyapunov: None,
        basin_fraction: 0.75,
    };
    let chaos = ListedAttractor {
        period: None,
        multiplier: None,
        lyapunov: Some((0.21, Some(0.02))),
        basin_fraction: 0.25,
    };
    feed_phase_with(&rec, &job, |gc| {
        let two = (gc.row, gc.column) == (row, column);
        gc.cell.attractors = Some(if two { 2 } else { 1 });
        if two {
            gc.listed = vec![fp, chaos];
        }
    });
    h.run_steps(3);
    let tns = theta_nu_grid(0.0, std::f64::consts::FRAC_PI_2, 30);
    let ks = theta_nu_grid(1.0, 42.0, 30);
    // One mark, at that cell's centre, and its legend entry.
    assert_eq!(
        multistable_centres(&h.state().jobs.phase.data),
        vec![[tns[column], ks[row]]]
    );
    assert!(h.query_by_label("multistable").is_some(), "legend entry");
    let pos = phase_cell_pos(&h, &job, row, column);
    h.hover_at(pos);
    h.run_steps(3);
    assert!(
        h.query_by_label_contains("2 attractors (multistable): a click lists them")
            .is_some()
    );
    // A click lists them: kind, multiplier or λ, basin fraction.
    h.drag_at(pos);
    h.step();
    h.drop_at(pos);
    h.run_steps(3);
    assert!(
        h.query_by_label_contains("Attractors at θν = 0.3792, κ = 29.2759: 2 counted")
            .is_some()
    );
    // "FP" twice: the legend's and the list's.
    assert_eq!(h.query_all_by_label("FP").count(), 2);
    for text in [
        "multiplier -0.6000",
        "basin 75 %",
        "chaotic",
        "λ = 0.210 ± 0.020",
        "basin 25 %",
    ] {
        assert!(h.query_by_label(text).is_some(), "{text}");
    }
    // Close hides it; a click on a cell with one attractor lists nothing.
    h.get_by_label("Close").click();
    h.run_steps(2);
    assert!(h.query_by_label("basin 75 %").is_none());
    let other = phase_cell_pos(&h, &job, 3, 3);
    h.drag_at(other);
    h.step();
    h.drop_at(other);
    h.run_steps(3);
    assert!(h.query_by_label_contains("Attractors at").is_none());
    // Fewer seeds recompute the grid; none: no counts, no legend entry.
    h.state_mut().settings.phase.seeds = 4;
    h.run_steps(2);
    h.state_mut().settings.phase.seeds = 0;
    h.run_steps(2);
    let sent = seeds_sent(&rec);
    assert_eq!(sent.last(), Some(&(0, false)), "{sent:?}");
    assert!(sent.contains(&(4, true)), "{sent:?}");
    assert!(h.query_by_label("multistable").is_none());
}

#[test]
fn the_doubling_curves_generalised_flips_are_marked_and_listed() {
    let rec = Recorder::new();
    let mut h = harness(&rec, phase_tab());
    h.run_steps(2);
    h.get_by_label("Boundaries").click();
    h.run_steps(2);
    let generation = rec
        .commands()
        .into_iter()
        .find_map(|c| match c {
            Command::Run {
                generation,
                spec: Spec::Curves(..),
            } => Some(generation),
            _ => None,
        })
        .expect("the curves job was sent");
    let point = |tn: f64, k: f64| CurvePoint {
        lambda: [tn, k],
        theta: tn,
        multiplier: -1.0,
    };
    let curve = Curve {
        kind: CurveKind::PeriodDoubling,
        period: 1,
        params: [ContParam::ThetaNu, ContParam::Kappa],
        points: vec![point(1.0, 20.0), point(1.2, 30.0), point(1.4, 40.0)],
        ends: ["left the box".into(), "left the box".into()],
        map_evals: 100,
        generalised_flips: vec![GeneralisedFlip {
            lambda: [1.25, 32.5],
            coefficients: [0.5, -1.5],
        }],
    };
    for u in [
        Update::Curve { generation, curve },
        Update::Finished {
            generation,
            lane: Lane::Curves,
            outcome: Outcome::Completed,
        },
    ] {
        rec.push(u);
    }
    h.run_steps(3);
    assert_eq!(h.state().jobs.curves.data.curves.len(), 1);
    // The legend: the curve (a doubling of the fixed point) and the marker.
    assert!(h.query_by_label("FP to P2").is_some());
    assert!(h.query_by_label("generalised flip").is_some());
    // The table: (θν, κ) and c either side.
    h.get_by_label("Generalised flips (1)").click();
    h.run_steps(2);
    for text in ["P1 to P2", "1.25", "32.5", "0.5", "-1.5"] {
        assert!(h.query_by_label(text).is_some(), "{text}");
    }
}
