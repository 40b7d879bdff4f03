//! The derivative of the map, and the grid its graph is drawn on (periods
//! are detected in `super::period`).

use std::sync::atomic::{AtomicU64, Ordering};

use super::{SimError, Simulator, SlipEvent, cycle_pair};
use crate::model::{is_on_exit_arc, wrap_angle};

/// f'(θ) asked of [`map_derivative`] and [`cycle_with_derivative`] in this
/// process, and how many of those fell back to the secant.
static SLOPES: [AtomicU64; 2] = [AtomicU64::new(0), AtomicU64::new(0)];

/// How many f'(θ) [`map_derivative`] and [`cycle_with_derivative`] have
/// computed in this process, and how many of them were the secant's
/// because f has no derivative there (docs/derivatives.md gives the share
/// on the paper's phase grid).
pub fn slope_counts() -> (u64, u64) {
    (
        SLOPES[0].load(Ordering::Relaxed),
        SLOPES[1].load(Ordering::Relaxed),
    )
}

/// Counts one f'(θ), `secant` when it was the difference's.
fn count_slope(secant: bool) {
    SLOPES[0].fetch_add(1, Ordering::Relaxed);
    if secant {
        SLOPES[1].fetch_add(1, Ordering::Relaxed);
    }
}

/// The window of θ a return-map picture of `thetas` shows: their range
/// padded by a quarter on each side (at least 0.02 rad), so a fixed point
/// still shows the slope of f through it. `None` for no finite value.
pub fn return_map_window(thetas: &[f64]) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &t in thetas.iter().filter(|t| t.is_finite()) {
        lo = lo.min(t);
        hi = hi.max(t);
    }
    if !lo.is_finite() {
        return None;
    }
    let pad = ((hi - lo) * 0.25).max(0.02);
    Some((lo - pad, hi + pad))
}

