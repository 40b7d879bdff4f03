//! Every kind of job on the single-threaded host in the page's slices of
//! time, counted in pieces (`oneblock bench-worker --pieces`): a piece is
//! one step of the host, and its length is how long the page's frame is
//! held by it. Run again with a slice that has always passed, each step is
//! one unit that cannot pause: the longest of those is what a piece cannot
//! be shorter than, however idle the machine. The specs are the window's
//! defaults at the paper's Fig. 3b point (or smaller ones, for a quick
//! check).

use std::time::Duration;
use web_time::Instant;

use super::diagram::{PAGE_SLICE, fig3b, fig3b_diagram};
use crate::integrate::{Method, SolverSettings};
use crate::jobs::{
    Axis, BasinsSpec, BoundarySpec, CascadeFrom, ContinuationSpec, IterateSpec, Kind, Local,
    MapBasinsSpec, Outcome, PassageSpec, PhaseSpec, PhaseTuning, ScanSpec, Shape, Spec, TimeSlice,
    TrajectorySpec, Update, WorkPrecisionSpec,
};
use crate::model::Params;
use crate::numerics::budget::budget_for;
use crate::numerics::quick::{
    QUICK_POINTS, QUICK_TIME_PER_SETTING, QUICK_TRANSIENT, quick_subjects,
};
use crate::sim::MapChoice;
use crate::sim::attractors::CellOptions;
use crate::sim::continuation::ContParam;

/// How one job ran in pieces.
#[derive(Clone, Debug, PartialEq)]
pub struct Pieces {
    pub kind: Kind,
    /// Steps of the host, from the job's start to its end.
    pub pieces: usize,
    /// The longest step, in milliseconds.
    pub longest_ms: f64,
    /// Slip cycles (or continuation points) the job polled for in its
    /// longest step ([`crate::jobs::Sink::cycle`]): what that piece held.
    pub longest_cycles: u64,
    /// The longest step when the job pauses wherever it can (every step
    /// one unit that cannot pause), in milliseconds.
    pub longest_unit_ms: f64,
    /// The job's last summary line, if it sent one (how it ended).
    pub summary: Option<String>,
}

/// The solver the window's Auto accuracy picks for `kind` (the Events
/// view's own, dop853 at 1e-8, for its jobs; none for work-precision).
fn window_settings(kind: Kind) -> SolverSettings {
    match kind.accuracy() {
        Some(accuracy) => budget_for(accuracy.target()).settings,
        None => SolverSettings::adaptive(Method::Dop853, 1e-8),
    }
}

/// The Events view's preset: κ = 50, θν = 1.4.
fn intermittent() -> Params {
    crate::model::preset("intermittent").map_or_else(Params::default, |p| p.params)
}

/// The spec of `kind` the window starts at Fig. 3b (θν = 1.1 where the
/// job is at one point) with its defaults and its Auto accuracy, or,
/// `quick`, a small one of the same kind (a few seconds for them all).
pub fn representative(kind: Kind, quick: bool) -> Spec {
    let settings = window_settings(kind);
    let here = Params {
        theta_nu: 1.1,
        ..fig3b()
    };
    let grid = |n: usize| Axis::new(0.0, std::f64::consts::FRAC_PI_2, n);
    let (theta_box, kappa_box) = if quick {
        ((0.9, 1.3), (17.0, 21.0))
    } else {
        ((0.0, std::f64::consts::FRAC_PI_2), (1.0, 42.0))
    };
    let q = |small: usize, full: usize| if quick { small } else { full };
    match kind {
        Kind::Trajectory => Spec::Trajectory(TrajectorySpec {
            params: here,
            settings,
            theta0: None,
            transient: 0,
            spacing: 0.02,
            cycles: Some(q(40, 400)),
            max_samples: None,
        }),
        Kind::Iterate => Spec::Iterate(IterateSpec {
            params: here,
            settings,
            theta0: None,
            transient: q(100, 1000),
            keep: q(50, 300),
            graph_powers: 1,
            options: crate::jobs::IterateOptions::default(),
        }),
        Kind::Sweep => {
            let mut spec = fig3b_diagram(q(16, 400), q(50, 300), q(20, 200), 1e-8);
            spec.settings = settings;
            Spec::Sweep(spec)
        }
        Kind::Phase => Spec::Phase(PhaseSpec {
            params: here,
            settings,
            theta_nu: grid(q(6, 30)),
            kappa: Axis::new(1.0, 42.0, q(6, 30)),
            transient: q(100, 400),
            keep: q(32, 128),
            tuning: PhaseTuning::default(),
        }),
        Kind::Numerics => work_precision(here, quick),
        Kind::Branches => find_bifurcations(settings, quick),
        Kind::Curves => Spec::Curves(BoundarySpec {
            params: fig3b(),
            settings,
            theta_nu: theta_box,
            kappa: kappa_box,
        }),
        Kind::Passage => Spec::Passage(PassageSpec {
            params: intermittent(),
            settings,
            near: 0.1,
        }),
        Kind::Scan => Spec::Scan(ScanSpec {
            params: intermittent(),
            settings,
        }),
        Kind::Basins => Spec::Basins(BasinsSpec {
            params: fig3b(),
            settings,
            param: ContParam::ThetaNu,
            axis: grid(q(4, 48)),
            cells: CellOptions::column(),
        }),
        Kind::MapBasins => Spec::MapBasins(MapBasinsSpec::here(here, settings)),
    }
}

