//! Chebyshev series on an interval: the points of the second kind, the
//! coefficients of the polynomial through values there, the test that a
//! series has resolved its function, its derivative, and Clenshaw's sum.
//!
//! The points of n = 2^m + 1 nest (those of n are every other point of
//! 2n − 1), so a piece sampled at 33 points and found unresolved reuses
//! them at 65. The interpolant of the map (`sim::MapInterpolant`) is built
//! from these parts.

use std::f64::consts::PI;

/// The n Chebyshev points of the second kind on [−1, 1], from 1 down to −1:
/// x_j = cos(jπ/(n − 1)). Written as sin(π(n − 1 − 2j)/(2(n − 1))) so that
/// they are symmetric to the last bit and the middle one is exactly 0.
pub fn points(n: usize) -> Vec<f64> {
    if n < 2 {
        return vec![0.0; n];
    }
    let m = (n - 1) as f64;
    (0..n)
        .map(|j| (PI * (m - 2.0 * j as f64) / (2.0 * m)).sin())
        .collect()
}

/// The coefficients c_0 … c_{n−1} of the polynomial of degree n − 1 that
/// takes `values[j]` at `points(n)[j]`: p(x) = Σ c_k T_k(x). A direct
/// O(n²) cosine sum (n ≤ 129 here, where it is a few µs, far below the map
/// evaluations that produced the values).
pub fn coefficients(values: &[f64]) -> Vec<f64> {
    let n = values.len();
    if n <= 1 {
        return values.to_vec();
    }
    let m = n - 1;
    // cos(π·i/m) for i in 0..2m: jk mod 2m indexes it.
    let table: Vec<f64> = (0..2 * m)
        .map(|i| (PI * i as f64 / m as f64).cos())
        .collect();
    let mut c = vec![0.0; n];
    for (k, ck) in c.iter_mut().enumerate() {
        let mut s = 0.0;
        for (j, &v) in values.iter().enumerate() {
            let w = if j == 0 || j == m { 0.5 } else { 1.0 };
            s += w * v * table[(j * k) % (2 * m)];
        }
        let w = if k == 0 || k == m { 0.5 } else { 1.0 };
        *ck = 2.0 * w * s / m as f64;
    }
    c
}

/// Σ c_k T_k(x) by Clenshaw's recurrence.
#[inline]
pub fn clenshaw(c: &[f64], x: f64) -> f64 {
    let (mut b1, mut b2) = (0.0, 0.0);
    let x2 = 2.0 * x;
    for &ck in c.iter().skip(1).rev() {
        let b = ck + x2 * b1 - b2;
        b2 = b1;
        b1 = b;
    }
    c.first().copied().unwrap_or(0.0) + x * b1 - b2
}

/// The coefficients of the derivative d/dx of Σ c_k T_k(x) (one fewer).
pub fn derivative(c: &[f64]) -> Vec<f64> {
    let n = c.len();
    if n <= 1 {
        return vec![0.0];
    }
    let mut d = vec![0.0; n - 1];
    // d_{k−1} = d_{k+1} + 2k c_k, from the top down; d_0 is halved.
    for k in (1..n).rev() {
        let above = if k + 1 < n - 1 { d[k + 1] } else { 0.0 };
        d[k - 1] = above + 2.0 * k as f64 * c[k];
    }
    d[0] *= 0.5;
    d
}

/// Whether the series has resolved its function to the absolute tolerance
/// `tol`: the coefficients have fallen below tol/8 over the last eighth of
/// the series (at least its last 4). The sum of the dropped tail bounds the
/// interpolation error where the coefficients decay geometrically, and a
/// function that only plateaus at the noise of its samples passes once the
/// plateau is below the tolerance. The a-posteriori check at independent
/// points is what the interpolant finally trusts.
pub fn resolved(c: &[f64], tol: f64) -> bool {
    let n = c.len();
    if n < 9 {
        return false;
    }
    let tail = (n / 8).max(4);
    c[n - tail..].iter().all(|x| x.abs() <= tol / 8.0)
}

/// The shortest leading part of a resolved series whose dropped tail sums
/// to at most `tol`/4 (at least 2 coefficients are kept).
pub fn chop(c: &[f64], tol: f64) -> Vec<f64> {
    let mut n = c.len();
    let mut dropped = 0.0;
    while n > 2 {
        let next = dropped + c[n - 1].abs();
        if next > tol / 4.0 {
            break;
        }
        dropped = next;
        n -= 1;
    }
    c[..n].to_vec()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// e^x through 17 points: the coefficients are 2·I_k(1) (modified
    /// Bessel functions; I_0(1) alone), the sum reproduces e^x to
    /// rounding, and the derivative's series reproduces e^x as well.
    #[test]
    fn exp_is_resolved_and_differentiated() {
        let x = points(17);
        let c = coefficients(&x.iter().map(|t| t.exp()).collect::<Vec<_>>());
        assert!((c[0] - 1.266_065_877_752_008_4).abs() < 1e-15, "{}", c[0]);
        assert!((c[1] - 2.0 * 0.565_159_103_992_485).abs() < 1e-15);
        // c_13 ≈ 2·I_13(1) ≈ 3.9e-14: resolved to 1e-12, not to 1e-14.
        assert!(resolved(&c, 1e-12) && !resolved(&c, 1e-14));
        let d = derivative(&c);
        for i in 0..101 {
            let t = -1.0 + 0.02 * i as f64;
            assert!((clenshaw(&c, t) - t.exp()).abs() < 5e-15, "{t}");
            // The derivative loses up to ~n² roundings at the ends.
            assert!((clenshaw(&d, t) - t.exp()).abs() < 1e-12, "{t}");
        }
        let short = chop(&c, 1e-10);
        assert!(short.len() < 14 && short.len() > 8, "{}", short.len());
        assert!((clenshaw(&short, 0.3) - 0.3f64.exp()).abs() < 1e-10);
    }

    /// |x| is not resolved by 129 points; the nesting of the points holds.
    #[test]
    fn a_kink_is_not_resolved_and_points_nest() {
        let x = points(129);
        let c = coefficients(&x.iter().map(|t| t.abs()).collect::<Vec<_>>());
        assert!(!resolved(&c, 1e-10));
        let coarse = points(65);
        for (j, p) in coarse.iter().enumerate() {
            assert_eq!(p.to_bits(), x[2 * j].to_bits());
        }
        assert_eq!(x[64], 0.0);
    }
}
