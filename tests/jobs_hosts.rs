//! Every kind of job, run to completion by the single-threaded host
//! (`jobs::Local`, a unit per step, as a browser build runs them), by the
//! worker (threads and generations, as the window runs them) and by the
//! command line's host (`jobs::run_collect`), gives the same results, bit
//! for bit: a job is defined once, and its plan does not depend on who
//! runs it or on how many threads.

use crate::common;

use std::collections::BTreeMap;

use common::fixture::preset;
use common::until_finished;
use oneblock::integrate::{Method, SolverSettings};
use oneblock::jobs::{
    Axis, BasinsSpec, BoundarySpec, CascadeFrom, ContinuationSpec, CurveFollow, GivenCycle,
    IterateSpec, Local, Outcome, PassageSpec, PhaseSpec, PhaseTuning, ScanSpec, Shape, Spec,
    SweepSpec, TimeSlice, TrajectorySpec, Update, WorkPrecisionSpec, run_collect,
};
use oneblock::model::Params;
use oneblock::numerics::Subject;
use oneblock::sim::continuation::{Attractor, ContParam, CurveKind, attractor_cycle};
use oneblock::sim::{
    ColumnJob, LaneEnd, MapChoice, Simulator, SweepOptions, Yield, column_start, default_settings,
    run_columns, sweep_columns, theta_nu_grid,
};
use oneblock::worker::{Command, Worker, WorkerConfig};

/// What a job computed, in a form that does not depend on how its updates
/// were batched or ordered in time: progress (timing) is left out, columns
/// and cells are keyed by their place, streamed iterates concatenated, and
/// work-precision rows keep their errors and costs but not their timings.
#[derive(Clone, Debug, PartialEq, Default)]
struct Results {
    samples: Vec<(f64, f64, f64)>,
    slips: Vec<String>,
    iterates: Vec<f64>,
    last_analysis: String,
    graphs: Vec<String>,
    columns: BTreeMap<usize, (f64, Vec<f64>)>,
    /// Columns sent again (a seeded sweep's neighbour pass amends them).
    resent: usize,
    lyapunovs: BTreeMap<usize, String>,
    column_costs: BTreeMap<usize, u64>,
    /// How each column's points after the transient were computed.
    column_maps: BTreeMap<usize, String>,
    cells: BTreeMap<(usize, usize), String>,
    rows: Vec<String>,
    /// Basins columns by index (a parallel job's come in any order).
    basins: BTreeMap<usize, String>,
    other: Vec<String>,
    outcome: Option<Outcome>,
}

fn results(ups: &[Update]) -> Results {
    let mut r = Results::default();
    for u in ups {
        match u {
            Update::TrajectoryChunk { samples, .. } => {
                r.samples.extend(samples.iter().map(|s| (s.t, s.x, s.y)));
            }
            Update::Slip { event, .. } => r.slips.push(format!("{event:?}")),
            Update::MapIterates {
                thetas,
                period,
                lyapunov,
                ..
            } => {
                r.iterates.extend(thetas);
                r.last_analysis = format!("{period:?} {lyapunov:?}");
            }
            Update::MapGraph {
                thetas,
                values,
                powers,
                ..
            } => {
                r.graphs.push(format!("{thetas:?} {values:?} {powers:?}"));
            }
            Update::Column {
                index,
                value: theta_nu,
                thetas,
                attractor,
                lyapunov,
                rhs_evals,
                map,
                ..
            } => {
                r.lyapunovs.insert(*index, format!("{lyapunov:?}"));
                r.column_costs.insert(*index, *rhs_evals);
                r.column_maps.insert(*index, format!("{map:?}"));
                // Each attractor label folded into its value (θ + 100·label),
                // so that the hosts must agree on both.
                let labelled = thetas
                    .iter()
                    .zip(attractor.iter().chain(std::iter::repeat(&0)))
                    .map(|(t, &a)| t + 100.0 * a as f64)
                    .collect();
                if r.columns.insert(*index, (*theta_nu, labelled)).is_some() {
                    r.resent += 1;
                }
            }
            Update::PhaseCells { cells, .. } => {
                for c in cells {
                    let key = (c.row, c.column);
                    let cell = format!("{:?} listed {:?}", c.cell, c.listed);
                    assert!(r.cells.insert(key, cell).is_none());
                }
            }
            Update::WorkPrecisionRow { index, row, .. } => r.rows.push(format!(
                "{index} {} {} {} {} {} {} {}",
                row.method,
                row.setting,
                row.failed,
                row.max_error,
                row.median_error,
                row.max_stop_error,
                row.evals_per_iterate
            )),
            Update::Basins { column, .. } => {
                r.basins.insert(column.index, format!("{column:?}"));
            }
            Update::Progress { .. } => {}
            Update::Finished { outcome, .. } => r.outcome = Some(outcome.clone()),
            Update::Error { message, .. } => r.other.push(format!("error: {message}")),
            other => r.other.push(strip_generation(other)),
        }
    }
    r
}

