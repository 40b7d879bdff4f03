//! One cycle with exact derivatives of θ' = f(θ) along chosen directions
//! (`sim::variational`): all six, f' alone, or f' with a few parameters.
//! A direction costs the same whichever it is, and the tangents' share of
//! an iterate grows with their number, so each caller asks for what it
//! uses (docs/derivatives.md, "Cost").

use super::{SimError, Simulator, SlipEvent};
use crate::model::point_from_theta;
use crate::sim::variational::{
    self, ALL_DIRS, D_THETA, Grad, MapDerivatives, NotDifferentiable, ev_field,
};

/// The cycle's event, the derivatives (or why f has none there) and the
/// evaluations they cost beyond the cycle's own.
pub type WithPartials<T> = (SlipEvent, Result<T, NotDifferentiable>, u64);

impl Simulator {
    /// One cycle from the onset at θ (time `onset_time`) with the exact
    /// derivatives of θ' = f(θ): the event (bitwise what
    /// [`Simulator::cycle`] gives), f' and ∂f/∂(θν, κ, γ, ν, Ω) or why
    /// f has none there, and the evaluations the derivatives cost beyond
    /// the cycle's own `rhs_evals` (every evaluation of the cycle carries
    /// the tangents; these are the extra ones at the switching events).
    pub fn cycle_derivatives(
        &self,
        theta: f64,
        onset_time: f64,
    ) -> Result<WithPartials<MapDerivatives>, SimError> {
        let (ev, d, n) = self.cycle_partials(theta, onset_time, ALL_DIRS)?;
        Ok((ev, d.map(|g| MapDerivatives::from_grad(&g)), n))
    }

    /// [`Simulator::cycle_derivatives`] with f'(θ) alone: one tangent
    /// direction instead of six, for the callers that use only the slope
    /// (Lyapunov exponents, the cycle solver).
    pub fn cycle_slope(&self, theta: f64, onset_time: f64) -> Result<WithPartials<f64>, SimError> {
        let (ev, d, n) = self.cycle_partials(theta, onset_time, [D_THETA])?;
        Ok((ev, d.map(|[g]| g), n))
    }

    /// [`Simulator::cycle_derivatives`] along the directions `dirs`
    /// (`sim::variational`'s `D_` constants, in any order): ∂θ'/∂`dirs[i]`
    /// in slot i. The backward sweep gives all six at once; this picks.
    pub fn cycle_partials<const N: usize>(
        &self,
        theta: f64,
        onset_time: f64,
        dirs: [usize; N],
    ) -> Result<WithPartials<Grad<N>>, SimError> {
        self.check_onset(theta)?;
        let onset = point_from_theta(self.params.kappa, theta);
        let end = self.slip::<true>(theta, onset, onset_time, None)?;
        let ev = self.complete(theta, onset, onset_time, &end, None);
        let (d, extra) = match end.derivs {
            Some(Ok(tape)) => {
                let extra = tape.extra_evals;
                let fld = ev_field(&self.params, &self.field);
                let d = if ev.restarted {
                    Err(NotDifferentiable::Restart)
                } else {
                    match variational::stop_gradient(&fld, [ev.stop_x, ev.stop_y], &tape.stop) {
                        Some(Ok(g)) => {
                            let all = tape.gradient(&g, theta, &self.params);
                            Ok(dirs.map(|d| all[d]))
                        }
                        Some(Err(e)) => Err(e),
                        None => Err(NotDifferentiable::Restart),
                    }
                };
                tape.recycle();
                (d, extra)
            }
            Some(Err(_)) if ev.restarted => (Err(NotDifferentiable::Restart), 0),
            Some(Err(e)) => (Err(e), 0),
            None => unreachable!("a slip with derivatives ends with its tape or a reason"),
        };
        Ok((ev, d, extra))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Params;
    use crate::sim::default_settings;

    /// The backward sweep this CPU runs (four wide, fused, where it has
    /// AVX2 and FMA) and the portable one agree, on a Fig. 3b slip and on
    /// a creep-sized one, from the stop's own gradient and from a unit one.
    #[test]
    fn the_fast_and_the_portable_sweeps_agree() {
        let cases = [(18.95, 6.5, 1e-3, 1.25, 0.5), (3.0, 0.5, 1e-3, 0.5, 0.3)];
        for (kappa, gamma, nu, theta_nu, theta) in cases {
            let p = Params {
                kappa,
                gamma,
                nu,
                theta_nu,
                omega: 50.0,
            };
            let sim = Simulator::new(p, default_settings(1e-10)).unwrap();
            let onset = point_from_theta(kappa, theta);
            let end = sim.slip::<true>(theta, onset, 0.0, None).unwrap();
            let ev = sim.complete(theta, onset, 0.0, &end, None);
            let Some(Ok(tape)) = end.derivs else {
                panic!("no tape at {theta}");
            };
            let fld = ev_field(&p, &sim.field);
            let g = variational::stop_gradient(&fld, [ev.stop_x, ev.stop_y], &tape.stop)
                .unwrap()
                .unwrap();
            let mut unit = [0.0; variational::EV];
            unit[2] = 1.0;
            for g in [g, unit] {
                let [(l1, f1, m1), (l2, f2, m2)] = tape.both_sweeps(&g);
                let a = l1.iter().chain(&f1).chain(&m1);
                let b = l2.iter().chain(&f2).chain(&m2);
                for (x, y) in a.zip(b) {
                    assert!((x - y).abs() <= 1e-12 * (1.0 + x.abs()), "{x} vs {y}");
                }
            }
        }
    }
}
