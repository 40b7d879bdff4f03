//! Settings' own tests.
use super::*;

#[test]
fn smooth_lines_auto_is_off_only_on_software_gl() {
    let mut s = Settings::default();
    assert!(s.smooth_lines_on(false));
    assert!(!s.smooth_lines_on(true));
    s.smooth_lines = Some(true);
    assert!(s.smooth_lines_on(true));
    s.smooth_lines = Some(false);
    assert!(!s.smooth_lines_on(false));
}

#[test]
fn a_saved_basins_zoom_outside_theta_nus_range_or_reversed_is_dropped() {
    let mut s = Settings::default();
    s.basins.zoom = vec![(1.35, 1.43), (-100.0, 100.0), (1.4, 1.3), (f64::NAN, 1.0)];
    s.basins.columns = 1_000_000;
    let (s, bad) = s.sanitised();
    assert_eq!(s.basins.zoom, [(1.35, 1.43)]);
    assert_eq!(s.basins.columns, MAX_COLUMNS);
    assert!(bad.contains(&"basins view"), "{bad:?}");
    let (_, bad) = Settings::default().sanitised();
    assert!(!bad.contains(&"basins view"));
}

#[test]
fn saved_phase_settings_are_brought_into_range() {
    let s = PhaseSettings {
        theta_nu_steps: 0,
        kappa_steps: 100_000,
        transient: 10_000_000,
        keep: 2,
        range: PhaseRange {
            theta_nu: (0.0, f64::NAN),
            kappa: (-1.0, 5.0),
        },
        zoom: vec![PhaseRange {
            theta_nu: (1.0, 0.5),
            kappa: (1.0, 2.0),
        }],
        seeds: 1000,
    }
    .sanitised();
    assert_eq!(s.seeds, MAX_SWEEP_SEEDS);
    assert_eq!((s.theta_nu_steps, s.kappa_steps), (MIN_STEPS, MAX_STEPS));
    assert_eq!((s.transient, s.keep), (MAX_BUDGET, 16));
    assert_eq!(s.range, PhaseRange::PAPER);
    assert!(s.zoom.is_empty());
}
