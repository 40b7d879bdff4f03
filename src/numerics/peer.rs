//! The peer: the same slip, on the same equations ([`SlipField`]), integrated
//! by the `ode_solvers` crate's Dopri5 or Dop853 in the same process, so that
//! the work-precision chart compares our integrators with another
//! implementation of the same methods.
//!
//! `ode_solvers` integrates from x to x_end and calls `solout` after each
//! accepted step, which may stop the run; its dense output is not public (and
//! Dop853 has no continuous-output model). Events are therefore located as
//! well as that interface allows:
//! - the end of the acceleration phase is bracketed by `solout` (dv_r/dt
//!   changes sign over an accepted step) and then found by the Illinois
//!   method, each trial point being a fresh integration from the start of the
//!   bracketing step to the trial time (which the crate hits exactly);
//! - the deceleration is integrated in segments that end at a fraction
//!   (0.7, as in our loop) of the time v_r/|dv_r/dt| left before the
//!   extrapolated stop; a step that reverses v_r anyway is discarded and the
//!   segment restarted from the point before it; below v_r = √tol the stop
//!   is placed by the same linear extrapolation as ours.
//!
//! Every right-hand-side evaluation is counted, including those the crate
//! spends on its initial-step guess and those of the event search.

use std::cell::Cell;

use ode_solvers::dop_shared::IntegrationError;
use ode_solvers::{Dop853, Dopri5, OutputType, System, Vector4};

use super::sample::Iterate;
use crate::model::{Params, point_from_theta, stick_exit_point, theta_from_point};
use crate::sim::field::{SlipField, speed_growth};

type V4 = Vector4<f64>;

/// Which `ode_solvers` method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PeerMethod {
    Dopri5,
    Dop853,
}

impl PeerMethod {
    pub fn name(self) -> &'static str {
        match self {
            PeerMethod::Dopri5 => "ode_solvers-dopri5",
            PeerMethod::Dop853 => "ode_solvers-dop853",
        }
    }
}

/// Why the peer could not finish a slip.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PeerError {
    #[error("ode_solvers: {0}")]
    Solver(String),
    #[error("the slip did not stop within {0} time units")]
    TooLong(f64),
    #[error("the event search did not converge")]
    NoEvent,
}

impl From<IntegrationError> for PeerError {
    fn from(e: IntegrationError) -> Self {
        PeerError::Solver(e.to_string())
    }
}

/// What `solout` watches for.
#[derive(Clone, Copy, PartialEq)]
enum Watch {
    Nothing,
    /// dv_r/dt crossing zero from above (acceleration phase).
    AccelEnd,
    /// v_r reversing, or falling below the cut-off (deceleration phase).
    Stop,
}

struct Phase<'a> {
    field: SlipField,
    decel: bool,
    watch: Watch,
    cutoff: f64,
    armed: bool,
    prev_v: [f64; 2],
    evals: &'a Cell<u64>,
    hit: &'a Cell<bool>,
}

impl Phase<'_> {
    fn rhs(&self, s: &[f64; 4]) -> [f64; 4] {
        self.evals.set(self.evals.get() + 1);
        if self.decel {
            self.field.decel(s)
        } else {
            self.field.accel(s)
        }
    }
}

fn arr(y: &V4) -> [f64; 4] {
    [y[0], y[1], y[2], y[3]]
}

impl System<f64, V4> for Phase<'_> {
    fn system(&self, _t: f64, y: &V4, dy: &mut V4) {
        let f = self.rhs(&arr(y));
        for i in 0..4 {
            dy[i] = f[i];
        }
    }

    fn solout(&mut self, _t: f64, y: &V4, dy: &V4) -> bool {
        let s = arr(y);
        let stop = match self.watch {
            Watch::Nothing => false,
            Watch::AccelEnd => {
                let g = speed_growth(&s, &arr(dy));
                let fired = self.armed && g <= 0.0;
                self.armed |= g > 0.0;
                fired
            }
            Watch::Stop => {
                let turn = self.prev_v[0] * s[2] + self.prev_v[1] * s[3];
                self.prev_v = [s[2], s[3]];
                turn <= 0.0 || s[2].hypot(s[3]) < self.cutoff
            }
        };
        if stop {
            self.hit.set(true);
        }
        stop
    }
}

