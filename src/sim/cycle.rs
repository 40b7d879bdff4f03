//! One stick–slip cycle: slip onset on C → acceleration phase → deceleration
//! phase → stop → closed-form stick phase → next onset (MODEL.md, "One
//! cycle"). This is where the map θ → θ' is computed.

use std::cell::Cell;

use serde::{Deserialize, Serialize};

use super::SimError;
use super::field::{SlipField, speed_growth};
use super::trajectory::{Phase, Sampler};
use crate::integrate::{Dense, Method, Rhs, Solver, SolverSettings, State, find_root};
use crate::model::{
    Params, elastic_energy, exit_arc, is_on_exit_arc, point_from_theta, stick_exit_point,
    theta_from_point,
};

/// Everything one cycle yields (MODEL.md, "What a slip event reports").
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SlipEvent {
    /// θ of the slip onset.
    pub theta: f64,
    pub onset_x: f64,
    pub onset_y: f64,
    /// Time of the onset since the start of the run.
    pub onset_time: f64,
    /// Duration of the acceleration phase.
    pub accel_duration: f64,
    /// Duration of the whole slip (acceleration + deceleration).
    pub slip_duration: f64,
    pub stop_x: f64,
    pub stop_y: f64,
    /// |stop − onset|.
    pub slip_distance: f64,
    /// The largest relative speed, reached where the acceleration phase ends.
    pub peak_vr: f64,
    /// ½(κx² + y²) at onset minus the same at the stop.
    pub energy_released: f64,
    /// The stick phase that follows (0 when the block restarts at once).
    pub stick_duration: f64,
    /// θ of the next onset: the map value f(θ).
    pub theta_next: f64,
    /// The stop landed on or outside C and a new slip started at once there
    /// (MODEL.md rule 5; in practice a sign of numerical error).
    pub restarted: bool,
    /// Right-hand-side evaluations this cycle cost (machine-independent cost).
    pub rhs_evals: u64,
    /// Integration steps tried (accepted + rejected).
    pub steps: u32,
}

/// A validated parameter set with its solver: the entry point to cycles,
/// map iterates and orbits.
#[derive(Clone, Copy, Debug)]
pub struct Simulator {
    params: Params,
    settings: SolverSettings,
    field: SlipField,
    weights: State,
    h_max: f64,
    cutoff: f64,
    t_tol: f64,
    avx2: bool,
}

/// One phase's right-hand side, counting its evaluations. A type rather
/// than a closure so that `eval` is always inlined into the stepping loop
/// and compiled with its target features (see [`Rhs`]).
struct Counted<'a> {
    field: &'a SlipField,
    evals: &'a Cell<u64>,
    accel: bool,
}

impl Rhs for Counted<'_> {
    #[inline(always)]
    fn eval(&mut self, y: &State) -> State {
        self.evals.set(self.evals.get() + 1);
        if self.accel {
            self.field.accel(y)
        } else {
            self.field.decel(y)
        }
    }
}

/// How a try at a stiff stop ended (see `Simulator::stiff_stop`).
enum StiffEnd {
    /// The slip's end is not (yet) stiff enough: nothing was integrated.
    NotStiff,
    /// The reduced motion was integrated for `steps` steps, then left: the
    /// slip goes on from where the try started.
    GaveUp { steps: u32 },
    /// The stop, the time it took from the try's start, and the steps.
    Stopped {
        stop: [f64; 2],
        duration: f64,
        steps: u32,
    },
}

/// The state at the end of a slip.
struct SlipEnd {
    stop: [f64; 2],
    accel_duration: f64,
    duration: f64,
    peak_vr: f64,
    rhs_evals: u64,
    steps: u32,
}

