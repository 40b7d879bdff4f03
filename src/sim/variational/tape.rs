//! Reverse mode: a slip's tape and its backward sweep.
//!
//! θ' is one number and the directions it is wanted along are six, so the
//! map's gradient is cheapest by the adjoint: one 4-component adjoint
//! swept back through the slip's steps gives the derivatives along all
//! six for about the price of one forward tangent (docs/derivatives.md).
//!
//! **Forward**, the slip runs as a plain slip does, and each evaluation of
//! an accepted step leaves on the tape its state and what the field
//! computed there that the Jacobian needs (`SlipField::accel_aux`; the
//! values are bitwise the plain field's, so the steps are the plain
//! slip's). The switching events (the end of the acceleration phase, the
//! stop) are short and few: their Jacobians against the state where they
//! begin and against the parameters are taken by forward mode there, with
//! [`EV`] slots (the four state components, then θν, κ, γ, ν, Ω), and
//! kept on the tape.
//!
//! **Backward**, from the gradient of θ' with respect to the state where
//! the slip's steps ended: each step is the discrete map
//! Y⁺ = Y + h Σ b_j K_j, K_i = J_i T_i + J_p,i P, T_i = Y + h Σ a_ij K_j,
//! whose transpose runs its stages in reverse: ν_i = h (b_i λ + Σ_l a_li μ_l),
//! μ_i = J_iᵀ ν_i, λ⁻ = λ + Σ μ_i, and the parameters gather J_p,iᵀ ν_i.
//! This is the exact transpose of the forward tangent's recurrence with
//! the same Jacobians: the same numbers up to rounding.

use std::cell::RefCell;

use super::linear::{Lin, madd};
use super::stages::{Coeffs, Field};
use super::{
    D_GAMMA, D_KAPPA, D_NU, D_OMEGA, D_THETA_NU, DIRS, Grad, Jet, NotDifferentiable, TanField,
};
use crate::integrate::tableau::{self, Tableau};
use crate::integrate::{Method, State};
use crate::model::Params;
use crate::sim::field::{AccelAux, Aux, DecelAux, SlipField};

/// Runs `$body` for each stage of an `$s`-stage method, last first, with
/// `$i` bound to the stage's index as a constant (no closure: one build
/// left a closure's body out of line, and with it the intrinsics).
macro_rules! stages_rev {
    ($s:expr, $i:ident => $body:expr) => {
        match $s {
            12 => stages_rev!(@each $i => $body; 11 10 9 8 7 6 5 4 3 2 1 0),
            7 => stages_rev!(@each $i => $body; 6 5 4 3 2 1 0),
            4 => stages_rev!(@each $i => $body; 3 2 1 0),
            1 => stages_rev!(@each $i => $body; 0),
            _ => {
                for $i in (0..$s).rev() {
                    $body;
                }
            }
        }
    };
    (@each $i:ident => $body:expr; $($n:literal)*) => {{
        $( { let $i: usize = $n; $body; } )*
    }};
}

/// The slots of an event's forward-mode derivatives: the four state
/// components where it begins, then θν, κ, γ, ν, Ω.
pub const EV: usize = 9;
/// A slot that seeds no parameter (`TanField::seeded` ignores it): a
/// state component's.
const STATE: usize = usize::MAX;
/// What the [`EV`] slots seed, for `TanField::seeded`.
pub const EV_DIRS: [usize; EV] = [
    STATE, STATE, STATE, STATE, D_THETA_NU, D_KAPPA, D_GAMMA, D_NU, D_OMEGA,
];

/// The tangent an event starts from: the identity on the state's slots.
pub fn ev_seed() -> Jet<EV> {
    let mut t = [[0.0; EV]; 4];
    for (c, row) in t.iter_mut().enumerate() {
        row[c] = 1.0;
    }
    t
}

/// The parameters with their [`EV`] slots.
pub fn ev_field(p: &Params, field: &SlipField) -> TanField<EV> {
    TanField::seeded(p, field, EV_DIRS)
}

