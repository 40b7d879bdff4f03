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

// Both functions sit on the critical path of every acceleration-phase
// evaluation (state → Δ → turn → friction direction), and an integration step
// waits for each stage before it can start the next: their *latency*, not
// their throughput, is what a map iterate pays. So the polynomials are
// evaluated by Estrin's scheme (independent pairs combined with z², z⁴, z⁸:
// about 4 dependent multiply-adds instead of Horner's 10), and atan2 divides
// once before its rational function instead of up to twice. On the Fig. 3b
// attractor this took the two from 45 % to about 25 % of all samples.

/// atan(small/big) for 0 ≤ small ≤ big, big > 0: Cephes' degree-4/5 rational approximation (peak relative
/// error 2.6e-18 on [0, 0.66]) with its range reduction
/// atan(r) = π/4 + atan((r − 1)/(r + 1)) above 0.66, here
/// (small − big)/(small + big): one division either way.
#[inline(always)]
fn atan_ratio(small: f64, big: f64) -> f64 {
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
    let (x, base, extra) = if small > 0.66 * big {
        (
            (small - big) / (small + big),
            std::f64::consts::FRAC_PI_4,
            MOREBITS_HALF,
        )
    } else {
        (small / big, 0.0, 0.0)
    };
    let z = x * x;
    let z2 = z * z;
    let z4 = z2 * z2;
    // num = P0 z⁴ + P1 z³ + P2 z² + P3 z + P4, den = z⁵ + Q0 z⁴ + … + Q4.
    let num = (P[3] * z + P[4]) + z2 * (P[1] * z + P[2]) + z4 * P[0];
    let den = (Q[3] * z + Q[4]) + z2 * (Q[1] * z + Q[2]) + z4 * (z + Q[0]);
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
    let mut a = atan_ratio(ax.min(ay), big);
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
    let z2 = z * z;
    let z4 = z2 * z2;
    let z8 = z4 * z4;
    // Σ_{i ≤ 10} K[i] zⁱ by Estrin's scheme.
    let estrin = |k: &[f64; 11]| {
        let p01 = k[1] * z + k[0];
        let p23 = k[3] * z + k[2];
        let p45 = k[5] * z + k[4];
        let p67 = k[7] * z + k[6];
        let p89 = k[9] * z + k[8];
        let p03 = p23 * z2 + p01;
        let p47 = p67 * z2 + p45;
        let p8a = k[10] * z2 + p89;
        (p8a * z8 + p47 * z4) + p03
    };
    let ps = estrin(&S);
    let pc = estrin(&C);
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
