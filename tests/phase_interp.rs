//! Phase cells on the map's verified interpolant (`PhaseOptions::map`): a
//! cell with a long budget is classified as with direct integration for
//! far fewer map evaluations; the paper's budget never builds it; where it
//! is refused the cell integrates, exactly as without it.
#![allow(clippy::unwrap_used)]

use crate::common;
use common::fixture::preset;

use oneblock::Params;
use oneblock::sim::MapChoice;
use oneblock::sim::default_settings;
use oneblock::sim::interpolant::MapUsed;
use oneblock::sim::phase::{CellClass, PhaseCell, PhaseOptions, phase_cell, phase_row};
use oneblock::sim::theta_nu_grid;

fn params(kappa: f64, theta_nu: f64) -> Params {
    Params {
        kappa,
        theta_nu,
        ..preset("fig4")
    }
}

fn opts(transient: usize, keep: usize, map: MapChoice) -> PhaseOptions {
    PhaseOptions {
        transient,
        keep,
        map,
        ..PhaseOptions::for_settings(&default_settings(1e-10))
    }
}

/// The cell at (κ, θν) from θ = θν.
fn cell(kappa: f64, theta_nu: f64, o: &PhaseOptions) -> PhaseCell {
    phase_cell(
        params(kappa, theta_nu),
        default_settings(1e-10),
        theta_nu,
        o,
        &|| false,
    )
}

fn interpolant_error(c: &PhaseCell) -> f64 {
    match &c.map {
        MapUsed::Interpolant(s) => s.max_map_error,
        other => panic!("the cell did not use the interpolant: {other:?}"),
    }
}

/// κ = 23, θν = 1.2043 is undecided on the paper's grid (400 + 128): a
/// period-4 orbit approached so slowly that 1195 integrated iterates pass
/// before the period test settles. With a budget of 20 000 + 2000 the
/// interpolant gives the same period-4 cycle (solved by Newton's method on
/// the direct map, so its exponent agrees to the solver's accuracy) for
/// less than half the map evaluations; `Auto` chooses it for this budget.
#[test]
fn a_slow_cell_is_the_same_on_the_interpolant_for_fewer_map_evaluations() {
    let (kappa, theta_nu) = (23.0, 1.2042771838760873);
    let direct = cell(kappa, theta_nu, &opts(20_000, 2000, MapChoice::Direct));
    let interp = cell(kappa, theta_nu, &opts(20_000, 2000, MapChoice::Interpolant));
    assert_eq!(direct.map, MapUsed::Direct);
    assert!(matches!(direct.class, CellClass::Periodic(4)), "{direct:?}");
    assert!(direct.iterates > 1000, "{}", direct.iterates);
    assert_eq!(interp.class, direct.class);
    let (ld, li) = (direct.lyapunov.unwrap(), interp.lyapunov.unwrap());
    assert!((ld - li).abs() < 1e-6, "{ld} vs {li}");
    assert!(
        2 * interp.iterates < direct.iterates,
        "{} vs {} map evaluations",
        interp.iterates,
        direct.iterates
    );
    assert!(interpolant_error(&interp) <= 1e-10);
    let auto = cell(kappa, theta_nu, &opts(20_000, 2000, MapChoice::Auto));
    assert_eq!(auto, interp);
}

/// Fig. 3b's chaotic point with a 20 000-iterate transient: the period is
/// looked for over the whole transient before λ is computed. Both runs
/// find chaos, with exponents within 4 combined standard errors (the two
/// orbits are different pseudo-orbits: only statistics compare), and the
/// interpolated cell costs less than half the map evaluations, its
/// construction included.
#[test]
fn a_long_chaotic_transient_is_the_same_on_the_interpolant() {
    let (kappa, theta_nu) = (18.95, 1.25);
    let direct = cell(kappa, theta_nu, &opts(20_000, 2000, MapChoice::Direct));
    let interp = cell(kappa, theta_nu, &opts(20_000, 2000, MapChoice::Interpolant));
    assert_eq!(direct.class, CellClass::Chaos);
    assert_eq!(interp.class, CellClass::Chaos);
    let (ld, sd) = (direct.lyapunov.unwrap(), direct.lyapunov_stderr.unwrap());
    let (li, si) = (interp.lyapunov.unwrap(), interp.lyapunov_stderr.unwrap());
    assert!(
        (ld - li).abs() <= 4.0 * sd.hypot(si),
        "{ld} ± {sd} vs {li} ± {si}"
    );
    assert!(
        2 * interp.iterates < direct.iterates,
        "{} vs {} map evaluations",
        interp.iterates,
        direct.iterates
    );
    assert!(interpolant_error(&interp) <= 1e-10);
}

/// With the paper's budget (400 + 128) `Auto` never builds the
/// interpolant: a row through periodic, slow and chaotic cells is bitwise
/// the direct one.
#[test]
fn the_papers_budget_never_builds_it() {
    let thetas = theta_nu_grid(1.0, 1.5, 11);
    let run = |map| {
        let o = PhaseOptions {
            map,
            ..PhaseOptions::for_settings(&default_settings(1e-10))
        };
        phase_row(
            params(23.0, 1.0),
            default_settings(1e-10),
            &thetas,
            &o,
            &|| false,
            &|_| {},
        )
    };
    let auto = run(MapChoice::Auto);
    assert!(auto.iter().all(|c| c.map == MapUsed::Direct));
    assert!(auto.iter().any(|c| c.class == CellClass::Chaos));
    assert_eq!(auto, run(MapChoice::Direct));
}

/// κ = 3, θν = 1.1257 (chaotic): the map there cannot be resolved within
/// the cell's evaluation budget (half its iterates after the direct part).
/// The refusal is recorded with its reason and the cell integrates: the
/// same orbit, class and exponent as without the interpolant, the refused
/// construction's evaluations (at most the budget and one batch) on top.
#[test]
fn a_refused_interpolant_leaves_the_cell_as_it_was() {
    let (kappa, theta_nu) = (3.0, 1.1257373675363425);
    let direct = cell(kappa, theta_nu, &opts(2000, 200, MapChoice::Direct));
    let tried = cell(kappa, theta_nu, &opts(2000, 200, MapChoice::Interpolant));
    match &tried.map {
        MapUsed::Refused(why) => assert!(why.contains("map evaluations"), "{why}"),
        other => panic!("expected a refusal, got {other:?}"),
    }
    assert_eq!(tried.class, direct.class);
    assert_eq!(tried.lyapunov, direct.lyapunov);
    assert_eq!(tried.theta_last, direct.theta_last);
    let extra = tried.iterates - direct.iterates;
    assert!(extra > 0 && extra <= 900 + 129 * 8, "{extra}");
}
