//! Forward tangents through Runge–Kutta steps: the same stages as the
//! state's, with the same coefficients and step, on the tangents. The
//! slip's own steps are differentiated in reverse (`variational::tape`);
//! these carry the stiff stop's few steps on the slow manifold, whose
//! field is differentiated on [`super::Tan`] numbers, against the [`EV`]
//! slots where the stiff stop begins.
//!
//! The solver computes the state's stage arguments and calls the
//! right-hand side once per stage, in order; the right-hand side hands
//! each call to [`Tangents::eval`], which returns the field's value and
//! forms the tangent's stage, K_i = J_i (Y + h Σ a_ij K_j) + J_p,i P, at
//! once. A rejected attempt's tangent stages are thrown away, as its state
//! stages are. The caller says where a step begins ([`Tangents::begin`]),
//! when the next evaluation is f(y_new) ([`Tangents::finishing`]) and when
//! it moves on to the new state ([`Tangents::commit`]): anything else
//! (dense output, event location) is evaluated plain.
//!
//! [`EV`]: super::EV

use super::linear;
use super::{DIRS, Jet, TanField, split, tan_state};
use crate::integrate::{Method, State, tableau};
use crate::sim::field::SlipField;

/// The most stages of any method (DOP853's twelve).
pub(crate) const MAX_STAGES: usize = 12;

/// What the next evaluation is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    /// Not part of a step (dense output, events): plain.
    Off,
    /// Stage `idx` of the step being attempted.
    Stage,
    /// f at the new solution of an accepted step (methods without FSAL).
    Final,
}

/// Which field the tangents are evaluated on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Field {
    Accel,
    Decel,
    /// The stiff stop's motion on the slow manifold.
    Manifold,
}

/// A method's Runge–Kutta coefficients, laid out for the tangents' sums
/// (forward, here) and the adjoint's (backward, `variational::tape`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Coeffs {
    pub a: [[f64; MAX_STAGES]; MAX_STAGES],
    pub b: [f64; MAX_STAGES],
    /// The stages each row of a (and, last, b) weighs: the nonzero
    /// coefficients' columns, so that the sums skip the zeros without a
    /// branch per coefficient.
    nz: [[u8; MAX_STAGES]; MAX_STAGES + 1],
    nz_len: [u8; MAX_STAGES + 1],
    pub stages: usize,
    pub fsal: bool,
}

impl Coeffs {
    pub fn new(method: Method) -> Self {
        let mut a = [[0.0; MAX_STAGES]; MAX_STAGES];
        let mut b = [0.0; MAX_STAGES];
        let (stages, fsal) = match method {
            Method::Dop853 => copy(&tableau::DOP853, &mut a, &mut b),
            Method::Dp54 => copy(&tableau::DP54, &mut a, &mut b),
            Method::Rk4 => copy(&tableau::RK4, &mut a, &mut b),
            Method::Euler => copy(&tableau::EULER, &mut a, &mut b),
        };
        let mut nz = [[0u8; MAX_STAGES]; MAX_STAGES + 1];
        let mut nz_len = [0u8; MAX_STAGES + 1];
        for (row, w) in a.iter().take(stages).chain([&b]).enumerate() {
            let r = if row < stages { row } else { MAX_STAGES };
            for (j, &x) in w.iter().enumerate().take(stages) {
                if x != 0.0 {
                    nz[r][nz_len[r] as usize] = j as u8;
                    nz_len[r] += 1;
                }
            }
        }
        Coeffs {
            a,
            b,
            nz,
            nz_len,
            stages,
            fsal,
        }
    }

    /// The columns of row `row`'s nonzero coefficients (a's rows, or
    /// `MAX_STAGES` for b).
    #[inline(always)]
    pub fn nonzero(&self, row: usize) -> &[u8] {
        &self.nz[row][..self.nz_len[row] as usize]
    }
}

/// One integration's tangents along `N` directions: at the current
/// state, and during a step.
pub(crate) struct Tangents<const N: usize = DIRS> {
    /// The parameters with their directions.
    pub fld: TanField<N>,
    /// The same parameters' values, for the plain field.
    plain: SlipField,
    /// The tangents' arithmetic may use AVX2 (as the plain slip does); on
    /// other targets (wasm) the portable path.
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    avx2: bool,
    c: Coeffs,
    /// The tangent of the current state, and of f there.
    pub y: Jet<N>,
    pub k0: Jet<N>,
    k: [Jet<N>; MAX_STAGES],
    h: f64,
    idx: usize,
    mode: Mode,
    /// The attempt's new solution's tangent and f's there, for `commit`.
    final_y: Jet<N>,
    final_k: Jet<N>,
    /// Evaluations beyond the plain cycle's (partial steps to events).
    pub extra_evals: u64,
}

