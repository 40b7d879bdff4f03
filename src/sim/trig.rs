//! atan2 and sin/cos for the acceleration phase's friction direction, the
//! hot spot of the whole map: glibc's atan2 and sincos were ~40% of all
//! instructions (about 130 and 95 per call), because they handle every
//! argument range with correct rounding. Here the ranges are known (Δ is an
//! angle in (−π, π], the turn is at most π in size), so a short argument
//! reduction and fixed polynomials give the same results to a few ulp at a
//! third of the cost. The tests check them against `std` over millions of
//! arguments.

// Published coefficients, kept digit for digit as their sources print them.
#![allow(clippy::excessive_precision)]

use std::f64::consts::{FRAC_PI_2, PI};

/// atan(x) for 0 ≤ x ≤ 1: Cephes' degree-4/5 rational approximation
/// (peak relative error 2.6e-18 on [0, 0.66]) with its range reduction
/// atan(x) = π/4 + atan((x − 1)/(x + 1)) above 0.66.
#[inline(always)]
fn atan_unit(x: f64) -> f64 {
    const P: [f64; 5] = [
        -8.750608600031904122785e-1,
        -1.615753718733365076637e1,
        -7.500855792314704667340e1,
        -1.228866684490136173410e2,
        -6.485021904942025371773e1,
    ];
    const Q: [f64; 5] = [
        2.485846490142306297962e1,
        1.650270098316988542046e2,
        4.328810604912902668951e2,
        4.853903996359136964868e2,
        1.945506571482613964425e2,
    ];
    // The low half of π/4 in double: adding it keeps the reduced branch
    // accurate to the last bit.
    const MOREBITS_HALF: f64 = 0.5 * 6.123233995736765886130e-17;
    let (x, base, extra) = if x > 0.66 {
        (
            (x - 1.0) / (x + 1.0),
            std::f64::consts::FRAC_PI_4,
            MOREBITS_HALF,
        )
    } else {
        (x, 0.0, 0.0)
    };
    let z = x * x;
    let num = (((P[0] * z + P[1]) * z + P[2]) * z + P[3]) * z + P[4];
    let den = ((((z + Q[0]) * z + Q[1]) * z + Q[2]) * z + Q[3]) * z + Q[4];
    base + (x + x * (z * num / den) + extra)
}

/// atan2(y, x) in (−π, π] (−π never occurs: a zero y counts as positive).
#[inline(always)]
pub fn atan2(y: f64, x: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    let big = ax.max(ay);
    if !(big > 0.0) {
        return 0.0;
    }
    let r = ax.min(ay) / big;
    let mut a = atan_unit(r);
    if ay > ax {
        a = FRAC_PI_2 - a;
    }
    if x < 0.0 {
        a = PI - a;
    }
    if y < 0.0 { -a } else { a }
}

/// (sin u, cos u) for |u| ≤ π (larger arguments fall back to `std`): Taylor
/// polynomials on u/2 ∈ [−π/2, π/2] (remainder below 3e-18), then the
/// double-angle formulas.
#[inline(always)]
pub fn sin_cos(u: f64) -> (f64, f64) {
    if !(u.abs() <= PI) {
        return u.sin_cos();
    }
    let v = 0.5 * u;
    let z = v * v;
    // 1/(2k+1)! and 1/(2k)! for the two series.
    const S: [f64; 11] = [
        -1.0 / 6.0,
        1.0 / 120.0,
        -1.0 / 5040.0,
        1.0 / 362880.0,
        -1.0 / 39916800.0,
        1.0 / 6227020800.0,
        -1.0 / 1307674368000.0,
        1.0 / 355687428096000.0,
        -1.0 / 121645100408832000.0,
        1.0 / 51090942171709440000.0,
        -1.0 / 25852016738884976640000.0,
    ];
    const C: [f64; 11] = [
        -1.0 / 2.0,
        1.0 / 24.0,
        -1.0 / 720.0,
        1.0 / 40320.0,
        -1.0 / 3628800.0,
        1.0 / 479001600.0,
        -1.0 / 87178291200.0,
        1.0 / 20922789888000.0,
        -1.0 / 6402373705728000.0,
        1.0 / 2432902008176640000.0,
        -1.0 / 1124000727777607680000.0,
    ];
    let mut ps = S[10];
    let mut pc = C[10];
    for i in (0..10).rev() {
        ps = ps * z + S[i];
        pc = pc * z + C[i];
    }
    let s = v + v * z * ps;
    let c = 1.0 + z * pc;
    (2.0 * s * c, (c - s) * (c + s))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (xorshift) so the test needs no crate.
    fn uniform(state: &mut u64) -> f64 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn atan2_matches_std_to_a_few_ulp() {
        let mut st = 0x9e3779b97f4a7c15;
        let mut worst = 0.0f64;
        for i in 0..2_000_000 {
            let scale = 10f64.powi(i % 13 - 6);
            let y = (2.0 * uniform(&mut st) - 1.0) * scale;
            let x = 2.0 * uniform(&mut st) - 1.0;
            let d = (atan2(y, x) - y.atan2(x)).abs();
            worst = worst.max(d);
        }
        assert!(worst <= 4.5e-16, "worst |Δ| = {worst:e}");
        // Axes and the seam: (−π, π].
        assert_eq!(atan2(0.0, 1.0), 0.0);
        assert!((atan2(1.0, 0.0) - FRAC_PI_2).abs() < 1e-16);
        assert!((atan2(0.0, -1.0) - PI).abs() < 1e-16);
        assert!((atan2(-0.0, -1.0) - PI).abs() < 1e-16);
        assert!((atan2(-1e-300, -1.0) + PI).abs() < 1e-15);
        assert_eq!(atan2(0.0, 0.0), 0.0);
    }

    #[test]
    fn sin_cos_matches_std_to_a_few_ulp() {
        let mut st = 0x1234567887654321;
        let mut worst = 0.0f64;
        for i in 0..2_000_000 {
            let scale = if i % 3 == 0 { 1e-6 } else { 1.0 };
            let u = (2.0 * uniform(&mut st) - 1.0) * PI * scale;
            let (s, c) = sin_cos(u);
            let (s0, c0) = u.sin_cos();
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
        }
        // Within 3 ulp of values of size 1.
        assert!(worst <= 6.7e-16, "worst |Δ| = {worst:e}");
        let (s, c) = sin_cos(7.0);
        assert_eq!((s, c), 7f64.sin_cos());
    }
}
