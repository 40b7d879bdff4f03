//! The stick phase in closed form: the block rides with the surface,
//! p(t) = p_s + V t, until κ²x² + y² = 1.

/// The time for a block stuck at `p` (inside C) to reach C when carried at
/// velocity `v`: the positive root of a t² + b t + c = 0 with
/// a = κ²Vx² + Vy², b = 2(κ²x Vx + y Vy), c = κ²x² + y² − 1 < 0.
///
/// The root is taken in its cancellation-free form: when b > 0 the textbook
/// (−b + √D)/2a subtracts nearly equal numbers (b² ≫ 4a|c| once ν is
/// small), so we use the equivalent 2|c|/(b + √D) there. Returns `None` when
/// the point is not strictly inside C or the velocity is zero.
#[inline]
pub fn stick_exit_time(kappa: f64, p: [f64; 2], v: [f64; 2]) -> Option<f64> {
    let k2 = kappa * kappa;
    let a = k2 * v[0] * v[0] + v[1] * v[1];
    let b = 2.0 * (k2 * p[0] * v[0] + p[1] * v[1]);
    // 1 − κ²x² − y², formed so that a point near C keeps its small margin.
    let kx = kappa * p[0];
    let neg_c = (1.0 - p[1]) * (1.0 + p[1]) - kx * kx;
    if !(neg_c > 0.0) || !(a > 0.0) {
        return None;
    }
    let disc = b * b + 4.0 * a * neg_c;
    let sq = disc.sqrt();
    let t = if b > 0.0 {
        2.0 * neg_c / (b + sq)
    } else {
        (sq - b) / (2.0 * a)
    };
    (t.is_finite() && t >= 0.0).then_some(t)
}

/// Where the stick phase from `p` meets C, and after how long.
pub fn stick_exit_point(kappa: f64, p: [f64; 2], v: [f64; 2]) -> Option<([f64; 2], f64)> {
    let t = stick_exit_time(kappa, p, v)?;
    Some(([p[0] + v[0] * t, p[1] + v[1] * t], t))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// March with tiny steps until the point leaves C, then bisect: an
    /// independent computation of the exit time.
    fn brute_force(kappa: f64, p: [f64; 2], v: [f64; 2]) -> f64 {
        let inside = |t: f64| {
            let x = p[0] + v[0] * t;
            let y = p[1] + v[1] * t;
            kappa * kappa * x * x + y * y < 1.0
        };
        let speed = (v[0] * v[0] + v[1] * v[1]).sqrt();
        let dt = 1e-3 / speed / kappa.max(1.0);
        let mut t = 0.0;
        while inside(t + dt) {
            t += dt;
        }
        let (mut lo, mut hi) = (t, t + dt);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if inside(mid) { lo = mid } else { hi = mid }
        }
        0.5 * (lo + hi)
    }

    #[test]
    fn closed_form_matches_marching() {
        let cases = [
            (18.95, [0.01, 0.1], 1.0, 1e-3),
            (50.0, [0.012, 0.29], 0.3, 1e-4),
            (3.0, [0.2, 0.78], 0.7, 1e-3),
            (0.05, [-3.0, 0.5], 2.0, 1e-2),
            (10.0, [-0.026, -0.579], 1.2, 1e-3),
        ];
        for (k, p, tn, nu) in cases {
            let v = [nu * f64::cos(tn), nu * f64::sin(tn)];
            let (q, t) = stick_exit_point(k, p, v).unwrap();
            let tb = brute_force(k, p, v);
            assert!((t - tb).abs() <= 1e-9 * tb.max(1.0), "k={k}: {t} vs {tb}");
            assert!((k * k * q[0] * q[0] + q[1] * q[1] - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn tiny_speed_keeps_its_digits() {
        // With ν = 1e-8 the naive root loses most digits; the product of the
        // roots c/a is an independent check of the positive one.
        let k = 50.0;
        let p = [0.0122, 0.293];
        let tn = 0.3_f64;
        let v = [1e-8 * tn.cos(), 1e-8 * tn.sin()];
        let t = stick_exit_time(k, p, v).unwrap();
        let a = k * k * v[0] * v[0] + v[1] * v[1];
        let b = 2.0 * (k * k * p[0] * v[0] + p[1] * v[1]);
        let c = k * k * p[0] * p[0] + p[1] * p[1] - 1.0;
        let residual = a * t * t + b * t + c;
        assert!(residual.abs() < 1e-14, "residual {residual}");
        assert!(
            stick_exit_time(k, [0.1, 0.0], v).is_none(),
            "outside C has no stick phase"
        );
    }
}