/// An update's text without its generation (the hosts number jobs apart).
fn strip_generation(u: &Update) -> String {
    let text = format!("{u:?}");
    let g = format!("generation: {}", u.generation());
    text.replacen(&g, "generation: _", 1)
}

/// The job to its end on the single-threaded host, one unit per step.
fn local(spec: Spec) -> Results {
    let updates = Local::start(spec, 1, Shape::default()).run_to_end(1);
    results(&updates)
}

/// The job to its end on the single-threaded host with a deadline that has
/// always passed: every unit that can pause does so after one cycle or
/// slope, and is resumed by the next step. Also the number of steps taken.
fn local_paused(spec: Spec) -> (Results, usize) {
    let mut host = Local::start(spec, 1, Shape::default());
    let mut steps = 0;
    let spent = TimeSlice {
        start: web_time::Instant::now(),
        end: web_time::Instant::now(),
    };
    while host.step_until(1, Some(spent)) {
        steps += 1;
    }
    (results(&host.drain()), steps)
}

/// The job to its end on the worker (two threads for a parallel job), sent
/// as the generic `Command::Run`.
fn threaded(cmd: Command) -> Results {
    let (generation, spec) = cmd.into_job().expect("a job");
    let lane = spec.lane();
    let w = Worker::spawn(WorkerConfig::default(), std::sync::Arc::new(|| {}));
    assert!(w.send(Command::Run { generation, spec }));
    let (mut ups, outcome) = until_finished(&w, generation, lane);
    ups.push(Update::Finished {
        generation,
        lane,
        outcome,
    });
    w.shutdown();
    results(&ups)
}

/// Runs `cmd` on both hosts and checks they agree and completed.
fn same_on_both_hosts(cmd: Command) -> Results {
    let spec = cmd.clone().into_job().expect("a job").1;
    let single = local(spec);
    let many = threaded(cmd);
    assert_eq!(single.outcome, Some(Outcome::Completed), "{single:?}");
    assert_eq!(single, many);
    single
}

fn settings() -> SolverSettings {
    default_settings(1e-8)
}

#[test]
fn a_trajectory_is_the_same_on_every_host() {
    let r = same_on_both_hosts(Command::run(
        3,
        TrajectorySpec {
            params: preset("fig3b"),
            settings: settings(),
            theta0: Some(0.5),
            transient: 0,
            spacing: 0.05,
            cycles: Some(12),
            max_samples: None,
        },
    ));
    assert_eq!(r.slips.len(), 12);
    assert!(r.samples.len() > 12);
}

#[test]
fn map_iterates_are_the_same_on_every_host() {
    let r = same_on_both_hosts(Command::run(
        4,
        IterateSpec {
            params: preset("fig3b"),
            settings: settings(),
            theta0: None,
            transient: 30,
            keep: 40,
            graph_powers: 2,
            options: oneblock::jobs::IterateOptions::default(),
        },
    ));
    assert_eq!(r.iterates.len(), 40);
    assert_eq!(r.graphs.len(), 2, "f, then f with f²");
}

