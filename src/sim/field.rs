//! The slip equations of motion in the relative-velocity variables
//! (x, y, v_r,x, v_r,y): integrating v_r instead of the lab velocity keeps
//! creep-sized slips free of the cancellation u − V_x (docs/model.md).

use super::trig;
use crate::integrate::State;
use crate::model::Params;

/// The right-hand sides of the two slip phases, with the parameters
/// pre-multiplied for the inner loop.
#[derive(Clone, Copy, Debug)]
pub struct SlipField {
    pub kappa: f64,
    /// 2γ: Φ(2γ v_r) = 1/(1 + 2γ v_r).
    pub two_gamma: f64,
    pub omega: f64,
    /// The surface velocity V.
    pub v: [f64; 2],
}

impl SlipField {
    pub fn new(p: &Params) -> Self {
        SlipField {
            kappa: p.kappa,
            two_gamma: 2.0 * p.gamma,
            omega: p.omega,
            v: p.velocity(),
        }
    }

    /// Friction magnitude Φ(2γ v_r).
    #[inline(always)]
    pub fn phi(&self, vr: f64) -> f64 {
        1.0 / (1.0 + self.two_gamma * vr)
    }

    /// Acceleration phase: friction of magnitude Φ at the angle
    /// φ_fr = π + φ_el − Δ (1 − e^(−Ω v_r)), Δ = wrap(φ_el − φ_vr).
    ///
    /// Written without φ_el itself: Δ is the angle from v_r to F_el, one
    /// atan2 of their cross and dot products, and the friction direction is
    /// −F̂_el rotated by −Δ(1 − e^(−Ω v_r)).
    #[inline(always)]
    pub fn accel(&self, s: &State) -> State {
        self.accel_aux(s).0
    }

    /// [`SlipField::accel`] and what it computed on the way that its
    /// Jacobian needs ([`AccelAux`], packed): the same expressions, so the value is
    /// bitwise the same. A slip with derivatives keeps these for its
    /// backward sweep (`variational::tape`), which then forms the Jacobian
    /// without the transcendentals.
    #[inline(always)]
    pub fn accel_aux(&self, s: &State) -> (State, Aux) {
        let [x, y, a, b] = *s;
        let fx = -self.kappa * x;
        let fy = -y;
        let vr = (a * a + b * b).sqrt();
        let inv_f = 1.0 / (fx * fx + fy * fy).sqrt();
        let (ex, ey) = (fx * inv_f, fy * inv_f);
        let delta = trig::atan2(a * fy - b * fx, a * fx + b * fy);
        // −expm1 keeps the turn accurate while Ω v_r is tiny (early slip).
        let e = trig::exp_m1_neg(-self.omega * vr);
        let turn = e * delta; // = −Δ(1 − e^(−Ω v_r))
        let (sn, cs) = trig::sin_cos(turn);
        let phi = self.phi(vr);
        let value = [
            a + self.v[0],
            b + self.v[1],
            fx - phi * (ex * cs - ey * sn),
            fy - phi * (ex * sn + ey * cs),
        ];
        let aux = AccelAux {
            vr,
            phi,
            inv_f,
            delta,
            e,
            sn,
            cs,
        };
        (value, aux.pack())
    }

    /// The direction v̂_r takes, to first order in 1/k, when it relaxes
    /// towards F̂_el much faster than v_r falls (k = |F_el|/|dv_r/dt| ≫ 1:
    /// creep-sized stops), at position (x, y) and relative speed `vr`.
    ///
    /// With α the angle from F̂_el to v̂_r and ω the turning rate of F_el,
    /// the deceleration's field gives dα/dt = −(|F|/v_r) sin α − ω. Its slow
    /// manifold is sin α = −(v_r/|F|)(ω + dα_qs/dt), with the zeroth-order
    /// α_qs = −ω v_r/|F| differentiated along the motion (v̂_r ≈ F̂,
    /// dv_r/dt ≈ −D, dv_r/dt ê + v_r ω ê⊥ for the relative acceleration);
    /// what is left out is O(α/k²).
    #[inline(always)]
    pub fn manifold(&self, x: f64, y: f64, vr: f64) -> Manifold {
        let k = self.kappa;
        let (fx, fy) = (-k * x, -y);
        let f2 = fx * fx + fy * fy;
        let fnorm = f2.sqrt();
        // Two divisions in all (this is the right-hand side of the stiff
        // stop's steps, and they wait for each other).
        let inv_f = 1.0 / fnorm;
        let inv_f2 = inv_f * inv_f;
        let phi = self.phi(vr);
        let (ux, uy) = (fx * inv_f, fy * inv_f);
        // F' = −K ẋ with ẋ = V + v_r F̂.
        let (dfx, dfy) = (-k * (self.v[0] + vr * ux), -(self.v[1] + vr * uy));
        let omega = (fx * dfy - fy * dfx) * inv_f2;
        let d = phi - fnorm;
        // v̇_r ≈ −D F̂ + v_r ω F̂⊥, so F'' = −K v̇_r.
        let (ax, ay) = (-d * ux - vr * omega * uy, -d * uy + vr * omega * ux);
        let (ddfx, ddfy) = (-k * ax, -ay);
        let f_dot_df = fx * dfx + fy * dfy;
        let domega = ((fx * ddfy - fy * ddfx) - 2.0 * omega * f_dot_df) * inv_f2;
        // d|F|/dt = F·F'/|F|.
        let dfnorm = f_dot_df * inv_f;
        let dalpha_qs = ((d * omega - vr * domega) + omega * vr * dfnorm * inv_f) * inv_f;
        let sa = (-(vr * inv_f) * (omega + dalpha_qs)).clamp(-1.0, 1.0);
        let ca = (1.0 - sa * sa).sqrt();
        Manifold {
            sin_alpha: sa,
            dir: [ux * ca - uy * sa, ux * sa + uy * ca],
            dvr: fnorm * ca - phi,
        }
    }