/// Runs `spec` to its end on the single-threaded host, a step per slice
/// of `slice` as the page runs it (one unit per step), and counts its
/// pieces; then again pausing wherever it can, for its longest unit; the
/// job's error if it did not complete.
pub fn count_pieces(spec: Spec, slice: Duration) -> Result<Pieces, String> {
    let (pieces, longest_ms, longest_cycles, summary) = steps(spec.clone(), slice)?;
    let (_, longest_unit_ms, _, _) = steps(spec.clone(), Duration::ZERO)?;
    Ok(Pieces {
        kind: spec.kind(),
        pieces,
        longest_ms,
        longest_cycles,
        longest_unit_ms,
        summary,
    })
}

/// What a run in slices came to: its steps, the longest (ms), the cycles
/// that one polled for, and the job's last summary line.
type Steps = (usize, f64, u64, Option<String>);

/// The steps of `spec` in slices of `slice`.
fn steps(spec: Spec, slice: Duration) -> Result<Steps, String> {
    let kind = spec.kind();
    let mut host = Local::start(spec, 1, Shape::default());
    let (mut pieces, mut longest, mut longest_cycles) = (0, 0.0_f64, 0);
    let (mut outcome, mut summary) = (None, None);
    loop {
        let cycles = host.cycles();
        let started = Instant::now();
        let more = host.step_until(1, Some(TimeSlice::from_now(slice)));
        let ms = 1e3 * started.elapsed().as_secs_f64();
        pieces += 1;
        if ms > longest {
            (longest, longest_cycles) = (ms, host.cycles() - cycles);
        }
        for u in host.drain() {
            match u {
                Update::Error { message, .. } => return Err(message),
                Update::Finished { outcome: o, .. } => outcome = Some(o),
                Update::Summary { text, .. } => summary = Some(text),
                _ => {}
            }
        }
        if !more {
            break;
        }
    }
    match outcome {
        Some(Outcome::Completed) => Ok((pieces, longest, longest_cycles, summary)),
        o => Err(format!("the {kind:?} job did not complete ({o:?})")),
    }
}

/// Every kind's [`representative`] job in [`PAGE_SLICE`]s, in
/// [`Kind::ALL`]'s order.
pub fn every_kind(quick: bool) -> Result<Vec<Pieces>, String> {
    Kind::ALL
        .iter()
        .map(|&k| count_pieces(representative(k, quick), PAGE_SLICE))
        .collect()
}

/// The rarer paths on the map's interpolant, which the window's defaults
/// do not reach: a long orbit (the iterate job's scout, build and series)
/// and long chaotic columns of a diagram (each column's build, then its
/// points from the series), at Fig. 3b's chaotic θν = 1.25, each with a
/// label; `quick`, shorter.
pub fn on_interpolant(quick: bool) -> Result<Vec<(&'static str, Pieces)>, String> {
    let q = |small: usize, full: usize| if quick { small } else { full };
    let chaos = Params {
        theta_nu: 1.25,
        ..fig3b()
    };
    let settings = window_settings(Kind::Iterate);
    let orbit = Spec::Iterate(IterateSpec {
        params: chaos,
        settings,
        theta0: None,
        transient: 1000,
        keep: q(20_000, 200_000),
        graph_powers: 1,
        options: crate::jobs::IterateOptions {
            map: MapChoice::Interpolant,
            ..Default::default()
        },
    });
    let mut sweep = fig3b_diagram(q(2, 8), 200, 8000, 1e-8);
    sweep.axis = Axis::new(1.2, 1.29, q(2, 8));
    sweep.map = MapChoice::Interpolant;
    sweep.settings = window_settings(Kind::Sweep);
    Ok(vec![
        ("a long orbit", count_pieces(orbit, PAGE_SLICE)?),
        (
            "long columns",
            count_pieces(Spec::Sweep(sweep), PAGE_SLICE)?,
        ),
    ])
}

/// The Numerics view's quick measurement at `here`.
fn work_precision(here: Params, quick: bool) -> Spec {
    Spec::Numerics(WorkPrecisionSpec {
        attractors: vec![crate::numerics::quick::current_attractor(
            here,
            None,
            if quick { 50 } else { QUICK_TRANSIENT },
        )],
        points: if quick { 2 } else { QUICK_POINTS },
        timing: crate::jobs::Timing::PerSetting(if quick {
            Duration::from_millis(5)
        } else {
            QUICK_TIME_PER_SETTING
        }),
        subjects: quick_subjects(),
    })
}

/// Find bifurcations over the Fig. 3b cascade (docs/continuation.md), a
/// zoom of the window's diagram, up to P32 (P4 over [1, 1.2], `quick`).
fn find_bifurcations(settings: SolverSettings, quick: bool) -> Spec {
    Spec::Branches(ContinuationSpec {
        params: fig3b(),
        settings,
        param: ContParam::ThetaNu,
        from: 1.0,
        to: if quick { 1.2 } else { 1.6 },
        max_period: if quick { 4 } else { 32 },
        cycle: None,
        cascade: CascadeFrom::Branch,
        curves: None,
    })
}
