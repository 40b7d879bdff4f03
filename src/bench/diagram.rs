//! The Fig. 3b diagram timed on the single-threaded host ([`Local`]), the
//! browser's: the same job, plan and code path natively and in wasm, so
//! that `oneblock bench-worker --single-thread` and the page's
//! `bench_diagram` (web/test) measure what the browser costs against one
//! native core, in the same run.

use std::time::Duration;
use web_time::Instant;

use crate::integrate::{Method, SolverSettings};
use crate::jobs::{Axis, Local, Outcome, Shape, Spec, SweepSpec, TimeSlice, Update};
use crate::model::Params;
use crate::sim::MapChoice;

/// The paper's Fig. 3b point, θν = 0 (it is swept): κ = 18.95, γ = 6.5,
/// ν = 1e-3, Ω = 50.
pub fn fig3b() -> Params {
    Params {
        theta_nu: 0.0,
        ..Params::default()
    }
}

/// The paper's Fig. 3b diagram as the worker benchmark times it: κ = 18.95,
/// γ = 6.5, ν = 1e-3 over θν ∈ [0, π/2], dop853 at `tol`.
pub fn fig3b_diagram(columns: usize, transient: usize, keep: usize, tol: f64) -> SweepSpec {
    SweepSpec {
        params: fig3b(),
        settings: SolverSettings::adaptive(Method::Dop853, tol),
        param: crate::sim::continuation::ContParam::ThetaNu,
        axis: Axis::new(0.0, std::f64::consts::FRAC_PI_2, columns),
        transient,
        keep,
        map: MapChoice::Auto,
        theta0: None,
        seeds: 0,
    }
}

/// What a single-threaded run of a diagram took.
#[derive(Clone, Debug, PartialEq)]
pub struct LocalTiming {
    /// Wall-clock seconds from the job's start to its end.
    pub seconds: f64,
    /// Points the diagram kept.
    pub points: usize,
    /// Its steps' durations in seconds, sorted.
    pub steps: Vec<f64>,
}

impl LocalTiming {
    /// The `q`-quantile of the steps' durations in milliseconds (0 with
    /// no step).
    pub fn step_ms(&self, q: f64) -> f64 {
        let n = self.steps.len();
        let i = ((q * n as f64) as usize).min(n.saturating_sub(1));
        self.steps.get(i).map_or(0.0, |s| 1e3 * s)
    }
}

/// The page's compute slice per frame (the explorer's pump budget).
pub const PAGE_SLICE: Duration = Duration::from_millis(12);

/// Runs `spec` to its end on the single-threaded host, one unit per step,
/// or with `slice` one step per slice of that length as the page runs it
/// (units pause at its end), and times it and each step; the job's error if
/// it failed.
pub fn time_diagram(spec: SweepSpec, slice: Option<Duration>) -> Result<LocalTiming, String> {
    let started = Instant::now();
    let mut host = Local::start(Spec::Sweep(spec), 1, Shape::default());
    let mut points = 0;
    let mut outcome = None;
    let mut steps = Vec::new();
    loop {
        let step = Instant::now();
        let more = host.step_until(1, slice.map(TimeSlice::from_now));
        steps.push(step.elapsed().as_secs_f64());
        for u in host.drain() {
            match u {
                Update::Column { thetas, .. } => points += thetas.len(),
                Update::Error { message, .. } => return Err(message),
                Update::Finished { outcome: o, .. } => outcome = Some(o),
                _ => {}
            }
        }
        if !more {
            break;
        }
    }
    let seconds = started.elapsed().as_secs_f64();
    steps.sort_by(f64::total_cmp);
    match outcome {
        Some(Outcome::Completed) => Ok(LocalTiming {
            seconds,
            points,
            steps,
        }),
        o => Err(format!("the diagram did not complete ({o:?})")),
    }
}

/// `repeats` runs of the diagram on the single-threaded host, reported in
/// one line with their median, and one more run in the page's slices with
/// its longest steps (`oneblock bench-worker --single-thread`).
pub fn single_thread_report(
    columns: usize,
    transient: usize,
    keep: usize,
    tol: f64,
    repeats: usize,
) -> Result<String, String> {
    let mut times = Vec::with_capacity(repeats);
    let mut points = 0;
    for _ in 0..repeats.max(1) {
        let t = time_diagram(fig3b_diagram(columns, transient, keep, tol), None)?;
        times.push(t.seconds);
        points = t.points;
    }
    times.sort_by(f64::total_cmp);
    let sliced = time_diagram(
        fig3b_diagram(columns, transient, keep, tol),
        Some(PAGE_SLICE),
    )?;
    Ok(format!(
        "single-threaded host: Fig. 3b diagram, {columns} columns x ({transient} transient + {keep} kept), \
         dop853, tol = {tol:e}: median {:.3} s (min {:.3}, max {:.3}) over {} runs; {points} points; \
         in {} ms slices: {:.3} s, steps p99 {:.1} ms, longest {:.1} ms",
        times[times.len() / 2],
        times[0],
        times[times.len() - 1],
        times.len(),
        PAGE_SLICE.as_millis(),
        sliced.seconds,
        sliced.step_ms(0.99),
        sliced.step_ms(1.0),
    ))
}
