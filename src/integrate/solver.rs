//! The one stepping loop: an embedded pair with a PI step-size controller
//! (Hairer's DOPRI5/DOP853 drivers are the model), or a fixed step.
//!
//! The solver does not own the state: the caller passes (t, y, f(y)) in and
//! gets an accepted step back, so that a hybrid system can stop between
//! steps, locate an event on the last step's dense output, switch the
//! right-hand side and go on (diffsol's `step()` shape).

use super::tableau::{self, Tableau};
use super::{Dense, Method, Rhs, SolverSettings, State, axpy};

/// Counters of one integration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    pub accepted: u32,
    pub rejected: u32,
}

/// Why a step could not be taken.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum IntegrateError {
    #[error("gave up after {max} steps (bound: max_steps)")]
    TooManySteps { max: u32 },
    #[error(
        "step size underflow at t = {t} (h = {h:e}): the solution is not smooth enough for the tolerance"
    )]
    StepSizeUnderflow { t: f64, h: f64 },
    #[error("the solution became non-finite at t = {t}")]
    NonFinite { t: f64 },
}

/// Step-size controller constants (Hairer, Nørsett & Wanner, II.4).
const SAFETY: f64 = 0.9;

/// One integration's attempt, for [`Solver::stages_lanes`]: its solver,
/// right-hand side, state y, f(y) and step.
pub struct LaneAttempt<'a, F> {
    pub solver: &'a mut Solver,
    pub f: F,
    pub y: &'a State,
    pub k0: &'a State,
    pub h: f64,
}

/// Drives one method over the steps of a phase.
pub struct Solver {
    settings: SolverSettings,
    /// Scale of each component in the error norm: (κ, 1, √κ, 1), so the
    /// error is measured in κx (which is what θ = atan2(y, κx) sees).
    weights: State,
    /// The step the controller proposes next.
    pub h: f64,
    ln_err_prev: f64,
    /// The previous accepted step (0 before the first), for the predictive
    /// controller.
    h_prev: f64,
    /// Whether the next steps use Gustafsson's predictive controller as well
    /// (see `grow_factor`): set by the caller where the solution's time
    /// scale shrinks steadily step after step, as on the approach to a stop.
    pub predictive: bool,
    /// The error norm is multiplied by this: 1 keeps the settings' rtol and
    /// atol, 5 divides both by 5 (set by the caller for a stretch of the
    /// integration that needs more accuracy than the rest).
    pub err_scale: f64,
    pub stats: Stats,
    // The last accepted step, kept for dense output.
    k: [State; 16],
    t_old: f64,
    h_last: f64,
    y_old: State,
    y_new: State,
    f_new: State,
    dense_ready: bool,
}

impl Solver {
    /// A solver with the given error weights and first step `h0` (the
    /// fixed-step methods use `settings.step` instead).
    pub fn new(settings: SolverSettings, weights: State, h0: f64) -> Self {
        let h = if settings.method.is_adaptive() {
            h0
        } else {
            settings.step
        };
        Solver {
            settings,
            weights,
            h,
            ln_err_prev: (1e-4f64).ln(),
            h_prev: 0.0,
            predictive: false,
            err_scale: 1.0,
            stats: Stats::default(),
            k: [[0.0; 4]; 16],
            t_old: 0.0,
            h_last: 0.0,
            y_old: [0.0; 4],
            y_new: [0.0; 4],
            f_new: [0.0; 4],
            dense_ready: false,
        }
    }

    pub fn settings(&self) -> &SolverSettings {
        &self.settings
    }

    /// Total steps tried so far (accepted + rejected).
    pub fn steps(&self) -> u32 {
        self.stats.accepted + self.stats.rejected
    }

    /// Takes one accepted step from (t, y), where `k0` = f(y), no longer
    /// than `h_max`. Returns (t_new, y_new, f(y_new)).
    ///
    /// The same as a loop over [`begin_attempt`](Self::begin_attempt),
    /// [`stages`](Self::stages) and [`end_attempt`](Self::end_attempt),
    /// which a caller stepping several integrations together uses instead.
    #[inline(always)]
    pub fn step<F: Rhs>(
        &mut self,
        f: &mut F,
        t: f64,
        y: &State,
        k0: &State,
        h_max: f64,
    ) -> Result<(f64, State, State), IntegrateError> {
        loop {
            let h = self.begin_attempt(t, h_max)?;
            let y_new = self.stages(f, y, k0, h);
            if let Some(done) = self.end_attempt(f, t, y, &y_new, h)? {
                return Ok(done);
            }
        }
    }

