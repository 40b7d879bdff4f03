//! The phase-diagram view: a grid runs only while the view is shown (or
//! after Compute), γ recomputes it and κ, θν do not, Stop keeps it stopped;
//! the cells are drawn and described on hover, a click moves θν and κ there,
//! and a box recomputes that range at full resolution.
#![cfg(feature = "gui")]

#[path = "common/window.rs"]
mod window;

use eframe::egui::accesskit::Role;
use egui_kittest::kittest::{NodeT, Queryable};

use oneblock::app::jobs::JobState;
use oneblock::app::{Recorder, Settings, ViewKind};
use oneblock::sim::theta_nu_grid;
use oneblock::worker::Update;
use window::{
    feed_phase, harness, last_trajectory, phase_cancels, phase_cell_pos, phase_jobs, phase_tab,
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
