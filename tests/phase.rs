//! The phase diagram (θν, κ) against the paper's description of its Fig. 4
//! (γ = 6.5, ν = 1e-3, reduced transients), its determinism across thread
//! counts, and the `oneblock phase` command's handling of bad input and
//! Ctrl+C.

use crate::common;
use common::fixture::preset;

use std::f64::consts::FRAC_PI_2;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::Duration;

use oneblock::Params;
use oneblock::sim::default_settings;
use oneblock::sim::phase::{CellClass, PhaseCell, PhaseOptions, phase_row};
use oneblock::sim::theta_nu_grid;

fn opts() -> PhaseOptions {
    PhaseOptions {
        transient: 300,
        keep: 96,
        ..PhaseOptions::for_settings(&default_settings(1e-10))
    }
}

/// One κ row over `n` values of θν in [from, to].
fn row(kappa: f64, from: f64, to: f64, n: usize) -> Vec<PhaseCell> {
    let params = Params {
        kappa,
        theta_nu: from,
        ..preset("fig4")
    };
    let cells = phase_row(
        params,
        default_settings(1e-10),
        &theta_nu_grid(from, to, n),
        &opts(),
        &|| false,
        &|_| {},
    );
    for c in &cells {
        assert!(
            c.error.is_none(),
            "kappa {kappa} theta-nu {}: {:?}",
            c.theta_nu,
            c.error
        );
    }
    cells
}

fn labels(cells: &[PhaseCell]) -> String {
    cells
        .iter()
        .map(|c| format!("{:.3}:{}", c.theta_nu, c.class.label()))
        .collect::<Vec<_>>()
        .join(" ")
}

#[test]
fn kappa_near_one_is_a_fixed_point_everywhere() {
    let cells = row(1.2, 0.0, FRAC_PI_2, 13);
    assert!(
        cells.iter().all(|c| c.class == CellClass::Periodic(1)),
        "{}",
        labels(&cells)
    );
    // A stable fixed point: its multiplier is below 1 in modulus.
    assert!(cells.iter().all(|c| c.lyapunov.is_some_and(|l| l < 0.0)));
    // γ = 6.5 with κ < 42.25 is pure stick-slip.
    assert!(
        cells
            .iter()
            .all(|c| c.regime.map(|r| r.name()) == Some("stick-slip"))
    );
}

#[test]
fn kappa_ten_goes_fixed_point_period_two_fixed_point() {
    let cells = row(10.0, 0.0, FRAC_PI_2, 25);
    let s = labels(&cells);
    let first_p2 = cells
        .iter()
        .position(|c| c.class == CellClass::Periodic(2))
        .unwrap_or_else(|| panic!("no period 2: {s}"));
    let last_p2 = cells
        .iter()
        .rposition(|c| c.class == CellClass::Periodic(2))
        .unwrap_or(0);
    assert!(first_p2 > 0, "{s}");
    assert!(
        cells[..first_p2]
            .iter()
            .all(|c| c.class == CellClass::Periodic(1)),
        "{s}"
    );
    assert!(last_p2 + 1 < cells.len(), "{s}");
    assert!(
        cells[last_p2 + 1..]
            .iter()
            .all(|c| c.class == CellClass::Periodic(1)),
        "{s}"
    );
    // Nothing beyond period 2 at κ = 10.
    assert!(
        cells
            .iter()
            .all(|c| matches!(c.class, CellClass::Periodic(1 | 2))),
        "{s}"
    );
}

/// Just past the first flip at κ = 10 (θν = 0.8702) the attractor is a
/// period-2 cycle of small amplitude with multiplier ≈ 0.997: an orbit
/// leaves the unstable fixed point too slowly to settle within the budget
/// (this cell was undecided alone and chaotic, from λ = +3e-4, inside a
/// row). It is decided as the P2, checked against Newton's cycle solved
/// separately.
#[test]
fn cells_just_past_a_flip_are_the_small_period_two_cycle() {
    let params = Params {
        kappa: 10.0,
        theta_nu: 0.8704,
        ..preset("fig4")
    };
    let settings = default_settings(1e-10);
    let alone = oneblock::sim::phase::phase_cell(params, settings, 0.8704, &opts(), &|| false);
    let cells = row(10.0, 0.866, 0.88, 8);
    let s = labels(&cells);
    for c in cells.iter().filter(|c| c.theta_nu > 0.8703).chain([&alone]) {
        assert_eq!(c.class, CellClass::Periodic(2), "{s} / {alone:?}");
        let sim =
            oneblock::sim::Simulator::new(params.with_theta_nu(c.theta_nu), settings).unwrap();
        let cycle = oneblock::sim::solve_cycle(
            &sim,
            c.theta_last,
            2,
            &oneblock::sim::CycleOptions::for_settings(&settings),
        )
        .unwrap();
        assert_eq!(cycle.minimal_period, 2, "{cycle:?}");
        assert!(
            cycle.multiplier > 0.0 && cycle.multiplier < 1.0,
            "{cycle:?}"
        );
        let expected = cycle.multiplier.ln() / 2.0;
        assert!(
            (c.lyapunov.unwrap() - expected).abs() < 1e-6,
            "{c:?} {cycle:?}"
        );
        assert!(c.lyapunov_stderr.is_none(), "{c:?}");
    }
    assert!(
        cells
            .iter()
            .all(|c| matches!(c.class, CellClass::Periodic(1 | 2))),
        "{s}"
    );
}