    /// The length of the next attempt from t (at most `h_max`), or why no
    /// attempt can be made.
    #[inline(always)]
    pub fn begin_attempt(&self, t: f64, h_max: f64) -> Result<f64, IntegrateError> {
        if self.steps() >= self.settings.max_steps {
            return Err(IntegrateError::TooManySteps {
                max: self.settings.max_steps,
            });
        }
        let h = self.h.min(h_max);
        if !(h > 1e-15 * t.abs().max(1.0)) {
            return Err(IntegrateError::StepSizeUnderflow { t, h });
        }
        Ok(h)
    }

    /// The stages of an attempt of length `h` from y (`k0` = f(y)): the
    /// propagated solution, its error estimate left for `end_attempt`.
    #[inline(always)]
    pub fn stages<F: Rhs>(&mut self, f: &mut F, y: &State, k0: &State, h: f64) -> State {
        let k = &mut self.k;
        match self.settings.method {
            Method::Dp54 => dp54_stages([Lane { k, f, y, k0, h }])[0],
            Method::Dop853 => dop853_stages([Lane { k, f, y, k0, h }])[0],
            Method::Rk4 => stages(&tableau::RK4, f, y, k0, h, k),
            Method::Euler => stages(&tableau::EULER, f, y, k0, h, k),
        }
    }

