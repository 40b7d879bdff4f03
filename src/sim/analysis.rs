//! The derivative of the map, and the grid its graph is drawn on (periods
//! are detected in `super::period`).

use super::{SimError, Simulator, SlipEvent, cycle_pair, cycles_in_lanes};
use crate::model::{is_on_exit_arc, wrap_angle};

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

/// The step of the central difference for f'(θ).
pub const DERIVATIVE_STEP: f64 = 1e-5;

/// f'(θ), and the right-hand-side evaluations it cost, by a central difference with step h = 1e-5, given f(θ) = `f_theta`
/// (used only when one side leaves the exit arc, for a one-sided
/// difference). Its error is about ε/h + h² |f'''|/6 for a map error ε:
/// with ε ≈ 1e-10 that is ~1e-5 absolute, far below what the Lyapunov
/// exponent's statistical error is over a few hundred iterates.
pub fn map_derivative(sim: &Simulator, theta: f64, f_theta: f64) -> Result<(f64, u64), SimError> {
    let h = DERIVATIVE_STEP;
    let p = sim.params();
    let up = is_on_exit_arc(p.kappa, p.theta_nu, theta + h);
    let down = is_on_exit_arc(p.kappa, p.theta_nu, theta - h);
    let pick = |r: Result<SlipEvent, SimError>| r.map(|e| (e.theta_next, e.rhs_evals));
    let f = |th: f64| pick(sim.cycle(th, 0.0, None));
    match (up, down) {
        (true, true) => {
            // Two independent cycles: their slips are stepped together
            // (`cycle_pair`), bitwise the values `f` gives, ~1.2× sooner.
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

/// The cycle from θ (onset time `t0`) and f'(θ) with the evaluations it
/// cost: `(event, f'(θ), evaluations of f')`, bitwise what
/// [`Simulator::cycle`] and then [`map_derivative`] give. When both sides
/// of the central difference are on the exit arc, the cycle and the
/// difference's two cycles are independent, so the three are stepped
/// together in lanes (`sim::cycles_in_lanes`): an orbit with its Lyapunov
/// exponent takes about the time of the cycle alone per kept iterate
/// instead of that plus a pair. An error of the cycle comes first, as in
/// the sequence.
pub fn cycle_with_derivative(
    sim: &Simulator,
    theta: f64,
    t0: f64,
) -> Result<(SlipEvent, f64, u64), SimError> {
    let h = DERIVATIVE_STEP;
    let p = sim.params();
    if is_on_exit_arc(p.kappa, p.theta_nu, theta + h)
        && is_on_exit_arc(p.kappa, p.theta_nu, theta - h)
    {
        let tasks = [
            (sim, theta, t0),
            (sim, theta + h, 0.0),
            (sim, theta - h, 0.0),
        ];
        // One result per task, in order (the fallback cannot happen).
        let mut r = cycles_in_lanes(&tasks).into_iter();
        let mut next = || r.next().unwrap_or(Err(SimError::Cancelled));
        let (ev, plus, minus) = (next()?, next()?, next()?);
        let d = wrap_angle(plus.theta_next - minus.theta_next) / (2.0 * h);
        return Ok((ev, d, plus.rhs_evals + minus.rhs_evals));
    }
    let ev = sim.cycle(theta, t0, None)?;
    let (d, n) = map_derivative(sim, ev.theta, ev.theta_next)?;
    Ok((ev, d, n))
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

    /// The cycle and f'(θ) in lanes are bitwise the cycle and then
    /// `map_derivative`: on chaotic points (a central difference) and next
    /// to both ends of the exit arc (one-sided, run in sequence).
    #[test]
    fn cycle_with_derivative_is_the_cycle_then_the_derivative() {
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
            let (ev, d, n) = cycle_with_derivative(&sim, th, t0).expect("a value");
            let alone = sim.cycle(th, t0, None).expect("a value");
            let (d_alone, n_alone) = map_derivative(&sim, th, alone.theta_next).expect("a value");
            assert_eq!(format!("{ev:?}"), format!("{alone:?}"), "θ = {th}");
            assert_eq!((d.to_bits(), n), (d_alone.to_bits(), n_alone), "θ = {th}");
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