#[test]
fn kappa_sixteen_cascades_to_chaos_and_back() {
    let cells = row(16.0, 1.0, FRAC_PI_2, 25);
    let s = labels(&cells);
    let chaos: Vec<&PhaseCell> = cells
        .iter()
        .filter(|c| c.class == CellClass::Chaos)
        .collect();
    assert!(!chaos.is_empty(), "{s}");
    for c in &chaos {
        let (l, se) = (
            c.lyapunov.unwrap_or(f64::NAN),
            c.lyapunov_stderr.unwrap_or(f64::NAN),
        );
        assert!(
            l - 3.0 * se > 0.0,
            "chaos without a positive exponent: {l} ± {se}"
        );
    }
    // A periodic class is an attracting cycle: its exponent is negative.
    for c in cells.iter().filter(|c| c.class.period() > 0) {
        assert!(c.lyapunov.is_some_and(|l| l < 0.0), "{:?}", c);
    }
    let last_chaos = cells
        .iter()
        .rposition(|c| c.class == CellClass::Chaos)
        .unwrap_or(0);
    // Back to period 2 and then the fixed point before π/2.
    let after = &cells[last_chaos + 1..];
    assert!(
        after.iter().any(|c| c.class == CellClass::Periodic(2)),
        "{s}"
    );
    assert_eq!(
        cells.last().map(|c| c.class),
        Some(CellClass::Periodic(1)),
        "{s}"
    );
    // The cascade on the way in: a period 4 before the first chaos.
    let first_chaos = cells
        .iter()
        .position(|c| c.class == CellClass::Chaos)
        .unwrap_or(0);
    assert!(
        cells[..first_chaos]
            .iter()
            .any(|c| c.class == CellClass::Periodic(4)),
        "{s}"
    );
}

#[test]
fn kappa_18_95_matches_the_fig_3b_sweep() {
    // The bifurcation sweep of Fig. 3b found FP up to θν ≈ 1.05, P2 at
    // 1.1–1.15, P4 at 1.2, chaos at 1.25, P3 at 1.3 and 1.45, P6 at 1.35–1.4.
    let cells = row(18.95, 1.0, 1.45, 10);
    let got: Vec<String> = cells.iter().map(|c| c.class.label()).collect();
    let want = [
        "FP", "FP", "P2", "P2", "P4", "chaos", "P3", "P6", "P6", "P3",
    ];
    assert_eq!(got, want, "{}", labels(&cells));
}

/// Indices of periodic cells with period ≥ 3 lying between two chaotic cells.
fn windows_in_chaos(cells: &[PhaseCell]) -> Vec<usize> {
    let first = cells.iter().position(|c| c.class == CellClass::Chaos);
    let last = cells.iter().rposition(|c| c.class == CellClass::Chaos);
    match (first, last) {
        (Some(a), Some(b)) => (a + 1..b)
            .filter(|&i| cells[i].class.period() >= 3)
            .collect(),
        _ => vec![],
    }
}

#[test]
fn kappa_nineteen_has_a_period_three_window_between_chaotic_bands() {
    let cells = row(19.0, 1.1, 1.5, 21);
    let s = labels(&cells);
    let w = windows_in_chaos(&cells);
    assert!(
        w.iter().any(|&i| cells[i].class == CellClass::Periodic(3)),
        "{s}"
    );
}

#[test]
fn larger_kappa_has_windows_of_several_periods_inside_chaos() {
    let mut periods = std::collections::BTreeSet::new();
    let mut all = String::new();
    for kappa in [25.0, 30.0, 36.0] {
        let cells = row(kappa, 1.2, 1.55, 29);
        for i in windows_in_chaos(&cells) {
            periods.insert(cells[i].class.period());
        }
        all += &format!("\nkappa {kappa}: {}", labels(&cells));
    }
    let small: Vec<&usize> = periods.iter().filter(|&&p| (3..=6).contains(&p)).collect();
    assert!(small.len() >= 2, "periods {periods:?}{all}");
}

