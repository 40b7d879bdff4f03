//! Exact derivatives of the map θ' = f(θ; θν, κ, γ, ν, Ω)
//! (docs/derivatives.md).
//!
//! θ' is one number and the directions are six, so the gradient is taken
//! in reverse: a slip with derivatives runs as a plain slip does and
//! leaves on its tape (`variational::tape`) what each evaluation's
//! Jacobian needs; a backward sweep of one 4-component adjoint through the
//! steps then gives all six derivatives at once. The field's Jacobian is
//! formed from the values an evaluation computed (`variational::linear`).
//! The rarer parts are differentiated forward, on [`Tan`] numbers (a value
//! and its derivatives along a few directions): the switching events (the
//! end of the acceleration phase and the stop, with the event time's own
//! sensitivity: the saltation rule), the stiff stop's motion
//! (`variational::stages`), and the closed-form stick phase and θ'.

mod events;
mod linear;
mod stages;
mod tape;

use std::ops::{Add, Div, Mul, Neg, Sub};

use super::field::SlipField;
use super::trig;
use crate::integrate::State;
use crate::model::Params;
pub(crate) use events::{accel_end, extrapolated_stop, stop_at_root};
pub(crate) use stages::{Field, Tangents, field_tangent};
pub(crate) use tape::Tape;
pub use tape::{EV, ev_field, ev_seed, stop_gradient};

/// How many directions a [`Tan`] carries.
pub const DIRS: usize = 6;
/// The direction of the onset θ.
pub const D_THETA: usize = 0;
/// The direction of θν.
pub const D_THETA_NU: usize = 1;
/// The direction of κ.
pub const D_KAPPA: usize = 2;
/// The direction of γ.
pub const D_GAMMA: usize = 3;
/// The direction of ν.
pub const D_NU: usize = 4;
/// The direction of Ω.
pub const D_OMEGA: usize = 5;

/// The six directions in their order: what [`Simulator::cycle_derivatives`]
/// carries.
///
/// [`Simulator::cycle_derivatives`]: crate::Simulator::cycle_derivatives
pub const ALL_DIRS: [usize; DIRS] = [D_THETA, D_THETA_NU, D_KAPPA, D_GAMMA, D_NU, D_OMEGA];

/// Derivatives along `N` of the six directions (all six by default).
pub type Grad<const N: usize = DIRS> = [f64; N];
/// The tangent of a slip state: one [`Grad`] per component.
pub type Jet<const N: usize = DIRS> = [Grad<N>; 4];

/// A value with its derivatives along `N` directions (forward-mode
/// automatic differentiation). Every operation computes its value exactly
/// as the plain `f64` code does, so values agree to the bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tan<const N: usize = DIRS> {
    /// The value.
    pub v: f64,
    /// Its derivatives.
    pub d: Grad<N>,
}

impl<const N: usize> Tan<N> {
    /// A constant: no derivative.
    #[inline(always)]
    pub fn c(v: f64) -> Self {
        Tan { v, d: [0.0; N] }
    }

    #[inline(always)]
    fn map_d(v: f64, d: &Grad<N>, k: f64) -> Self {
        let mut o = [0.0; N];
        for i in 0..N {
            o[i] = d[i] * k;
        }
        Tan { v, d: o }
    }

    /// √x; its derivative is taken as 0 at x = 0, where only a state at
    /// rest (v_r = 0, whose tangent is 0 too) asks for it.
    #[inline(always)]
    pub fn sqrt(self) -> Self {
        let v = self.v.sqrt();
        let k = if v > 0.0 { 0.5 / v } else { 0.0 };
        Tan::map_d(v, &self.d, k)
    }

    /// 1/x.
    #[inline(always)]
    pub fn recip(self) -> Self {
        let v = 1.0 / self.v;
        Tan::map_d(v, &self.d, -v * v)
    }

