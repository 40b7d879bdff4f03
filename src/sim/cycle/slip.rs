//! One slip, advanced one step attempt at a time.
//!
//! A slip is a loop of steps with logic between them (the acceleration
//! phase's end, the stiff stop, the extrapolated stop, overshoot retries).
//! Written as a value that says what its next attempt is ([`SlipRun::prepare`])
//! and takes the attempt's stages back ([`SlipRun::finish`]), the same slip
//! runs alone ([`Simulator::slip_impl`]) or beside another one whose stages
//! are computed together with its own (`slip_pair_impl`): two independent
//! chains of dependent evaluations that the CPU overlaps. Both drivers call
//! the same code in the same order for each slip, so a slip's result does
//! not depend on which one ran it.

use std::cell::{Cell, RefCell};

use super::{SimError, Simulator, SlipEnd, StiffEnd};
use crate::integrate::{Dense, LaneAttempt, Method, Rhs, Solver, State, find_root};
use crate::model::onset_stiffness;
use crate::sim::field::{SlipField, speed_growth};
use crate::sim::trajectory::{Phase, Sampler};
use crate::sim::variational::{EV, Field, Grad, NotDifferentiable, Tape};

mod derivs;

/// How much tighter than the settings the acceleration phase of a creep or
/// near-critical onset is integrated (see `SlipRun::start`).
const NEAR_CRITICAL_ACCEL_TIGHTENING: f64 = 5.0;

/// h λ within which DOP853's step damps a mode e^(−λt) (`SlipRun::stability_cap`):
/// its stability interval on the negative axis is [−6.39, 0], |R(−5)| = 0.057.
const DOP853_STABLE_REACH: f64 = 5.0;
/// The same for DP54: its interval is [−3.30, 0], |R(−2.6)| = 0.28.
const DP54_STABLE_REACH: f64 = 2.6;

/// One phase's right-hand side, counting its evaluations. A type rather
/// than a closure so that `eval` is always inlined into the stepping loop
/// and compiled with its target features (see [`Rhs`]). With `TAPE` (a
/// slip with derivatives) each evaluation also leaves what its Jacobian
/// needs on the slip's tape; the value is bitwise the same.
pub(super) struct Counted<'a, const TAPE: bool = false> {
    pub(super) field: &'a SlipField,
    pub(super) evals: &'a Cell<u64>,
    pub(super) accel: bool,
    pub(super) tape: Option<&'a RefCell<Box<Tape>>>,
}

impl<'a, const TAPE: bool> Counted<'a, TAPE> {
    /// The right-hand side of the phase `stage` is in.
    #[inline(always)]
    fn of(
        field: &'a SlipField,
        evals: &'a Cell<u64>,
        stage: Stage,
        tape: Option<&'a RefCell<Box<Tape>>>,
    ) -> Self {
        Counted {
            field,
            evals,
            accel: matches!(stage, Stage::Accel { .. }),
            tape,
        }
    }
}

impl<const TAPE: bool> Rhs for Counted<'_, TAPE> {
    #[inline(always)]
    fn eval(&mut self, y: &State) -> State {
        self.evals.set(self.evals.get() + 1);
        if TAPE {
            let (v, aux) = if self.accel {
                self.field.accel_aux(y)
            } else {
                self.field.decel_aux(y)
            };
            if let Some(tape) = self.tape {
                tape.borrow_mut().record(y, aux);
            }
            return v;
        }
        if self.accel {
            self.field.accel(y)
        } else {
            self.field.decel(y)
        }
    }
}

/// Where a slip stands between attempts.
#[derive(Clone, Copy)]
enum Stage {
    /// Acceleration phase; `g` = v_r · (ẍ, ÿ) at the last accepted state,
    /// `armed` once it has been positive (it is exactly 0 at the onset).
    Accel { g: f64, armed: bool },
    /// Deceleration phase, from the end of the acceleration phase.
    Decel {
        t_a: f64,
        peak_vr: f64,
        accel_steps: u32,
        /// One stiff stop that gave up is enough for a slip: it cost up to
        /// 400 steps, and the state that fooled it is still ahead.
        stiff_gave_up: bool,
    },
}

/// What a slip asks for next.
pub(super) enum Next {
    /// Compute the stages of an attempt of this length from `state()`.
    Attempt(f64),
    /// The slip is over.
    Done(SlipEnd),
}

