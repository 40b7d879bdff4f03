//! Explicit Runge–Kutta integration written once: tableaus as data
//! (`tableau`), one stepping loop with step-size control (`solver`), dense
//! output (`dense`) and root finding on it (`roots`). The right-hand side is
//! an [`Rhs`] (any closure is one) over a fixed-size state, so the inner loop
//! is monomorphised and allocation-free.

mod dense;
mod roots;
mod settings;
mod solver;
pub mod tableau;

pub use dense::Dense;
pub use roots::find_root;
pub use settings::{Method, SettingsError, SolverSettings};
pub use solver::{IntegrateError, LaneAttempt, Solver, Stats};

/// The state integrated during a slip: (x, y, v_r,x, v_r,y).
pub type State = [f64; 4];

/// A right-hand side f(y). Closures are right-hand sides; a type of its own
/// with an `#[inline(always)]` `eval` is guaranteed to be inlined into the
/// stepping loop, and so compiled with that loop's target features (a
/// closure is a function of its own, which LLVM declined to inline for the
/// large acceleration-phase field).
pub trait Rhs {
    fn eval(&mut self, y: &State) -> State;
}

impl<F: FnMut(&State) -> State> Rhs for F {
    #[inline(always)]
    fn eval(&mut self, y: &State) -> State {
        self(y)
    }
}

#[inline(always)]
pub(crate) fn axpy(y: &mut State, a: f64, x: &State) {
    for i in 0..4 {
        y[i] += a * x[i];
    }
}
