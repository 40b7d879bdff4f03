//! A slip with derivatives: its tape (`variational::tape`) told where
//! steps are committed, and the switching events' own derivatives against
//! the [`EV`] slots where they begin (docs/derivatives.md).

use std::cell::RefCell;

use super::SlipRun;
use crate::integrate::State;
use crate::sim::variational::{
    self, EV, Field, NotDifferentiable, Tape, ev_field, ev_seed, field_tangent,
};

impl<const TAPE: bool> SlipRun<'_, TAPE> {
    /// The same slip with derivatives: its tape.
    pub(in crate::sim::cycle) fn with_tape(mut self) -> Self {
        let sim = self.sim;
        self.tape = Some(RefCell::new(Tape::new(
            sim.settings.method,
            sim.field,
            &self.y,
        )));
        self
    }

    /// The slip moves on to the accepted step's new state: so does its
    /// tape. A tape that is full is dropped (its memory with it): the slip
    /// goes on without derivatives, and says why.
    #[inline(always)]
    pub(super) fn commit(&mut self) {
        let Some(tape) = &self.tape else { return };
        let full = {
            let mut tape = tape.borrow_mut();
            tape.commit();
            tape.is_full().then(|| tape.steps())
        };
        if let Some(steps) = full {
            self.tape = None;
            self.stop_d = Some(Err(NotDifferentiable::TapeFull { steps }));
        }
    }

    /// Adds `n` evaluations to the tape's extra ones.
    fn count_extra(&self, n: u64) {
        if let Some(tape) = &self.tape {
            tape.borrow_mut().extra_evals += n;
        }
    }

    /// The tape across the end of the acceleration phase at `ya`, `dt`
    /// after the current state (f there: `self.k`): the step to it, then
    /// the switch's own Jacobian. A switch met tangentially leaves the slip
    /// without derivatives.
    pub(super) fn switch_tangents(&mut self, ya: &State, dt: f64) {
        let Some(tape) = &self.tape else { return };
        let sim = self.sim;
        let mut tape = tape.borrow_mut();
        tape.partial_step(Field::Accel, &self.y, &self.k, dt);
        let fld = ev_field(&sim.params, &sim.field);
        match variational::accel_end(&fld, ya, &ev_seed()) {
            Ok(m) => tape.switch(m, ya),
            Err(e) => {
                drop(tape);
                self.stop_d = Some(Err(e));
                self.tape = None;
            }
        }
    }

    /// The tangent of a stop located `dt` after the current state, where
    /// v_r · `w` changes sign (a fixed step's reversal): the step to it on
    /// the tape, the root's own derivative against the [`EV`] slots there.
    pub(super) fn reversal_tangents(&mut self, dt: f64, w: [f64; 2]) {
        let Some(tape) = &self.tape else { return };
        let sim = self.sim;
        let ys = tape
            .borrow_mut()
            .partial_step(Field::Decel, &self.y, &self.k, dt);
        let f = sim.field.decel(&ys);
        self.count_extra(1);
        self.stop_d = Some(variational::stop_at_root(&ev_seed(), &f, w, 2));
    }

    /// The tangent of the stop placed by linear extrapolation from the
    /// current state (f there: `self.k`), with derivatives.
    pub(super) fn extrapolated_stop_tangent(&mut self) {
        if self.tape.is_none() {
            return;
        }
        let sim = self.sim;
        let (fld, seed) = (ev_field(&sim.params, &sim.field), ev_seed());
        let kt = field_tangent::<EV, false>(Field::Decel, &sim.field, &fld, &self.y, &seed).1;
        let d = variational::extrapolated_stop(&fld, &self.y, &seed, &self.k, &kt);
        self.stop_d = Some(Ok(d));
        self.count_extra(1);
    }
}