/// One integration of the peer from (t0, y0) to t1; returns the accepted
/// points (t, y), the first being (t0, y0), and whether `solout` stopped it.
struct Run {
    t: Vec<f64>,
    y: Vec<[f64; 4]>,
    hit: bool,
}

/// The peer's integrator settings.
#[derive(Clone, Copy, Debug)]
pub struct Peer {
    pub method: PeerMethod,
    pub tol: f64,
    pub max_slip_time: f64,
    pub max_segments: usize,
}

impl Peer {
    pub fn new(method: PeerMethod, tol: f64) -> Self {
        Peer {
            method,
            tol,
            max_slip_time: 1e4,
            max_segments: 100_000,
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        field: SlipField,
        decel: bool,
        watch: Watch,
        (t0, t1): (f64, f64),
        y0: &[f64; 4],
        h0: f64,
        h_max: f64,
        evals: &Cell<u64>,
    ) -> Result<Run, PeerError> {
        let hit = Cell::new(false);
        let sys = Phase {
            field,
            decel,
            watch,
            cutoff: self.tol.sqrt(),
            armed: false,
            prev_v: [y0[2], y0[3]],
            evals,
            hit: &hit,
        };
        let y = V4::new(y0[0], y0[1], y0[2], y0[3]);
        let (tol, h0) = (self.tol, h0.min(t1 - t0));
        let h_max = h_max.min(t1 - t0);
        let (ts, ys) = match self.method {
            PeerMethod::Dop853 => {
                let mut s = Dop853::from_param(
                    sys,
                    t0,
                    t1,
                    0.0,
                    y,
                    tol,
                    tol,
                    0.9,
                    0.0,
                    0.333,
                    6.0,
                    h_max,
                    h0,
                    100_000,
                    1000,
                    OutputType::Sparse,
                );
                s.integrate()?;
                (s.x_out().clone(), s.y_out().iter().map(arr).collect())
            }
            PeerMethod::Dopri5 => {
                let mut s = Dopri5::from_param(
                    sys,
                    t0,
                    t1,
                    0.0,
                    y,
                    tol,
                    tol,
                    0.9,
                    0.04,
                    0.2,
                    10.0,
                    h_max,
                    h0,
                    100_000,
                    1000,
                    OutputType::Sparse,
                );
                s.integrate()?;
                (s.x_out().clone(), s.y_out().iter().map(arr).collect())
            }
        };
        Ok(Run {
            t: ts,
            y: ys,
            hit: hit.get(),
        })
    }

    /// The state at `t1` integrated from (t0, y0) with first step t1 − t0.
    fn state_at(
        &self,
        field: SlipField,
        decel: bool,
        (t0, y0): (f64, &[f64; 4]),
        t1: f64,
        h_max: f64,
        evals: &Cell<u64>,
    ) -> Result<[f64; 4], PeerError> {
        if t1 <= t0 {
            return Ok(*y0);
        }
        let r = self.run(
            field,
            decel,
            Watch::Nothing,
            (t0, t1),
            y0,
            t1 - t0,
            h_max,
            evals,
        )?;
        r.y.last().copied().ok_or(PeerError::NoEvent)
    }

    /// One cycle from the onset at θ: slip, stop, stick, next onset.
    pub fn cycle(&self, params: &Params, theta: f64) -> Result<Iterate, PeerError> {
        let field = SlipField::new(params);
        let kappa = params.kappa;
        let h_max = 1.0 / kappa.max(1.0).sqrt();
        let evals = Cell::new(0u64);
        let p0 = point_from_theta(kappa, theta);
        let max_t = self.max_slip_time;

        // Acceleration phase, then the Illinois search for dv_r/dt = 0.
        let y0 = [p0[0], p0[1], 0.0, 0.0];
        let r = self.run(
            field,
            false,
            Watch::AccelEnd,
            (0.0, max_t),
            &y0,
            0.0,
            h_max,
            &evals,
        )?;
        let n = r.t.len();
        if !r.hit || n < 2 {
            return Err(PeerError::TooLong(max_t));
        }
        let (ta, ya) = (r.t[n - 2], r.y[n - 2]);
        let g = |s: &[f64; 4]| {
            evals.set(evals.get() + 1);
            speed_growth(s, &field.accel(s))
        };
        let (mut a, mut ga) = (ta, g(&ya));
        let (mut b, mut gb) = (r.t[n - 1], g(&r.y[n - 1]));
        let mut yb = r.y[n - 1];
        let t_tol = (self.tol * 1e-2).clamp(1e-14, 1e-8) * b.max(1.0);
        let mut side = 0i8;
        for _ in 0..60 {
            if (b - a).abs() <= t_tol {
                break;
            }
            let c = (a * gb - b * ga) / (gb - ga);
            let c = if c > a && c < b { c } else { 0.5 * (a + b) };
            let yc = self.state_at(field, false, (ta, &ya), c, h_max, &evals)?;
            let gc = g(&yc);
            if gc > 0.0 {
                (a, ga) = (c, gc);
                if side == -1 {
                    gb *= 0.5;
                }
                side = -1;
            } else {
                (b, gb, yb) = (c, gc, yc);
                if side == 1 {
                    ga *= 0.5;
                }
                side = 1;
            }
        }
        let (t_switch, y_switch) = (b, yb);

        // Deceleration, in segments that stop short of the extrapolated stop.
        let (mut t, mut y) = (t_switch, y_switch);
        let mut h0 = 0.0;
        let cutoff = self.tol.sqrt();
        let mut segments = 0;
        let stop = loop {
            segments += 1;
            if segments > self.max_segments || t >= max_t {
                return Err(PeerError::TooLong(max_t));
            }
            evals.set(evals.get() + 1);
            let k = field.decel(&y);
            let vr = y[2].hypot(y[3]);
            let dvr = speed_growth(&y, &k) / vr;
            if vr < cutoff && dvr < 0.0 && vr < -dvr * h_max {
                let dt = vr / -dvr;
                t += dt;
                break [
                    y[0] + (field.v[0] + 0.5 * y[2]) * dt,
                    y[1] + (field.v[1] + 0.5 * y[3]) * dt,
                ];
            }
            let cap = if dvr < 0.0 {
                0.7 * vr / -dvr
            } else {
                f64::INFINITY
            };
            let t1 = (t + cap).min(max_t);
            let r = self.run(field, true, Watch::Stop, (t, t1), &y, h0, h_max, &evals)?;
            let n = r.t.len();
            let last = r.y[n - 1];
            let reversed = y[2] * last[2] + y[3] * last[3] <= 0.0
                || (n >= 2 && {
                    let prev = r.y[n - 2];
                    prev[2] * last[2] + prev[3] * last[3] <= 0.0
                });
            if r.hit && reversed {
                // Back to the point before the step that crossed the stop.
                if n >= 3 {
                    (t, y) = (r.t[n - 2], r.y[n - 2]);
                    h0 = r.t[n - 2] - r.t[n - 3];
                } else {
                    h0 = 0.3 * (r.t[n - 1] - r.t[0]);
                }
                continue;
            }
            if n >= 2 {
                h0 = r.t[n - 1] - r.t[n - 2];
            }
            (t, y) = (r.t[n - 1], last);
        };
        let v = field.v;
        let theta_next = match stick_exit_point(kappa, stop, v) {
            Some((exit, _)) => theta_from_point(kappa, exit),
            None => theta_from_point(kappa, stop),
        };
        Ok(Iterate {
            theta_next,
            stop,
            slip_duration: t,
            rhs_evals: evals.get(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peer_reproduces_the_first_worked_example() {
        // docs/model.md: κ = 18.95, γ = 6.5, ν = 1e-3, θν = 1, θ = 0.5.
        let p = Params::default();
        for m in [PeerMethod::Dopri5, PeerMethod::Dop853] {
            let it = Peer::new(m, 1e-11).cycle(&p, 0.5).unwrap();
            assert!(
                (it.theta_next - 0.2037551562).abs() < 1e-8,
                "{m:?}: {}",
                it.theta_next
            );
            assert!((it.slip_duration - 3.123143632).abs() < 1e-7);
        }
    }
}
