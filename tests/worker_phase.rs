//! The worker's phase lane, headless: every cell once, coarse lattice first,
//! each cell equal to the core's `continue_cell` seeded by the planned
//! neighbour (and the coarse lattice to `phase_grid`), classes equal to the
//! core's rows on a robust grid, prompt cancellation with nothing stale
//! after it, bad input named, and `SetParams`. Assertions are on cells,
//! cycles and generations, never on wall-clock time (timeouts only guard
//! against hangs).

use crate::common;
use common::fixture::preset;
use common::{recv, until_ack, until_finished};
use oneblock::worker::Spec;
use std::collections::{HashMap, HashSet};
use std::f64::consts::FRAC_PI_2;
use std::sync::Arc;
use std::time::Duration;

use oneblock::integrate::SolverSettings;
use oneblock::model::Params;
use oneblock::sim::MapChoice;
use oneblock::sim::phase::{CellClass, PhaseCell, PhaseOptions, Seed, continue_cell, phase_grid};
use oneblock::sim::{default_settings, theta_nu_grid};
use oneblock::worker::PhaseTuning;
use oneblock::worker::{
    Axis, COARSE_STRIDE, Command, Generation, GridCell, Lane, Outcome, PhaseSpec, SweepSpec,
    TrajectorySpec, Update, Worker, WorkerConfig, phase_plan,
};

const THREADS: usize = 2;

fn spawn(update_capacity: usize) -> Worker {
    Worker::spawn(
        WorkerConfig {
            update_capacity,
            sweep_threads: THREADS,
            ..WorkerConfig::default()
        },
        Arc::new(|| {}),
    )
}

fn params(gamma: f64) -> Params {
    Params {
        gamma,
        ..preset("fig3b")
    }
}

/// A phase grid over θν ∈ [t.0, t.1] (t.2 columns) and κ ∈ [k.0, k.1] (k.2 rows).
struct Grid {
    params: Params,
    settings: SolverSettings,
    t: (f64, f64, usize),
    k: (f64, f64, usize),
    transient: usize,
    keep: usize,
}

impl Grid {
    fn small() -> Grid {
        Grid {
            params: params(6.5),
            settings: default_settings(1e-8),
            t: (0.8, 1.5, 9),
            k: (14.0, 20.0, 6),
            transient: 60,
            keep: 32,
        }
    }

    fn command(&self, generation: Generation) -> Command {
        Command::run(
            generation,
            PhaseSpec {
                params: self.params,
                settings: self.settings,
                theta_nu: Axis::new(self.t.0, self.t.1, self.t.2),
                kappa: Axis::new(self.k.0, self.k.1, self.k.2),
                transient: self.transient,
                keep: self.keep,
                tuning: PhaseTuning::default(),
            },
        )
    }

    fn opts(&self) -> PhaseOptions {
        PhaseOptions {
            transient: self.transient,
            keep: self.keep,
            ..PhaseOptions::for_settings(&self.settings)
        }
    }
}

/// The cells of `generation` in the order they arrived, with their batch's
/// coarse flag.
fn cells_of(ups: &[Update], generation: Generation) -> Vec<(GridCell, bool)> {
    ups.iter()
        .filter_map(|u| match u {
            Update::PhaseCells {
                generation: g,
                cells,
                coarse,
            } if *g == generation => Some(cells.iter().map(move |c| (c.clone(), *coarse))),
            _ => None,
        })
        .flatten()
        .collect()
}

/// The core's cell at (`kappa`, `theta_nu`) seeded by a finished
/// neighbour, exactly as the plan runs the cell after it
/// (`continue_cell`: its orbit from θ = θν, the neighbour's cycle solved
/// first, the shorter transient after a chaotic one).
fn core_cell(g: &Grid, kappa: f64, theta_nu: f64, neighbour: Option<&PhaseCell>) -> PhaseCell {
    let seed = neighbour.map(Seed::of);
    continue_cell(
        g.params,
        g.settings,
        kappa,
        theta_nu,
        seed,
        &g.opts(),
        &|| false,
    )
}

