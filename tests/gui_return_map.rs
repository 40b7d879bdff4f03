//! The return map's f², f³, f⁴, through the whole window with the real
//! worker: ticking f³ in the period-3 window (κ = 18.95, γ = 6.5,
//! ν = 1e-3, θν = 1.30) draws a graph that meets θ' = θ at the orbit's
//! three points, tangentially (slope between 0 and 1: a period-3 orbit just
//! born in a tangent bifurcation), and whose values agree with three cycles
//! integrated here one after another.
#![cfg(feature = "gui")]

use std::sync::Arc;
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

use oneblock::app::jobs::JobState;
use oneblock::app::{Explorer, Layout, Settings, ViewKind};
use oneblock::integrate::SolverSettings;
use oneblock::model::Params;
use oneblock::sim::{Period, Simulator};
use oneblock::worker::{Worker, WorkerConfig};

fn window(settings: Settings) -> Harness<'static, Explorer> {
    let worker = Worker::spawn(WorkerConfig::default(), Arc::new(|| {}));
    let app = Explorer::new(Box::new(worker), settings);
    Harness::builder()
        .with_size([1280.0, 800.0])
        .build_ui_state(
            |ui, app: &mut Explorer| {
                app.logic_step(ui.ctx());
                app.show(ui);
            },
            app,
        )
}

/// Steps the window until `done` holds (at most `limit`).
fn step_until(
    h: &mut Harness<'static, Explorer>,
    limit: Duration,
    done: impl Fn(&Explorer) -> bool,
) {
    let t0 = Instant::now();
    while !done(h.state()) {
        assert!(t0.elapsed() < limit, "timed out waiting for the worker");
        h.step();
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The value at `x` of the graph (xs, ys) by linear interpolation between
/// the neighbours around it, and the slope there.
fn interpolate(xs: &[f64], ys: &[f64], x: f64) -> (f64, f64) {
    let i = xs.partition_point(|&t| t < x).clamp(1, xs.len() - 1);
    let (x0, x1, y0, y1) = (xs[i - 1], xs[i], ys[i - 1], ys[i]);
    let slope = (y1 - y0) / (x1 - x0);
    (y0 + slope * (x - x0), slope)
}

#[test]
fn f3_touches_the_diagonal_in_the_period_3_window() {
    let params = Params {
        kappa: 18.95,
        gamma: 6.5,
        nu: 1e-3,
        theta_nu: 1.30,
        ..Params::default()
    };
    let settings = Settings {
        params,
        layout: Layout::Tabs,
        tab: ViewKind::ReturnMap,
        // A small diagram: this test is about the orbit lane.
        columns: 20,
        sweep_transient: 0,
        sweep_keep: 1,
        trajectory_cycles: 200,
        ..Settings::default()
    };
    let mut h = window(settings);
    let analysed = |a: &Explorer| {
        a.jobs.iterate.state == JobState::Done && !a.jobs.iterate.data.graph.is_empty()
    };
    step_until(&mut h, Duration::from_secs(120), analysed);
    assert!(
        h.state().jobs.iterate.data.powers.is_empty(),
        "f alone until asked"
    );

    h.get_by_label("f³").click();
    step_until(&mut h, Duration::from_secs(120), |a| {
        a.settings.map_powers[1] && analysed(a) && a.jobs.iterate.data.powers.len() == 2
    });
    let it = &h.state().jobs.iterate.data;
    assert_eq!(
        it.period,
        Some(Period::Periodic(3)),
        "θν = 1.30 is in the period-3 window"
    );
    let xs: Vec<f64> = it.graph.iter().map(|p| p[0]).collect();
    let f3 = &it.powers[1];
    assert_eq!(f3.len(), xs.len());

    // The orbit's three points.
    let mut orbit: Vec<f64> = it.thetas[it.thetas.len() - 3..].to_vec();
    orbit.sort_by(f64::total_cmp);
    let spacing = (xs[xs.len() - 1] - xs[0]) / xs.len() as f64;
    for &p in &orbit {
        let (v, slope) = interpolate(&xs, f3, p);
        // f³ meets the diagonal there, to within what a chord over one
        // graph step can miss of the curve.
        assert!(
            (v - p).abs() < spacing,
            "f³({p}) = {v}: not on the diagonal (graph step {spacing:.2e})"
        );
        // And touches it: a stable period-3 point just past a tangent
        // bifurcation has a slope of f³ below 1 and still positive.
        assert!(
            (0.0..1.0).contains(&slope),
            "slope of f³ at {p} is {slope}: not a tangency"
        );
    }

    // Independent: f³ at a few graph points as three cycles integrated
    // here in turn, against the worker's values.
    let sim = Simulator::new(
        params,
        SolverSettings::adaptive(oneblock::integrate::Method::Dop853, 1e-10),
    )
    .expect("valid parameters");
    let mut checked = 0;
    for i in (0..xs.len()).step_by(37) {
        if !f3[i].is_finite() {
            continue;
        }
        let mut th = xs[i];
        for _ in 0..3 {
            th = sim.cycle(th, 0.0, None).expect("cycle").theta_next;
        }
        assert!(
            (th - f3[i]).abs() < 1e-4,
            "f³({}) = {} here, {} from the worker",
            xs[i],
            th,
            f3[i]
        );
        checked += 1;
    }
    assert!(checked >= 3, "only {checked} points compared");
}