#[test]
fn fixed_point_for_every_kappa_at_small_theta_nu() {
    for kappa in [1.0, 6.0, 11.0, 16.0, 21.0, 26.0, 31.0, 36.0, 42.0] {
        let cells = row(kappa, 0.0, 0.3, 4);
        assert!(
            cells.iter().all(|c| c.class == CellClass::Periodic(1)),
            "kappa {kappa}: {}",
            labels(&cells)
        );
        // The early exit: a fixed point costs tens of iterates, not 400.
        assert!(
            cells.iter().all(|c| c.iterates < 200),
            "kappa {kappa}: {:?}",
            cells.iter().map(|c| c.iterates).collect::<Vec<_>>()
        );
    }
}

#[test]
fn brute_force_agrees_on_a_clear_row() {
    // κ = 10, away from the two bifurcations: the same classes with and
    // without the early exit, for a fraction of the iterates.
    let params = Params {
        kappa: 10.0,
        theta_nu: 0.0,
        ..preset("fig4")
    };
    let grid = [0.3, 0.6, 1.1, 1.2, 1.5];
    let fast = phase_row(
        params,
        default_settings(1e-10),
        &grid,
        &opts(),
        &|| false,
        &|_| {},
    );
    let brute_opts = PhaseOptions {
        early_exit: false,
        ..opts()
    };
    let brute = phase_row(
        params,
        default_settings(1e-10),
        &grid,
        &brute_opts,
        &|| false,
        &|_| {},
    );
    for (f, b) in fast.iter().zip(&brute) {
        assert_eq!(f.class, b.class, "theta-nu {}", f.theta_nu);
    }
    let it = |r: &[PhaseCell]| r.iter().map(|c| c.iterates).sum::<u64>();
    assert!(
        it(&fast) * 3 < it(&brute),
        "{} vs {}",
        it(&fast),
        it(&brute)
    );
}

fn oneblock(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args(args)
        .output()
        .expect("the oneblock binary runs")
}

const GRID: [&str; 14] = [
    "phase",
    "--gamma",
    "6.5",
    "--nu",
    "1e-3",
    "--kappa-from",
    "14",
    "--kappa-to",
    "20",
    "--kappa-steps",
    "3",
    "--theta-nu-from",
    "1.2",
    "--transient",
];

fn grid_args<'a>(out: &'a str, threads: &'a str) -> Vec<&'a str> {
    let mut v = GRID.to_vec();
    v.extend([
        "200",
        "--keep",
        "64",
        "--theta-nu-to",
        "1.5",
        "--theta-nu-steps",
        "5",
        "--threads",
        threads,
        "--out",
        out,
    ]);
    v
}

#[test]
fn same_csv_on_one_and_two_threads_and_a_png() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let a = dir.path().join("one.csv");
    let b = dir.path().join("two.csv");
    let png = dir.path().join("two.png");
    let (a_s, b_s, png_s) = (
        a.to_string_lossy().to_string(),
        b.to_string_lossy().to_string(),
        png.to_string_lossy().to_string(),
    );
    let o1 = oneblock(&grid_args(&a_s, "1"));
    assert!(
        o1.status.success(),
        "{}",
        String::from_utf8_lossy(&o1.stderr)
    );
    let mut args2 = grid_args(&b_s, "2");
    args2.extend(["--png", &png_s]);
    let o2 = oneblock(&args2);
    assert!(
        o2.status.success(),
        "{}",
        String::from_utf8_lossy(&o2.stderr)
    );
    // Past the `#` lines, which name each run's own --threads.
    let data = |p: &std::path::Path| -> Vec<u8> {
        let t = std::fs::read_to_string(p).expect("csv");
        let kept: Vec<&str> = t.lines().filter(|l| !l.starts_with('#')).collect();
        kept.join("\n").into_bytes()
    };
    let (ta, tb) = (data(&a), data(&b));
    assert_eq!(ta, tb, "the CSV depends on the thread count");
    let text = String::from_utf8_lossy(&ta);
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("theta_nu,kappa,period,lyapunov,regime,iterates,class,lyapunov_stderr")
    );
    assert_eq!(lines.count(), 15);
    let bytes = std::fs::read(&png).expect("the png");
    assert_eq!(&bytes[1..4], b"PNG");
}