    /// The stages of `L` DOP853 or `L` DP5(4) attempts computed together,
    /// stage by stage, so that one integration's chain of dependent
    /// evaluations fills the cycles another's leaves idle (`lockstep` in
    /// benches/map_iterate.rs). Each result is bitwise what
    /// [`stages`](Self::stages) gives. Every solver must run the same one
    /// of the two methods ([`Method::steps_in_lanes`]).
    #[inline(always)]
    pub fn stages_lanes<F: Rhs, const L: usize>(mut lanes: [LaneAttempt<'_, F>; L]) -> [State; L] {
        let method = lanes[0].solver.settings.method;
        debug_assert!(
            method.steps_in_lanes() && lanes.iter().all(|a| a.solver.settings.method == method)
        );
        let lanes = lanes.each_mut().map(|a| Lane {
            k: &mut a.solver.k,
            f: &mut a.f,
            y: a.y,
            k0: a.k0,
            h: a.h,
        });
        if method == Method::Dp54 {
            dp54_stages(lanes)
        } else {
            dop853_stages(lanes)
        }
    }

    /// Accepts the attempt (Some((t + h, y_new, f(y_new)))) and proposes the
    /// next step, or rejects it (None) with a shorter one to try.
    #[inline(always)]
    pub fn end_attempt<F: Rhs>(
        &mut self,
        f: &mut F,
        t: f64,
        y: &State,
        y_new: &State,
        h: f64,
    ) -> Result<Option<(f64, State, State)>, IntegrateError> {
        match self.settings.method {
            Method::Dp54 => self.end_with(&tableau::DP54, f, t, y, y_new, h),
            Method::Dop853 => self.end_with(&tableau::DOP853, f, t, y, y_new, h),
            Method::Rk4 => self.end_with(&tableau::RK4, f, t, y, y_new, h),
            Method::Euler => self.end_with(&tableau::EULER, f, t, y, y_new, h),
        }
    }

    #[inline(always)]
    fn end_with<F: Rhs, const S: usize>(
        &mut self,
        tab: &Tableau<S>,
        f: &mut F,
        t: f64,
        y: &State,
        y_new: &State,
        h: f64,
    ) -> Result<Option<(f64, State, State)>, IntegrateError> {
        let adaptive = self.settings.method.is_adaptive();
        let y_new = *y_new;
        let err = if adaptive {
            self.err_scale * self.error_norm(tab, y, &y_new, h)
        } else {
            0.0
        };
        let finite = y_new.iter().all(|v| v.is_finite());
        if !finite && !adaptive {
            return Err(IntegrateError::NonFinite { t: t + h });
        }
        if finite && err <= 1.0 {
            let k_new = if tab.fsal {
                self.k[S - 1]
            } else {
                f.eval(&y_new)
            };
            self.stats.accepted += 1;
            self.t_old = t;
            self.h_last = h;
            self.y_old = *y;
            self.y_new = y_new;
            self.f_new = k_new;
            self.dense_ready = false;
            if adaptive {
                let ln_err = err.max(1e-4).ln();
                self.h = h * self.grow_factor(tab, err, h, ln_err);
                self.h_prev = h;
                self.ln_err_prev = ln_err;
            }
            return Ok(Some((t + h, y_new, k_new)));
        }
        self.stats.rejected += 1;
        let shrink = if finite {
            (SAFETY * err.powf(-1.0 / (tab.err_order as f64 + 1.0))).max(0.2)
        } else {
            0.25
        };
        self.h = h * shrink.min(0.9);
        Ok(None)
    }

    /// The step factor after an accepted step `h` with error `err`
    /// (`ln_err` = ln max(err, 1e-4)): the PI controller's, or with
    /// `predictive` the smaller of it and Gustafsson's predictive one,
    /// h_new = h · SAFETY · (h/h_prev) · (err_prev/err)^(1/q) · err^(−1/q), as Hairer's RADAU5 does. The PI factor assumes the error constant stays
    /// put from step to step; on the approach to a stop it grows every step
    /// (the remaining time shrinks geometrically), so nearly every proposed
    /// step was rejected once (17 rejections in 83 steps of one DOP853 slip
    /// at tol 1e-10). The h/h_prev factor carries that trend forward: 2
    /// rejections, and 19 % fewer evaluations on the Fig. 3b attractor.
    #[inline(always)]
    fn grow_factor<const S: usize>(&self, tab: &Tableau<S>, err: f64, h: f64, ln_err: f64) -> f64 {
        let q = tab.err_order as f64 + 1.0;
        let beta = 0.4 / q;
        let alpha = 1.0 / q - 0.75 * beta;
        let (fmin, fmax) = if S == 12 { (0.333, 6.0) } else { (0.2, 10.0) };
        if err == 0.0 {
            return fmax;
        }
        // err^(−α)·err_prev^β as one exp of logs (two powf cost more); the
        // caller's ln_err is ln(max(err, 1e-4)), so it is ln(err) itself at
        // and above 1e-4 (most steps), bitwise, and one ln is saved there.
        let ln_e = if err >= 1e-4 { ln_err } else { err.ln() };
        let pi = SAFETY * (beta * self.ln_err_prev - alpha * ln_e).exp();
        let f = if self.predictive && self.h_prev > 0.0 {
            let gus = SAFETY * (h / self.h_prev) * ((self.ln_err_prev - 2.0 * ln_err) / q).exp();
            pi.min(gus)
        } else {
            pi
        };
        f.clamp(fmin, fmax)
    }

    #[inline(always)]
    fn error_norm<const S: usize>(
        &self,
        tab: &Tableau<S>,
        y: &State,
        y_new: &State,
        h: f64,
    ) -> f64 {
        let (rtol, atol) = (self.settings.rtol, self.settings.atol);
        let (e5, e3) = error_sums(tab, &self.k);
        let mut sc = [0.0; 4];
        for i in 0..4 {
            let w = self.weights[i];
            sc[i] = w / (atol + rtol * (w * y[i]).abs().max((w * y_new[i]).abs()));
        }
        let (mut s5, mut s3) = (0.0, 0.0);
        for i in 0..4 {
            let a = e5[i] * sc[i];
            let b = e3[i] * sc[i];
            s5 += a * a;
            s3 += b * b;
        }
        if tab.e3.is_none() {
            return h.abs() * (s5 / 4.0).sqrt();
        }
        // Hairer's DOP853 combination of the 5th- and 3rd-order estimates.
        let mut den = s5 + 0.01 * s3;
        if den <= 0.0 {
            den = 1.0;
        }
        h.abs() * s5 / (den * 4.0).sqrt()
    }

    /// The dense output of the last accepted step. For DOP853 this costs
    /// three extra evaluations of `f` (the first call after each step only).
    pub fn dense<F: Rhs>(&mut self, f: &mut F) -> Dense {
        let (t0, h, y0, y1) = (self.t_old, self.h_last, self.y_old, self.y_new);
        match self.settings.method {
            Method::Dp54 => {
                let mut q = [[0.0; 4]; 4];
                for (j, row) in tableau::DP54_DENSE.iter().enumerate() {
                    for m in 0..4 {
                        if row[m] != 0.0 {
                            axpy(&mut q[m], row[m], &self.k[j]);
                        }
                    }
                }
                Dense::power(t0, h, y0, q)
            }
            Method::Dop853 => {
                if !self.dense_ready {
                    // Stage 13 is f at the new point; the extra rows read it.
                    self.k[12] = self.f_new;
                    for s in 0..3 {
                        let mut yi = y0;
                        for (j, &a) in tableau::DOP853_EXTRA_A[s].iter().enumerate() {
                            if a != 0.0 {
                                axpy(&mut yi, h * a, &self.k[j]);
                            }
                        }
                        self.k[13 + s] = f.eval(&yi);
                    }
                    self.dense_ready = true;
                }
                let f_old = self.k[0];
                let f_new = self.f_new;
                let mut fs = [[0.0; 4]; 7];
                for i in 0..4 {
                    let dy = y1[i] - y0[i];
                    fs[0][i] = dy;
                    fs[1][i] = h * f_old[i] - dy;
                    fs[2][i] = 2.0 * dy - h * (f_new[i] + f_old[i]);
                }
                for (m, row) in tableau::DOP853_D.iter().enumerate() {
                    let mut acc = [0.0; 4];
                    for (j, &d) in row.iter().enumerate() {
                        if d != 0.0 {
                            axpy(&mut acc, d, &self.k[j]);
                        }
                    }
                    for i in 0..4 {
                        fs[3 + m][i] = h * acc[i];
                    }
                }
                Dense::dop853(t0, h, y0, fs)
            }
            Method::Rk4 | Method::Euler => Dense::hermite(t0, h, y0, y1, self.k[0], self.f_new),
        }
    }
}

/// Σ_j row[j]·k[j] over the listed nonzero columns, unrolled at compile
/// time: the coefficients come from the `const` tableau, so they fold into
/// immediates and no zero is multiplied.
macro_rules! comb {
    ($row:expr, $k:expr; $($j:literal),+) => {{
        let k = $k;
        let mut out = [0.0; 4];
        // One 4-wide multiply-add per coefficient: written as whole-vector
        // updates so the compiler packs the four components (the per-
        // component sum chains it left scalar).
        $(axpy(&mut out, $row[$j], &k[$j]);)+
        out
    }};
}

/// y + h·Σ_j row[j]·k[j] (a stage argument).
macro_rules! stage_arg {
    ($y:expr, $h:expr, $row:expr, $k:expr; $($j:literal),+) => {{
        let s = comb!($row, $k; $($j),+);
        let mut out = *$y;
        for c in 0..4 {
            out[c] += $h * s[c];
        }
        out
    }};
}

/// The stages of one step of `tab` from y (k[0] = f(y) given); returns the
/// propagated solution. With FSAL the last stage's argument is the solution.
/// DOP853 (`dop853_stages`) and DP5(4) (`dp54_stages`) take unrolled paths
/// over their nonzero coefficients (the stage arithmetic was a third of the
/// cost as a generic double loop); the values still come from the one
/// tableau.
#[inline(always)]
fn stages<F: Rhs, const S: usize>(
    tab: &Tableau<S>,
    f: &mut F,
    y: &State,
    k0: &State,
    h: f64,
    k: &mut [State; 16],
) -> State {
    k[0] = *k0;
    let mut y_fsal = *y;
    for i in 1..S {
        let mut yi = *y;
        for j in 0..i {
            let a = tab.a[i][j];
            if a != 0.0 {
                axpy(&mut yi, h * a, &k[j]);
            }
        }
        k[i] = f.eval(&yi);
        if tab.fsal && i == S - 1 {
            y_fsal = yi;
        }
    }
    if tab.fsal {
        return y_fsal;
    }
    let mut y_new = *y;
    for j in 0..S {
        if tab.b[j] != 0.0 {
            axpy(&mut y_new, h * tab.b[j], &k[j]);
        }
    }
    y_new
}

/// One stage of an unrolled tableau for every lane (`dop853_stages`,
/// `dp54_stages`): each lane's argument y + h Σ a_ij k_j over the nonzero
/// coefficients `j`, then the evaluations, so that the lanes' chains
/// interleave. The block's value is the arguments.
macro_rules! lanes_stage {
    ($lanes:ident, $l:ident, $row:expr; $i:literal; $($j:literal),+) => {{
        let mut args = [[0.0; 4]; $l];
        for l in 0..$l {
            let ln = &$lanes[l];
            args[l] = stage_arg!(ln.y, ln.h, $row, &*ln.k; $($j),+);
        }
        for l in 0..$l {
            let ln = &mut $lanes[l];
            ln.k[$i] = ln.f.eval(&args[l]);
        }
        args
    }};
}

/// One attempt's share of `dop853_stages` or `dp54_stages`.
struct Lane<'a, F> {
    k: &'a mut [State; 16],
    f: &'a mut F,
    y: &'a State,
    k0: &'a State,
    h: f64,
}