#[test]
fn a_phase_grid_streams_every_cell_once_coarse_first_equal_to_the_core() {
    let g = Grid::small();
    let w = spawn(256);
    assert!(w.send(g.command(5)));
    let (ups, outcome) = until_finished(&w, 5, Lane::Phase);
    assert_eq!(outcome, Outcome::Completed);
    assert!(ups.iter().all(|u| u.generation() == 5), "{ups:?}");
    let got = cells_of(&ups, 5);
    let (rows, cols) = (g.k.2, g.t.2);

    // Every cell exactly once.
    assert_eq!(got.len(), rows * cols);
    let seen: HashSet<(usize, usize)> = got.iter().map(|(c, _)| (c.row, c.column)).collect();
    assert_eq!(seen.len(), rows * cols);

    // The coarse lattice first, all of it, flagged as such.
    let plan = phase_plan(rows, cols, COARSE_STRIDE);
    let coarse: HashSet<(usize, usize)> = plan
        .iter()
        .filter(|p| p.coarse)
        .map(|p| (p.row, p.column))
        .collect();
    assert!(coarse.len() < rows * cols, "some refinement to test");
    let n = coarse.len();
    assert!(
        got[..n]
            .iter()
            .all(|(c, flag)| *flag && coarse.contains(&(c.row, c.column)))
    );
    assert!(got[n..].iter().all(|(_, flag)| !flag));

    // Progress ends at 1.
    let last_progress = ups.iter().rev().find_map(|u| match u {
        Update::Progress { fraction, .. } => Some(*fraction),
        _ => None,
    });
    assert_eq!(last_progress, Some(1.0));

    // Each cell equals the core's, continued from its planned neighbour.
    let kappas = theta_nu_grid(g.k.0, g.k.1, rows);
    let theta_nus = theta_nu_grid(g.t.0, g.t.1, cols);
    let by_place: HashMap<(usize, usize), PhaseCell> = got
        .iter()
        .map(|(c, _)| ((c.row, c.column), c.cell.clone()))
        .collect();
    let mut core: HashMap<(usize, usize), PhaseCell> = HashMap::new();
    let mut after_chaos = 0;
    for p in &plan {
        let neighbour = p.parent.map(|q| &core[&q]);
        after_chaos += usize::from(neighbour.is_some_and(|c| c.class == CellClass::Chaos));
        let cell = core_cell(&g, kappas[p.row], theta_nus[p.column], neighbour);
        assert!(cell.error.is_none(), "{:?}", cell.error);
        assert_eq!(by_place[&(p.row, p.column)], cell, "cell {p:?}");
        core.insert((p.row, p.column), cell);
    }
    let classes: HashSet<String> = core.values().map(|c| c.class.label()).collect();
    assert!(
        classes.len() >= 2,
        "a grid with more than one class: {classes:?}"
    );
    assert!(after_chaos > 0, "some cell continues from a chaotic one");

    // The coarse lattice is the core's own phase_grid on it.
    let mut crow: Vec<usize> = coarse.iter().map(|c| c.0).collect();
    let mut ccol: Vec<usize> = coarse.iter().map(|c| c.1).collect();
    crow.sort();
    crow.dedup();
    ccol.sort();
    ccol.dedup();
    let ck: Vec<f64> = crow.iter().map(|&r| kappas[r]).collect();
    let ct: Vec<f64> = ccol.iter().map(|&c| theta_nus[c]).collect();
    let grid = phase_grid(
        g.params,
        g.settings,
        &ck,
        &ct,
        &g.opts(),
        &|| false,
        &|_| {},
    )
    .expect("the core's grid");
    for (i, row) in grid.iter().enumerate() {
        for (j, cell) in row.iter().enumerate() {
            assert_eq!(&by_place[&(crow[i], ccol[j])], cell);
        }
    }
    w.shutdown();
}

#[test]
fn classes_equal_the_core_rows_at_kappa_one_point_two_and_ten() {
    // tests/phase.rs's rows: κ = 1.2 a fixed point everywhere, κ = 10
    // FP → P2 → FP; the worker's continuation order differs from a row's,
    // the attractors it finds do not.
    let g = Grid {
        params: params(6.5),
        settings: default_settings(1e-10),
        t: (0.0, FRAC_PI_2, 25),
        k: (1.2, 10.0, 2),
        transient: 300,
        keep: 96,
    };
    let w = spawn(256);
    assert!(w.send(g.command(1)));
    let (ups, outcome) = until_finished(&w, 1, Lane::Phase);
    assert_eq!(outcome, Outcome::Completed);
    let got = cells_of(&ups, 1);
    assert_eq!(got.len(), 50);
    let kappas = [1.2, 10.0];
    let theta_nus = theta_nu_grid(g.t.0, g.t.1, g.t.2);
    let rows = phase_grid(
        g.params,
        g.settings,
        &kappas,
        &theta_nus,
        &g.opts(),
        &|| false,
        &|_| {},
    )
    .expect("the core's grid");
    let mut p2 = 0;
    for (c, _) in &got {
        let want = &rows[c.row][c.column];
        assert_eq!(
            c.cell.class, want.class,
            "kappa {} theta-nu {}",
            want.kappa, want.theta_nu
        );
        assert_eq!(c.cell.kappa.to_bits(), want.kappa.to_bits());
        assert_eq!(c.cell.theta_nu.to_bits(), want.theta_nu.to_bits());
        if c.cell.class == CellClass::Periodic(2) {
            p2 += 1;
        }
    }
    assert!(p2 > 0, "the kappa = 10 row has its period-2 window");
    w.shutdown();
}

