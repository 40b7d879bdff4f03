//! One stick–slip cycle: slip onset on C → acceleration phase → deceleration
//! phase → stop → closed-form stick phase → next onset (docs/model.md, "One
//! cycle"). This is where the map θ → θ' is computed.

use std::cell::{Cell, RefCell};

use serde::{Deserialize, Serialize};

mod derivatives;
mod lanes;
mod slip;

use super::SimError;
use super::field::SlipField;
use super::trajectory::{Phase, Sampler};
use super::variational::{
    self, EV, Field, Grad, NotDifferentiable, Tangents, Tape, ev_field, ev_seed,
};
use crate::integrate::{IntegrateError, Method, Rhs, Solver, SolverSettings, State, find_root};
use crate::model::{
    Params, elastic_energy, exit_arc, is_on_exit_arc, point_from_theta, stick_exit_point,
    theta_from_point,
};
pub use lanes::{LANES, Task, cycle_pair, cycles_in_lanes, run_lanes};
use slip::{Next, SlipRun};

/// Everything one cycle yields (docs/model.md, "What a slip event reports").
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
    /// (docs/model.md rule 5; in practice a sign of numerical error).
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
    /// The deceleration phase's error norm is scaled by this: its tolerance
    /// is 10× the settings' but never looser than 1e-5 (nor than the
    /// settings'). The acceleration phase grows from rest like e^(λt) over
    /// ~12 e-folds and the map's error comes from there; the deceleration
    /// is damped by the friction opposing v_r, and its local errors barely
    /// reach θ'. Measured on the chart's 65 points (DOP853): at tol 1e-9
    /// the max map error went from 7.5e-10 to 6.5e-10 with 6.7 % fewer
    /// evaluations, at 1e-12 from 1.57e-12 to 1.60e-12 with 17 % fewer; 3×
    /// looser gave less. Looser decelerations are not for maps (at tol
    /// 1e-4 one at 1e-3 was off by 6e-4) nor for the slip's duration, which
    /// is its least accurate quantity. The stop's extrapolation keeps the
    /// settings' own cut-off.
    pub(super) decel_err_scale: f64,
    t_tol: f64,
    /// AVX2 detected at run time (x86_64); elsewhere (the browser's wasm)
    /// always false: the portable path, tested against the AVX2 one.
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    avx2: bool,
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
        /// The stop's tangent against the [`EV`] slots where the try
        /// started, for a slip with derivatives.
        stop_d: Option<Result<[Grad<EV>; 2], NotDifferentiable>>,
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
    /// A slip with derivatives: its tape, with the stop's tangent, or why
    /// f has no derivative there.
    derivs: Option<Result<Box<Tape>, NotDifferentiable>>,
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
            decel_err_scale: (settings.rtol / 1e-5).clamp(0.1, 1.0),
            #[cfg(target_arch = "x86_64")]
            avx2: std::arch::is_x86_feature_detected!("avx2"),
            #[cfg(not(target_arch = "x86_64"))]
            avx2: false,
        })
    }

    /// The relative speed below which the stop is placed by linear
    /// extrapolation from the state `y` (speed `vr`). That extrapolation
    /// misplaces the stop by O(v_r²) along v̂_r, and the error norm measures
    /// x as κx, so for the adaptive methods the cut-off √tol shrinks by
    /// 2/√|W v̂_r| (W = diag(κ, 1)) where that is below 1: on the chart's
    /// long-stick attractor (κ = 50) the large slips' stops, which run
    /// along x, were off by 3.5e-9 at tol 1e-9 with √tol alone and by
    /// 7.5e-10 with it, for 0.4 % more evaluations on the sample (1/√|W v̂_r|
    /// cost 1.5 % on Fig. 3b for no gain within 1e-9). Fixed steps keep
    /// h^(p/2), which matches their own error.
    #[inline(always)]
    pub(crate) fn stop_cutoff(&self, y: &State, vr: f64) -> f64 {
        if !self.settings.method.is_adaptive() {
            return self.cutoff;
        }
        let kx = self.params.kappa * y[2];
        let wv = (kx * kx + y[3] * y[3]).sqrt() / vr;
        if wv > 4.0 {
            self.cutoff * 2.0 / wv.sqrt()
        } else {
            self.cutoff
        }
    }

    pub fn params(&self) -> &Params {
        &self.params
    }

    pub fn settings(&self) -> &SolverSettings {
        &self.settings
    }

    /// Checks that θ is a reachable onset (docs/model.md, "The exit arc").
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
        let onset = point_from_theta(self.params.kappa, theta);
        let end = self.slip::<false>(theta, onset, onset_time, sampler.as_deref_mut())?;
        Ok(self.complete(theta, onset, onset_time, &end, sampler))
    }

    /// The cycle whose slip from `onset` (at θ, time `onset_time`) ended
    /// with `end`: the closed-form stick phase, the next onset, the event.
    fn complete(
        &self,
        theta: f64,
        onset: [f64; 2],
        onset_time: f64,
        end: &SlipEnd,
        sampler: Option<&mut Sampler>,
    ) -> SlipEvent {
        let kappa = self.params.kappa;
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
        SlipEvent {
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
        }
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
    /// both versions round identically. (The step controller's ln and e^x
    /// are libm's, which glibc may dispatch to FMA builds by CPU: across
    /// machines a step size can, rarely, differ in its last bit.)
    fn slip<const TAPE: bool>(
        &self,
        theta: f64,
        p0: [f64; 2],
        t_abs: f64,
        sampler: Option<&mut Sampler>,
    ) -> Result<SlipEnd, SimError> {
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` was set from `is_x86_feature_detected!("avx2")`.
            return unsafe { self.slip_avx2::<TAPE>(theta, p0, t_abs, sampler) };
        }
        self.slip_impl::<TAPE>(theta, p0, t_abs, sampler)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn slip_avx2<const TAPE: bool>(
        &self,
        theta: f64,
        p0: [f64; 2],
        t_abs: f64,
        sampler: Option<&mut Sampler>,
    ) -> Result<SlipEnd, SimError> {
        self.slip_impl::<TAPE>(theta, p0, t_abs, sampler)
    }

    /// One slip from its onset to its stop, step after step
    /// (`slip::SlipRun` holds the logic between the steps).
    #[inline(always)]
    fn slip_impl<const TAPE: bool>(
        &self,
        theta: f64,
        p0: [f64; 2],
        t_abs: f64,
        mut sampler: Option<&mut Sampler>,
    ) -> Result<SlipEnd, SimError> {
        let mut run = SlipRun::<TAPE>::start(self, theta, p0, t_abs, sampler.as_deref_mut())?;
        if TAPE {
            run = run.with_tape();
        }
        loop {
            match run.prepare(sampler.as_deref_mut())? {
                Next::Done(end) => return Ok(end),
                Next::Attempt(h) => {
                    let y_new = run.stages(h);
                    if let Some(end) = run.finish(&y_new, h, sampler.as_deref_mut())? {
                        return Ok(end);
                    }
                }
            }
        }
    }

    /// Where [`Self::stiff_stop`] may take over: v_r at `y` when the slip is
    /// stiff (k = |F_el|/D ≥ [`MIN_STIFFNESS`]), v̂_r points along F̂_el and
    /// the manifold's error bound is below [`ERROR_SHARE`] of the tolerance.
    fn stiff_entry(&self, y: &State, decel: f64) -> Option<f64> {
        // The caller's v_r, formed the same way.
        let vr = (y[2] * y[2] + y[3] * y[3]).sqrt();
        let kappa = self.params.kappa;
        let (fx, fy) = (-kappa * y[0], -y[1]);
        let fnorm = fx.hypot(fy);
        let k = fnorm / decel;
        if !(k >= MIN_STIFFNESS) {
            return None;
        }
        // v̂_r must point along F̂_el, not against it (sin α alone cannot
        // tell: a slip along an axis has sin α = 0 both before and after
        // the block passes the centre, where F_el turns round).
        let cos0 = (fx * y[2] + fy * y[3]) / (fnorm * vr);
        if !(cos0 > 0.5) {
            return None;
        }
        let sin0 = (fx * y[3] - fy * y[2]) / (fnorm * vr);
        let m = self.field.manifold(y[0], y[1], vr);
        let moved = vr * vr / decel;
        let bound = ((sin0 - m.sin_alpha).abs() / (k + 2.0) + m.sin_alpha.abs() / (k * k))
            * moved
            * kappa.max(1.0);
        (bound <= ERROR_SHARE * self.settings.rtol).then_some(vr)
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
        decel: f64,
        t_abs: f64,
        mut sampler: Option<&mut Sampler>,
        evals: &Cell<u64>,
        tape: Option<&RefCell<Box<Tape>>>,
    ) -> StiffEnd {
        let Some(vr) = self.stiff_entry(y, decel) else {
            return StiffEnd::NotStiff;
        };
        let field = self.field;
        let kappa = self.params.kappa;
        // z = (x, y, v_r, unused) on the manifold, against time; with
        // derivatives, its tangent against the [`EV`] slots at `y` (the
        // direction's is dropped with it: it relaxes onto the manifold).
        let zvar = tape.map(|_| {
            let seed = ev_seed();
            let mut zt = [seed[0], seed[1], [0.0; EV], [0.0; EV]];
            for i in 0..EV {
                zt[2][i] = (y[2] * seed[2][i] + y[3] * seed[3][i]) / vr;
            }
            let z0 = [y[0], y[1], vr, 0.0];
            let fld = ev_field(&self.params, &self.field);
            let mut t = Tangents::new(self.settings.method, fld, zt, zt);
            t.k0 = t.field_at(Field::Manifold, &z0, &zt).1;
            RefCell::new(t)
        });
        let v = field.v;
        let mut rhs = |z: &State| -> State {
            evals.set(evals.get() + 1);
            if let Some(zv) = &zvar
                && let Some(r) = zv.borrow_mut().eval(Field::Manifold, z)
            {
                return r;
            }
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
            let stepped =
                manifold_step(&mut solver, &mut rhs, zvar.as_ref(), t, &z, &f, self.h_max);
            let Ok((tn, zn, fnew)) = stepped else {
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
                let stop_d = zvar.map(|zv| {
                    let mut zv = zv.into_inner();
                    let (zs, zt) = zv.partial_step(Field::Manifold, &z, &f, ts - t);
                    let (fz, _) = zv.field_at(Field::Manifold, &zs, &zt);
                    if let Some(tape) = tape {
                        tape.borrow_mut().extra_evals += zv.extra_evals + 1;
                    }
                    variational::stop_at_root(&zt, &fz, [1.0, 0.0], 2)
                });
                return StiffEnd::Stopped {
                    stop: [stop[0], stop[1]],
                    duration: ts,
                    steps: solver.steps(),
                    stop_d,
                };
            }
            if let Some(s) = sampler.as_deref_mut() {
                let d = solver.dense(&mut rhs);
                s.sample_step_with(t_abs, &d, tn, Phase::Decel, v, slip_state);
            }
            (t, z, f) = (tn, zn, fnew);
            if let Some(zv) = &zvar {
                zv.borrow_mut().commit();
            }
        }
    }
}

/// Stiff stops ([`Simulator::stiff_stop`]): the least k = |F_el|/D taken
/// as stiff, the manifold's error allowed as a share of the tolerance, and
/// the most steps on the manifold before giving up.
const MIN_STIFFNESS: f64 = 10.0;
const ERROR_SHARE: f64 = 0.01;
const MAX_STEPS: u32 = 400;

/// One accepted step on the slow manifold: `Solver::step`'s loop, with the
/// tangents (when derivatives are taken) told where each attempt begins
/// and ends.
fn manifold_step<F: Rhs>(
    solver: &mut Solver,
    rhs: &mut F,
    zvar: Option<&RefCell<Box<Tangents<EV>>>>,
    t: f64,
    z: &State,
    f: &State,
    h_max: f64,
) -> Result<(f64, State, State), IntegrateError> {
    loop {
        let h = solver.begin_attempt(t, h_max)?;
        if let Some(zv) = zvar {
            zv.borrow_mut().begin(h);
        }
        let zn = solver.stages(rhs, z, f, h);
        if let Some(zv) = zvar {
            zv.borrow_mut().finishing();
        }
        let r = solver.end_attempt(rhs, t, z, &zn, h);
        if let Some(zv) = zvar {
            zv.borrow_mut().end();
        }
        if let Some(done) = r? {
            return Ok(done);
        }
    }
}

/// Convenience: the default method at tolerance `tol`.
pub fn default_settings(tol: f64) -> SolverSettings {
    SolverSettings::adaptive(Method::Dop853, tol)
}