#[test]
fn an_orbit_on_the_interpolant_is_the_same_on_every_host_and_paused_after_every_piece() {
    // Fig. 3b's chaotic band: the scout's 300 integrated iterates, the
    // build (at most 64 map evaluations a piece), then 512 iterates of the
    // series a piece, extensions where the orbit leaves the interval.
    let spec = IterateSpec {
        params: Params {
            theta_nu: 1.25,
            ..preset("fig3b")
        },
        settings: settings(),
        theta0: None,
        transient: 1000,
        keep: 30_000,
        graph_powers: 0,
        options: oneblock::jobs::IterateOptions {
            map: MapChoice::Interpolant,
            report: true,
            ..Default::default()
        },
    };
    let r = same_on_both_hosts(Command::run(4, spec.clone()));
    assert_eq!(r.iterates.len(), 30_000);
    let report = r
        .other
        .iter()
        .find(|o| o.starts_with("Orbit"))
        .expect("the orbit");
    assert!(report.contains("map: Interpolant("), "{report}");
    let (paused, steps) = local_paused(Spec::Iterate(spec.clone()));
    assert_eq!(paused, r);
    assert!(steps > 300 + 31_000 / 512, "{steps} steps");
    // The library's blocking call runs the same loop: the same orbit.
    let sim = Simulator::new(spec.params, spec.settings).expect("valid");
    let opts = oneblock::sim::OrbitOptions {
        transient: spec.transient,
        keep: spec.keep,
        lyapunov: true,
        period_tol: oneblock::sim::OrbitOptions::period_tol_of(&spec.settings),
    };
    let iopts = oneblock::sim::InterpolantOptions::for_settings(&spec.settings);
    let io = oneblock::sim::orbit_interpolated(&sim, spec.params.theta_nu, &opts, iopts, &|| false)
        .expect("the interpolant is built");
    assert_eq!(io.orbit.thetas(), r.iterates);
}

#[test]
fn a_column_on_the_interpolant_pauses_in_its_build_and_its_points() {
    // Chaotic columns of Fig. 3b keeping 8000 points: after the transient
    // each builds the interpolant over its recent onsets (in pieces of at
    // most 64 map evaluations) and takes its points from it (64 a piece).
    let spec = SweepSpec {
        params: preset("fig3b"),
        settings: settings(),
        param: ContParam::ThetaNu,
        axis: Axis::new(1.25, 1.29, 2),
        transient: 200,
        keep: 8000,
        map: MapChoice::Interpolant,
        theta0: None,
        seeds: 0,
    };
    let r = same_on_both_hosts(Command::run(5, spec.clone()));
    assert_eq!(r.columns.len(), 2);
    assert!(
        r.column_maps
            .values()
            .all(|m| m.starts_with("Interpolant(")),
        "{:?}",
        r.column_maps
    );
    assert!(r.columns.values().all(|(_, t)| t.len() == 8000));
    let (paused, steps) = local_paused(Spec::Sweep(spec));
    assert_eq!(paused, r);
    // Each build is about 10 000 map evaluations: 150 pieces at least.
    assert!(steps > 2 * (200 + 8000 / 64 + 150), "{steps} steps");
}

#[test]
fn a_sweep_is_the_same_on_every_host_and_on_the_command_lines() {
    let spec = SweepSpec {
        params: preset("fig3b"),
        settings: default_settings(1e-6),
        param: ContParam::ThetaNu,
        axis: Axis::new(0.9, 1.5, 21),
        transient: 60,
        keep: 12,
        map: MapChoice::Auto,
        theta0: None,
        seeds: 0,
    };
    let r = same_on_both_hosts(Command::run(5, spec.clone()));
    assert_eq!(r.columns.len(), 21);
    assert!(r.lyapunovs.values().all(|l| l.starts_with("Some")), "{r:?}");
    // Paused after every cycle and every λ slope, and resumed: the same
    // diagram and exponents, in many more steps than columns.
    let (paused, steps) = local_paused(Spec::Sweep(spec.clone()));
    assert_eq!(paused, r);
    assert!(steps > 10 * 21, "{steps} steps");
    // The command line's host, on one thread and on three.
    for threads in [1, 3] {
        let ups = run_collect(Spec::Sweep(spec.clone()), threads, |_| {}, || false)
            .expect("the sweep completes");
        assert_eq!(results(&ups).columns, r.columns, "{threads} thread(s)");
    }
}