#[test]
fn cancelling_stops_a_grid_at_once_and_nothing_stale_follows() {
    let big = Grid {
        t: (0.0, FRAC_PI_2, 200),
        k: (1.0, 42.0, 200),
        transient: 400,
        keep: 128,
        ..Grid::small()
    };
    let w = spawn(8);
    let stats = w.stats();
    for round in 0..3u64 {
        let (job, cancel) = (10 * round + 1, 10 * round + 2);
        assert!(w.send(big.command(job)));
        // Let it run: wait for its first cells.
        loop {
            if matches!(recv(&w), Update::PhaseCells { generation, .. } if generation == job) {
                break;
            }
        }
        assert!(w.send(Command::Cancel {
            generation: cancel,
            lane: if round == 2 { None } else { Some(Lane::Phase) },
        }));
        let ups = until_ack(&w, cancel);
        assert!(
            ups.iter().any(|u| matches!(
                u,
                Update::Finished {
                    generation,
                    lane: Lane::Phase,
                    outcome: Outcome::Cancelled
                } if *generation == job
            )),
            "the job got its Finished{{Cancelled}} before the ack: {ups:?}"
        );
        let at_ack = stats.cycles();
        // Nothing more of the job arrives, and no more cycles start than one
        // per thread that had passed its check when the ack went out.
        std::thread::sleep(Duration::from_millis(300));
        let mut late = Vec::new();
        while let Some(u) = w.try_recv() {
            late.push(u);
        }
        assert!(late.is_empty(), "after the ack: {late:?}");
        assert!(
            stats.cycles() - at_ack <= THREADS as u64,
            "{} cycles started after the ack",
            stats.cycles() - at_ack
        );
    }

    // A newer grid supersedes the running one within the lane.
    let small = Grid::small();
    assert!(w.send(big.command(100)));
    loop {
        if matches!(
            recv(&w),
            Update::PhaseCells {
                generation: 100,
                ..
            }
        ) {
            break;
        }
    }
    assert!(w.send(small.command(101)));
    let (ups, outcome) = until_finished(&w, 101, Lane::Phase);
    assert_eq!(outcome, Outcome::Completed);
    let fin = ups
        .iter()
        .position(|u| {
            matches!(
                u,
                Update::Finished {
                    generation: 100,
                    outcome: Outcome::Cancelled,
                    ..
                }
            )
        })
        .expect("the old grid was cancelled");
    assert!(
        ups[fin + 1..].iter().all(|u| u.generation() == 101),
        "nothing of the old grid after its Finished"
    );
    assert_eq!(cells_of(&ups, 101).len(), 54);
    w.shutdown();
}

#[test]
fn a_phase_grid_leaves_the_sweep_and_the_trajectory_running() {
    let w = spawn(256);
    assert!(w.send(Command::run(
        1,
        SweepSpec {
            params: params(6.5),
            settings: default_settings(1e-8),
            param: oneblock::sim::continuation::ContParam::ThetaNu,
            axis: Axis::new(0.5, 1.4, 12),
            transient: 20,
            keep: 10,
            map: MapChoice::Auto,
            theta0: None,
            seeds: 0,
        }
    )));
    assert!(w.send(Command::run(
        2,
        TrajectorySpec {
            params: params(6.5),
            settings: default_settings(1e-8),
            theta0: None,
            transient: 0,
            spacing: 0.05,
            cycles: Some(5),
            max_samples: None,
        }
    )));
    assert!(w.send(Grid::small().command(3)));
    let mut outcomes = HashMap::new();
    while outcomes.len() < 3 {
        if let Update::Finished {
            generation,
            lane,
            outcome,
        } = recv(&w)
        {
            outcomes.insert(generation, (lane, outcome));
        }
    }
    assert_eq!(outcomes[&1], (Lane::Sweep, Outcome::Completed));
    assert_eq!(outcomes[&2], (Lane::Orbit, Outcome::Completed));
    assert_eq!(outcomes[&3], (Lane::Phase, Outcome::Completed));
    w.shutdown();
}