impl Simulator {
    /// Validates the parameters and the settings once.
    pub fn new(params: Params, settings: SolverSettings) -> Result<Self, SimError> {
        params.validate()?;
        settings.validate()?;
        let sk = params.kappa.sqrt();
        let omega = params.kappa.max(1.0).sqrt();
        Ok(Simulator {
            params,
            settings,
            field: SlipField::new(&params),
            weights: [params.kappa, 1.0, sk, 1.0],
            // A sixth of the fastest oscillation period: no step can hide two
            // sign changes of dv_r/dt.
            h_max: 1.0 / omega,
            // Fixed steps: v_r = h^(p/2) makes the extrapolation's O(v_r²)
            // error that of the method, O(h^p).
            cutoff: if settings.method.is_adaptive() {
                settings.stop_cutoff * settings.rtol.sqrt()
            } else {
                settings.stop_cutoff * settings.step.powf(0.5 * settings.method.order() as f64)
            },
            t_tol: (settings.rtol * 1e-2).clamp(1e-14, 1e-8),
            #[cfg(target_arch = "x86_64")]
            avx2: std::arch::is_x86_feature_detected!("avx2"),
            #[cfg(not(target_arch = "x86_64"))]
            avx2: false,
        })
    }

    pub fn params(&self) -> &Params {
        &self.params
    }

    pub fn settings(&self) -> &SolverSettings {
        &self.settings
    }

    /// Checks that θ is a reachable onset (MODEL.md, "Domain").
    pub fn check_onset(&self, theta: f64) -> Result<(), SimError> {
        let p = &self.params;
        if theta.is_finite() && is_on_exit_arc(p.kappa, p.theta_nu, theta) {
            return Ok(());
        }
        let (psi, half) = exit_arc(p.kappa, p.theta_nu);
        Err(SimError::OffExitArc {
            theta,
            lo: psi - half,
            hi: psi + half,
            kappa: p.kappa,
            theta_nu: p.theta_nu,
        })
    }

    /// The map θ' = f(θ).
    pub fn map(&self, theta: f64) -> Result<f64, SimError> {
        Ok(self.cycle(theta, 0.0, None)?.theta_next)
    }

    /// One full cycle from the onset at θ (time `onset_time`), optionally
    /// sampling the path for display.
    pub fn cycle(
        &self,
        theta: f64,
        onset_time: f64,
        mut sampler: Option<&mut Sampler>,
    ) -> Result<SlipEvent, SimError> {
        self.check_onset(theta)?;
        let kappa = self.params.kappa;
        let onset = point_from_theta(kappa, theta);
        let end = self.slip(theta, onset, onset_time, sampler.as_deref_mut())?;
        let stop = end.stop;
        let v = self.field.v;
        let (theta_next, stick_duration, restarted) = match stick_exit_point(kappa, stop, v) {
            Some((exit, t)) => (theta_from_point(kappa, exit), t, false),
            None => (theta_from_point(kappa, stop), 0.0, true),
        };
        if let Some(s) = sampler {
            let t_stop = onset_time + end.duration;
            if stick_duration > 0.0 {
                // A straight line at constant velocity: its two ends are all
                // a view needs to draw it.
                s.push(t_stop, stop, v, Phase::Stick);
                let exit = [
                    stop[0] + v[0] * stick_duration,
                    stop[1] + v[1] * stick_duration,
                ];
                s.push(t_stop + stick_duration, exit, v, Phase::Stick);
            }
        }
        let dx = stop[0] - onset[0];
        let dy = stop[1] - onset[1];
        Ok(SlipEvent {
            theta,
            onset_x: onset[0],
            onset_y: onset[1],
            onset_time,
            accel_duration: end.accel_duration,
            slip_duration: end.duration,
            stop_x: stop[0],
            stop_y: stop[1],
            slip_distance: dx.hypot(dy),
            peak_vr: end.peak_vr,
            energy_released: elastic_energy(kappa, onset) - elastic_energy(kappa, stop),
            stick_duration,
            theta_next,
            restarted,
            rhs_evals: end.rhs_evals,
            steps: end.steps,
        })
    }

    fn integrate_err(&self, theta: f64, e: crate::integrate::IntegrateError) -> SimError {
        SimError::Integrate {
            theta,
            params: self.params,
            source: e,
        }
    }

    fn too_large(&self, theta: f64, event: &'static str) -> SimError {
        SimError::StepTooLarge {
            h: self.settings.step,
            event,
            theta,
            params: self.params,
        }
    }