/// Asks for the thread back every time, counting the asks.
struct AlwaysPause(std::cell::Cell<usize>);

impl Yield for AlwaysPause {
    fn pause(&self) -> bool {
        self.0.set(self.0.get() + 1);
        true
    }
    fn defer_heavy(&self) -> bool {
        false
    }
}

#[test]
fn a_cycle_solve_pauses_between_map_evaluations_and_resumes_bit_for_bit() {
    // Fig. 3b near θν = 1.38, where the diagram's columns are solved onto
    // a slow 6-cycle and each hands it to the next, which solves for it
    // before its first cycle (20 to 30 ms in one piece in wasm before).
    let params = preset("fig3b");
    let settings = default_settings(1e-6);
    let opts = SweepOptions {
        transient: 60,
        keep: 12,
        map: MapChoice::Auto,
    };
    let grid = theta_nu_grid(0.9, 1.5, 61);
    let cols = sweep_columns(params, settings, &grid, &opts, None, &|| false, |_| {});
    let (i, handed) = (48..cols.len())
        .find_map(|i| Some((i, cols[i - 1].handover()?)).filter(|(_, h)| h.slow_period.is_some()))
        .expect("a column continuing its neighbour's slow cycle");
    let whole = &cols[i];
    assert_eq!(whole.slow_period, handed.slow_period, "{whole:?}");
    let theta_nu = grid[i];
    let start = column_start(params.kappa, theta_nu, Some(handed.theta));
    let sim = Simulator::new(params.with_theta_nu(theta_nu), settings).expect("valid");
    // The same column on a lane whose host wants its thread back at every
    // chance: each call makes one map evaluation of the solve and pauses.
    let asks = AlwaysPause(std::cell::Cell::new(0));
    let (mut paused, mut done, mut calls) = (None, None, 0);
    while done.is_none() {
        calls += 1;
        assert!(calls < 10_000, "the column never ends");
        let mut job = Some(ColumnJob {
            sim: Ok(&sim),
            theta_nu,
            start,
            slow_period: handed.slow_period,
            resume: paused.take(),
        });
        run_columns(&opts, &|| false, &asks, |_, ended| {
            match ended {
                Some(LaneEnd::Paused(p)) => paused = Some(p),
                Some(LaneEnd::Finished(c)) => done = Some(c),
                None => {}
            }
            job.take()
        });
    }
    let period = handed.slow_period.unwrap_or(0);
    assert!(calls > period, "{calls} calls for a {period}-cycle's solve");
    assert_eq!(done.as_ref(), Some(whole), "paused {calls} times");
    assert_eq!(done.map(|c| c.rhs_evals), Some(whole.rhs_evals));
}

#[test]
fn a_seeded_sweep_and_grid_are_the_same_on_every_host() {
    let params = Params {
        kappa: 10.0,
        gamma: 6.5,
        nu: 1e-3,
        theta_nu: 1.4,
        omega: 50.0,
    };
    let spec = SweepSpec {
        params,
        settings: default_settings(1e-8),
        param: ContParam::ThetaNu,
        axis: Axis::new(1.36, 1.44, 9),
        transient: 100,
        keep: 24,
        map: MapChoice::Auto,
        theta0: None,
        seeds: 1,
    };
    let r = same_on_both_hosts(Command::run(5, spec.clone()));
    // Columns show a second attractor (labels are in the hundreds) from
    // the cell graph, the same on every host.
    let multistable = r.columns.values().filter(|c| c.1.iter().any(|&t| t > 50.0));
    assert!(multistable.count() >= 3, "{r:?}");
    let (paused, _) = local_paused(Spec::Sweep(spec.clone()));
    assert_eq!(paused, r);
    for threads in [1, 3] {
        let ups =
            run_collect(Spec::Sweep(spec.clone()), threads, |_| {}, || false).expect("completes");
        let cli = results(&ups);
        assert_eq!((cli.columns, cli.resent), (r.columns.clone(), r.resent));
    }
    let grid = PhaseSpec {
        params,
        settings: default_settings(1e-8),
        theta_nu: Axis::new(1.36, 1.44, 5),
        kappa: Axis::new(9.0, 10.0, 2),
        transient: 100,
        keep: 32,
        tuning: PhaseTuning {
            seeds: 4,
            list_attractors: true,
            ..PhaseTuning::default()
        },
    };
    let r = same_on_both_hosts(Command::run(6, grid.clone()));
    assert_eq!(r.cells.len(), 10);
    assert!(
        r.cells.values().any(|c| c.contains("attractors: Some(2)")),
        "{r:?}"
    );
    assert!(r.cells.values().any(|c| !c.ends_with("listed []")), "{r:?}");
    // Paused after every piece (a cell's iterates, a solve's steps, the
    // cell graph's interpolant, levels and verdicts): the same cells and
    // the same lists of attractors.
    let (paused, steps) = local_paused(Spec::Phase(grid));
    assert_eq!(paused, r);
    assert!(steps > 10 * 20, "{steps} steps");
}

