//! The curve C (κ²x² + y² = 1), the critical ellipse (κ³x² + y² = γ²), the
//! angle θ that labels points of C, and the exit arc where a stick phase can
//! end.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// The largest |θ| the bifurcation diagram's θ axis takes (`figure
/// --theta-from` and `--theta-to`, a session's zoom), in radians: θν's
/// bound in `bifurcation` and `continue`. θ is an angle: an axis wider
/// shows nothing more.
pub const MAX_ABS_THETA: f64 = 1000.0;

/// Maps an angle into (−π, π].
#[inline]
pub fn wrap_angle(a: f64) -> f64 {
    if a > -PI && a <= PI {
        return a;
    }
    let r = a.rem_euclid(TAU); // [0, 2π)
    if r > PI { r - TAU } else { r }
}

/// The point of C labelled θ: x = cos(θ)/κ, y = sin(θ) (docs/model.md).
#[inline]
pub fn point_from_theta(kappa: f64, theta: f64) -> [f64; 2] {
    let (s, c) = theta.sin_cos();
    [c / kappa, s]
}

/// θ = atan2(y, κx): the direction opposite to the elastic force at (x, y).
#[inline]
pub fn theta_from_point(kappa: f64, p: [f64; 2]) -> f64 {
    p[1].atan2(kappa * p[0])
}

/// The elastic energy ½(κx² + y²).
#[inline]
pub fn elastic_energy(kappa: f64, p: [f64; 2]) -> f64 {
    0.5 * (kappa * p[0] * p[0] + p[1] * p[1])
}

/// A point of C at the parameter s ∈ [0, 2π) (for drawing).
pub fn ellipse_c_point(kappa: f64, s: f64) -> [f64; 2] {
    point_from_theta(kappa, s)
}

/// A point of the critical ellipse κ³x² + y² = γ² at the parameter s (for
/// drawing): where the onset's linear stability changes (paper, Fig. 2).
pub fn critical_ellipse_point(kappa: f64, gamma: f64, s: f64) -> [f64; 2] {
    let (sn, c) = s.sin_cos();
    [gamma * c / kappa.powf(1.5), gamma * sn]
}

/// The exit arc as (centre ψ, half-width π/2): the onsets θ with
/// κ cos θ cos θν + sin θ sin θν > 0, i.e. cos(θ − ψ) > 0 with
/// ψ = atan2(sin θν, κ cos θν). Only there can the surface carry a sticking
/// block outwards through C.
#[inline]
pub fn exit_arc(kappa: f64, theta_nu: f64) -> (f64, f64) {
    let (s, c) = theta_nu.sin_cos();
    (s.atan2(kappa * c), FRAC_PI_2)
}

/// Whether θ lies strictly on the exit arc.
#[inline]
pub fn is_on_exit_arc(kappa: f64, theta_nu: f64, theta: f64) -> bool {
    let (sn, cn) = theta_nu.sin_cos();
    let (s, c) = theta.sin_cos();
    kappa * c * cn + s * sn > 0.0
}

/// Moves θ onto the exit arc, at least `margin` radians inside its ends.
/// Used when a sweep continues from the previous column's attractor and θν
/// has moved the arc under it.
pub fn project_onto_exit_arc(kappa: f64, theta_nu: f64, theta: f64, margin: f64) -> f64 {
    let (psi, half) = exit_arc(kappa, theta_nu);
    let lim = half - margin.clamp(0.0, half);
    let d = wrap_angle(theta - psi);
    wrap_angle(psi + d.clamp(-lim, lim))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_lands_in_half_open_interval() {
        assert_eq!(wrap_angle(PI), PI);
        assert!((wrap_angle(-PI) - PI).abs() < 1e-15);
        assert!((wrap_angle(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(0.5 + 4.0 * TAU) - 0.5).abs() < 1e-12);
        assert!((wrap_angle(-0.5 - TAU) + 0.5).abs() < 1e-12);
    }

    #[test]
    fn theta_round_trips_through_c() {
        for &k in &[0.05, 1.0, 18.95, 50.0] {
            for i in 0..64 {
                let th = wrap_angle(-3.1 + 0.1 * i as f64);
                let p = point_from_theta(k, th);
                assert!((k * k * p[0] * p[0] + p[1] * p[1] - 1.0).abs() < 1e-14);
                assert!((theta_from_point(k, p) - th).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn exit_arc_agrees_with_the_normal_test() {
        for &k in &[0.1, 3.0, 50.0] {
            for &tn in &[0.0, 0.3, 1.2, 1.5, 2.5, -1.0] {
                let (psi, half) = exit_arc(k, tn);
                for i in 0..200 {
                    let th = -PI + 0.0314 * i as f64;
                    let inside = wrap_angle(th - psi).abs() < half;
                    if (wrap_angle(th - psi).abs() - half).abs() > 1e-9 {
                        assert_eq!(inside, is_on_exit_arc(k, tn, th), "k={k} tn={tn} th={th}");
                    }
                }
                let q = project_onto_exit_arc(k, tn, psi + 3.0, 1e-3);
                assert!(is_on_exit_arc(k, tn, q));
            }
        }
    }
}
