//! Bifurcation sweeps over θν: each column's orbit starts from the last
//! iterate of the previous column, so a sweep follows one attractor.

use super::{SimError, Simulator};
use crate::integrate::SolverSettings;
use crate::model::{Params, project_onto_exit_arc};

/// How long each column runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepOptions {
    pub transient: usize,
    pub keep: usize,
}

/// One column of a bifurcation diagram.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    pub theta_nu: f64,
    /// The kept onsets θ (empty if the column failed).
    pub thetas: Vec<f64>,
    /// The onset after the last kept one, where a neighbour continues.
    pub theta_last: f64,
    /// Why the column is empty or short, if it is.
    pub error: Option<SimError>,
    /// Right-hand-side evaluations the column cost.
    pub rhs_evals: u64,
}

/// `n` values of θν evenly spaced from `from` to `to` inclusive.
pub fn theta_nu_grid(from: f64, to: f64, n: usize) -> Vec<f64> {
    match n {
        0 => vec![],
        1 => vec![from],
        _ => (0..n)
            .map(|i| from + (to - from) * i as f64 / (n - 1) as f64)
            .collect(),
    }
}

/// Where a column at θν starts: the neighbour's last onset moved onto the new
/// exit arc, or θ = θν (always on the arc) when there is none.
pub fn column_start(kappa: f64, theta_nu: f64, neighbour: Option<f64>) -> f64 {
    match neighbour {
        Some(th) if th.is_finite() => project_onto_exit_arc(kappa, theta_nu, th, 1e-6),
        _ => theta_nu,
    }
}

impl Column {
    /// Runs one column at `theta_nu` from `theta_start`; `cancel` is polled
    /// every cycle. A failed cycle ends the column with its error.
    pub fn run(
        params: Params,
        settings: SolverSettings,
        theta_nu: f64,
        theta_start: f64,
        opts: &SweepOptions,
        cancel: &dyn Fn() -> bool,
    ) -> Column {
        let mut col = Column {
            theta_nu,
            thetas: Vec::with_capacity(opts.keep),
            theta_last: theta_start,
            error: None,
            rhs_evals: 0,
        };
        let sim = match Simulator::new(params.with_theta_nu(theta_nu), settings) {
            Ok(s) => s,
            Err(e) => {
                col.error = Some(e);
                return col;
            }
        };
        let mut theta = theta_start;
        for i in 0..opts.transient + opts.keep {
            if cancel() {
                col.error = Some(SimError::Cancelled);
                return col;
            }
            match sim.cycle(theta, 0.0, None) {
                Ok(ev) => {
                    col.rhs_evals += ev.rhs_evals;
                    if i >= opts.transient {
                        col.thetas.push(ev.theta);
                    }
                    theta = sim.next_onset(&ev);
                }
                Err(e) => {
                    col.error = Some(e);
                    return col;
                }
            }
        }
        col.theta_last = theta;
        col
    }
}

/// A continued sweep over `theta_nus`, in order, starting from `theta0` (or
/// θν). After a failed column the next one starts afresh from θν.
pub fn sweep_columns(
    params: Params,
    settings: SolverSettings,
    theta_nus: &[f64],
    opts: &SweepOptions,
    theta0: Option<f64>,
    cancel: &dyn Fn() -> bool,
    mut on_column: impl FnMut(&Column),
) -> Vec<Column> {
    let mut out = Vec::with_capacity(theta_nus.len());
    let mut prev = theta0;
    for &tn in theta_nus {
        let start = column_start(params.kappa, tn, prev);
        let col = Column::run(params, settings, tn, start, opts, cancel);
        prev = if col.error.is_none() {
            Some(col.theta_last)
        } else {
            None
        };
        on_column(&col);
        let cancelled = matches!(col.error, Some(SimError::Cancelled));
        out.push(col);
        if cancelled {
            break;
        }
    }
    out
}