    /// atan2(y, x) with the slip field's own `atan2`; derivative 0 at the
    /// origin (as for [`Tan::sqrt`]).
    #[inline(always)]
    pub fn atan2(y: Self, x: Self) -> Self {
        let v = trig::atan2(y.v, x.v);
        let r2 = x.v * x.v + y.v * y.v;
        let inv = if r2 > 0.0 { 1.0 / r2 } else { 0.0 };
        let mut d = [0.0; N];
        for i in 0..N {
            d[i] = (x.v * y.d[i] - y.v * x.d[i]) * inv;
        }
        Tan { v, d }
    }

    /// e^x − 1 for x ≤ 0, with the slip field's own function.
    #[inline(always)]
    pub fn exp_m1_neg(self) -> Self {
        let v = trig::exp_m1_neg(self.v);
        Tan::map_d(v, &self.d, v + 1.0)
    }

    /// (sin, cos) with the slip field's own function.
    #[inline(always)]
    pub fn sin_cos(self) -> (Self, Self) {
        let (s, c) = trig::sin_cos(self.v);
        (Tan::map_d(s, &self.d, c), Tan::map_d(c, &self.d, -s))
    }

    /// x · k for a constant k.
    #[inline(always)]
    pub fn scale(self, k: f64) -> Self {
        Tan::map_d(self.v * k, &self.d, k)
    }

    /// x + k for a constant k.
    #[inline(always)]
    pub fn add_c(self, k: f64) -> Self {
        Tan {
            v: self.v + k,
            d: self.d,
        }
    }

    /// `f64::clamp` (a clamped value is constant).
    #[inline(always)]
    pub fn clamp(self, lo: f64, hi: f64) -> Self {
        let v = self.v.clamp(lo, hi);
        if v == self.v { self } else { Tan::c(v) }
    }
}

impl<const N: usize> Add for Tan<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        let mut d = self.d;
        for i in 0..N {
            d[i] += o.d[i];
        }
        Tan { v: self.v + o.v, d }
    }
}

impl<const N: usize> Sub for Tan<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        let mut d = self.d;
        for i in 0..N {
            d[i] -= o.d[i];
        }
        Tan { v: self.v - o.v, d }
    }
}

impl<const N: usize> Mul for Tan<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        let mut d = [0.0; N];
        for i in 0..N {
            d[i] = self.v * o.d[i] + o.v * self.d[i];
        }
        Tan { v: self.v * o.v, d }
    }
}

impl<const N: usize> Div for Tan<N> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        let v = self.v / o.v;
        let inv = 1.0 / o.v;
        let mut d = [0.0; N];
        for i in 0..N {
            d[i] = (self.d[i] - v * o.d[i]) * inv;
        }
        Tan { v, d }
    }
}

impl<const N: usize> Neg for Tan<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        let mut d = self.d;
        for x in d.iter_mut() {
            *x = -*x;
        }
        Tan { v: -self.v, d }
    }
}

/// A state with its tangent, as [`Tan`] numbers.
#[inline(always)]
pub fn tan_state<const N: usize>(y: &State, t: &Jet<N>) -> [Tan<N>; 4] {
    std::array::from_fn(|i| Tan { v: y[i], d: t[i] })
}

/// The values and the tangent of a [`Tan`] state.
#[inline(always)]
pub fn split<const N: usize>(s: &[Tan<N>; 4]) -> (State, Jet<N>) {
    (s.map(|x| x.v), s.map(|x| x.d))
}

/// The slip field's parameters as [`Tan`] numbers: seeded with their
/// directions (κ, γ, Ω, and V through θν and ν), or constant.
#[derive(Clone, Copy, Debug)]
pub struct TanField<const N: usize = DIRS> {
    pub kappa: Tan<N>,
    pub two_gamma: Tan<N>,
    pub omega: Tan<N>,
    pub v: [Tan<N>; 2],
}

