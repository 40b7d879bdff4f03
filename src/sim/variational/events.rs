//! The tangent at the slip's switching events: the end of the
//! acceleration phase (where the friction law changes) and the stop.

use super::{Grad, Jet, NotDifferentiable, Tan, TanField, event_tangent, split, tan_state};
use crate::integrate::State;

/// The direction of the flow as a tangent in direction 0, for
/// derivatives along it (ġ = ∂g/∂y·ẏ).
fn along<const N: usize>(f: &State) -> Jet<N> {
    let mut d = [[0.0; N]; 4];
    for c in 0..4 {
        d[c][0] = f[c];
    }
    d
}

/// v_r · (ẍ, ÿ) on tangents: ½ d(v_r²)/dt, the acceleration phase's event.
fn speed_growth<const N: usize>(s: &[Tan<N>; 4], f: &[Tan<N>; 4]) -> Tan<N> {
    s[2] * f[2] + s[3] * f[3]
}

/// The deceleration's tangent just after the acceleration phase ends at
/// the state `ya` (tangent `t` there, before the switch): the event time's
/// sensitivity τ_p from g = v_r·(ẍ, ÿ) = 0, and the jump
/// Y⁺ = Y⁻ + (f_accel − f_decel) τ_p of the saltation rule.
pub(crate) fn accel_end<const N: usize>(
    fld: &TanField<N>,
    ya: &State,
    t: &Jet<N>,
) -> Result<Jet<N>, NotDifferentiable> {
    let s = tan_state(ya, t);
    let f = fld.accel(&s);
    let g = speed_growth(&s, &f);
    let (fa, _) = split(&f);
    let flow = fld.constant();
    let s1 = tan_state(ya, &along(&fa));
    let g_dot = speed_growth(&s1, &flow.accel(&s1)).d[0];
    let (mut y, tau) = event_tangent(t, &fa, &g.d, g_dot, "end of acceleration")?;
    let (fd, _) = split(&flow.decel(&tan_state(ya, &[[0.0; N]; 4])));
    for c in 0..4 {
        for i in 0..N {
            y[c][i] -= fd[c] * tau[i];
        }
    }
    Ok(y)
}

/// The stop placed by linear extrapolation from the state `y` (tangent
/// `t`, f = `k` with tangent `kt`), differentiated as it is computed:
/// stop = (x, y) + (V + v_r/2)·dt with dt = v_r/|dv_r/dt|.
pub(crate) fn extrapolated_stop<const N: usize>(
    fld: &TanField<N>,
    y: &State,
    t: &Jet<N>,
    k: &State,
    kt: &Jet<N>,
) -> [Grad<N>; 2] {
    let s = tan_state(y, t);
    let f = tan_state(k, kt);
    let vr = (s[2] * s[2] + s[3] * s[3]).sqrt();
    let dvr = speed_growth(&s, &f) / vr;
    let dt = vr / -dvr;
    let v = fld.v;
    [
        (s[0] + (v[0] + s[2].scale(0.5)) * dt).d,
        (s[1] + (v[1] + s[3].scale(0.5)) * dt).d,
    ]
}

/// The stop where g = z[which] · w crosses 0 (w fixed), at the state `z`
/// with tangent `t` and f = `f` there: the tangent of the stop's position.
/// For the stiff stop (z = (x, y, v_r, ·), g = v_r) and for a fixed step's
/// reversal of v_r (g = v_r · v_r(step start)).
pub(crate) fn stop_at_root<const N: usize>(
    t: &Jet<N>,
    f: &State,
    w: [f64; 2],
    which: usize,
) -> Result<[Grad<N>; 2], NotDifferentiable> {
    let dg: Grad<N> = std::array::from_fn(|i| t[which][i] * w[0] + t[which + 1][i] * w[1]);
    let g_dot = f[which] * w[0] + f[which + 1] * w[1];
    let (y, _) = event_tangent(t, f, &dg, g_dot, "stop")?;
    Ok([y[0], y[1]])
}