    /// Integrates one slip from rest relative to the surface at `p0`.
    ///
    /// The 4-component state fits one AVX2 register, so on CPUs that have it
    /// the same code is compiled a second time with AVX2 enabled and chosen
    /// at run time. Rust never contracts a·b + c into an FMA on its own, so
    /// both versions round identically: results do not depend on the CPU.
    fn slip(
        &self,
        theta: f64,
        p0: [f64; 2],
        t_abs: f64,
        sampler: Option<&mut Sampler>,
    ) -> Result<SlipEnd, SimError> {
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` was set from `is_x86_feature_detected!("avx2")`.
            return unsafe { self.slip_avx2(theta, p0, t_abs, sampler) };
        }
        self.slip_impl(theta, p0, t_abs, sampler)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn slip_avx2(
        &self,
        theta: f64,
        p0: [f64; 2],
        t_abs: f64,
        sampler: Option<&mut Sampler>,
    ) -> Result<SlipEnd, SimError> {
        self.slip_impl(theta, p0, t_abs, sampler)
    }

    #[inline(always)]
    fn slip_impl(
        &self,
        theta: f64,
        p0: [f64; 2],
        t_abs: f64,
        mut sampler: Option<&mut Sampler>,
    ) -> Result<SlipEnd, SimError> {
        let field = self.field;
        let evals = Cell::new(0u64);
        let mut acc = Counted {
            field: &field,
            evals: &evals,
            accel: true,
        };
        let mut dec = Counted {
            field: &field,
            evals: &evals,
            accel: false,
        };
        let adaptive = self.settings.method.is_adaptive();
        let max_t = self.settings.max_slip_time;
        let v = field.v;
        // The first step is short: at the onset the net force vanishes and
        // v_r grows from rest, where a long first step's error estimate was
        // seen to under-report (DOP853 at tol 1e-9 off by 15·tol at one point
        // with 0.05·h_max; at most 4.6·tol over 193 points with 0.01·h_max).
        let mut solver = Solver::new(self.settings, self.weights, 0.01 * self.h_max);
        // A fixed step takes exactly the step asked for (the adaptive methods
        // are capped at h_max). Beyond h_max = 1/√max(κ, 1), a sixth of the
        // fastest oscillation, a step can hide two sign changes of dv_r/dt:
        // the events cannot be resolved, and saying so beats a wrong number.
        if !adaptive && self.settings.step > self.h_max {
            return Err(self.too_large(
                theta,
                "slip oscillation (a step longer than 1/sqrt(max(kappa, 1)))",
            ));
        }
        let h_cap = if adaptive { self.h_max } else { f64::INFINITY };

        // Acceleration phase: until dv_r/dt crosses zero from above. At the
        // onset it is exactly zero, so the test arms only once it has been
        // positive.
        let mut y: State = [p0[0], p0[1], 0.0, 0.0];
        let mut k = acc.eval(&y);
        let mut t = 0.0;
        let mut g = 0.0;
        let mut armed = false;
        if let Some(s) = sampler.as_deref_mut() {
            s.start_slip(t_abs, &y, v);
        }
        let (t_a, y_a) = loop {
            if t >= max_t {
                return Err(SimError::SlipTooLong {
                    theta,
                    params: self.params,
                    max: max_t,
                });
            }
            let (tn, yn, kn) = solver
                .step(&mut acc, t, &y, &k, h_cap.min(max_t - t))
                .map_err(|e| self.integrate_err(theta, e))?;
            let gn = speed_growth(&yn, &kn);
            if armed && !adaptive && y[2] * yn[2] + y[3] * yn[3] < 0.0 {
                // v_r passed through zero inside one accelerating step.
                return Err(self.too_large(theta, "end of the acceleration phase"));
            }
            if armed && gn <= 0.0 {
                if !adaptive && solver.stats.accepted < 2 {
                    return Err(self.too_large(theta, "end of the acceleration phase"));
                }
                let d = solver.dense(&mut acc);
                let ta = find_root(
                    |tt| {
                        let s = d.at(tt);
                        speed_growth(&s, &acc.eval(&s))
                    },
                    t,
                    g,
                    tn,
                    gn,
                    self.t_tol * tn.max(1.0),
                );
                let ya = d.at(ta);
                if let Some(s) = sampler.as_deref_mut() {
                    s.sample_step(t_abs, &d, ta, Phase::Accel, v);
                    s.push_state(t_abs + ta, &ya, v, Phase::Decel);
                }
                break (ta, ya);
            }
            if let Some(s) = sampler.as_deref_mut() {
                let d = solver.dense(&mut acc);
                s.sample_step(t_abs, &d, tn, Phase::Accel, v);
            }
            armed |= gn > 0.0;
            (t, y, k, g) = (tn, yn, kn, gn);
        };
        let peak_vr = (y_a[2] * y_a[2] + y_a[3] * y_a[3]).sqrt();

        // Deceleration phase: friction opposes v_r until v_r reaches 0.
        let accel_steps = solver.stats.accepted;
        let (mut t, mut y) = (t_a, y_a);
        let mut k = dec.eval(&y);
        let mut extra_steps = 0;
        // One stiff stop that gave up is enough for a slip: it cost up to
        // 400 steps, and the state that fooled it is still ahead.
        let mut stiff_gave_up = false;
        let stop = loop {
            let vr = (y[2] * y[2] + y[3] * y[3]).sqrt();
            let dvr = speed_growth(&y, &k) / vr;
            if adaptive && dvr < 0.0 && !stiff_gave_up && self.settings.stiff_stop {
                let at = t_abs + t;
                match self.stiff_stop(&y, vr, -dvr, at, sampler.as_deref_mut(), &evals) {
                    StiffEnd::NotStiff => {}
                    StiffEnd::GaveUp { steps } => {
                        stiff_gave_up = true;
                        extra_steps += steps;
                    }
                    StiffEnd::Stopped {
                        stop,
                        duration,
                        steps,
                    } => {
                        extra_steps += steps;
                        t += duration;
                        if let Some(s) = sampler.as_deref_mut() {
                            s.push(t_abs + t, stop, v, Phase::Decel);
                        }
                        break stop;
                    }
                }
            }
            // A fixed step aims at the stop too once the stop lies within
            // one step: RK4's stages past it see the reversed friction, and
            // the block then chatters on at v_r ≈ 0 instead of stopping (a
            // creep slip at κ = 3, h = 0.01 slid for 874 time units).
            let stop_near = adaptive || vr < -dvr * self.settings.step;
            // The extrapolation holds over at most the field's fastest time
            // scale, 1/√max(κ, 1): without that bound a creep slip whose
            // peak v_r is already below the cut-off (tol ≥ 1e-4) was
            // extrapolated from its first decelerating step and slid on.
            if stop_near && vr < self.cutoff && dvr < 0.0 && vr < -dvr * self.h_max {
                // Linear extrapolation of v_r to zero: the mean relative
                // velocity over the remaining time is half the current one.
                let dt = vr / -dvr;
                if !adaptive && t + dt - t_a < 2.0 * self.settings.step {
                    // As for a reversal: a phase shorter than two steps is
                    // not resolved, however its end is placed.
                    return Err(self.too_large(theta, "stop"));
                }
                let stop = [
                    y[0] + (v[0] + 0.5 * y[2]) * dt,
                    y[1] + (v[1] + 0.5 * y[3]) * dt,
                ];
                t += dt;
                if let Some(s) = sampler.as_deref_mut() {
                    s.push(t_abs + t, stop, v, Phase::Decel);
                }
                break stop;
            }
            if t >= max_t {
                return Err(SimError::SlipTooLong {
                    theta,
                    params: self.params,
                    max: max_t,
                });
            }
            // Once v_r falls, the steps shrink towards the stop: the
            // controller extrapolates that trend (see `Solver::grow_factor`).
            solver.predictive = dvr < 0.0;
            let cap = if stop_near && dvr < 0.0 {
                self.settings.stop_fraction * vr / -dvr
            } else {
                f64::INFINITY
            };
            // Fixed steps: the friction −Φ v̂_r turns v_r at the rate Φ/v_r,
            // which an explicit step outruns once h·Φ/v_r > 1 (the stiff
            // approach to a creep stop); steps are held below v_r/Φ there.
            let cap = if adaptive {
                cap
            } else {
                cap.min(vr / field.phi(vr))
            };
            let (tn, yn, kn) = solver
                .step(&mut dec, t, &y, &k, cap.min(h_cap).min(max_t - t))
                .map_err(|e| self.integrate_err(theta, e))?;
            let turn = y[2] * yn[2] + y[3] * yn[3];
            if turn <= 0.0 || !(yn[2] * yn[2] + yn[3] * yn[3] > 0.0) {
                if adaptive {
                    // The step aimed past the stop despite the cap: retry shorter.
                    solver.h = 0.3 * (tn - t);
                    continue;
                }
                if solver.stats.accepted - accel_steps < 2 {
                    return Err(self.too_large(theta, "stop"));
                }
                // Fixed step: locate the reversal of v_r on the step's interpolant.
                let d = solver.dense(&mut dec);
                let v0 = [y[2], y[3]];
                let gv = |s: &State| s[2] * v0[0] + s[3] * v0[1];
                let ts = find_root(
                    |tt| gv(&d.at(tt)),
                    t,
                    vr * vr,
                    tn,
                    turn,
                    self.t_tol * tn.max(1.0),
                );
                let s = d.at(ts);
                t = ts;
                if let Some(sm) = sampler.as_deref_mut() {
                    sm.push(t_abs + t, [s[0], s[1]], v, Phase::Decel);
                }
                break [s[0], s[1]];
            }
            if let Some(s) = sampler.as_deref_mut() {
                let d: Dense = solver.dense(&mut dec);
                s.sample_step(t_abs, &d, tn, Phase::Decel, v);
            }
            (t, y, k) = (tn, yn, kn);
        };
        Ok(SlipEnd {
            stop,
            accel_duration: t_a,
            duration: t,
            peak_vr,
            rhs_evals: evals.get(),
            steps: solver.steps() + extra_steps,
        })
    }

    /// The end of a creep-sized slip, where the deceleration is stiff.
    ///
    /// Near a stop the direction of v_r relaxes towards F̂_el at the rate
    /// |F_el|/v_r while v_r itself falls at D = |dv_r/dt|. When the stop is
    /// close to C (|F_el| ≈ 1 ≈ Φ, so D ≪ |F_el|) the ratio k = |F_el|/D is
    /// large, and an explicit step is held by stability, not accuracy, to a
    /// fraction of the time left: a creep slip at κ = 3 took ~180 DOP853
    /// steps at tol 1e-10, ~150 of them in this phase. But there the
    /// direction sits on its slow manifold ([`SlipField::manifold`]), and
    /// the motion on it, (x, y, v_r) against time, is smooth and not stiff
    /// (smooth through v_r = 0 as well, so the stop is the sign change of
    /// v_r, located on the dense output). It is integrated with the same
    /// method and tolerance: a handful of steps.
    ///
    /// Taken only where the manifold's own error is below 1 % of the
    /// tolerance: the state's angle α0 differs from the manifold's α1 by a
    /// transient that decays like (v_r/v0)^k and moves the stop by about
    /// |sin α0 − sin α1|·v0²/((k + 2) D); the manifold's neglected O(1/k²)
    /// term moves it by about |sin α1|·v0²/(k² D). Their sum, in κx, must stay
    /// below 0.01·tol, and v̂_r must point along F̂_el; otherwise `NotStiff`
    /// (go on stepping). It gives up (`GaveUp`: go on stepping from where it
    /// started, its samples dropped) when on the way v_r stops falling, k
    /// falls below 5, a step fails or 400 steps pass: then the manifold was
    /// not what it seemed.
    fn stiff_stop(
        &self,
        y: &State,
        vr: f64,
        decel: f64,
        t_abs: f64,
        mut sampler: Option<&mut Sampler>,
        evals: &Cell<u64>,
    ) -> StiffEnd {
        const MIN_STIFFNESS: f64 = 10.0;
        const ERROR_SHARE: f64 = 0.01;
        const MAX_STEPS: u32 = 400;
        let field = self.field;
        let kappa = self.params.kappa;
        let (fx, fy) = (-kappa * y[0], -y[1]);
        let fnorm = fx.hypot(fy);
        let k = fnorm / decel;
        if !(k >= MIN_STIFFNESS) {
            return StiffEnd::NotStiff;
        }
        // v̂_r must point along F̂_el, not against it (sin α alone cannot
        // tell: a slip along an axis has sin α = 0 both before and after
        // the block passes the centre, where F_el turns round).
        let cos0 = (fx * y[2] + fy * y[3]) / (fnorm * vr);
        if !(cos0 > 0.5) {
            return StiffEnd::NotStiff;
        }
        let sin0 = (fx * y[3] - fy * y[2]) / (fnorm * vr);
        let m = field.manifold(y[0], y[1], vr);
        let moved = vr * vr / decel;
        let bound = ((sin0 - m.sin_alpha).abs() / (k + 2.0) + m.sin_alpha.abs() / (k * k))
            * moved
            * kappa.max(1.0);
        if !(bound <= ERROR_SHARE * self.settings.rtol) {
            return StiffEnd::NotStiff;
        }
        // z = (x, y, v_r, unused) on the manifold, against time.
        let v = field.v;
        let mut rhs = |z: &State| -> State {
            evals.set(evals.get() + 1);
            let s = z[2];
            let m = field.manifold(z[0], z[1], s);
            [v[0] + s * m.dir[0], v[1] + s * m.dir[1], m.dvr, 0.0]
        };
        let slip_state = |z: &State| -> State {
            let m = field.manifold(z[0], z[1], z[2]);
            [z[0], z[1], z[2] * m.dir[0], z[2] * m.dir[1]]
        };
        let mark = sampler.as_deref().map(Sampler::mark);
        let weights = [kappa, 1.0, kappa.sqrt(), 0.0];
        let h0 = (0.1 * vr / decel).min(self.h_max);
        let mut solver = Solver::new(self.settings, weights, h0);
        let mut z: State = [y[0], y[1], vr, 0.0];
        let mut f = rhs(&z);
        let mut t = 0.0;
        loop {
            // v_r must keep falling, and stay stiff (k ≥ 5) on the way: D
            // grows as Φ rises with falling v_r, and k with it only if
            // |F_el| does not fall much, which a long way left would allow.
            // Nor may the stop recede for ever (one just on C).
            let f_el = (kappa * z[0]).hypot(z[1]);
            if !(f[2] < 0.0 && f_el >= -0.5 * MIN_STIFFNESS * f[2]) || solver.steps() > MAX_STEPS {
                if solver.steps() == 0 {
                    // Nothing integrated: just past the peak D ≈ 0 and the
                    // manifold's dv_r/dt can still be ≥ 0. Try again later.
                    return StiffEnd::NotStiff;
                }
                if let (Some(s), Some(mark)) = (sampler, mark) {
                    s.rewind(mark);
                }
                return StiffEnd::GaveUp {
                    steps: solver.steps(),
                };
            }
            let Ok((tn, zn, fnew)) = solver.step(&mut rhs, t, &z, &f, self.h_max) else {
                // The normal steps will get there: a step-size underflow
                // here says the manifold was not smooth after all.
                if let (Some(s), Some(mark)) = (sampler, mark) {
                    s.rewind(mark);
                }
                return StiffEnd::GaveUp {
                    steps: solver.steps(),
                };
            };
            if zn[2] <= 0.0 {
                let d = solver.dense(&mut rhs);
                let tol = self.t_tol * tn.max(1.0);
                let ts = find_root(|tt| d.at(tt)[2], t, z[2], tn, zn[2], tol);
                if let Some(s) = sampler.as_deref_mut() {
                    s.sample_step_with(t_abs, &d, ts, Phase::Decel, v, slip_state);
                }
                let stop = d.at(ts);
                return StiffEnd::Stopped {
                    stop: [stop[0], stop[1]],
                    duration: ts,
                    steps: solver.steps(),
                };
            }
            if let Some(s) = sampler.as_deref_mut() {
                let d = solver.dense(&mut rhs);
                s.sample_step_with(t_abs, &d, tn, Phase::Decel, v, slip_state);
            }
            (t, z, f) = (tn, zn, fnew);
        }
    }
}

/// Convenience: the default method at tolerance `tol`.
pub fn default_settings(tol: f64) -> SolverSettings {
    SolverSettings::adaptive(Method::Dop853, tol)
}