/// The command line runs the window's phase job: its CSV is the job's
/// cells, each written as `formats::phase_row`, rows of increasing κ, as the
/// single-threaded host computes them.
#[test]
fn the_command_line_grid_is_the_windows_phase_job() {
    use oneblock::jobs::{Axis, Local, PhaseSpec, PhaseTuning, Shape, Spec, Update};
    let dir = tempfile::tempdir().expect("a temporary folder");
    let out = dir.path().join("grid.csv");
    let out_s = out.to_string_lossy().to_string();
    let o = oneblock(&grid_args(&out_s, "2"));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&out).expect("csv");
    let spec = PhaseSpec {
        params: Params {
            kappa: 14.0,
            gamma: 6.5,
            nu: 1e-3,
            theta_nu: 1.2,
            omega: 50.0,
        },
        settings: oneblock::SolverSettings::default(),
        theta_nu: Axis::new(1.2, 1.5, 5),
        kappa: Axis::new(14.0, 20.0, 3),
        transient: 200,
        keep: 64,
        tuning: PhaseTuning::default(),
    };
    let updates = Local::start(Spec::Phase(spec), 1, Shape::default()).run_to_end(1);
    let mut cells = std::collections::BTreeMap::new();
    for u in updates {
        if let Update::PhaseCells { cells: cs, .. } = u {
            for c in cs {
                cells.insert(
                    (c.row, c.column),
                    oneblock::formats::phase_row(&c.cell, false),
                );
            }
        }
    }
    let want: Vec<String> = cells.into_values().collect();
    let got: Vec<&str> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .collect();
    assert_eq!(got, want);
}

fn usage_error(extra: &[&str], flag: &str) {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let out = dir.path().join("x.csv");
    let out_s = out.to_string_lossy().to_string();
    let mut args = vec![
        "phase",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--kappa-from",
        "1",
        "--kappa-to",
        "2",
        "--kappa-steps",
        "2",
        "--theta-nu-steps",
        "2",
        "--out",
        &out_s,
    ];
    // Later flags override earlier ones only for these tests' own values.
    args.extend(extra);
    let o = oneblock(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{extra:?}: {err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains(flag), "{extra:?} should name {flag}: {err}");
    assert!(!Path::new(&out).exists());
}

#[test]
fn bad_input_is_a_one_line_usage_error_naming_the_flag() {
    let usage = |flags: &[&str], name: &str| {
        // Replace a default flag by giving the whole command again.
        usage_error(flags, name)
    };
    usage(&["--keep", "3"], "--keep");
    usage(&["--threads", "0"], "--threads");
    usage(&["--theta-nu-to", "nan"], "--theta-nu-to");
    usage(&["--tol", "1"], "tol");
    usage(&["--omega", "-1"], "omega");
    usage(&["--period-tol", "0"], "--period-tol");
    usage(&["--png", "-"], "--png");
}

#[test]
fn zero_steps_and_a_negative_kappa_are_usage_errors() {
    let o = oneblock(&[
        "phase",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--kappa-from",
        "-1",
        "--kappa-to",
        "2",
        "--kappa-steps",
        "2",
        "--theta-nu-steps",
        "2",
        "--out",
        "-",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--kappa-from"));
    let o = oneblock(&[
        "phase",
        "--gamma",
        "6.5",
        "--nu",
        "1e-3",
        "--kappa-from",
        "1",
        "--kappa-to",
        "2",
        "--kappa-steps",
        "0",
        "--theta-nu-steps",
        "2",
        "--out",
        "-",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--kappa-steps"));
}

#[test]
fn ctrl_c_writes_nothing() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let out = dir.path().join("big.csv");
    let png = dir.path().join("big.png");
    let child = Command::new(env!("CARGO_BIN_EXE_oneblock"))
        .args([
            "phase",
            "--gamma",
            "6.5",
            "--nu",
            "1e-3",
            "--kappa-from",
            "1",
            "--kappa-to",
            "42",
            "--kappa-steps",
            "200",
            "--theta-nu-steps",
            "200",
            "--threads",
            "1",
        ])
        .arg("--out")
        .arg(&out)
        .arg("--png")
        .arg(&png)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the oneblock binary starts");
    std::thread::sleep(Duration::from_millis(1500));
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(killed.success());
    let o = child.wait_with_output().expect("the run ends");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("interrupted"), "{err}");
    assert!(!out.exists() && !png.exists());
    // No temporary file left behind either.
    assert_eq!(
        std::fs::read_dir(dir.path())
            .map(|d| d.count())
            .unwrap_or(0),
        0
    );
}
