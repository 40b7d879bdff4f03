//! An orbit run for its summary only is the whole run's orbit without its
//! events: the same period, exponent, error bar and counts, bit for bit.

use super::*;
use crate::integrate::{Method, SolverSettings};
use crate::model::Params;

fn sim(theta_nu: f64) -> Simulator {
    let settings = SolverSettings::adaptive(Method::Dop853, 1e-9);
    Simulator::new(Params::default().with_theta_nu(theta_nu), settings).unwrap()
}

fn run_to_end(sim: &Simulator, mut run: OrbitRun) -> Orbit {
    loop {
        if let Some(r) = run.advance(sim, &|| false) {
            return r.unwrap();
        }
    }
}

fn options(keep: usize, lyapunov: bool) -> OrbitOptions {
    OrbitOptions {
        transient: 300,
        keep,
        lyapunov,
        period_tol: 1e-5,
    }
}

/// The whole run's orbit with its events dropped.
fn summary_of(mut whole: Orbit) -> Orbit {
    assert_eq!(whole.events.len(), whole.kept);
    whole.events.clear();
    whole
}

#[test]
fn a_summary_only_orbit_is_the_whole_orbit_without_its_events() {
    // Fig. 3b: a fixed point, a 4-cycle, chaos (its error bar from batch
    // means), each with and without the exponent.
    for (tn, period) in [(1.0, Some(1)), (1.2, Some(4)), (1.25, None)] {
        let s = sim(tn);
        for lyapunov in [true, false] {
            let opts = options(2000, lyapunov);
            let whole = run_to_end(&s, OrbitRun::new(&s, tn, &opts).unwrap());
            let summary = run_to_end(&s, OrbitRun::new(&s, tn, &opts).unwrap().summary_only());
            assert!(summary.events.is_empty());
            assert_eq!(summary.kept, 2000);
            assert_eq!(
                whole.period,
                period.map_or(Period::Aperiodic, Period::Periodic)
            );
            assert_eq!(
                summary.lyapunov_stderr.is_some(),
                lyapunov && period.is_none()
            );
            assert_eq!(summary_of(whole), summary, "θν = {tn}");
        }
    }
}

#[test]
fn on_the_interpolant_too() {
    let s = sim(1.25);
    let opts = options(30_000, true);
    let iopts = InterpolantOptions::for_settings(s.settings());
    let whole = run_to_end(&s, OrbitRun::interpolated(&s, 1.25, &opts, iopts).unwrap());
    let run = OrbitRun::interpolated(&s, 1.25, &opts, iopts).unwrap();
    let summary = run_to_end(&s, run.summary_only());
    assert!(matches!(whole.period, Period::Aperiodic));
    // The exponent and its error as the kept ln|f'| give them.
    assert!(whole.lyapunov.is_some_and(|l| l > 0.3 && l < 0.4));
    assert!(whole.lyapunov_stderr.is_some_and(|e| e > 0.0 && e < 0.01));
    assert_eq!(summary_of(whole), summary);
}

#[test]
fn the_recent_onsets_hold_the_last_advance_and_a_window_before_it() {
    let s = sim(1.25);
    let opts = options(5000, false);
    let mut run = OrbitRun::new(&s, 1.25, &opts).unwrap();
    let mut all = Vec::new();
    while run.advance(&s, &|| false).is_none() {
        let recent = run.recent_onsets();
        assert!(recent.len() <= 4 * WINDOW_MAX);
        let new = run.kept() - all.len();
        all.extend_from_slice(&recent[recent.len() - new..]);
        assert!(recent.len() >= all.len().min(WINDOW_MAX + new));
        assert_eq!(recent, &all[all.len() - recent.len()..]);
    }
    assert_eq!(
        all,
        run_to_end(&s, OrbitRun::new(&s, 1.25, &opts).unwrap()).thetas()
    );
}

#[test]
fn kept_events_outside_the_model_are_counted_without_being_kept() {
    let s = sim(1.0);
    let opts = options(3, false);
    let mut run = OrbitRun::new(&s, 1.0, &opts).unwrap().summary_only();
    let ev = s.cycle(1.0, 0.0, None).unwrap();
    let odd = SlipEvent {
        energy_released: -1e-3,
        ..ev
    };
    run.keep(ev, 0.5);
    run.keep(odd, 0.5);
    run.keep(odd, 0.5);
    assert_eq!((run.kept(), run.anomalies), (3, 2));
    assert!(matches!(
        run.first_anomaly,
        Some(EventAnomaly::NegativeEnergy { energy_released }) if energy_released == -1e-3
    ));
}
