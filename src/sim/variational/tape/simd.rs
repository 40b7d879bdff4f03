//! The adjoint step four wide, for x86-64 with AVX2 and FMA (see the
//! declaration in `tape.rs`).

use std::arch::x86_64::*;

use super::{Field, Lin, Rec, SlipField, Tableau};

/// λ before the step from λ after it, and the step's share of the
/// field parameters' gradient (κ, 2γ, Ω, V_x, V_y).
///
/// # Safety
/// Only in code compiled with the `avx2` and `fma` target features.
#[inline(always)]
pub(super) unsafe fn step_adjoint<const S: usize>(
    tab: &Tableau<S>,
    h: f64,
    sf: &SlipField,
    field: Field,
    recs: &[Rec],
    lam: [f64; 4],
) -> ([f64; 4], [f64; 5]) {
    // SAFETY (all intrinsics): the caller's target features.
    unsafe {
        let l = _mm256_loadu_pd(lam.as_ptr());
        let mut nu = [_mm256_setzero_pd(); S];
        for (n, b) in nu.iter_mut().zip(tab.b) {
            *n = _mm256_mul_pd(_mm256_set1_pd(h * b), l);
        }
        let mut acc = l;
        let mut pk = _mm256_setzero_pd();
        let mut pv = _mm256_setzero_pd();
        // Each stage's Jacobian is formed one stage ahead of its use:
        // it waits for nothing, and so runs while the chain does.
        let mut next = super::jacobian(sf, field, &recs[S - 1]);
        // (The last stage's `next` is not read.)
        #[allow(unused_assignments)]
        {
            stages_rev!(S, i => {
                let lin = next;
                if i > 0 {
                    next = super::jacobian(sf, field, &recs[i - 1]);
                }
                stage_adjoint(tab, h, i, &lin, &mut nu, &mut acc, &mut pk, &mut pv)
            });
        }
        let mut out = [0.0; 4];
        _mm256_storeu_pd(out.as_mut_ptr(), acc);
        let (mut k, mut v) = ([0.0; 4], [0.0; 4]);
        _mm256_storeu_pd(k.as_mut_ptr(), pk);
        _mm256_storeu_pd(v.as_mut_ptr(), pv);
        (out, [k[0], k[1], k[2], v[0], v[1]])
    }
}

/// Stage `i` of [`step_adjoint`] (a function, not a closure, so that it
/// is inlined with its caller's target features).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn stage_adjoint<const S: usize>(
    tab: &Tableau<S>,
    h: f64,
    i: usize,
    lin: &Lin,
    nu: &mut [__m256d; S],
    acc: &mut __m256d,
    pk: &mut __m256d,
    pv: &mut __m256d,
) {
    // SAFETY (all intrinsics): the caller's target features.
    unsafe {
        let n = nu[i];
        let hi = _mm256_permute2f128_pd::<0x11>(n, n);
        let n2 = _mm256_permute_pd::<0b0000>(hi);
        let n3 = _mm256_permute_pd::<0b1111>(hi);
        // (0, 0, ν₀, ν₁).
        let sh = _mm256_permute2f128_pd::<0x08>(n, n);
        let r2 = _mm256_loadu_pd(lin.js[0].as_ptr());
        let r3 = _mm256_loadu_pd(lin.js[1].as_ptr());
        let mu = _mm256_fmadd_pd(r2, n2, _mm256_fmadd_pd(r3, n3, sh));
        *acc = _mm256_add_pd(*acc, mu);
        let [p2, p3] = lin.jp;
        let p2 = _mm256_set_pd(0.0, p2[2], p2[1], p2[0]);
        let p3 = _mm256_set_pd(0.0, p3[2], p3[1], p3[0]);
        *pk = _mm256_fmadd_pd(p2, n2, _mm256_fmadd_pd(p3, n3, *pk));
        *pv = _mm256_add_pd(*pv, n);
        for j in 0..i {
            let a = tab.a[i][j];
            if a != 0.0 {
                nu[j] = _mm256_fmadd_pd(_mm256_set1_pd(h * a), mu, nu[j]);
            }
        }
    }
}
