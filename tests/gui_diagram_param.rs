//! The bifurcation diagram and "Find bifurcations" in a parameter other
//! than θν (issue 42, "any parameter in the window"), through the path a
//! user takes: κ picked in the view's selector, the sweep and the
//! continuation run by the real worker, and the same computed by the
//! `oneblock` binary.
//!
//! - At Fig. 3b's θν = 1.25 the diagram over κ ∈ [2, 5] (a log axis: its
//!   columns evenly spaced in log10 κ) has, column by column, the points
//!   of `oneblock bifurcation` run on that one κ alone (a single-column
//!   run, from θ = θν), to 1e-9; and every point of
//!   `bifurcation --param kappa` over the same range, bit for bit.
//! - Find bifurcations over it locates the folds and the doubling that
//!   `oneblock continue --param kappa` does, to 1e-7.
//! - Boundaries draws the fixed point's fold curve (κ = 2.5, where it
//!   folds twice along θν) beside its doubling curve, with its legend.
//! - Find bifurcations over Fig. 3b's cascade (θν ∈ [1.0, 1.3]) shows the
//!   table of its doublings and the ratios δₙ of their gaps that
//!   `oneblock continue --cascade` prints.
#![cfg(feature = "gui")]

use crate::cli_support;
use crate::window;

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

use oneblock::app::bifurcation::Zoom;
use oneblock::app::diagram_axis::{SELECTOR, title};
use oneblock::app::jobs::JobState;
use oneblock::app::overlay::curve_style;
use oneblock::app::points_table::{FEIGENBAUM_DELTA, cascade_rows};
use oneblock::app::settings::PhaseRange;
use oneblock::app::{Explorer, Layout, Recorder, Settings, ViewKind, preset};
use oneblock::integrate::SolverSettings;
use oneblock::sim::continuation::{ContParam, CurveKind, SpecialKind};
use oneblock::sim::param_grid;
use oneblock::worker::{Command, ContinuationSpec, Lane, Spec, SweepSpec};

use cli_support::{assert_ok, num, oneblock, parse_csv, stdout};

/// κ's range of the test: the fixed point's two folds (2.37, 2.80) and
/// its doubling (2.99) at θν = 1.25, then the 2-cycle.
const KAPPA: (f64, f64) = (2.0, 5.0);
const COLUMNS: usize = 21;
const TRANSIENT: usize = 300;
const KEEP: usize = 20;

/// Fig. 3b at θν = 1.25 in the bifurcation tab, the diagram still in θν
/// (κ's range already set: the selector is what the test uses).
fn settings() -> Settings {
    let mut s = Settings {
        layout: Layout::Tabs,
        tab: ViewKind::Bifurcation,
        columns: COLUMNS,
        sweep_transient: TRANSIENT,
        sweep_keep: KEEP,
        ..Settings::default()
    };
    s.params = preset("fig3b").expect("preset").params;
    s.params.theta_nu = 1.25;
    s.diagram.kappa = KAPPA;
    s
}

/// The window of [`settings`], its diagram, Find bifurcations and
/// Boundaries on the real worker.
fn harness(rec: &Recorder) -> Harness<'static, Explorer> {
    window::harness_on_lanes(
        rec,
        settings(),
        &[Lane::Sweep, Lane::Continuation, Lane::Curves],
    )
}

/// Picks `p` in the view's selector, as a user does: opens it, clicks
/// the parameter's entry.
fn pick(h: &mut Harness<'static, Explorer>, p: ContParam) {
    h.get_by_label(SELECTOR).click();
    h.run_steps(2);
    h.get_by_label(title(p)).click();
    h.run_steps(2);
}