impl<const N: usize> Tangents<N> {
    /// Tangents for `method` from the state tangent `y`, where f's tangent
    /// is `k0`.
    pub fn new(method: Method, fld: TanField<N>, y: Jet<N>, k0: Jet<N>) -> Box<Self> {
        let plain = SlipField {
            kappa: fld.kappa.v,
            two_gamma: fld.two_gamma.v,
            omega: fld.omega.v,
            v: [fld.v[0].v, fld.v[1].v],
        };
        Box::new(Tangents {
            fld,
            plain,
            #[cfg(target_arch = "x86_64")]
            avx2: std::arch::is_x86_feature_detected!("avx2"),
            #[cfg(not(target_arch = "x86_64"))]
            avx2: false,
            c: Coeffs::new(method),
            y,
            k0,
            k: [[[0.0; N]; 4]; MAX_STAGES],
            h: 0.0,
            idx: 0,
            mode: Mode::Off,
            final_y: [[0.0; N]; 4],
            final_k: [[0.0; N]; 4],
            extra_evals: 0,
        })
    }

    /// Evaluates `field` at the state y with tangent t: the slip's two
    /// fields by their Jacobian applied to t, the stiff stop's motion (a
    /// handful of steps per stop) on [`super::Tan`] numbers.
    #[inline(always)]
    pub fn field_at(&self, field: Field, y: &State, t: &Jet<N>) -> (State, Jet<N>) {
        self.field_with::<false>(field, y, t)
    }

    #[inline(always)]
    fn field_with<const FMA: bool>(&self, field: Field, y: &State, t: &Jet<N>) -> (State, Jet<N>) {
        field_tangent::<N, FMA>(field, &self.plain, &self.fld, y, t)
    }

    /// An attempt of length `h` from the current state begins.
    #[inline(always)]
    pub fn begin(&mut self, h: f64) {
        self.h = h;
        self.idx = 1;
        self.k[0] = self.k0;
        self.mode = Mode::Stage;
    }

    /// The next evaluation, if any, is f at the new solution.
    #[inline(always)]
    pub fn finishing(&mut self) {
        self.mode = Mode::Final;
    }

    /// The attempt is over (accepted or not); later evaluations are plain.
    #[inline(always)]
    pub fn end(&mut self) {
        self.mode = Mode::Off;
    }

    /// The integration moves on to the accepted step's new state: so do
    /// the tangents, to the new solution's tangent and f's there.
    #[inline(always)]
    pub fn commit(&mut self) {
        (self.y, self.k0) = (self.final_y, self.final_k);
    }

    /// Y + h Σ_j w_j K_j over row `row`'s nonzero weights `w` (a's rows,
    /// or `MAX_STAGES` for b). A tangent's 4·N numbers are taken as one
    /// flat run, so that the sums go four at a time (rows of six do not
    /// fill 4-wide registers).
    #[inline(always)]
    fn combine<const FMA: bool>(&self, w: &[f64; MAX_STAGES], row: usize) -> Jet<N> {
        let mut out = self.y;
        let flat = out.as_flattened_mut();
        for &j in self.c.nonzero(row) {
            let j = j as usize;
            let hw = self.h * w[j];
            for (o, &x) in flat.iter_mut().zip(self.k[j].as_flattened()) {
                *o = linear::madd::<FMA>(hw, x, *o);
            }
        }
        out
    }

