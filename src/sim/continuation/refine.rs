//! A located PD or fold located again on the multiplier at a tighter
//! tolerance.
//!
//! The multiplier from the variational equations is less accurate than
//! the cycle: at κ = 19, γ = 10, ν = 1e-3 (DOP853, tol 1e-10) it is off by
//! 6e-7 at the first flip, where dm/dθν ≈ 2.4, so Illinois on it closes
//! its bracket 2.5e-7 from the true flip, wherever the bracket started.
//! The error falls with the tolerance (2e-8 at 1e-12, ~1e-9 at 1e-14), so
//! the point is located again with the solver at 1e-4 of its tolerance
//! (at least 1e-14): a bracket about the first location, as wide as the
//! two tolerances' multipliers say it is off, closed by Illinois on the
//! tighter one (a few evaluations, each ~3× a coarse one).

use super::Problem;
use super::branch::{Ctx, Located};
use crate::integrate::SolverSettings;

/// The solver at 1e-4 of `settings`' tolerance, at least 1e-14; `None`
/// for a fixed-step method or one already there.
pub(super) fn tighter(settings: &SolverSettings) -> Option<SolverSettings> {
    if !settings.method.is_adaptive() {
        return None;
    }
    let rtol = (settings.rtol * 1e-4).max(1e-14);
    (rtol < settings.rtol).then(|| SolverSettings {
        rtol,
        atol: (settings.atol * 1e-4).max(1e-16),
        ..*settings
    })
}

impl Ctx<'_> {
    /// `coarse`, the zero of `test` located along `t`, located again at the tighter tolerance ([`tighter`]);
    /// `coarse` itself where there is none or no bracket is found. The
    /// samples stay the coarse ones (dm/dλ from one tolerance).
    pub(super) async fn refine(
        &mut self,
        coarse: Located,
        t: [f64; 2],
        test: impl Fn(f64) -> f64 + Copy,
    ) -> Located {
        let Some(settings) = tighter(&self.prob.settings) else {
            return coarse;
        };
        let fine = Problem {
            settings,
            ..*self.prob
        };
        let mut fctx = Ctx {
            pace: self.pace,
            prob: &fine,
            opts: self.opts,
            evals: 0,
            last_fail: None,
        };
        let found = fctx.bracket(&coarse, t, test).await;
        self.evals += fctx.evals;
        match found {
            Some(l) if l.real => Located {
                samples: coarse.samples,
                ..l
            },
            _ => coarse,
        }
    }

    /// On this (tighter) problem: the point on the coarse location's
    /// hyperplane, a second one past the zero along the coarse slope of
    /// the test in arclength, and Illinois between them.
    async fn bracket(
        &mut self,
        coarse: &Located,
        t: [f64; 2],
        test: impl Fn(f64) -> f64 + Copy,
    ) -> Option<Located> {
        let fa = self.correct(coarse.pt.x, t).await.ok()?;
        let f0 = test(fa.e.multiplier);
        if f0 == 0.0 {
            return Some(Located {
                pt: fa,
                real: true,
                off: 0.0,
                samples: Vec::new(),
                slope: coarse.slope,
            });
        }
        if !(coarse.slope.is_finite() && coarse.slope != 0.0) {
            return None;
        }
        let mut ds = -1.5 * f0 / coarse.slope;
        for _ in 0..4 {
            let pred = [fa.x[0] + ds * t[0], fa.x[1] + ds * t[1]];
            let fb = self.correct(pred, t).await.ok()?;
            if test(fb.e.multiplier) * f0 < 0.0 {
                return Some(self.locate(&fa, &fb, t, ds, test).await);
            }
            ds *= 3.0;
        }
        None
    }
}