/// `n` onsets evenly spread over [lo, hi] that lie on the exit arc (the
/// others dropped): where the graph of f is drawn.
pub fn map_graph_grid(kappa: f64, theta_nu: f64, lo: f64, hi: f64, n: usize) -> Vec<f64> {
    let n = n.max(2);
    (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .filter(|&t| is_on_exit_arc(kappa, theta_nu, t))
        .collect()
}

/// The step of the central difference for f'(θ), used only where f has
/// no derivative (see [`map_derivative`]).
pub const DERIVATIVE_STEP: f64 = 1e-5;

/// f'(θ), and the right-hand-side evaluations it cost, from the
/// variational equations ([`Simulator::cycle_slope`]: one cycle whose
/// evaluations carry the tangent along θ alone). Where f has no derivative
/// (`sim::variational::NotDifferentiable`: a restart at the stop, the edge
/// of the exit arc, a jump) a number is still wanted by the Lyapunov
/// exponent, so the slope of the secant over ±1e-5 is returned there,
/// given f(θ) = `f_theta` (for a one-sided difference next to the edge of
/// the exit arc).
pub fn map_derivative(sim: &Simulator, theta: f64, f_theta: f64) -> Result<(f64, u64), SimError> {
    let (ev, d, n) = sim.cycle_slope(theta, 0.0)?;
    count_slope(d.is_err());
    match d {
        Ok(d) => Ok((d, ev.rhs_evals + n)),
        Err(_) => central_difference(sim, theta, f_theta),
    }
}

/// The secant slope of f over θ ± 1e-5 (one-sided next to the edge of the
/// exit arc), with the evaluations it cost.
pub(crate) fn central_difference(
    sim: &Simulator,
    theta: f64,
    f_theta: f64,
) -> Result<(f64, u64), SimError> {
    let h = DERIVATIVE_STEP;
    let p = sim.params();
    let up = is_on_exit_arc(p.kappa, p.theta_nu, theta + h);
    let down = is_on_exit_arc(p.kappa, p.theta_nu, theta - h);
    let pick = |r: Result<SlipEvent, SimError>| r.map(|e| (e.theta_next, e.rhs_evals));
    let f = |th: f64| pick(sim.cycle(th, 0.0, None));
    match (up, down) {
        (true, true) => {
            let [p, m] = cycle_pair([(sim, theta + h, 0.0), (sim, theta - h, 0.0)]);
            let ((fp, np), (fm, nm)) = (pick(p)?, pick(m)?);
            Ok((wrap_angle(fp - fm) / (2.0 * h), np + nm))
        }
        (true, false) => {
            let (fp, n) = f(theta + h)?;
            Ok((wrap_angle(fp - f_theta) / h, n))
        }
        _ => {
            let (fm, n) = f(theta - h)?;
            Ok((wrap_angle(f_theta - fm) / h, n))
        }
    }
}

/// The cycle from θ (onset time `t0`) and f'(θ) with the evaluations the
/// derivative cost beyond the cycle's own: one cycle with the variational
/// equations ([`Simulator::cycle_slope`]); its event is bitwise what
/// [`Simulator::cycle`] gives. Where f has no derivative, the secant slope
/// of [`map_derivative`] and its cycles' evaluations.
pub fn cycle_with_derivative(
    sim: &Simulator,
    theta: f64,
    t0: f64,
) -> Result<(SlipEvent, f64, u64), SimError> {
    let (ev, d, n) = sim.cycle_slope(theta, t0)?;
    count_slope(d.is_err());
    match d {
        Ok(d) => Ok((ev, d, n)),
        Err(_) => {
            let (d, n) = central_difference(sim, theta, ev.theta_next)?;
            Ok((ev, d, n))
        }
    }
}

/// A fixed point θ* = f(θ*) found by the secant method on
/// g(θ) = wrap(f(θ) − θ) from θ0, to |g| ≤ `tol` in at most 60 steps; with
/// its multiplier f'(θ*). Iterating the map converges far too slowly where
/// f'(θ*) = 1 − O(ν) (pure creep), which is why this exists.
pub fn fixed_point(sim: &Simulator, theta0: f64, tol: f64) -> Result<Option<(f64, f64)>, SimError> {
    let g = |th: f64| -> Result<f64, SimError> { Ok(wrap_angle(sim.map(th)? - th)) };
    let p = sim.params();
    let mut a = theta0;
    let mut ga = g(a)?;
    // A second point a small step away, on the side the map points to.
    let mut b = theta0 + ga.signum() * 1e-3_f64.min(ga.abs().max(1e-7));
    if !is_on_exit_arc(p.kappa, p.theta_nu, b) {
        b = theta0 - (b - theta0);
    }
    let mut gb = g(b)?;
    for _ in 0..60 {
        if gb.abs() <= tol {
            let (d, _) = map_derivative(sim, b, b + gb)?;
            return Ok(Some((b, d)));
        }
        if gb == ga {
            return Ok(None);
        }
        let c = b - gb * (b - a) / (gb - ga);
        if !c.is_finite() || !is_on_exit_arc(p.kappa, p.theta_nu, c) {
            return Ok(None);
        }
        (a, ga) = (b, gb);
        b = c;
        gb = g(b)?;
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::SolverSettings;
    use crate::model::{Params, exit_arc};
    use crate::numerics::fixed_sample;

    /// The cycle with f'(θ) is bitwise the plain cycle (the tangents do
    /// not change a step), on chaotic points and next to both ends of the
    /// exit arc; its f' is the exact one where f has a derivative.
    #[test]
    fn cycle_with_derivative_is_the_cycle_with_the_exact_slope() {
        let p = Params {
            kappa: 18.95,
            gamma: 6.5,
            nu: 1e-3,
            theta_nu: 1.25,
            omega: 50.0,
        };
        let sim = Simulator::new(p, SolverSettings::default()).expect("valid");
        let (centre, half) = exit_arc(p.kappa, p.theta_nu);
        let mut thetas = fixed_sample::CHAOS[..20].to_vec();
        thetas.extend([centre - half + 5e-6, centre + half - 5e-6]);
        for (i, &th) in thetas.iter().enumerate() {
            let t0 = i as f64;
            let (ev, d, _) = cycle_with_derivative(&sim, th, t0).expect("a value");
            let alone = sim.cycle(th, t0, None).expect("a value");
            assert_eq!(format!("{ev:?}"), format!("{alone:?}"), "θ = {th}");
            let (_, exact, _) = sim.cycle_derivatives(th, t0).expect("a value");
            if let Ok(exact) = exact {
                assert_eq!(d.to_bits(), exact.d_theta.to_bits(), "θ = {th}");
            }
        }
    }

    #[test]
    fn window_pads_the_range_and_keeps_a_floor() {
        let (lo, hi) = return_map_window(&[0.4, 0.5, f64::NAN, 0.45]).expect("finite");
        assert!((lo - 0.375).abs() < 1e-12 && (hi - 0.525).abs() < 1e-12);
        let (lo, hi) = return_map_window(&[1.0]).expect("finite");
        assert!((lo - 0.98).abs() < 1e-12 && (hi - 1.02).abs() < 1e-12);
        assert_eq!(return_map_window(&[f64::NAN]), None);
    }

    #[test]
    fn graph_grid_keeps_only_onsets_on_the_exit_arc() {
        // κ = 1, θν = 0: the exit arc is (−π/2, π/2).
        let g = map_graph_grid(1.0, 0.0, -2.0, 2.0, 401);
        assert!(g.iter().all(|&t| t.abs() < std::f64::consts::FRAC_PI_2));
        assert!(g.windows(2).all(|p| p[0] < p[1]));
        let expected = (0..401)
            .filter(|i| (-2.0 + 0.01 * *i as f64).abs() < std::f64::consts::FRAC_PI_2)
            .count();
        assert!(
            (g.len() as i64 - expected as i64).abs() <= 1,
            "{} vs {expected}",
            g.len()
        );
    }
}