/// The most a slip's tape holds, in bytes of its records: a few MB,
/// whatever the slip costs. A slip of more steps than fit (one near
/// κ = 16,570 once took 210 MB of tape) ends without derivatives,
/// [`NotDifferentiable::TapeFull`], rather than with unbounded memory.
///
/// [`NotDifferentiable::TapeFull`]: super::NotDifferentiable::TapeFull
pub const MAX_TAPE_BYTES: usize = 4 << 20;

/// [`MAX_TAPE_BYTES`] in records.
const MAX_RECS: usize = MAX_TAPE_BYTES / std::mem::size_of::<Rec>();

thread_local! {
    /// The thread's last tape, for reuse ([`Tape::recycle`]).
    static SPARE: RefCell<Option<Box<Tape>>> = const { RefCell::new(None) };
}

/// One evaluation on the tape: its state and the field's [`Aux`] there.
#[derive(Clone, Copy, Debug)]
struct Rec {
    y: State,
    aux: Aux,
}

/// What the tape holds, in order.
#[derive(Clone, Copy, Debug)]
enum Entry {
    /// An accepted step of length `h` on `field`: its stages' [`Rec`]s,
    /// stage 0 the step's start.
    Step { h: f64, field: Field },
    /// A switching event: its Jacobian, the next of `Tape::events`.
    Event,
}

/// A slip's tape (see the module's text). The slip says where an attempt
/// begins ([`Tape::begin`]), when its next evaluation is f at the new
/// solution ([`Tape::finishing`]), when it is over ([`Tape::end`]) and
/// when the slip moves on to its new state ([`Tape::commit`]); what is
/// evaluated outside an attempt (dense output, event location) is not
/// recorded, and a rejected attempt's records are dropped.
pub(crate) struct Tape {
    method: Method,
    c: Coeffs,
    field: SlipField,
    recs: Vec<Rec>,
    entries: Vec<Entry>,
    /// Each event's tangent after it against the [`EV`] slots before it.
    events: Vec<Jet<EV>>,
    /// The records of the committed steps: `recs[..committed]`.
    committed: usize,
    recording: bool,
    finishing: bool,
    /// The field's record at the current state, and at the attempt's new
    /// solution (methods without FSAL evaluate f there once accepted).
    cur: Rec,
    next: Rec,
    h: f64,
    step_field: Field,
    /// Evaluations beyond the plain slip's (the events' forward mode).
    pub extra_evals: u64,
    /// The stop's tangent against the [`EV`] slots at the slip's last
    /// state, once the slip has ended.
    pub stop: [Grad<EV>; 2],
}

impl Tape {
    /// A tape for a slip of `method` on `field` from rest at `y0`.
    pub fn new(method: Method, field: SlipField, y0: &State) -> Box<Self> {
        let cur = Rec {
            y: *y0,
            aux: field.accel_aux(y0).1,
        };
        // A thread's last tape's buffers (and coefficients, for the same
        // method): a cycle with derivatives then allocates next to nothing.
        let spare = SPARE.with(|s| s.borrow_mut().take()).map(|t| *t);
        let (c, mut recs, mut entries, mut events) = match spare {
            Some(t) => {
                let c = if t.method == method {
                    t.c
                } else {
                    Coeffs::new(method)
                };
                (c, t.recs, t.entries, t.events)
            }
            None => {
                let c = Coeffs::new(method);
                let recs = Vec::with_capacity(64 * c.stages);
                (c, recs, Vec::with_capacity(64), Vec::new())
            }
        };
        recs.clear();
        entries.clear();
        events.clear();
        Box::new(Tape {
            method,
            c,
            field,
            recs,
            entries,
            events,
            committed: 0,
            recording: false,
            finishing: false,
            cur,
            next: cur,
            h: 0.0,
            step_field: Field::Accel,
            extra_evals: 1,
            stop: [[0.0; EV]; 2],
        })
    }

