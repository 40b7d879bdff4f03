//! Bifurcation sweeps over θν: each column's orbit starts from the last
//! iterate of the previous column, so a sweep follows one attractor.

use super::{SimError, Simulator};
use crate::integrate::SolverSettings;
use crate::model::{Params, project_onto_exit_arc, wrap_angle};

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
        let total = opts.transient + opts.keep;
        let rep_tol = (100.0 * settings.rtol).clamp(1e-12, 1e-6);
        // onsets[k] is the onset of cycle k.
        let mut onsets = Vec::with_capacity(total + 1);
        onsets.push(theta_start);
        for i in 0..total {
            if cancel() {
                col.error = Some(SimError::Cancelled);
                return col;
            }
            match sim.cycle(onsets[i], 0.0, None) {
                Ok(ev) => {
                    col.rhs_evals += ev.rhs_evals;
                    onsets.push(sim.next_onset(&ev));
                }
                Err(e) => {
                    col.error = Some(e);
                    // The kept cycles that completed before the failure.
                    col.thetas = onsets[opts.transient.min(i)..i].to_vec();
                    return col;
                }
            }
            // A column that has settled onto a short cycle repeats it: the
            // rest of its iterates are the cycle's, to within rep_tol, so
            // they are not integrated again (most columns of a diagram are
            // fixed points or short cycles).
            if let Some(p) = settled_period(&onsets, rep_tol) {
                for k in onsets.len()..=total {
                    let next = onsets[k - p];
                    onsets.push(next);
                }
                break;
            }
        }
        col.thetas = onsets[opts.transient..total].to_vec();
        col.theta_last = onsets[total];
        col
    }
}

/// The period p ≤ 16 onto which the onsets have settled, if any: over the
/// last max(4p, 8) onsets, θ_k repeats θ_{k−p} within `tol`, and the
/// differences are either at rounding level or shrinking fast enough that
/// what is left of the approach (a geometric series) is below `tol` too.
/// A slowly converging orbit (multiplier near 1) is therefore not cut short.
fn settled_period(onsets: &[f64], tol: f64) -> Option<usize> {
    let n = onsets.len();
    (1..=16).find(|&p| {
        let w = (4 * p).max(8);
        if n < w + p {
            return false;
        }
        let d = |j: usize| wrap_angle(onsets[j] - onsets[j - p]).abs();
        if !(n - w..n).all(|j| d(j) <= tol) {
            return false;
        }
        let (first, last) = (d(n - w), d(n - 1));
        if last <= 1e-3 * tol {
            return true;
        }
        let r = (last / first).powf(1.0 / (w - 1) as f64);
        r < 1.0 && last * r / (1.0 - r) <= tol
    })
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::Method;

    /// Every cycle integrated: the reference the early exit must reproduce.
    fn brute_force(
        params: Params,
        settings: SolverSettings,
        theta_nu: f64,
        opts: &SweepOptions,
    ) -> Vec<f64> {
        let sim = Simulator::new(params.with_theta_nu(theta_nu), settings).unwrap();
        let mut theta = theta_nu;
        let mut kept = vec![];
        for i in 0..opts.transient + opts.keep {
            let ev = sim.cycle(theta, 0.0, None).unwrap();
            if i >= opts.transient {
                kept.push(ev.theta);
            }
            theta = sim.next_onset(&ev);
        }
        kept
    }

    #[test]
    fn settled_columns_match_full_integration() {
        let params = Params::default();
        let settings = SolverSettings::adaptive(Method::Dop853, 1e-8);
        let opts = SweepOptions {
            transient: 300,
            keep: 200,
        };
        // Fig. 3b: fixed points, period 2 and 4, chaos, period 3; and a slow
        // pure-creep fixed point (multiplier ≈ 0.99), which must not be cut short.
        let creep = Params {
            kappa: 3.0,
            gamma: 0.5,
            nu: 1e-3,
            theta_nu: 0.7,
            omega: 50.0,
        };
        for (p, tn) in [
            (params, 0.3),
            (params, 1.0),
            (params, 1.12),
            (params, 1.2),
            (params, 1.25),
            (params, 1.3),
            (creep, 0.7),
        ] {
            let col = Column::run(p, settings, tn, tn, &opts, &|| false);
            let reference = brute_force(p, settings, tn, &opts);
            assert_eq!(col.thetas.len(), reference.len());
            let worst = col
                .thetas
                .iter()
                .zip(&reference)
                .map(|(a, b)| wrap_angle(a - b).abs())
                .fold(0.0, f64::max);
            // Chaotic columns never settle, so they are bit-identical; the
            // others agree to far below a pixel (1e-3 of the θ range).
            assert!(worst < 1e-5, "θν = {tn}: early exit differs by {worst:e}");
        }
    }
}