    /// Deceleration phase: friction −Φ v̂_r. Only called with v_r > 0.
    #[inline(always)]
    pub fn decel(&self, s: &State) -> State {
        self.decel_aux(s).0
    }

    /// [`SlipField::decel`] and what its Jacobian needs ([`DecelAux`], packed),
    /// as [`SlipField::accel_aux`].
    #[inline(always)]
    pub fn decel_aux(&self, s: &State) -> (State, Aux) {
        let [x, y, a, b] = *s;
        let q = a * a + b * b;
        let vr = q.sqrt();
        // Φ/v_r = 1/(v_r + 2γ v_r²): one division after the square root
        // instead of two in a row (decel_chained 20 → 15.5 ns, the Fig. 3b
        // iterate −6 %).
        let c = 1.0 / (vr + self.two_gamma * q);
        let value = [
            a + self.v[0],
            b + self.v[1],
            -self.kappa * x - c * a,
            -y - c * b,
        ];
        (value, DecelAux { vr, q, c }.pack())
    }
}

/// What an evaluation of a slip field computed that its Jacobian needs
/// (`variational::linear`), kept per stage by a slip with derivatives
/// (`variational::tape`): the acceleration phase's values, or the
/// deceleration's in the first three slots.
pub type Aux = [f64; 7];

/// The acceleration phase's [`Aux`], by name.
#[derive(Clone, Copy, Debug)]
pub struct AccelAux {
    pub vr: f64,
    pub phi: f64,
    /// 1/|F_el|.
    pub inv_f: f64,
    /// Δ, the angle from v_r to F_el.
    pub delta: f64,
    /// e^(−Ω v_r) − 1.
    pub e: f64,
    /// sin and cos of the turn e·Δ.
    pub sn: f64,
    pub cs: f64,
}

impl AccelAux {
    #[inline(always)]
    pub fn pack(self) -> Aux {
        [
            self.vr, self.phi, self.inv_f, self.delta, self.e, self.sn, self.cs,
        ]
    }

    #[inline(always)]
    pub fn unpack(a: &Aux) -> Self {
        let [vr, phi, inv_f, delta, e, sn, cs] = *a;
        AccelAux {
            vr,
            phi,
            inv_f,
            delta,
            e,
            sn,
            cs,
        }
    }
}

/// The deceleration phase's [`Aux`], by name.
#[derive(Clone, Copy, Debug)]
pub struct DecelAux {
    pub vr: f64,
    /// v_r².
    pub q: f64,
    /// Φ/v_r = 1/(v_r + 2γ v_r²).
    pub c: f64,
}

impl DecelAux {
    #[inline(always)]
    pub fn pack(self) -> Aux {
        [self.vr, self.q, self.c, 0.0, 0.0, 0.0, 0.0]
    }

    #[inline(always)]
    pub fn unpack(a: &Aux) -> Self {
        DecelAux {
            vr: a[0],
            q: a[1],
            c: a[2],
        }
    }
}

/// The deceleration's slow manifold at a point (see [`SlipField::manifold`]).
#[derive(Clone, Copy, Debug)]
pub struct Manifold {
    /// sin α, α the angle from F̂_el to v̂_r.
    pub sin_alpha: f64,
    /// v̂_r.
    pub dir: [f64; 2],
    /// dv_r/dt (negative on the way to a stop).
    pub dvr: f64,
}

/// ½ d(v_r²)/dt = v_r · (ẍ, ÿ): positive while the relative speed grows.
#[inline(always)]
pub fn speed_growth(s: &State, f: &State) -> f64 {
    s[2] * f[2] + s[3] * f[3]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn friction_opposes_elastic_force_at_onset() {
        let p = Params::default();
        let fld = SlipField::new(&p);
        let th = 0.5_f64;
        let s = [th.cos() / p.kappa, th.sin(), 0.0, 0.0];
        let f = fld.accel(&s);
        // On C, |F_el| = 1 = Φ(0): the net force vanishes at onset.
        assert!(f[2].abs() < 1e-15 && f[3].abs() < 1e-15, "{f:?}");
        assert_eq!([f[0], f[1]], fld.v);
    }

    #[test]
    fn fast_slip_friction_opposes_relative_velocity() {
        let p = Params::default();
        let fld = SlipField::new(&p);
        // v_r large: e^(−Ω v_r) ≈ 0, so both phases agree.
        let s = [0.01, 0.3, -0.4, 0.7];
        let a = fld.accel(&s);
        let d = fld.decel(&s);
        for i in 0..4 {
            assert!((a[i] - d[i]).abs() < 1e-12, "{i}: {} vs {}", a[i], d[i]);
        }
    }
}