#[test]
fn a_phase_grid_is_the_same_on_every_host() {
    let spec = PhaseSpec {
        params: preset("fig3b"),
        settings: default_settings(1e-8),
        theta_nu: Axis::new(0.6, 1.5, 6),
        kappa: Axis::new(10.0, 20.0, 5),
        transient: 100,
        keep: 32,
        tuning: PhaseTuning::default(),
    };
    let r = same_on_both_hosts(Command::run(6, spec.clone()));
    assert_eq!(r.cells.len(), 30);
    // Paused after every piece (at most 32 map evaluations, or one step of
    // a solve): the same grid; a cell of 100 iterates or more is several
    // pieces.
    let (paused, steps) = local_paused(Spec::Phase(spec));
    assert_eq!(paused, r);
    assert!(steps > 30 * 3, "{steps} steps");
}

#[test]
fn a_work_precision_measurement_is_the_same_on_every_host_but_its_timings() {
    let subjects = [Method::Dop853, Method::Dp54]
        .into_iter()
        .flat_map(|m| [1e-6, 1e-8].map(|tol| Subject::Own(SolverSettings::adaptive(m, tol))))
        .collect();
    let spec = Spec::Numerics(WorkPrecisionSpec {
        attractors: vec![oneblock::numerics::quick::current_attractor(
            preset("fig3b"),
            None,
            100,
        )],
        points: 3,
        timing: oneblock::jobs::Timing::PerSetting(std::time::Duration::from_millis(3)),
        subjects,
    });
    let r = same_on_both_hosts(Command::run(7, spec.clone()));
    assert_eq!(r.rows.len(), 4);
    // Paused after every piece (a reference cycle, a pair of points'
    // references, a check, a timing): the same rows.
    let (paused, steps) = local_paused(spec);
    assert_eq!(paused, r);
    assert!(steps > 100 + 4 * 3, "{steps} steps");
}

#[test]
fn a_basins_column_paused_after_every_piece_is_the_same() {
    // Fig. 3b at θν = 1.1 and 1.4 (one attractor; two), the diagram's
    // cells: pieces are the arc's interpolant (at most 64 map evaluations
    // each), each level of subdivision, each piece of a set at its floor
    // (1 500 iterates of its orbit, a solve, a piece of a sharpening) and
    // each verdict.
    let spec = BasinsSpec {
        params: preset("fig3b"),
        settings: SolverSettings::adaptive(Method::Dop853, 1e-10),
        param: oneblock::sim::continuation::ContParam::ThetaNu,
        axis: Axis::new(1.1, 1.4, 2),
        cells: oneblock::sim::attractors::CellOptions::column(),
    };
    let r = same_on_both_hosts(Command::run(8, spec.clone()));
    assert_eq!(r.basins.len(), 2, "{r:?}");
    let (paused, steps) = local_paused(Spec::Basins(spec));
    // The same columns; the births and deaths are located where the job
    // runs whole, not on a host that slices it for a page's frames (the
    // page says so).
    let is_events = |o: &String| o.starts_with("BasinEvents");
    assert_eq!(r.other.iter().filter(|o| is_events(o)).count(), 1, "{r:?}");
    let mut whole = r.clone();
    whole.other.retain(|o| !is_events(o));
    assert_eq!(paused, whole);
    // The arc's interpolant alone is thousands of map evaluations.
    assert!(steps > 2 * 40, "{steps} steps");
}