#[test]
fn bad_phase_input_is_named_and_the_next_grid_runs() {
    let w = spawn(64);
    let g = Grid::small();
    type Case = (&'static str, Box<dyn Fn(&mut PhaseSpec)>);
    let cases: Vec<Case> = vec![
        ("theta-nu-from", Box::new(|s| s.theta_nu.from = f64::NAN)),
        ("theta-nu-to", Box::new(|s| s.theta_nu.to = f64::INFINITY)),
        ("kappa-from", Box::new(|s| s.kappa.from = 0.0)),
        ("kappa-from", Box::new(|s| s.kappa.from = -3.0)),
        ("kappa-to", Box::new(|s| s.kappa.to = f64::NAN)),
        ("kappa-to", Box::new(|s| s.kappa.to = 2e6)),
        ("theta-nu-steps", Box::new(|s| s.theta_nu.steps = 0)),
        ("kappa-steps", Box::new(|s| s.kappa.steps = 0)),
        (
            "kappa-steps",
            Box::new(|s| (s.kappa.steps, s.theta_nu.steps) = (5000, 5000)),
        ),
        ("keep", Box::new(|s| s.keep = 3)),
        ("gamma", Box::new(|s| s.params.gamma = f64::NAN)),
        ("tol", Box::new(|s| s.settings.rtol = 1.0)),
    ];
    let mut generation = 0;
    for (name, f) in &cases {
        generation += 1;
        let mut cmd = g.command(generation);
        if let Command::Run {
            spec: Spec::Phase(spec),
            ..
        } = &mut cmd
        {
            f(spec);
        }
        assert!(w.send(cmd));
        let (ups, outcome) = until_finished(&w, generation, Lane::Phase);
        assert!(matches!(outcome, Outcome::Failed(_)), "{name}: {outcome:?}");
        let errors: Vec<(&str, Option<&str>)> = ups
            .iter()
            .filter_map(|u| match u {
                Update::Error {
                    message, parameter, ..
                } => Some((message.as_str(), *parameter)),
                _ => None,
            })
            .collect();
        assert_eq!(errors.len(), 1, "{name}: {ups:?}");
        let (message, parameter) = errors[0];
        assert_eq!(parameter, Some(*name), "{message}");
        assert!(
            message.starts_with(name) && !message.contains('\n'),
            "{message}"
        );
        assert!(
            message.contains("must"),
            "the valid range is given: {message}"
        );
        assert!(
            cells_of(&ups, generation).is_empty(),
            "no work before the check"
        );
    }
    generation += 1;
    assert!(w.send(g.command(generation)));
    let (_, outcome) = until_finished(&w, generation, Lane::Phase);
    assert_eq!(outcome, Outcome::Completed);
    w.shutdown();
}

#[test]
fn set_params_reruns_the_grid_over_its_ranges_only_when_gamma_nu_omega_or_solver_change() {
    let w = spawn(256);
    let g = Grid {
        t: (0.9, 1.3, 5),
        k: (15.0, 17.0, 3),
        ..Grid::small()
    };
    assert!(w.send(g.command(1)));
    let (_, outcome) = until_finished(&w, 1, Lane::Phase);
    assert_eq!(outcome, Outcome::Completed);

    // New γ (and a κ, θν that must not matter): the same ranges, new cells,
    // equal to a grid sent directly with that γ.
    let new = Params {
        kappa: 99.0,
        theta_nu: 0.1,
        ..params(6.0)
    };
    assert!(w.send(Command::SetParams {
        generation: 2,
        params: new,
        // None: each job keeps its own solver settings.
        settings: None,
    }));
    let (ups, outcome) = until_finished(&w, 2, Lane::Phase);
    assert_eq!(outcome, Outcome::Completed);
    let mut rerun: Vec<GridCell> = cells_of(&ups, 2).into_iter().map(|c| c.0).collect();
    assert_eq!(rerun.len(), 15);
    let direct = Grid {
        params: params(6.0),
        ..g
    };
    assert!(w.send(direct.command(3)));
    let (ups, _) = until_finished(&w, 3, Lane::Phase);
    let mut want: Vec<GridCell> = cells_of(&ups, 3).into_iter().map(|c| c.0).collect();
    rerun.sort_by_key(|c| (c.row, c.column));
    want.sort_by_key(|c| (c.row, c.column));
    assert_eq!(rerun, want);

    // Only κ and θν change: the grid does not run again.
    assert!(w.send(Command::SetParams {
        generation: 4,
        params: Params {
            kappa: 3.0,
            theta_nu: 0.7,
            ..params(6.0)
        },
        settings: Some(g.settings),
    }));
    assert!(w.send(Command::Cancel {
        generation: 5,
        lane: Some(Lane::Phase),
    }));
    let ups = until_ack(&w, 5);
    assert!(ups.iter().all(|u| u.generation() != 4), "{ups:?}");

    // After a cancellation, a new γ does not bring the grid back.
    assert!(w.send(Command::SetParams {
        generation: 6,
        params: params(5.5),
        settings: Some(g.settings),
    }));
    assert!(w.send(Command::Cancel {
        generation: 7,
        lane: Some(Lane::Phase),
    }));
    let ups = until_ack(&w, 7);
    assert!(ups.iter().all(|u| u.generation() != 6), "{ups:?}");
    w.shutdown();
}