/// DOP853's stages for `L` integrations at once, unrolled over the nonzero
/// coefficients and interleaved stage by stage (each stage's arguments for
/// all of them, then their evaluations): with L = 1 the plain stages, with
/// L = 2 two independent chains the CPU overlaps. Every integration's
/// arithmetic is the same sequence whatever L is, so its results are too.
#[inline(always)]
fn dop853_stages<F: Rhs, const L: usize>(mut lanes: [Lane<'_, F>; L]) -> [State; L] {
    let a = &tableau::DOP853.a;
    for l in lanes.iter_mut() {
        l.k[0] = *l.k0;
    }
    macro_rules! stage {
        ($i:literal; $($j:literal),+) => {
            lanes_stage!(lanes, L, a[$i]; $i; $($j),+)
        };
    }
    stage!(1; 0);
    stage!(2; 0, 1);
    stage!(3; 0, 2);
    stage!(4; 0, 2, 3);
    stage!(5; 0, 3, 4);
    stage!(6; 0, 3, 4, 5);
    stage!(7; 0, 3, 4, 5, 6);
    stage!(8; 0, 3, 4, 5, 6, 7);
    stage!(9; 0, 3, 4, 5, 6, 7, 8);
    stage!(10; 0, 3, 4, 5, 6, 7, 8, 9);
    stage!(11; 0, 3, 4, 5, 6, 7, 8, 9, 10);
    let mut out = [[0.0; 4]; L];
    for l in 0..L {
        let ln = &lanes[l];
        out[l] = stage_arg!(ln.y, ln.h, tableau::DOP853.b, &*ln.k; 0, 5, 6, 7, 8, 9, 10, 11);
    }
    out
}

/// DP5(4)'s stages for `L` integrations at once, as `dop853_stages`; the
/// last stage's argument is the solution (FSAL), and its evaluation
/// f(y_new) is the seventh stage.
#[inline(always)]
fn dp54_stages<F: Rhs, const L: usize>(mut lanes: [Lane<'_, F>; L]) -> [State; L] {
    let a = &tableau::DP54.a;
    for l in lanes.iter_mut() {
        l.k[0] = *l.k0;
    }
    // The last stage's arguments are the solutions.
    macro_rules! stage {
        ($i:literal; $($j:literal),+) => {
            lanes_stage!(lanes, L, a[$i]; $i; $($j),+)
        };
    }
    stage!(1; 0);
    stage!(2; 0, 1);
    stage!(3; 0, 1, 2);
    stage!(4; 0, 1, 2, 3);
    stage!(5; 0, 1, 2, 3, 4);
    stage!(6; 0, 2, 3, 4, 5)
}

/// The error estimates Σ e_j k_j (and DOP853's 3rd-order one), unrolled like
/// the stages.
#[inline(always)]
fn error_sums<const S: usize>(tab: &Tableau<S>, k: &[State; 16]) -> (State, State) {
    if S == 12 {
        let e3 = match &tableau::DOP853.e3 {
            Some(e3) => comb!(e3, k; 0, 5, 6, 7, 8, 9, 10, 11),
            None => [0.0; 4],
        };
        return (comb!(tableau::DOP853.e, k; 0, 5, 6, 7, 8, 9, 10, 11), e3);
    }
    if S == 7 {
        return (comb!(tableau::DP54.e, k; 0, 2, 3, 4, 5, 6), [0.0; 4]);
    }
    let mut e = [0.0; 4];
    for j in 0..S {
        if tab.e[j] != 0.0 {
            axpy(&mut e, tab.e[j], &k[j]);
        }
    }
    (e, [0.0; 4])
}

#[cfg(test)]
mod tests;