    /// Room for one more step's records, growing the buffer by doubling
    /// but never past [`MAX_RECS`] (plus the step): the records' memory
    /// stays within [`MAX_TAPE_BYTES`] whatever the slip's length.
    #[inline(always)]
    fn reserve_step(&mut self) {
        let need = self.recs.len() + self.c.stages + 2;
        if need > self.recs.capacity() {
            let target = (2 * self.recs.capacity()).min(MAX_RECS).max(need);
            self.recs.reserve_exact(target - self.recs.len());
        }
    }

    /// Whether another step would take the tape past [`MAX_TAPE_BYTES`]:
    /// the slip then goes on without derivatives.
    pub fn is_full(&self) -> bool {
        self.recs.len() + self.c.stages + 2 > MAX_RECS
    }

    /// The steps on the tape.
    pub fn steps(&self) -> usize {
        self.entries.len()
    }

    /// Keeps this tape's buffers for the thread's next [`Tape::new`].
    pub fn recycle(self: Box<Self>) {
        SPARE.with(|s| *s.borrow_mut() = Some(self));
    }

    /// Records an evaluation at `y` (its field's `aux`) if it belongs to
    /// the attempt in progress.
    #[inline(always)]
    pub fn record(&mut self, y: &State, aux: Aux) {
        if !self.recording {
            return;
        }
        let r = Rec { y: *y, aux };
        if self.finishing {
            self.next = r;
        } else {
            self.recs.push(r);
        }
    }

    /// An attempt of length `h` on `field` begins from the current state.
    #[inline(always)]
    pub fn begin(&mut self, h: f64, field: Field) {
        self.recs.truncate(self.committed);
        self.reserve_step();
        self.recs.push(self.cur);
        (self.h, self.step_field) = (h, field);
        self.recording = true;
        self.finishing = false;
    }

    /// The next evaluation, if any, is f at the new solution.
    #[inline(always)]
    pub fn finishing(&mut self) {
        self.finishing = true;
    }

    /// The attempt is over (accepted or not).
    #[inline(always)]
    pub fn end(&mut self) {
        self.recording = false;
    }

    /// The slip moves on to the accepted attempt's new state.
    #[inline(always)]
    pub fn commit(&mut self) {
        debug_assert_eq!(self.recs.len(), self.committed + self.c.stages);
        self.entries.push(Entry::Step {
            h: self.h,
            field: self.step_field,
        });
        self.committed = self.recs.len();
        self.cur = if self.c.fsal {
            self.recs[self.committed - 1]
        } else {
            self.next
        };
    }

    /// A step of length `h` on `field` from the current state `y` (f
    /// there: `f0`) to an event inside the step that the slip just took,
    /// which its dense output located: recorded as a step. Returns its end.
    pub fn partial_step(&mut self, field: Field, y: &State, f0: &State, h: f64) -> State {
        let c = self.c;
        self.recs.truncate(self.committed);
        self.reserve_step();
        self.recs.push(self.cur);
        let mut k = [[0.0; 4]; super::stages::MAX_STAGES];
        k[0] = *f0;
        for i in 1..c.stages {
            let mut yi = *y;
            for &j in c.nonzero(i) {
                let w = h * c.a[i][j as usize];
                for m in 0..4 {
                    yi[m] += w * k[j as usize][m];
                }
            }
            let (v, aux) = match field {
                Field::Accel => self.field.accel_aux(&yi),
                _ => self.field.decel_aux(&yi),
            };
            k[i] = v;
            self.recs.push(Rec { y: yi, aux });
        }
        let mut yn = *y;
        for &j in c.nonzero(super::stages::MAX_STAGES) {
            let w = h * c.b[j as usize];
            for m in 0..4 {
                yn[m] += w * k[j as usize][m];
            }
        }
        self.entries.push(Entry::Step { h, field });
        self.committed = self.recs.len();
        self.extra_evals += c.stages as u64 - 1;
        yn
    }

    /// The acceleration phase ended at `ya`, the end of the tape's last
    /// step: the deceleration's tangent there is `m` against the [`EV`]
    /// slots before the switch.
    pub fn switch(&mut self, m: Jet<EV>, ya: &State) {
        self.recs.truncate(self.committed);
        self.entries.push(Entry::Event);
        self.events.push(m);
        self.cur = Rec {
            y: *ya,
            aux: self.field.decel_aux(ya).1,
        };
        self.extra_evals += 1;
    }

