//! atan2, sin/cos and e^x − 1 for the acceleration phase's friction
//! direction, the hot spot of the whole map: glibc's atan2 and sincos were ~40% of all
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

/// ±1/(2k+3)!: sin u = u + u·Σ S[k]·u^(2k+2) (Taylor).
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
/// ±1/(2k+2)!: cos u = 1 + Σ C[k]·u^(2k+2) (Taylor).
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

/// 1/(i+2)!: e^x − 1 = x + x²·Σ EXPM1[i]·xⁱ (Taylor).
const EXPM1: [f64; 12] = [
    1.0 / 2.0,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5040.0,
    1.0 / 40320.0,
    1.0 / 362880.0,
    1.0 / 3628800.0,
    1.0 / 39916800.0,
    1.0 / 479001600.0,
    1.0 / 6227020800.0,
];

/// (sin u, cos u) for |u| ≤ π (larger arguments fall back to `std`): Taylor
/// polynomials on u/2 ∈ [−π/2, π/2] (remainder below 3e-18), then the
/// double-angle formulas.
#[inline(always)]
pub fn sin_cos(u: f64) -> (f64, f64) {
    let au = u.abs();
    // The friction's turn is below 1e-3 in about half of a slip's
    // acceleration-field evaluations and below 1/2 in nearly all: shorter
    // polynomials there take levels off the chain each step waits for
    // (the branch follows the slip's slow growth, so it predicts well).
    if au < 1e-3 {
        // Remainders u⁷/7! and u⁸/8!: below 1e-24.
        let z = u * u;
        let s = u + u * z * (S[0] + z * S[1]);
        let c = 1.0 + z * (C[0] + z * (C[1] + z * C[2]));
        return (s, c);
    }
    if au <= 0.5 {
        // Taylor to u¹⁵ and u¹⁶ (remainders below 1e-19), Estrin's scheme.
        let z = u * u;
        let z2 = z * z;
        let z4 = z2 * z2;
        let pair = |k: &[f64; 11], i: usize| k[i] + z * k[i + 1];
        let ps = (pair(&S, 0) + z2 * pair(&S, 2)) + z4 * (pair(&S, 4) + z2 * S[6]);
        let pc = (pair(&C, 0) + z2 * pair(&C, 2)) + z4 * (pair(&C, 4) + z2 * pair(&C, 6));
        return (u + u * z * ps, 1.0 + z * pc);
    }
    if !(au <= PI) {
        return u.sin_cos();
    }
    let v = 0.5 * u;
    let z = v * v;
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

/// e^x − 1 for x ≤ 0, to a few ulp (relative), for the acceleration phase's
/// turn −Δ(1 − e^(−Ω v_r)). glibc's expm1 sits on that field's critical path
/// (it cost ~20 of its ~97 ns, chained); this one is branch-light and short:
/// above −0.35 the Taylor series to x¹³/13! (remainder below 1.5e-17
/// relative), below it e^x = 2^(k/32)·e^r with a 32-entry table of 2^(j/32)
/// (correctly rounded), |r| ≤ ln 2/64 and e^r − 1 to r⁷/7!; from −40 on the
/// result is −1 to the last bit.
#[inline(always)]
pub fn exp_m1_neg(x: f64) -> f64 {
    if x > -1e-3 {
        // Early in a slip Ω v_r is tiny: x + x²/2 + … + x⁶/6! (remainder
        // |x|⁷/7! < 2e-25).
        let z = x * x;
        let p = (EXPM1[0] + x * EXPM1[1]) + z * ((EXPM1[2] + x * EXPM1[3]) + z * EXPM1[4]);
        return x + z * p;
    }
    if x > -0.35 {
        // x + x²·Σ_{i<12} xⁱ/(i+2)!, by Estrin's scheme.
        let z = x * x;
        let z2 = z * z;
        let z4 = z2 * z2;
        let p01 = EXPM1[1] * x + EXPM1[0];
        let p23 = EXPM1[3] * x + EXPM1[2];
        let p45 = EXPM1[5] * x + EXPM1[4];
        let p67 = EXPM1[7] * x + EXPM1[6];
        let p89 = EXPM1[9] * x + EXPM1[8];
        let pab = EXPM1[11] * x + EXPM1[10];
        let p03 = p23 * z + p01;
        let p47 = p67 * z + p45;
        let p8b = pab * z + p89;
        let p = (p8b * z4 + p47 * z2) + p03;
        return x + z * p;
    }
    if !(x >= -40.0) {
        // e^x < 4.3e-18: −1 + e^x rounds to −1 (NaN stays NaN).
        return if x.is_nan() { x } else { -1.0 };
    }
    const T: [f64; 32] = [
        1.0,
        1.0218971486541166,
        1.0442737824274138,
        1.0671404006768237,
        1.0905077326652577,
        1.1143867425958924,
        1.1387886347566916,
        1.1637248587775775,
        1.189207115002721,
        1.215247359980469,
        1.241857812073484,
        1.2690509571917332,
        1.2968395546510096,
        1.3252366431597413,
        1.3542555469368927,
        1.383909881963832,
        std::f64::consts::SQRT_2,
        1.4451808069770467,
        1.4768261459394993,
        1.5091644275934228,
        1.5422108254079407,
        1.5759808451078865,
        1.6104903319492543,
        1.645755478153965,
        1.681792830507429,
        1.718619298122478,
        1.7562521603732995,
        1.7947090750031072,
        1.8340080864093424,
        1.8741676341103,
        1.9152065613971474,
        1.9571441241754002,
    ];
    // ln 2/32 in two parts, the high one with 22 trailing zero bits so
    // that k·HI is exact for |k| < 2^22.
    const LN2_32_HI: f64 = 0.02166084937925916;
    const LN2_32_LO: f64 = 1.3239129268154012e-11;
    const INV_LN2_32: f64 = 46.16624130844683;
    let kf = (x * INV_LN2_32).round();
    let r = (x - kf * LN2_32_HI) - kf * LN2_32_LO;
    let z = r * r;
    // e^r − 1 = r + r²(1/2 + r/6 + r²(1/24 + r/120 + r²(1/720 + r/5040))).
    let p = r + z
        * ((0.5 + r * (1.0 / 6.0))
            + z * ((1.0 / 24.0 + r * (1.0 / 120.0)) + z * (1.0 / 720.0 + r * (1.0 / 5040.0))));
    let k = kf as i32;
    // k = 32m + j, j in [0, 32): 2^(k/32) = 2^m·T[j], exact as a product.
    let scale = f64::from_bits(((1023 + (k >> 5)) as u64) << 52) * T[(k & 31) as usize];
    // e^x − 1 = scale·(e^r − 1) + (scale − 1); the result is at most −0.29,
    // so the last addition's rounding is a few ulp of it.
    scale * p + (scale - 1.0)
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
        let (mut worst, mut worst_rel) = (0.0f64, 0.0f64);
        for i in 0..2_000_000 {
            let scale = 10f64.powi(i % 13 - 6);
            let y = (2.0 * uniform(&mut st) - 1.0) * scale;
            // Now and then a pair as small as the first stages of a slip
            // make (v_r ~ 1e-30 … 1e-20).
            let tiny = if i % 7 == 0 { 1e-27 } else { 1.0 };
            let x = (2.0 * uniform(&mut st) - 1.0) * tiny;
            let y = y * tiny;
            let (a, a0) = (atan2(y, x), y.atan2(x));
            worst = worst.max((a - a0).abs());
            worst_rel = worst_rel.max(((a - a0) / a0).abs());
        }
        assert!(worst <= 4.5e-16, "worst |Δ| = {worst:e}");
        // Small angles keep their digits too.
        assert!(worst_rel <= 6.7e-16, "worst relative error {worst_rel:e}");
        // Axes and the seam: (−π, π].
        assert_eq!(atan2(0.0, 1.0), 0.0);
        assert!((atan2(1.0, 0.0) - FRAC_PI_2).abs() < 1e-16);
        assert!((atan2(0.0, -1.0) - PI).abs() < 1e-16);
        assert!((atan2(-0.0, -1.0) - PI).abs() < 1e-16);
        assert!((atan2(-1e-300, -1.0) + PI).abs() < 1e-15);
        assert_eq!(atan2(0.0, 0.0), 0.0);
    }

    #[test]
    fn exp_m1_neg_matches_std_to_a_few_ulp() {
        let mut st = 0x0ddba11cafef00d5;
        let mut worst = 0.0f64;
        for i in 0..2_000_000 {
            // Every scale the turn meets: Ω v_r from 1e-12 to 60.
            let x = -(10f64.powf(-12.0 + 13.8 * uniform(&mut st)));
            let (a, b) = (exp_m1_neg(x), x.exp_m1());
            worst = worst.max(((a - b) / b).abs());
            if i % 100_000 == 0 {
                assert!((-1.0..=0.0).contains(&a), "{x}: {a}");
            }
        }
        // Within 4 ulp, relative (3.8e-16 seen).
        assert!(worst <= 9e-16, "worst relative error {worst:e}");
        assert_eq!(exp_m1_neg(0.0), 0.0);
        assert_eq!(exp_m1_neg(-40.0), (-40f64).exp_m1());
        assert_eq!(exp_m1_neg(-1e3), -1.0);
        assert!(exp_m1_neg(f64::NAN).is_nan());
    }

    #[test]
    fn sin_cos_matches_std_to_a_few_ulp() {
        let mut st = 0x1234567887654321;
        let mut worst = 0.0f64;
        let mut worst_rel = 0.0f64;
        for i in 0..2_000_000 {
            // Every polynomial's range, and both sides of each switch.
            let scale = [1e-6, 1.0, 3.2e-4, 1.6e-1, 0.5 / PI][i % 5];
            let u = (2.0 * uniform(&mut st) - 1.0) * PI * scale;
            let (s, c) = sin_cos(u);
            let (s0, c0) = u.sin_cos();
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
            if u.abs() <= 1.0 {
                worst_rel = worst_rel.max(((s - s0) / s0).abs());
            }
        }
        // Within 3 ulp of values of size 1, and sin within 3 ulp relative
        // where the turns are (a small turn must not lose its digits).
        assert!(worst <= 6.7e-16, "worst |Δ| = {worst:e}");
        assert!(
            worst_rel <= 6.7e-16,
            "worst relative error of sin {worst_rel:e}"
        );
        let (s, c) = sin_cos(7.0);
        assert_eq!((s, c), 7f64.sin_cos());
    }
}