    /// The field at `y` for the solver: evaluated on tangents during a step
    /// (`Some` value), `None` when the evaluation is not part of one. This
    /// dispatch is inlined, the work behind it is not: the stepping loops
    /// are unrolled per stage and per lane, and a copy of the tangent field
    /// in each multiplied the code (and the plain slip's) many times over.
    #[inline(always)]
    pub fn eval(&mut self, field: Field, y: &State) -> Option<State> {
        // Unfused, as the [`super::Tan`] field of the stiff stop is.
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` was set from `is_x86_feature_detected!("avx2")`.
            return unsafe { self.eval_avx2(field, y) };
        }
        self.eval_plain(field, y)
    }

    /// [`Tangents::eval`] compiled with AVX2, unfused.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[inline(never)]
    fn eval_avx2(&mut self, field: Field, y: &State) -> Option<State> {
        self.eval_impl::<false>(field, y)
    }

    /// [`Tangents::eval`] for any CPU.
    #[inline(never)]
    fn eval_plain(&mut self, field: Field, y: &State) -> Option<State> {
        self.eval_impl::<false>(field, y)
    }

    #[inline(always)]
    fn eval_impl<const FMA: bool>(&mut self, field: Field, y: &State) -> Option<State> {
        match self.mode {
            Mode::Off => None,
            Mode::Stage => {
                let i = self.idx;
                self.idx += 1;
                let t = self.combine::<FMA>(&self.c.a[i], i);
                let (v, k) = self.field_with::<FMA>(field, y, &t);
                self.k[i] = k;
                if self.c.fsal && i == self.c.stages - 1 {
                    // The last stage's argument is the new solution.
                    (self.final_y, self.final_k) = (t, k);
                }
                Some(v)
            }
            Mode::Final => {
                let t = self.combine::<FMA>(&self.c.b, MAX_STAGES);
                let (v, k) = self.field_with::<FMA>(field, y, &t);
                (self.final_y, self.final_k) = (t, k);
                Some(v)
            }
        }
    }

    /// One step of length `h` from the current state (value `y`, f there
    /// `f0`), state and tangent together, to the tangent at its end: the
    /// tangent at an event inside the last step, which its dense output
    /// does not carry. Leaves the integration's tangents as they were.
    pub fn partial_step(&mut self, field: Field, y: &State, f0: &State, h: f64) -> (State, Jet<N>) {
        let saved_k = self.k;
        let (saved_h, saved_mode) = (self.h, self.mode);
        self.h = h;
        self.k[0] = self.k0;
        let mut kv = [[0.0; 4]; MAX_STAGES];
        kv[0] = *f0;
        let c = self.c;
        for i in 1..c.stages {
            let mut yi = *y;
            for j in 0..i {
                let a = c.a[i][j];
                if a != 0.0 {
                    for c in 0..4 {
                        yi[c] += h * a * kv[j][c];
                    }
                }
            }
            let t = self.combine::<false>(&c.a[i], i);
            let (v, k) = self.field_at(field, &yi, &t);
            kv[i] = v;
            self.k[i] = k;
        }
        let mut yn = *y;
        for j in 0..c.stages {
            for (m, ym) in yn.iter_mut().enumerate() {
                *ym += h * c.b[j] * kv[j][m];
            }
        }
        let out = self.combine::<false>(&c.b, MAX_STAGES);
        self.extra_evals += c.stages as u64 - 1;
        self.k = saved_k;
        (self.h, self.mode) = (saved_h, saved_mode);
        (yn, out)
    }
}

/// `field` at the state y with tangent t: its value from the plain
/// field's parameters `plain`, bitwise, and its tangent with the
/// parameters' seeds `fld`. The slip's two fields by their Jacobian
/// applied to t, the stiff stop's motion on [`super::Tan`] numbers.
#[inline(always)]
pub(crate) fn field_tangent<const N: usize, const FMA: bool>(
    field: Field,
    plain: &SlipField,
    fld: &TanField<N>,
    y: &State,
    t: &Jet<N>,
) -> (State, Jet<N>) {
    let (v, lin) = match field {
        Field::Accel => linear::accel(plain, y),
        Field::Decel => linear::decel(plain, y),
        Field::Manifold => return split(&fld.manifold_motion(&tan_state(y, t))),
    };
    (v, lin.apply::<N, FMA>(t, fld))
}

/// Copies a tableau's a and b into the fixed-size arrays; its stage count
/// and whether it is FSAL.
fn copy<const S: usize>(
    tab: &tableau::Tableau<S>,
    a: &mut [[f64; MAX_STAGES]; MAX_STAGES],
    b: &mut [f64; MAX_STAGES],
) -> (usize, bool) {
    for i in 0..S {
        a[i][..S].copy_from_slice(&tab.a[i]);
    }
    b[..S].copy_from_slice(&tab.b);
    (S, tab.fsal)
}