    /// The derivatives of θ' along the six directions (θ, θν, κ, γ, ν, Ω)
    /// of a slip from the onset at `theta`, given `g`, θ''s gradient
    /// against the [`EV`] slots at the slip's last committed state.
    pub fn gradient(&self, g: &Grad<EV>, theta: f64, p: &Params) -> Grad<DIRS> {
        let (lam, pf, pm) = self.backward(g);
        // The onset (cos θ/κ, sin θ, 0, 0).
        let (s, c) = theta.sin_cos();
        let k = p.kappa;
        // V = ν (cos θν, sin θν).
        let (snu, cnu) = p.theta_nu.sin_cos();
        let v = self.field.v;
        let [pk, p2g, po, pvx, pvy] = pf;
        [
            lam[0] * (-s / k) + lam[1] * c,
            pm[0] + (-v[1] * pvx + v[0] * pvy),
            pm[1] + pk + lam[0] * (-c / (k * k)),
            pm[2] + 2.0 * p2g,
            pm[3] + (cnu * pvx + snu * pvy),
            pm[4] + po,
        ]
    }

    /// The sweep as the CPU runs it and the portable one, for the test
    /// that they agree.
    #[cfg(test)]
    pub(crate) fn both_sweeps(&self, g: &Grad<EV>) -> [([f64; 4], [f64; 5], [f64; 5]); 2] {
        [self.backward(g), self.backward_impl::<false>(g)]
    }

    /// The backward sweep: the adjoint at the onset's state, and the
    /// gradient against the field's parameters (κ, 2γ, Ω, V_x, V_y) and
    /// against the model's (θν, κ, γ, ν, Ω, from the events).
    fn backward(&self, g: &Grad<EV>) -> ([f64; 4], [f64; 5], [f64; 5]) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            // SAFETY: both features were just detected.
            return unsafe { self.backward_fma(g) };
        }
        self.backward_impl::<false>(g)
    }

    /// [`Tape::backward`] with AVX2 and fused multiply-adds: a derivative's
    /// last bits may differ by CPU, a value never does.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn backward_fma(&self, g: &Grad<EV>) -> ([f64; 4], [f64; 5], [f64; 5]) {
        self.backward_impl::<true>(g)
    }

    #[inline(always)]
    fn backward_impl<const FMA: bool>(&self, g: &Grad<EV>) -> ([f64; 4], [f64; 5], [f64; 5]) {
        match self.method {
            Method::Dop853 => self.sweep::<12, FMA>(&tableau::DOP853, g),
            Method::Dp54 => self.sweep::<7, FMA>(&tableau::DP54, g),
            Method::Rk4 => self.sweep::<4, FMA>(&tableau::RK4, g),
            Method::Euler => self.sweep::<1, FMA>(&tableau::EULER, g),
        }
    }

    /// The sweep for a method of `S` stages. The tableau is a constant,
    /// so its zeros drop out and the stages' adjoints stay in registers:
    /// the sweep is one chain of dependent operations (stage after stage,
    /// step after step), whose length is what it costs.
    #[inline(always)]
    fn sweep<const S: usize, const FMA: bool>(
        &self,
        tab: &Tableau<S>,
        g: &Grad<EV>,
    ) -> ([f64; 4], [f64; 5], [f64; 5]) {
        let mut lam = [g[0], g[1], g[2], g[3]];
        let mut pm = [g[4], g[5], g[6], g[7], g[8]];
        let mut pf = [0.0; 5];
        let mut end = self.committed;
        let mut events = self.events.iter().rev();
        for entry in self.entries.iter().rev() {
            match *entry {
                Entry::Event => {
                    let m = events.next().expect("one Jacobian per event");
                    let mut before = [0.0; 4];
                    for (r, row) in m.iter().enumerate() {
                        for (col, b) in before.iter_mut().enumerate() {
                            *b = madd::<FMA>(row[col], lam[r], *b);
                        }
                        for (j, p) in pm.iter_mut().enumerate() {
                            *p = madd::<FMA>(row[4 + j], lam[r], *p);
                        }
                    }
                    lam = before;
                }
                Entry::Step { h, field } => {
                    let recs = &self.recs[end - S..end];
                    end -= S;
                    // The Jacobians first: they do not wait for the chain.
                    // Each stage's Jacobian is formed where the stage is
                    // swept: it does not wait for the chain, so the CPU
                    // forms the next one while the chain waits.
                    let lin = |i: usize| jacobian(&self.field, field, &recs[i]);
                    #[cfg(target_arch = "x86_64")]
                    if FMA {
                        // SAFETY: `FMA` is set only by `backward_fma`, which
                        // is compiled with AVX2 and FMA and called only
                        // where the CPU has both.
                        let (l, p) =
                            unsafe { simd::step_adjoint(tab, h, &self.field, field, recs, lam) };
                        lam = l;
                        for k in 0..5 {
                            pf[k] += p[k];
                        }
                        continue;
                    }
                    let mut nu = [[0.0; 4]; S];
                    for (n, b) in nu.iter_mut().zip(tab.b) {
                        for k in 0..4 {
                            n[k] = h * b * lam[k];
                        }
                    }
                    let mut acc = lam;
                    // Stage by stage, last first, each index a constant:
                    // the sums over the tableau's nonzeros are unrolled and
                    // the adjoints kept in registers.
                    stages_rev!(S, i => adjoint_stage::<S, FMA>(
                        tab, h, i, &lin(i), &mut nu, &mut acc, &mut pf
                    ));
                    lam = acc;
                }
            }
        }
        debug_assert_eq!(end, 0);
        (lam, pf, pm)
    }
}

