//! The variational equations' right-hand side as a small matrix product.
//!
//! The tangent's equation is linear: K = J_y·Y + J_p·P, with J the slip
//! field's Jacobian at the stage's state and P the parameters' seeds. So
//! each stage evaluates the field once, forms J from the values it has
//! already computed (a few dozen operations, whatever the number of
//! directions), and applies it to every direction: eight multiply-adds
//! per direction for the two nontrivial rows, instead of pushing every
//! elementary operation of the field through all directions.
//!
//! The first two rows are ẋ = v_r + V: K₀ = Y₂ + P_V₀, K₁ = Y₃ + P_V₁.
//! Rows 2 and 3 (the relative acceleration) depend on the state and on κ,
//! 2γ and Ω.

use super::{Jet, TanField};
use crate::integrate::State;
use crate::sim::field::{AccelAux, DecelAux, SlipField};

/// Rows 2 and 3 of the slip field's Jacobian at one state.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Lin {
    /// ∂(row 2, row 3)/∂(x, y, v_r,x, v_r,y).
    pub js: [[f64; 4]; 2],
    /// ∂(row 2, row 3)/∂(κ, 2γ, Ω).
    pub jp: [[f64; 3]; 2],
}

impl Lin {
    /// K = J·T + J_p·P for the state tangent `t` and the parameters' seeds
    /// in `fld`, direction by direction.
    #[inline(always)]
    pub fn apply<const N: usize, const FMA: bool>(&self, t: &Jet<N>, fld: &TanField<N>) -> Jet<N> {
        let mut k = [[0.0; N]; 4];
        let [r2, r3] = self.js;
        let [p2, p3] = self.jp;
        for i in 0..N {
            let (kp, gp, op) = (fld.kappa.d[i], fld.two_gamma.d[i], fld.omega.d[i]);
            k[0][i] = t[2][i] + fld.v[0].d[i];
            k[1][i] = t[3][i] + fld.v[1].d[i];
            let row = |r: [f64; 4], p: [f64; 3]| {
                let mut acc = madd::<FMA>(p[0], kp, madd::<FMA>(p[1], gp, p[2] * op));
                for (c, &rc) in r.iter().enumerate() {
                    acc = madd::<FMA>(rc, t[c][i], acc);
                }
                acc
            };
            k[2][i] = row(r2, p2);
            k[3][i] = row(r3, p3);
        }
        k
    }
}

/// a·b + c, fused (one rounding) when `FMA`: only in code compiled with
/// the `fma` target feature, where it is one instruction.
#[inline(always)]
pub(crate) fn madd<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA { a.mul_add(b, c) } else { a * b + c }
}

/// [`SlipField::accel`] (its value, bitwise) and its Jacobian.
#[inline(always)]
pub(crate) fn accel(f: &SlipField, s: &State) -> (State, Lin) {
    let (value, aux) = f.accel_aux(s);
    (value, Lin::accel(f, s, &AccelAux::unpack(&aux)))
}

/// [`SlipField::decel`] (its value, bitwise) and its Jacobian.
#[inline(always)]
pub(crate) fn decel(f: &SlipField, s: &State) -> (State, Lin) {
    let (value, aux) = f.decel_aux(s);
    (value, Lin::decel(f, s, &DecelAux::unpack(&aux)))
}

impl Lin {
    /// The Jacobian of [`SlipField::accel`] at `s`, from what the
    /// evaluation computed there (`aux`).
    ///
    /// With F = (−κx, −y) at angle ψ, v_r at angle φ_v, Δ = ψ − φ_v,
    /// W = e^(−Ω v_r), E = W − 1, u = R(EΔ) F̂ and u⊥ = R(π/2) u, the field is
    /// F − Φ u, so d(row 2, row 3) = dF − u dΦ − Φ u⊥ s with
    /// s = dψ + d(EΔ) = W dψ − E dφ_v − Δ W (Ω dv_r + v_r dΩ). At v_r = 0 (the onset)
    /// dv_r and dφ_v are taken as 0, as [`super::Tan`] takes them.
    #[inline(always)]
    pub(crate) fn accel(f: &SlipField, s: &State, aux: &AccelAux) -> Lin {
        let [x, y, a, b] = *s;
        let AccelAux {
            vr,
            phi,
            inv_f,
            delta,
            e,
            sn,
            cs,
        } = *aux;
        let fx = -f.kappa * x;
        let fy = -y;
        let (ex, ey) = (fx * inv_f, fy * inv_f);
        let (ux, uy) = (ex * cs - ey * sn, ex * sn + ey * cs);
        let w = e + 1.0;
        let inv_f2 = inv_f * inv_f;
        // dψ = (fx dfy − fy dfx)/|F|², dfx = −κ dx − x dκ, dfy = −dy.
        let (psi_x, psi_y, psi_k) = (fy * f.kappa * inv_f2, -fx * inv_f2, fy * x * inv_f2);
        // With v̂ = (a, b)/v_r: dv_r = v̂·dv, dφ_v = v̂⊥·dv/v_r; so
        // s = W dψ − E dφ_v − ΔW (Ω dv_r + v_r dΩ) has
        // (∂s/∂a, ∂s/∂b) = c₁ (b̂, −â) − c₂ (â, b̂), c₁ = E/v_r, c₂ = ΔWΩ.
        let inv_vr = if vr > 0.0 { 1.0 / vr } else { 0.0 };
        let (ia, ib) = (a * inv_vr, b * inv_vr);
        let dw = delta * w;
        let (c1, c2) = (e * inv_vr, dw * f.omega);
        let (s_x, s_y, s_k, s_o) = (w * psi_x, w * psi_y, w * psi_k, -dw * vr);
        // dΦ = −Φ² (2γ dv_r + v_r d(2γ)): (∂Φ/∂a, ∂Φ/∂b) = c₃ (â, b̂).
        let phi2 = phi * phi;
        let c3 = -phi2 * f.two_gamma;
        let ph_g = -phi2 * vr;
        // Row 2: dfx − ux dΦ + Φ uy s; row 3: dfy − uy dΦ − Φ ux s. Their
        // (a, b) columns are â A + b̂ B and b̂ A − â B.
        let (qx, qy) = (phi * uy, -phi * ux);
        let (a2, b2) = (-ux * c3 - qx * c2, qx * c1);
        let (a3, b3) = (-uy * c3 - qy * c2, qy * c1);
        Lin {
            js: [
                [
                    -f.kappa + qx * s_x,
                    qx * s_y,
                    ia * a2 + ib * b2,
                    ib * a2 - ia * b2,
                ],
                [
                    qy * s_x,
                    -1.0 + qy * s_y,
                    ia * a3 + ib * b3,
                    ib * a3 - ia * b3,
                ],
            ],
            jp: [
                [-x + qx * s_k, -ux * ph_g, qx * s_o],
                [qy * s_k, -uy * ph_g, qy * s_o],
            ],
        }
    }