impl<const N: usize> TanField<N> {
    /// The parameters of `field` (built from `p`), slot s carrying the
    /// direction `dirs[s]` (one of the `D_` constants).
    pub fn seeded(p: &Params, field: &SlipField, dirs: [usize; N]) -> Self {
        let mut kappa = Tan::c(field.kappa);
        let mut two_gamma = Tan::c(field.two_gamma);
        let mut omega = Tan::c(field.omega);
        let (s, c) = p.theta_nu.sin_cos();
        let mut v = [Tan::c(field.v[0]), Tan::c(field.v[1])];
        for (slot, dir) in dirs.into_iter().enumerate() {
            match dir {
                D_KAPPA => kappa.d[slot] = 1.0,
                D_GAMMA => two_gamma.d[slot] = 2.0,
                D_OMEGA => omega.d[slot] = 1.0,
                // V = ν (cos θν, sin θν).
                D_THETA_NU => (v[0].d[slot], v[1].d[slot]) = (-field.v[1], field.v[0]),
                D_NU => (v[0].d[slot], v[1].d[slot]) = (c, s),
                _ => {}
            }
        }
        TanField {
            kappa,
            two_gamma,
            omega,
            v,
        }
    }

    /// The same parameters held constant (for derivatives along the flow).
    pub fn constant(&self) -> Self {
        TanField {
            kappa: Tan::c(self.kappa.v),
            two_gamma: Tan::c(self.two_gamma.v),
            omega: Tan::c(self.omega.v),
            v: [Tan::c(self.v[0].v), Tan::c(self.v[1].v)],
        }
    }

    /// [`SlipField::accel`] on tangents, operation for operation.
    #[inline(always)]
    pub fn accel(&self, s: &[Tan<N>; 4]) -> [Tan<N>; 4] {
        let [x, y, a, b] = *s;
        let fx = -self.kappa * x;
        let fy = -y;
        let vr = (a * a + b * b).sqrt();
        let inv_f = (fx * fx + fy * fy).sqrt().recip();
        let (ex, ey) = (fx * inv_f, fy * inv_f);
        let delta = Tan::atan2(a * fy - b * fx, a * fx + b * fy);
        let turn = (-self.omega * vr).exp_m1_neg() * delta;
        let (sn, cs) = turn.sin_cos();
        let phi = (self.two_gamma * vr).add_c(1.0).recip();
        [
            a + self.v[0],
            b + self.v[1],
            fx - phi * (ex * cs - ey * sn),
            fy - phi * (ex * sn + ey * cs),
        ]
    }

    /// [`SlipField::decel`] on tangents, operation for operation.
    #[inline(always)]
    pub fn decel(&self, s: &[Tan<N>; 4]) -> [Tan<N>; 4] {
        let [x, y, a, b] = *s;
        let q = a * a + b * b;
        let vr = q.sqrt();
        let c = (vr + self.two_gamma * q).recip();
        [
            a + self.v[0],
            b + self.v[1],
            -self.kappa * x - c * a,
            -y - c * b,
        ]
    }

    /// The right-hand side of the stiff stop's motion on the slow manifold,
    /// z = (x, y, v_r, unused), from [`SlipField::manifold`] on tangents.
    #[inline(always)]
    pub fn manifold_motion(&self, z: &[Tan<N>; 4]) -> [Tan<N>; 4] {
        let (x, y, vr) = (z[0], z[1], z[2]);
        let k = self.kappa;
        let (fx, fy) = (-k * x, -y);
        let f2 = fx * fx + fy * fy;
        let fnorm = f2.sqrt();
        let inv_f = fnorm.recip();
        let inv_f2 = inv_f * inv_f;
        let phi = (self.two_gamma * vr).add_c(1.0).recip();
        let (ux, uy) = (fx * inv_f, fy * inv_f);
        let (dfx, dfy) = (-k * (self.v[0] + vr * ux), -(self.v[1] + vr * uy));
        let omega = (fx * dfy - fy * dfx) * inv_f2;
        let d = phi - fnorm;
        let (ax, ay) = (-d * ux - vr * omega * uy, -d * uy + vr * omega * ux);
        let (ddfx, ddfy) = (-k * ax, -ay);
        let f_dot_df = fx * dfx + fy * dfy;
        let domega = ((fx * ddfy - fy * ddfx) - omega.scale(2.0) * f_dot_df) * inv_f2;
        let dfnorm = f_dot_df * inv_f;
        let dalpha_qs = ((d * omega - vr * domega) + omega * vr * dfnorm * inv_f) * inv_f;
        let sa = (-(vr * inv_f) * (omega + dalpha_qs)).clamp(-1.0, 1.0);
        let ca = (Tan::c(1.0) - sa * sa).sqrt();
        let dir = [ux * ca - uy * sa, ux * sa + uy * ca];
        [
            self.v[0] + vr * dir[0],
            self.v[1] + vr * dir[1],
            fnorm * ca - phi,
            Tan::c(0.0),
        ]
    }
}