/// Steps the window until `done` (at most ~120 s).
fn until(h: &mut Harness<'static, Explorer>, what: &str, done: impl Fn(&Explorer) -> bool) {
    for _ in 0..6000 {
        h.step();
        if done(h.state()) {
            h.run_steps(2);
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    panic!("{what} did not end");
}

/// The latest sweep the window sent.
fn last_sweep(rec: &Recorder) -> SweepSpec {
    rec.commands()
        .into_iter()
        .rev()
        .find_map(|c| match c {
            Command::Run {
                spec: Spec::Sweep(spec),
                ..
            } => Some(spec),
            _ => None,
        })
        .expect("a sweep was sent")
}

/// The "Find bifurcations" job the window sent.
fn branches_spec(rec: &Recorder) -> ContinuationSpec {
    rec.commands()
        .into_iter()
        .find_map(|c| match c {
            Command::Run {
                spec: Spec::Branches(spec),
                ..
            } => Some(spec),
            _ => None,
        })
        .expect("the job was sent")
}

/// The solver flags of `s` (the window's Auto setting for its job).
fn solver_flags(s: &SolverSettings) -> Vec<String> {
    assert!(s.method.is_adaptive(), "{s:?}");
    vec![
        "--method".into(),
        s.method.to_string(),
        "--tol".into(),
        format!("{:e}", s.rtol),
    ]
}

/// `oneblock bifurcation` with the test's model, budget and solver; the
/// CSV's rows as (first column, θ).
fn bifurcation(solver: &[String], more: &[&str]) -> (String, Vec<(f64, f64)>) {
    let (t, k) = (TRANSIENT.to_string(), KEEP.to_string());
    let mut args: Vec<&str> = vec![
        "bifurcation",
        "--preset",
        "fig3b",
        "--theta-nu",
        "1.25",
        "--transient",
        &t,
        "--keep",
        &k,
        "--out",
        "-",
    ];
    args.extend(solver.iter().map(String::as_str));
    args.extend(more);
    let o = oneblock(&args);
    assert_ok(&o);
    let (header, rows) = parse_csv(&stdout(&o));
    let rows = rows.iter().map(|r| (num(&r[0]), num(&r[1]))).collect();
    (header[0].clone(), rows)
}

#[test]
fn a_diagram_in_kappa_picked_in_the_selector_is_the_command_lines() {
    let rec = Recorder::new();
    let mut h = harness(&rec);
    h.run_steps(2);
    pick(&mut h, ContParam::Kappa);
    assert_eq!(h.state().settings.diagram.param, ContParam::Kappa);
    // The sweep restarts over κ once the change has settled (250 ms).
    until(&mut h, "the diagram in κ", |app| {
        let sweep = &app.jobs.sweep;
        sweep.data.param == ContParam::Kappa
            && sweep.state == JobState::Done
            && sweep.data.filled == COLUMNS
    });
    let spec = last_sweep(&rec);
    assert_eq!(spec.param, ContParam::Kappa);
    assert_eq!(
        (spec.axis.from, spec.axis.to, spec.axis.steps),
        (2.0, 5.0, COLUMNS)
    );
    assert_eq!(spec.params.theta_nu, 1.25);
    let data = h.state().jobs.sweep.data.clone();
    let grid = param_grid(ContParam::Kappa, KAPPA.0, KAPPA.1, COLUMNS);
    // Evenly spaced in log10 κ: the middle column at √(2·5).
    assert!((grid[COLUMNS / 2] - 10f64.sqrt()).abs() < 1e-12);
    // The diagram is drawn, on a log axis: its frame spans log10 κ.
    let (x0, x1, ..) = h.state().views.bifurcation.bounds(&data);
    assert!(
        x0 < 2f64.log10() && x1 > 5f64.log10() && x1 < 0.75,
        "{x0}..{x1}"
    );

    let solver = solver_flags(&spec.settings);
    let window: Vec<(f64, Vec<f64>)> = data
        .columns
        .iter()
        .map(|c| {
            let c = c.as_ref().expect("every column");
            (c.value, c.thetas.clone())
        })
        .collect();
    for (i, (k, thetas)) in window.iter().enumerate() {
        assert_eq!(*k, grid[i], "column {i}");
        assert_eq!(thetas.len(), KEEP, "column {i}");
    }

    // Each column against `bifurcation` run on its κ alone (from θ = θν,
    // not from a neighbour): the same attractor, its points to 1e-9.
    let mut worst = 0.0f64;
    for (k, thetas) in &window {
        let kappa = format!("{k}");
        let (_, rows) = bifurcation(
            &solver,
            &[
                "--kappa",
                &kappa,
                "--theta-nu-from",
                "1.25",
                "--theta-nu-to",
                "1.25",
                "--columns",
                "1",
            ],
        );
        let mut a = thetas.clone();
        let mut b: Vec<f64> = rows.iter().map(|r| r.1).collect();
        a.sort_by(f64::total_cmp);
        b.sort_by(f64::total_cmp);
        assert_eq!(a.len(), b.len(), "κ = {k}");
        for (x, y) in a.iter().zip(&b) {
            worst = worst.max((x - y).abs());
        }
    }
    eprintln!("diagram in κ against single-column runs: largest difference {worst:e}");
    assert!(worst < 1e-9, "largest difference {worst:e}");
    let periods: Vec<usize> = window
        .iter()
        .map(|(_, t)| {
            let mut u = t.clone();
            u.sort_by(f64::total_cmp);
            u.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
            u.len()
        })
        .collect();
    assert_eq!(periods.first(), Some(&1), "{periods:?}");
    assert_eq!(
        periods.last(),
        Some(&2),
        "the doubling within the range: {periods:?}"
    );

    // The whole diagram against `bifurcation --param kappa`: one code path.
    let columns = COLUMNS.to_string();
    let (name, rows) = bifurcation(
        &solver,
        &[
            "--param",
            "kappa",
            "--from",
            "2",
            "--to",
            "5",
            "--columns",
            &columns,
        ],
    );
    assert_eq!(name, "kappa");
    let flat: Vec<(f64, f64)> = window
        .iter()
        .flat_map(|(k, t)| t.iter().map(move |&th| (*k, th)))
        .collect();
    assert_eq!(rows, flat, "bit for bit");
}

#[test]
fn find_bifurcations_in_kappa_locates_what_continue_does() {
    let rec = Recorder::new();
    let mut h = harness(&rec);
    h.run_steps(2);
    pick(&mut h, ContParam::Kappa);
    h.run_steps(2);
    h.get_by_label("Find bifurcations").click();
    h.step();
    let spec = branches_spec(&rec);
    assert_eq!(spec.param, ContParam::Kappa);
    assert_eq!((spec.from, spec.to), KAPPA);
    until(&mut h, "Find bifurcations", |app| {
        app.jobs.branches_settled()
    });
    let data = h.state().jobs.branches.data.clone();
    assert_eq!(data.param, Some(ContParam::Kappa));
    let p1 = data.branches.iter().find(|b| b.period == 1).expect("P1");
    assert_eq!(p1.param, ContParam::Kappa);

    let solver = solver_flags(&spec.settings);
    let dir = tempfile::tempdir().expect("tempdir");
    let (out, points) = (dir.path().join("b.csv"), dir.path().join("p.csv"));
    let mut args: Vec<String> = [
        "continue",
        "--preset",
        "fig3b",
        "--theta-nu",
        "1.25",
        "--param",
        "kappa",
        "--from",
        "2",
        "--to",
        "5",
        "--period",
        "1",
    ]
    .map(String::from)
    .to_vec();
    args.extend(solver);
    args.extend([
        "--out".into(),
        out.display().to_string(),
        "--points".into(),
        points.display().to_string(),
    ]);
    let o = cli_support::run(&args);
    assert_ok(&o);
    let text = std::fs::read_to_string(&points).expect("points");
    let (_, rows) = parse_csv(&text);
    let located: Vec<(String, f64)> = rows
        .iter()
        .filter(|r| r[0] == "PD" || r[0] == "fold")
        .map(|r| (r[0].clone(), num(&r[3])))
        .collect();
    assert_eq!(located.len(), 3, "two folds and a doubling: {located:?}");
    for (kind, value) in &located {
        let kind = match kind.as_str() {
            "PD" => SpecialKind::PeriodDoubling,
            _ => SpecialKind::Fold,
        };
        let near = p1
            .of_kind(kind)
            .map(|s| (s.lambda - value).abs())
            .fold(f64::INFINITY, f64::min);
        eprintln!("{kind:?} at κ = {value}: the window's is {near:e} away");
        assert!(
            near < 1e-7,
            "{kind:?} at κ = {value}: the window's is {near:e} away"
        );
    }
    // Drawn over the diagram: the legend names what is marked.
    for name in ["PD", "fold"] {
        assert!(h.query_by_label(name).is_some(), "legend {name}");
    }
}

#[test]
fn the_cascade_table_shows_the_ratios_of_continue_cascade() {
    let rec = Recorder::new();
    let mut h = harness(&rec);
    h.state_mut().views.bifurcation.zoom.push(Zoom {
        theta_nu: (1.0, 1.3),
        theta: (0.0, 1.6),
    });
    h.run_steps(2);
    h.get_by_label("Find bifurcations").click();
    h.step();
    until(&mut h, "Find bifurcations", |app| {
        app.jobs.branches_settled()
    });
    let data = h.state().jobs.branches.data.clone();
    let rows = cascade_rows(&data);
    assert!(rows.len() >= 5, "{rows:?}");
    h.get_by_label_contains("Cascade δ").click();
    h.run_steps(2);

    let solver = solver_flags(&branches_spec(&rec).settings);
    let dir = tempfile::tempdir().expect("tempdir");
    let mut args: Vec<String> = [
        "continue",
        "--preset",
        "fig3b",
        "--param",
        "theta-nu",
        "--from",
        "1.0",
        "--to",
        "1.3",
        "--period",
        "1",
        "--cascade",
    ]
    .map(String::from)
    .to_vec();
    args.extend(solver);
    args.extend([
        "--out".into(),
        dir.path().join("c.csv").display().to_string(),
    ]);
    let o = cli_support::run(&args);
    assert_ok(&o);
    // The CLI's table: "  n   period  theta-nu   gap   delta_n".
    let err = cli_support::stderr(&o);
    let table: Vec<Vec<&str>> = err
        .lines()
        .skip_while(|l| !l.starts_with("cascade:"))
        .skip(2)
        .take_while(|l| l.starts_with("  ") && !l.contains("Feigenbaum"))
        .map(|l| l.split_whitespace().collect())
        .collect();
    assert!(table.len() >= rows.len(), "{err}");
    for (mine, theirs) in rows.iter().zip(&table) {
        let (a, b) = (num(&mine[2]), num(theirs[2]));
        assert!((a - b).abs() < 1e-7, "b_{} = {a} against {b}", mine[0]);
        assert_eq!(mine[1], format!("P{}", theirs[1]));
        if !mine[4].is_empty() {
            assert_eq!(mine[4], theirs[4], "δ of row {}", mine[0]);
            assert!(
                h.query_by_label(&mine[4]).is_some(),
                "the table shows {}",
                mine[4]
            );
        }
    }
    let last = num(&rows[rows.len() - 1][4]);
    assert!((last - FEIGENBAUM_DELTA).abs() < 0.05, "{last}");
}

#[test]
fn boundaries_draw_the_fold_curve_with_its_legend() {
    let rec = Recorder::new();
    let mut h = harness(&rec);
    {
        let s = &mut h.state_mut().settings;
        s.tab = ViewKind::Phase;
        s.params.kappa = 2.5;
        s.params.theta_nu = 1.1;
        s.phase.range = PhaseRange {
            theta_nu: (1.1, 1.5),
            kappa: (2.0, 4.0),
        };
    }
    h.run_steps(2);
    // Each curve has its own legend entry: the fixed point's fold and its
    // doubling to P2.
    let fold = curve_style(CurveKind::Fold, 1).name;
    let doubling = curve_style(CurveKind::PeriodDoubling, 1).name;
    assert_eq!(
        (fold.as_str(), doubling.as_str()),
        ("fold of FP", "FP to P2")
    );
    assert!(h.query_by_label(&fold).is_none());
    h.get_by_label("Boundaries").click();
    h.step();
    until(&mut h, "Boundaries", |app| {
        let c = &app.jobs.curves;
        c.issued() && c.state != JobState::Running
    });
    let curves = &h.state().jobs.curves.data.curves;
    let kinds: Vec<CurveKind> = curves.iter().map(|c| c.kind).collect();
    assert!(kinds.contains(&CurveKind::Fold), "{kinds:?}");
    assert!(kinds.contains(&CurveKind::PeriodDoubling), "{kinds:?}");
    for c in curves.iter().filter(|c| c.kind == CurveKind::Fold) {
        assert!(c.points.iter().all(|q| (q.multiplier - 1.0).abs() < 1e-4));
    }
    assert!(h.query_by_label(&fold).is_some(), "the legend names it");
    assert!(h.query_by_label(&doubling).is_some());
}