/// Map evaluations that a continuation's branches and curves report.
fn map_evals(ups: &[Update]) -> u64 {
    ups.iter()
        .map(|u| match u {
            Update::Branch { branch, .. } => branch.map_evals,
            Update::Curve { curve, .. } => curve.map_evals,
            _ => 0,
        })
        .sum()
}

/// A continuation's `cmd` paused after every piece on the single-threaded
/// host, and run by the command line's host: the same results as `r` (the
/// worker's and the unpaused single thread's), the paused one in a step
/// per map evaluation at least (it pauses between any two).
fn same_paused_and_on_the_command_line(cmd: Command, r: &Results) {
    let spec = cmd.into_job().expect("a job").1;
    let (paused, steps) = local_paused(spec.clone());
    assert_eq!(&paused, r);
    let evals = map_evals(&Local::start(spec.clone(), 1, Shape::default()).run_to_end(1));
    assert!(
        evals > 100 && steps as u64 >= evals,
        "{steps} steps for {evals} map evaluations"
    );
    let ups = run_collect(spec, 1, |_| {}, || false).expect("it completes");
    let cli = Results {
        outcome: r.outcome.clone(),
        ..results(&ups)
    };
    assert_eq!(&cli, r);
}

#[test]
fn find_bifurcations_is_the_same_on_every_host_and_paused() {
    let cmd = Command::run(
        8,
        ContinuationSpec {
            params: preset("fig3b"),
            settings: settings(),
            param: ContParam::ThetaNu,
            from: 1.0,
            to: 1.2,
            max_period: 4,
            cycle: None,
            cascade: CascadeFrom::Branch,
            curves: None,
        },
    );
    let r = same_on_both_hosts(cmd.clone());
    // The P1 branch and the cascade's levels after it.
    let branches = r.other.iter().filter(|s| s.starts_with("Branch")).count();
    assert!(branches >= 2, "{r:?}");
    assert!(r.other.iter().any(|s| s.starts_with("Cascade")), "{r:?}");
    same_paused_and_on_the_command_line(cmd, &r);
}

/// `oneblock continue --curve pd`'s job: a given cycle (the attractor's
/// fixed point at θν = 0.9, as the command finds it), its branch with each
/// special point as it is located, and the doubling curves through it.
#[test]
fn a_given_cycle_and_its_curves_are_the_same_on_every_host_and_paused() {
    let params = ContParam::ThetaNu.set(&preset("fig3b"), 0.9);
    let Attractor::Cycle { period, theta } =
        attractor_cycle(params, settings(), &|| false).unwrap()
    else {
        panic!("fig3b at θν = 0.9 has a cycle for an attractor");
    };
    let cmd = Command::run(
        10,
        ContinuationSpec {
            params,
            settings: settings(),
            param: ContParam::ThetaNu,
            from: 0.9,
            to: 1.3,
            max_period: period,
            cycle: Some(GivenCycle { period, theta }),
            cascade: CascadeFrom::Branch,
            curves: Some(CurveFollow {
                kind: CurveKind::PeriodDoubling,
                param: ContParam::Kappa,
                range: [17.0, 21.0],
            }),
        },
    );
    let r = same_on_both_hosts(cmd.clone());
    for kind in ["Special", "Branch", "Curve"] {
        assert!(r.other.iter().any(|s| s.starts_with(kind)), "{kind}: {r:?}");
    }
    same_paused_and_on_the_command_line(cmd, &r);
}