/// Why f has no derivative at an onset: the number would be meaningless.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum NotDifferentiable {
    /// The stop landed on or outside C and a new slip started at once
    /// (docs/model.md, rule 5): f switches there between a stick phase and none.
    #[error("the slip restarts at its stop (the stop is on or outside C)")]
    Restart,
    /// The next onset is at the edge of the exit arc, where the stick phase
    /// meets C tangentially and f' is infinite.
    #[error("the next onset is at the edge of the exit arc")]
    ArcEdge,
    /// An event is met tangentially, where f jumps: the acceleration
    /// phase's end (d/dt of v_r·(ẍ, ÿ) is not negative there) or the stop
    /// (v_r reaches 0 without falling).
    #[error("a jump of f: the {event} is not crossed transversally")]
    Jump {
        /// "end of acceleration" or "stop".
        event: &'static str,
    },
    /// Not a property of f: the slip took more steps than the derivatives'
    /// tape holds (`tape::MAX_TAPE_BYTES`, a few MB), so its derivatives
    /// are not computed; θ' itself is.
    #[error(
        "the slip took more than {steps} steps, more than the derivatives' tape holds (4 MB): no derivatives"
    )]
    TapeFull {
        /// The steps on the tape when it filled.
        steps: usize,
    },
}

/// f(θ) and its derivatives at one onset.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MapDerivatives {
    /// f'(θ) = ∂θ'/∂θ.
    pub d_theta: f64,
    /// ∂θ'/∂θν.
    pub d_theta_nu: f64,
    /// ∂θ'/∂κ.
    pub d_kappa: f64,
    /// ∂θ'/∂γ.
    pub d_gamma: f64,
    /// ∂θ'/∂ν.
    pub d_nu: f64,
    /// ∂θ'/∂Ω.
    pub d_omega: f64,
}

impl MapDerivatives {
    /// From the gradient of θ' along the six directions ([`ALL_DIRS`]).
    pub fn from_grad(g: &Grad) -> Self {
        MapDerivatives {
            d_theta: g[D_THETA],
            d_theta_nu: g[D_THETA_NU],
            d_kappa: g[D_KAPPA],
            d_gamma: g[D_GAMMA],
            d_nu: g[D_NU],
            d_omega: g[D_OMEGA],
        }
    }