    /// The Jacobian of [`SlipField::decel`] at `s`, from what the
    /// evaluation computed there: rows 2, 3 = (−κx, −y) − c (a, b) with
    /// c = 1/(v_r + 2γ q), q = v_r².
    #[inline(always)]
    pub(crate) fn decel(f: &SlipField, s: &State, aux: &DecelAux) -> Lin {
        let [x, _, a, b] = *s;
        let DecelAux { vr, q, c } = *aux;
        // dc = −c² ((1/v_r + 2·2γ)(a da + b db) + q d(2γ)).
        let c2 = c * c;
        // 1/v_r = c (1 + 2γ v_r): no division.
        let m = -c2 * (c * (1.0 + f.two_gamma * vr) + 2.0 * f.two_gamma);
        let (c_a, c_b, c_g) = (m * a, m * b, -c2 * q);
        Lin {
            js: [
                [-f.kappa, 0.0, -c_a * a - c, -c_b * a],
                [0.0, -1.0, -c_a * b, -c_b * b - c],
            ],
            jp: [[-x, -c_g * a, 0.0], [0.0, -c_g * b, 0.0]],
        }
    }

    /// The adjoint of [`Lin::apply`]: for the adjoint `nu` of a stage's K,
    /// the adjoint of its argument, J_yᵀ·ν (rows 0 and 1 are ẋ = v_r + V),
    /// and of the field's parameters (κ, 2γ, Ω, V_x, V_y), J_pᵀ·ν.
    #[inline(always)]
    pub fn transpose_apply<const FMA: bool>(&self, nu: &[f64; 4]) -> ([f64; 4], [f64; 5]) {
        let [r2, r3] = self.js;
        let [p2, p3] = self.jp;
        // Four wide: ν₂ row 2 + ν₃ row 3 + (0, 0, ν₀, ν₁).
        let shifted = [0.0, 0.0, nu[0], nu[1]];
        let mut mu = [0.0; 4];
        for c in 0..4 {
            mu[c] = madd::<FMA>(r2[c], nu[2], madd::<FMA>(r3[c], nu[3], shifted[c]));
        }
        let pf = [
            madd::<FMA>(p2[0], nu[2], p3[0] * nu[3]),
            madd::<FMA>(p2[1], nu[2], p3[1] * nu[3]),
            madd::<FMA>(p2[2], nu[2], p3[2] * nu[3]),
            nu[0],
            nu[1],
        ];
        (mu, pf)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Params;
    use crate::sim::variational::{ALL_DIRS, DIRS, split, tan_state};

    /// The values are bitwise the plain fields', and J·T + J_p·P is the
    /// forward-mode tangent of the same field (six directions, the
    /// parameters seeded), at slipping states and at an onset (v_r = 0).
    #[test]
    fn jacobian_times_tangent_is_the_forward_mode_tangent() {
        let p = Params {
            kappa: 18.95,
            gamma: 6.5,
            nu: 1e-3,
            theta_nu: 1.0,
            omega: 50.0,
        };
        let field = SlipField::new(&p);
        let fld = TanField::seeded(&p, &field, ALL_DIRS);
        let states = [
            [0.01, 0.3, -0.04, 0.07],
            [-0.02, 0.5, 1e-4, -3e-4],
            [0.03, -0.2, 0.3, 0.01],
            [0.05, 0.8, 0.0, 0.0],
        ];
        for (n, y) in states.into_iter().enumerate() {
            let t: Jet = std::array::from_fn(|c| {
                std::array::from_fn(|i| ((3 * c + 5 * i + n) % 7) as f64 * 0.3 - 0.9)
            });
            let s = tan_state(&y, &t);
            let mut pairs = vec![(accel(&field, &y), split(&fld.accel(&s)), field.accel(&y))];
            if n < 3 {
                pairs.push((decel(&field, &y), split(&fld.decel(&s)), field.decel(&y)));
            }
            for ((v, lin), (tv, tt), plain) in pairs {
                let k = lin.apply::<DIRS, false>(&t, &fld);
                for c in 0..4 {
                    assert_eq!(v[c].to_bits(), plain[c].to_bits(), "{y:?} {c}");
                    assert_eq!(tv[c].to_bits(), plain[c].to_bits(), "{y:?} {c}");
                    for i in 0..DIRS {
                        let scale = 1.0 + tt[c][i].abs();
                        assert!(
                            (k[c][i] - tt[c][i]).abs() < 1e-12 * scale,
                            "{y:?} row {c} direction {i}: {} vs {}",
                            k[c][i],
                            tt[c][i]
                        );
                    }
                }
            }
        }
    }
}