#[test]
fn boundaries_are_the_same_on_every_host_and_paused() {
    let cmd = Command::run(
        9,
        BoundarySpec {
            params: preset("fig3b"),
            settings: settings(),
            theta_nu: (0.9, 1.3),
            kappa: (17.0, 21.0),
        },
    );
    let r = same_on_both_hosts(cmd.clone());
    assert!(r.other.iter().any(|s| s.starts_with("Curve")), "{r:?}");
    same_paused_and_on_the_command_line(cmd, &r);
}

#[test]
fn the_events_views_passage_and_scan_are_the_same_on_every_host_and_paused() {
    // The intermittent preset: an open creep channel at θ = 0.1, and a
    // tangency near θν located by continuation.
    let params = preset("intermittent");
    let settings = default_settings(1e-8);
    let passage = Spec::Passage(PassageSpec {
        params,
        settings,
        near: 0.1,
    });
    let r = same_on_both_hosts(Command::Run {
        generation: 9,
        spec: passage.clone(),
    });
    assert!(
        matches!(r.other.as_slice(), [p] if p.starts_with("Passage { generation: _, passage: Open(")),
        "{r:?}"
    );
    // Paused after every map evaluation, and resumed: the same passage,
    // in a step per evaluation (64 cells, then the entries).
    let (paused, steps) = local_paused(passage);
    assert_eq!(paused, r);
    assert!(steps > 64, "{steps} steps");
    let scan = Spec::Scan(ScanSpec { params, settings });
    let r = same_on_both_hosts(Command::Run {
        generation: 10,
        spec: scan.clone(),
    });
    assert!(
        matches!(r.other.as_slice(), [s] if s.starts_with("Scan { generation: _, scaling: Fitted {")),
        "{r:?}"
    );
    // Paused after every slip cycle and map evaluation (the continuation
    // of a window's cycle included): the same verdict.
    let (paused, steps) = local_paused(scan);
    assert_eq!(paused, r);
    assert!(steps > 8 * 2000, "{steps} steps");
}

#[test]
fn the_single_threaded_host_runs_within_its_budget_and_cancels() {
    let spec = Spec::Sweep(SweepSpec {
        params: preset("fig3b"),
        settings: default_settings(1e-6),
        param: ContParam::ThetaNu,
        axis: Axis::new(0.9, 1.5, 40),
        transient: 200,
        keep: 50,
        map: MapChoice::Auto,
        theta0: None,
        seeds: 0,
    });
    let mut host = Local::start(spec, 11, Shape::default());
    // A spent budget still moves the job on, by one slip cycle: the column
    // pauses there, and is resumed by the next call, until it is done.
    assert!(!host.run_for(std::time::Duration::ZERO, 1));
    assert_eq!(host.cycles(), 1);
    let mut calls = 1;
    let first = loop {
        let ups = host.drain();
        if ups.iter().any(|u| matches!(u, Update::Column { .. })) {
            break ups;
        }
        assert!(!host.run_for(std::time::Duration::ZERO, 1));
        calls += 1;
    };
    let columns = first
        .iter()
        .filter(|u| matches!(u, Update::Column { .. }))
        .count();
    assert_eq!(columns, 1, "one column at a time: {first:?}");
    assert!(calls > 10, "the first column came after {calls} calls");
    host.cancel();
    let last = host.drain();
    assert_eq!(
        last,
        vec![Update::Finished {
            generation: 11,
            lane: host.lane(),
            outcome: Outcome::Cancelled
        }]
    );
    assert!(host.is_done());
}

#[test]
fn a_spec_that_does_not_validate_fails_on_every_host_naming_its_parameter() {
    let mut params = preset("fig3b");
    params.kappa = -1.0;
    let spec = TrajectorySpec {
        params,
        settings: settings(),
        theta0: None,
        transient: 0,
        spacing: 0.05,
        cycles: Some(3),
        max_samples: None,
    };
    let single = local(Spec::Trajectory(spec.clone()));
    let many = threaded(Command::run(2, spec.clone()));
    assert_eq!(single, many);
    assert!(matches!(single.outcome, Some(Outcome::Failed(_))));
    assert!(
        single.other.iter().any(|s| s.contains("kappa")),
        "{single:?}"
    );
    assert!(run_collect(Spec::Trajectory(spec), 1, |_| {}, || false).is_err());
}
