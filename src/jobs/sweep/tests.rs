use super::*;
use crate::jobs::{Axis, Outcome};
use crate::model::Params;
use crate::sim::MapChoice;
use crate::sim::default_settings;
use crate::worker::{Command, Worker, WorkerConfig};
use std::collections::HashSet;
use std::sync::Arc;
use std::time::Duration;

/// Fault injection for the sweep threads: the column at this θν (its
/// bits; u64::MAX: none) panics. Only this module's tests set it, with
/// a θν no other test's sweep has, as tests run side by side.
static PANIC_AT_THETA_NU: AtomicU64 = AtomicU64::new(u64::MAX);

pub(super) fn inject_panic(index: usize, theta_nu: f64) {
    if theta_nu.to_bits() == PANIC_AT_THETA_NU.load(Ordering::SeqCst) {
        panic!("injected panic in column {index}");
    }
}

#[test]
fn a_panicking_column_is_reported_and_the_sweep_goes_on() {
    let w = Worker::spawn(
        WorkerConfig {
            coarse_columns: 4,
            ..WorkerConfig::default()
        },
        Arc::new(|| {}),
    );
    let sweep = |generation| {
        Command::run(
            generation,
            SweepSpec {
                params: Params::default(),
                settings: default_settings(1e-8),
                param: crate::sim::continuation::ContParam::ThetaNu,
                axis: Axis::new(0.2, 1.4, 10),
                transient: 3,
                keep: 3,
                map: MapChoice::Auto,
                theta0: None,
                seeds: 0,
            },
        )
    };
    let grid = crate::sim::theta_nu_grid(0.2, 1.4, 10);
    PANIC_AT_THETA_NU.store(grid[5].to_bits(), Ordering::SeqCst);
    assert!(w.send(sweep(1)));
    let mut columns = HashSet::new();
    let mut errors = vec![];
    let outcome = loop {
        match w.recv_timeout(Duration::from_secs(60)).expect("silent") {
            Update::Column { index, thetas, .. } => {
                assert!(columns.insert(index));
                assert_eq!(thetas.is_empty(), index == 5);
            }
            Update::Error { message, .. } => errors.push(message),
            Update::Finished { outcome, .. } => break outcome,
            _ => {}
        }
    };
    PANIC_AT_THETA_NU.store(u64::MAX, Ordering::SeqCst);
    assert_eq!(columns.len(), 10);
    assert_eq!(errors.len(), 1);
    assert!(errors[0].contains("column 5") && errors[0].contains("injected panic"));
    assert!(matches!(outcome, Outcome::Failed(_)));
    assert!(w.send(sweep(2)));
    let outcome = loop {
        if let Update::Finished { outcome, .. } =
            w.recv_timeout(Duration::from_secs(60)).expect("silent")
        {
            break outcome;
        }
    };
    assert_eq!(outcome, Outcome::Completed);
    w.shutdown();
}