/// The Jacobian of `field` at a record.
#[inline(always)]
fn jacobian(sf: &SlipField, field: Field, r: &Rec) -> Lin {
    match field {
        Field::Accel => Lin::accel(sf, &r.y, &AccelAux::unpack(&r.aux)),
        Field::Decel => Lin::decel(sf, &r.y, &DecelAux::unpack(&r.aux)),
        Field::Manifold => unreachable!("the stiff stop is not on the tape"),
    }
}

/// Stage `i` of a step's adjoint: μ_i = J_iᵀ ν_i into the step's adjoint
/// `acc` and the parameters' `pf`, and its share h a_ij μ_i of the earlier
/// stages' ν_j.
#[inline(always)]
fn adjoint_stage<const S: usize, const FMA: bool>(
    tab: &Tableau<S>,
    h: f64,
    i: usize,
    lin: &Lin,
    nu: &mut [[f64; 4]; S],
    acc: &mut [f64; 4],
    pf: &mut [f64; 5],
) {
    let (mu, p) = lin.transpose_apply::<FMA>(&nu[i]);
    for k in 0..5 {
        pf[k] += p[k];
    }
    for k in 0..4 {
        acc[k] += mu[k];
    }
    for j in 0..i {
        let a = tab.a[i][j];
        if a != 0.0 {
            let w = h * a;
            for k in 0..4 {
                nu[j][k] = madd::<FMA>(w, mu[k], nu[j][k]);
            }
        }
    }
}

/// A step's adjoint four wide, with AVX2 and FMA: ν_i in one register,
/// J_iᵀ ν_i as ν₂ row 2 + ν₃ row 3 + (0, 0, ν₀, ν₁) with in-lane
/// broadcasts, so that the chain from stage to stage is two shuffles and
/// three fused multiply-adds.
#[cfg(target_arch = "x86_64")]
mod simd;

/// The gradient of θ' against the [`EV`] slots at a slip's last state,
/// from its stop's tangent there (`None`: not strictly inside C).
pub fn stop_gradient(
    fld: &TanField<EV>,
    stop: [f64; 2],
    d: &[Grad<EV>; 2],
) -> Option<Result<Grad<EV>, NotDifferentiable>> {
    let stop = [0, 1].map(|i| super::Tan {
        v: stop[i],
        d: d[i],
    });
    super::next_theta_grad(fld, stop)
}