/// One slip in progress; with `TAPE`, one with derivatives.
pub(super) struct SlipRun<'a, const TAPE: bool = false> {
    sim: &'a Simulator,
    theta: f64,
    /// Time of the onset since the start of the run (for samples).
    t_abs: f64,
    evals: Cell<u64>,
    pub(super) solver: Solver,
    t: f64,
    y: State,
    k: State,
    stage: Stage,
    /// The bound on the step being attempted: `Some` while an attempt is
    /// retried after a rejection (the logic before a step must not rerun).
    h_max: Option<f64>,
    extra_steps: u32,
    /// The tape of a slip with derivatives (`None`: a plain slip, or one
    /// whose derivatives were found not to exist).
    pub(super) tape: Option<RefCell<Box<Tape>>>,
    /// The stop's tangent against the [`EV`] slots at the slip's last
    /// state, once the slip has ended (with derivatives).
    stop_d: Option<Result<[Grad<EV>; 2], NotDifferentiable>>,
}

impl<'a, const TAPE: bool> SlipRun<'a, TAPE> {
    /// A slip from rest relative to the surface at `p0`.
    #[inline(always)]
    pub(super) fn start(
        sim: &'a Simulator,
        theta: f64,
        p0: [f64; 2],
        t_abs: f64,
        sampler: Option<&mut Sampler>,
    ) -> Result<Self, SimError> {
        let adaptive = sim.settings.method.is_adaptive();
        // A fixed step takes exactly the step asked for (the adaptive methods
        // are capped at h_max). Beyond h_max = 1/√max(κ, 1), a sixth of the
        // fastest oscillation, a step can hide two sign changes of dv_r/dt:
        // the events cannot be resolved, and saying so beats a wrong number.
        if !adaptive && sim.settings.step > sim.h_max {
            return Err(sim.too_large(
                theta,
                "slip oscillation (a step longer than 1/sqrt(max(kappa, 1)))",
            ));
        }
        let y: State = [p0[0], p0[1], 0.0, 0.0];
        let mut run = SlipRun {
            sim,
            theta,
            t_abs,
            evals: Cell::new(0),
            // The first step is short: at the onset the net force vanishes
            // and v_r grows from rest, where a long first step's error
            // estimate was seen to under-report (DOP853 at tol 1e-9 off by
            // 15·tol at one point with 0.05·h_max; at most 4.6·tol over 193
            // points with 0.01·h_max).
            solver: Solver::new(sim.settings, sim.weights, 0.01 * sim.h_max),
            t: 0.0,
            y,
            k: [0.0; 4],
            stage: Stage::Accel {
                g: 0.0,
                armed: false,
            },
            h_max: None,
            extra_steps: 0,
            tape: None,
            stop_d: None,
        };
        // The acceleration phase of an onset that is creep or near-critical
        // stick-slip (A(θ) = κ cos²θ + sin²θ above 0.95 γ²) runs at a fifth of
        // the tolerance. Its growth from rest is slow and oscillatory, or
        // nearly so, and amplified by up to e^(γπ/√(A − γ²)) (huge near θc),
        // and its map errors per unit tolerance were 5–18× those of other
        // onsets: on the chart's sample at tol 1e-9, creep-sized slips near θc
        // were off by 1.8e-9 (long stick) and 5.3e-10 (intermittent), and
        // 1.7e-10 at most with a fifth; near-critical stick-slip onsets of the
        // long-stick orbit (A = 0.98–0.99 γ²) by up to 1.7e-9, then 6e-10.
        // Tightening the deceleration instead changed nothing. Far-from-
        // critical onsets (all of Fig. 3b's, A ≤ 0.45 γ²) are unaffected.
        if adaptive {
            let p = &sim.params;
            if onset_stiffness(p.kappa, theta) > 0.95 * p.gamma * p.gamma {
                run.solver.err_scale = NEAR_CRITICAL_ACCEL_TIGHTENING;
            }
        }
        run.k = run.rhs().eval(&y);
        if let Some(s) = sampler {
            s.start_slip(t_abs, &y, sim.field.v);
        }
        Ok(run)
    }