    /// The derivatives with their JSON names, in a fixed order.
    pub fn named(&self) -> [(&'static str, f64); 6] {
        [
            ("derivative", self.d_theta),
            ("d_theta_nu", self.d_theta_nu),
            ("d_kappa", self.d_kappa),
            ("d_gamma", self.d_gamma),
            ("d_nu", self.d_nu),
            ("d_omega", self.d_omega),
        ]
    }
}

/// The tangent of the state where an event g = 0 is crossed at time τ:
/// Y(τ) + ẏ(τ) τ_p with τ_p = −(∂g/∂y·Y + ∂g/∂p)/(∂g/∂y·ẏ), given
/// `dg` = ∂g/∂y·Y + ∂g/∂p and `g_dot` = ∂g/∂y·ẏ. Returns that tangent and
/// τ_p. `g_dot` must have the sign of a crossing from above (negative):
/// otherwise the event is met tangentially and f jumps there.
pub fn event_tangent<const N: usize>(
    y: &Jet<N>,
    f: &State,
    dg: &Grad<N>,
    g_dot: f64,
    event: &'static str,
) -> Result<(Jet<N>, Grad<N>), NotDifferentiable> {
    if !(g_dot < 0.0) {
        return Err(NotDifferentiable::Jump { event });
    }
    let tau: Grad<N> = std::array::from_fn(|i| -dg[i] / g_dot);
    let mut out = *y;
    for c in 0..4 {
        for i in 0..N {
            out[c][i] += f[c] * tau[i];
        }
    }
    if out.iter().flatten().chain(&tau).all(|x| x.is_finite()) {
        Ok((out, tau))
    } else {
        Err(NotDifferentiable::Jump { event })
    }
}

/// The gradient of the next onset's θ' from the stop (with its tangent):
/// the closed-form stick phase (`model::stick_exit_time`) and
/// θ' = atan2(y, κx), differentiated as computed. `None` when the stop is
/// not strictly inside C.
pub fn next_theta_grad<const N: usize>(
    fld: &TanField<N>,
    stop: [Tan<N>; 2],
) -> Option<Result<Grad<N>, NotDifferentiable>> {
    let k = fld.kappa;
    let v = fld.v;
    let k2 = k * k;
    let a = k2 * v[0] * v[0] + v[1] * v[1];
    let b = (k2 * stop[0] * v[0] + stop[1] * v[1]).scale(2.0);
    let kx = k * stop[0];
    let neg_c = (Tan::c(1.0) - stop[1]) * stop[1].add_c(1.0) - kx * kx;
    if !(neg_c.v > 0.0) || !(a.v > 0.0) {
        return None;
    }
    let disc = b * b + a.scale(4.0) * neg_c;
    // The stick line meets C tangentially at the edge of the exit arc:
    // there √disc = 0 and the exit time's derivative is infinite.
    if !(disc.v > 1e-24 * (b.v * b.v).max(a.v)) {
        return Some(Err(NotDifferentiable::ArcEdge));
    }
    let sq = disc.sqrt();
    let t = if b.v > 0.0 {
        neg_c.scale(2.0) / (b + sq)
    } else {
        (sq - b) / a.scale(2.0)
    };
    let ex = stop[0] + v[0] * t;
    let ey = stop[1] + v[1] * t;
    let theta = Tan::atan2(ey, k * ex);
    Some(if theta.d.iter().all(|x| x.is_finite()) {
        Ok(theta.d)
    } else {
        Err(NotDifferentiable::ArcEdge)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tangent fields' values are bitwise the plain fields' (so a cycle
    /// with derivatives steps exactly as one without), and their tangents
    /// match central differences of the plain fields.
    #[test]
    fn tangent_fields_are_the_plain_fields_with_their_derivatives() {
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
        ];
        for y in states {
            // A tangent with direction 0 along e_i.
            for i in 0..4 {
                let mut t = [[0.0; DIRS]; 4];
                t[i][0] = 1.0;
                let s = tan_state(&y, &t);
                // A step scaled to the component: the field turns fast at small v_r.
                let h = 1e-5 * y[i].abs().max(1e-3);
                let (mut yp, mut ym) = (y, y);
                yp[i] += h;
                ym[i] -= h;
                let pairs: [(State, [Tan; 4], State, State); 2] = [
                    (
                        field.accel(&y),
                        fld.accel(&s),
                        field.accel(&yp),
                        field.accel(&ym),
                    ),
                    (
                        field.decel(&y),
                        fld.decel(&s),
                        field.decel(&yp),
                        field.decel(&ym),
                    ),
                ];
                for (plain, tan, fp, fm) in pairs {
                    for c in 0..4 {
                        assert_eq!(plain[c].to_bits(), tan[c].v.to_bits(), "{y:?} {c}");
                        let fd = (fp[c] - fm[c]) / (2.0 * h);
                        let scale = 1.0 + fd.abs();
                        assert!((tan[c].d[0] - fd).abs() < 1e-6 * scale, "{y:?} {i} {c}");
                    }
                }
            }
            // The manifold's motion, against the plain manifold.
            let z = [Tan::c(y[0]), Tan::c(y[1]), Tan::c(0.01), Tan::c(0.0)];
            let m = field.manifold(y[0], y[1], 0.01);
            let r = fld.manifold_motion(&z);
            assert_eq!(r[2].v.to_bits(), m.dvr.to_bits());
            assert_eq!(r[0].v.to_bits(), (field.v[0] + 0.01 * m.dir[0]).to_bits());
        }
    }
}