    /// The current phase's right-hand side.
    #[inline(always)]
    pub(super) fn rhs(&self) -> Counted<'_, TAPE> {
        Counted::of(&self.sim.field, &self.evals, self.stage, self.tape.as_ref())
    }

    /// The stages of the attempt of length `h` that `prepare` asked for.
    #[inline(always)]
    pub(super) fn stages(&mut self, h: f64) -> State {
        let LaneAttempt {
            solver,
            mut f,
            y,
            k0,
            ..
        } = self.attempt(h);
        solver.stages(&mut f, y, k0, h)
    }

    /// The attempt of length `h` that `prepare` asked for, for stages
    /// computed beside other slips' (`Solver::stages_lanes`).
    #[inline(always)]
    pub(super) fn attempt(&mut self, h: f64) -> LaneAttempt<'_, Counted<'_, TAPE>> {
        LaneAttempt {
            f: Counted::of(&self.sim.field, &self.evals, self.stage, self.tape.as_ref()),
            solver: &mut self.solver,
            y: &self.y,
            k0: &self.k,
            h,
        }
    }

    /// Steps at most this long for an adaptive method: inside its
    /// stability interval for v̂_r's turning, the field's stiff mode.
    ///
    /// A turn of v_r decays at the rate λ = Φ(1 − e^(−Ω v_r))/v_r while the
    /// block accelerates (up to Φ Ω) and Φ/v_r while it decelerates. Off
    /// the axes the error control sees that mode and holds the steps near
    /// its stability limit; on a symmetry axis the state has no turn at all
    /// (near one, less than the tolerance) and the steps outgrew it
    /// (h λ ≈ 16), so the tangents, which do carry the mode, were amplified
    /// some 10⁴ times a step (f' ≈ 10²⁷ at θ = θν = 0). Decelerating, the cap
    /// is ≥ 1e-6: Φ/v_r is unbounded as v_r → 0 (a slip at ν = 1e-12).
    #[inline(always)]
    fn stability_cap(&self, decelerating: bool) -> f64 {
        let reach = match self.sim.settings.method {
            Method::Dop853 => DOP853_STABLE_REACH,
            Method::Dp54 => DP54_STABLE_REACH,
            Method::Rk4 | Method::Euler => return f64::INFINITY,
        };
        let y = &self.y;
        let vr = (y[2] * y[2] + y[3] * y[3]).sqrt();
        let field = &self.sim.field;
        let phi = field.phi(vr);
        let rate = match (vr > 0.0, decelerating) {
            (true, true) => (phi / vr).min(reach * 1e6),
            (true, false) => -phi * (-field.omega * vr).exp_m1() / vr,
            (false, _) => phi * field.omega,
        };
        reach / rate
    }

    /// Steps at most this long: a sixth of the fastest oscillation for the
    /// adaptive methods, none for the fixed ones (they take their step).
    #[inline(always)]
    fn h_cap(&self) -> f64 {
        if self.sim.settings.method.is_adaptive() {
            self.sim.h_max
        } else {
            f64::INFINITY
        }
    }

    fn too_long(&self) -> SimError {
        SimError::SlipTooLong {
            theta: self.theta,
            params: self.sim.params,
            max: self.sim.settings.max_slip_time,
        }
    }

    fn end(&mut self, stop: [f64; 2], duration: f64) -> SlipEnd {
        let Stage::Decel { t_a, peak_vr, .. } = self.stage else {
            unreachable!("a slip ends in its deceleration phase");
        };
        SlipEnd {
            stop,
            accel_duration: t_a,
            duration,
            peak_vr,
            rhs_evals: self.evals.get(),
            steps: self.solver.steps() + self.extra_steps,
            derivs: match (self.stop_d, self.tape.take()) {
                (Some(Ok(d)), Some(tape)) => {
                    let mut tape = tape.into_inner();
                    tape.stop = d;
                    Some(Ok(tape))
                }
                (Some(Err(e)), _) => Some(Err(e)),
                (None, None) => None,
                _ => unreachable!("a slip with derivatives ends with its stop's tangent"),
            },
        }
    }

    /// What comes next: the length of an attempt, or the end of the slip
    /// (a stop placed by the stiff stop or by extrapolation). The logic
    /// before a step runs once per step, not again when an attempt is
    /// retried after a rejection.
    #[inline(always)]
    pub(super) fn prepare(&mut self, mut sampler: Option<&mut Sampler>) -> Result<Next, SimError> {
        let sim = self.sim;
        let settings = &sim.settings;
        let adaptive = settings.method.is_adaptive();
        let max_t = settings.max_slip_time;
        let h_max = match (self.h_max, self.stage) {
            (Some(h), _) => h,
            (None, Stage::Accel { .. }) => {
                if self.t >= max_t {
                    return Err(self.too_long());
                }
                self.h_cap()
                    .min(self.stability_cap(false))
                    .min(max_t - self.t)
            }
            (None, Stage::Decel { stiff_gave_up, .. }) => {
                let (y, t) = (self.y, self.t);
                let v = sim.field.v;
                let vr = (y[2] * y[2] + y[3] * y[3]).sqrt();
                let dvr = speed_growth(&y, &self.k) / vr;
                if adaptive && dvr < 0.0 && !stiff_gave_up && settings.stiff_stop {
                    let at = self.t_abs + t;
                    let smp = sampler.as_deref_mut();
                    match sim.stiff_stop(&y, -dvr, at, smp, &self.evals, self.tape.as_ref()) {
                        StiffEnd::NotStiff => {}
                        StiffEnd::GaveUp { steps } => {
                            if let Stage::Decel { stiff_gave_up, .. } = &mut self.stage {
                                *stiff_gave_up = true;
                            }
                            self.extra_steps += steps;
                        }
                        StiffEnd::Stopped {
                            stop,
                            duration,
                            steps,
                            stop_d,
                        } => {
                            self.extra_steps += steps;
                            if stop_d.is_some() {
                                self.stop_d = stop_d;
                            }
                            if let Some(s) = sampler {
                                s.push(self.t_abs + (t + duration), stop, v, Phase::Decel);
                            }
                            return Ok(Next::Done(self.end(stop, t + duration)));
                        }
                    }
                }
                // A fixed step aims at the stop too once the stop lies within
                // one step: RK4's stages past it see the reversed friction, and
                // the block then chatters on at v_r ≈ 0 instead of stopping (a
                // creep slip at κ = 3, h = 0.01 slid for 874 time units).
                let stop_near = adaptive || vr < -dvr * settings.step;
                // The extrapolation holds over at most the field's fastest time
                // scale, 1/√max(κ, 1): without that bound a creep slip whose
                // peak v_r is already below the cut-off (tol ≥ 1e-4) was
                // extrapolated from its first decelerating step and slid on.
                if stop_near && vr < sim.stop_cutoff(&y, vr) && dvr < 0.0 && vr < -dvr * sim.h_max {
                    // Linear extrapolation of v_r to zero: the mean relative
                    // velocity over the remaining time is half the current one.
                    let dt = vr / -dvr;
                    let Stage::Decel { t_a, .. } = self.stage else {
                        unreachable!()
                    };
                    if !adaptive && t + dt - t_a < 2.0 * settings.step {
                        // As for a reversal: a phase shorter than two steps is
                        // not resolved, however its end is placed.
                        return Err(sim.too_large(self.theta, "stop"));
                    }
                    let stop = [
                        y[0] + (v[0] + 0.5 * y[2]) * dt,
                        y[1] + (v[1] + 0.5 * y[3]) * dt,
                    ];
                    self.extrapolated_stop_tangent();
                    if let Some(s) = sampler {
                        s.push(self.t_abs + (t + dt), stop, v, Phase::Decel);
                    }
                    return Ok(Next::Done(self.end(stop, t + dt)));
                }
                if t >= max_t {
                    return Err(self.too_long());
                }
                // Once v_r falls, the steps shrink towards the stop: the
                // controller extrapolates that trend (see `Solver::grow_factor`).
                self.solver.predictive = dvr < 0.0;
                let cap = if stop_near && dvr < 0.0 {
                    settings.stop_fraction * vr / -dvr
                } else {
                    f64::INFINITY
                };
                // Fixed steps: the friction −Φ v̂_r turns v_r at the rate Φ/v_r,
                // which an explicit step outruns once h·Φ/v_r > 1 (the stiff
                // approach to a creep stop); steps are held below v_r/Φ there.
                let cap = if adaptive {
                    cap.min(self.stability_cap(true))
                } else {
                    cap.min(vr / sim.field.phi(vr))
                };
                cap.min(self.h_cap()).min(max_t - t)
            }
        };
        self.h_max = Some(h_max);
        let h = self
            .solver
            .begin_attempt(self.t, h_max)
            .map_err(|e| sim.integrate_err(self.theta, e))?;
        if let Some(tape) = &self.tape {
            let field = match self.stage {
                Stage::Accel { .. } => Field::Accel,
                Stage::Decel { .. } => Field::Decel,
            };
            tape.borrow_mut().begin(h, field);
        }
        Ok(Next::Attempt(h))
    }

    /// Takes back the stages of the attempt of length `h` that `prepare`
    /// asked for: a rejection leaves the slip where it was, an accepted step
    /// moves it on (through the end of the acceleration phase if that falls
    /// in the step). Returns the slip's end if a fixed step located the stop.
    #[inline(always)]
    pub(super) fn finish(
        &mut self,
        y_new: &State,
        h: f64,
        mut sampler: Option<&mut Sampler>,
    ) -> Result<Option<SlipEnd>, SimError> {
        let sim = self.sim;
        let adaptive = sim.settings.method.is_adaptive();
        let v = sim.field.v;
        let (t, y) = (self.t, self.y);
        if let Some(tape) = &self.tape {
            tape.borrow_mut().finishing();
        }
        let tape = self.tape.as_ref();
        let mut f = Counted::<TAPE>::of(&sim.field, &self.evals, self.stage, tape);
        let accepted = self.solver.end_attempt(&mut f, t, &y, y_new, h);
        if let Some(tape) = tape {
            tape.borrow_mut().end();
        }
        let Some((tn, yn, kn)) = accepted.map_err(|e| sim.integrate_err(self.theta, e))? else {
            return Ok(None);
        };
        self.h_max = None;
        match self.stage {
            Stage::Accel { g, armed } => {
                let gn = speed_growth(&yn, &kn);
                if armed && !adaptive && y[2] * yn[2] + y[3] * yn[3] < 0.0 {
                    // v_r passed through zero inside one accelerating step.
                    return Err(sim.too_large(self.theta, "end of the acceleration phase"));
                }
                if armed && gn <= 0.0 {
                    if !adaptive && self.solver.stats.accepted < 2 {
                        return Err(sim.too_large(self.theta, "end of the acceleration phase"));
                    }
                    let d = self.solver.dense(&mut f);
                    let ta = find_root(
                        |tt| {
                            let s = d.at(tt);
                            speed_growth(&s, &f.eval(&s))
                        },
                        t,
                        g,
                        tn,
                        gn,
                        sim.t_tol * tn.max(1.0),
                    );
                    let ya = d.at(ta);
                    if let Some(s) = sampler {
                        s.sample_step(self.t_abs, &d, ta, Phase::Accel, v);
                        s.push_state(self.t_abs + ta, &ya, v, Phase::Decel);
                    }
                    // Deceleration phase: friction opposes v_r until v_r
                    // reaches 0, at a looser tolerance (`Simulator::decel_err_scale`).
                    self.solver.err_scale = sim.decel_err_scale;
                    self.stage = Stage::Decel {
                        t_a: ta,
                        peak_vr: (ya[2] * ya[2] + ya[3] * ya[3]).sqrt(),
                        accel_steps: self.solver.stats.accepted,
                        stiff_gave_up: false,
                    };
                    self.switch_tangents(&ya, ta - t);
                    self.t = ta;
                    self.y = ya;
                    self.k = self.rhs().eval(&ya);
                    return Ok(None);
                }
                if let Some(s) = sampler {
                    let d = self.solver.dense(&mut f);
                    s.sample_step(self.t_abs, &d, tn, Phase::Accel, v);
                }
                self.stage = Stage::Accel {
                    g: gn,
                    armed: armed || gn > 0.0,
                };
                (self.t, self.y, self.k) = (tn, yn, kn);
                self.commit();
                Ok(None)
            }
            Stage::Decel { accel_steps, .. } => {
                let turn = y[2] * yn[2] + y[3] * yn[3];
                if turn <= 0.0 || !(yn[2] * yn[2] + yn[3] * yn[3] > 0.0) {
                    if adaptive {
                        // The step aimed past the stop despite the cap: retry
                        // shorter (and from the logic before a step again).
                        self.solver.h = 0.3 * (tn - t);
                        return Ok(None);
                    }
                    if self.solver.stats.accepted - accel_steps < 2 {
                        return Err(sim.too_large(self.theta, "stop"));
                    }
                    // Fixed step: locate the reversal of v_r on the step's
                    // interpolant.
                    let vr = (y[2] * y[2] + y[3] * y[3]).sqrt();
                    let d = self.solver.dense(&mut f);
                    let v0 = [y[2], y[3]];
                    let gv = |s: &State| s[2] * v0[0] + s[3] * v0[1];
                    let ts = find_root(
                        |tt| gv(&d.at(tt)),
                        t,
                        vr * vr,
                        tn,
                        turn,
                        sim.t_tol * tn.max(1.0),
                    );
                    let s = d.at(ts);
                    self.reversal_tangents(ts - t, v0);
                    if let Some(sm) = sampler.as_deref_mut() {
                        sm.push(self.t_abs + ts, [s[0], s[1]], v, Phase::Decel);
                    }
                    return Ok(Some(self.end([s[0], s[1]], ts)));
                }
                if let Some(s) = sampler {
                    let d: Dense = self.solver.dense(&mut f);
                    s.sample_step(self.t_abs, &d, tn, Phase::Decel, v);
                }
                (self.t, self.y, self.k) = (tn, yn, kn);
                self.commit();
                Ok(None)
            }
        }
    }
}
