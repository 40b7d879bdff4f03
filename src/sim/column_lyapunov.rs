//! The Lyapunov exponent of one bifurcation column, from the column's own
//! kept onsets: the companion strip λ(θν) under the diagram and the
//! `lyapunov` column of the bifurcation CSV.
//!
//! - Where the onsets repeat with a period p, or contract onto a cycle
//!   ([`Simulator::settle`], or for longer periods
//!   [`super::period::closing_in`]), the cycle is solved and λ = ln|m|/p exactly,
//!   m its multiplier: no average, no error bar. So λ → 0⁻ is seen at each
//!   period doubling, where m → −1, and at the cascade's accumulation.
//! - Otherwise λ is the mean of ln|f′(θ)| over the last
//!   [`MAX_DERIVATIVES`] kept onsets, with its batch-means standard error:
//!   one variational cycle per onset, so the cost is bounded whatever the
//!   column keeps.
//!
//! Where the dots land may come from a loose integrator (the window's Auto
//! runs its diagram at dp54 1e-4, a pixel), but λ is printed to four
//! digits, and a multiplier from variational equations at 1e-4 is 1–2 %
//! off. So λ is always computed at [`lyapunov_settings`] (the command
//! line's dop853 1e-10 or tighter): the cycle the column's onsets settle on
//! is found with the column's own integrator and then solved again by
//! Newton at λ's setting, and every slope is taken at λ's setting.

use super::analysis::map_derivative;
use super::cycles::{CycleOptions, solve_counting};
use super::orbit::OrbitOptions;
use super::period::closing_in;
use super::stats::mean_and_stderr;
use super::{Column, NeverYield, Simulator, Yield, default_settings};
use crate::integrate::SolverSettings;

/// The loosest tolerance λ is computed at: the command line's default.
pub const LYAPUNOV_TOL: f64 = 1e-10;

/// The setting a column's λ is computed at, given the column's own: that
/// one if it is adaptive and at least as tight as [`LYAPUNOV_TOL`], else
/// the command line's default (dop853 at 1e-10).
pub fn lyapunov_settings(column: SolverSettings) -> SolverSettings {
    if column.method.is_adaptive() && column.rtol <= LYAPUNOV_TOL {
        column
    } else {
        default_settings(LYAPUNOV_TOL)
    }
}

/// The most onsets whose f′ an aperiodic column averages (8 batches of 25
/// for the standard error).
pub const MAX_DERIVATIVES: usize = 200;

/// λ of one column and how it was found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColumnLyapunov {
    /// ln|m|/p of the solved cycle, or the mean of ln|f′(θ)|.
    pub lyapunov: f64,
    /// The mean's standard error; `None` for a solved cycle (exact) or a
    /// mean over fewer than 16 onsets.
    pub stderr: Option<f64>,
    /// The solved cycle's period, when there is one.
    pub period: Option<usize>,
}

/// λ of a column computed at `sim`'s parameters (its θν), or `None` for an
/// empty column or one whose derivatives all failed. `sim` is the
/// column's; λ itself is computed at [`lyapunov_settings`].
pub fn column_lyapunov(sim: &Simulator, col: &Column) -> Option<ColumnLyapunov> {
    let exact = ExactSim::new(sim).ok()?;
    let mut run = LyapunovRun::new(col);
    run.advance((sim, exact.get(sim)), col, &NeverYield, true);
    run.result()
}

/// The simulator λ is computed with: the column's own when its setting is
/// λ's ([`lyapunov_settings`]), else one at λ's setting.
pub struct ExactSim(Option<Simulator>);

impl ExactSim {
    /// λ's simulator for a column run by `column` (its parameters).
    pub fn new(column: &Simulator) -> Result<Self, crate::sim::SimError> {
        let settings = lyapunov_settings(*column.settings());
        if settings == *column.settings() {
            return Ok(ExactSim(None));
        }
        Ok(ExactSim(Some(Simulator::new(*column.params(), settings)?)))
    }

    /// The simulator to use, given the column's.
    pub fn get<'a>(&'a self, column: &'a Simulator) -> &'a Simulator {
        self.0.as_ref().unwrap_or(column)
    }
}

/// The period and λ = ln|m|/p of the stable cycle that `kept` closes in
/// on slowly ([`closing_in`]: periods the settle test's contraction does
/// not reach, as Fig. 3b's P24 at θν ≈ 1.2286), solved by Newton from its
/// extrapolated points; `None` if they do not, or it is not found.
fn closing_in_solved(sim: &Simulator, kept: &[f64]) -> Option<(usize, f64)> {
    solve_closing(sim, &closing_in(kept)?)
}

/// The period and λ of the stable cycle Newton finds from the
/// extrapolated points `cycle` of an orbit closing in on it, if it is one
/// of that minimal period. A chaotic orbit passing a narrow channel (near
/// a window's tangency) can shrink its p-differences for three periods
/// too: there Newton finds no stable p-cycle.
pub(crate) fn solve_closing(sim: &Simulator, cycle: &[f64]) -> Option<(usize, f64)> {
    let p = cycle.len();
    let opts = CycleOptions::for_classifier(sim.settings());
    let c = solve_counting(sim, *cycle.last()?, p, &opts, &mut (0, 0)).ok()?;
    (c.minimal_period == p && c.stable).then(|| (p, c.lyapunov()))
}

/// [`column_lyapunov`] in pieces, for a host that wants its thread back
/// between them (the browser's): first the settled cycle's solve, if the
/// onsets settle (one heavy piece), then the slopes of an aperiodic column
/// one by one. The result is the same, bit for bit, wherever it stopped.
pub struct LyapunovRun {
    /// Whether the settle test (and its solve) has run.
    settled_tried: bool,
    /// The solved cycle's λ.
    settled: Option<ColumnLyapunov>,
    /// The next kept onset whose slope is taken.
    next: usize,
    logs: Vec<f64>,
    done: bool,
}

impl LyapunovRun {
    /// Ready to start on `col` (nothing computed yet).
    pub fn new(col: &Column) -> Self {
        let kept = &col.thetas;
        LyapunovRun {
            settled_tried: false,
            settled: None,
            next: kept.len().saturating_sub(MAX_DERIVATIVES),
            logs: Vec::new(),
            done: kept.is_empty() || col.error.is_some(),
        }
    }

    /// Computes until done (true) or `yielding` says stop (false). A
    /// `fresh` call (the first thing in its host's step) does at least one
    /// piece; another may stop before any. `sims` are the column's
    /// simulator and λ's ([`ExactSim`]).
    pub fn advance(
        &mut self,
        (sim, exact): (&Simulator, &Simulator),
        col: &Column,
        yielding: &dyn Yield,
        fresh: bool,
    ) -> bool {
        let kept = &col.thetas;
        let mut first = fresh;
        if !self.done && !self.settled_tried {
            if !first && yielding.defer_heavy() {
                return false;
            }
            first = false;
            self.settled_tried = true;
            let tol = OrbitOptions::period_tol_for(sim.settings().rtol);
            let mut spent = (0, 0);
            let settled = sim.settle(kept, col.theta_last, (None, None), tol, &mut spent);
            let solved = match (settled.cycle, settled.lyapunov) {
                (Some(c), Some(l)) if std::ptr::eq(sim, exact) => Some((c.period(), l)),
                (Some(c), Some(_)) => solve_closing(exact, &c.points),
                _ => closing_in_solved(exact, kept),
            };
            if let Some((period, l)) = solved
                && l.is_finite()
            {
                self.settled = Some(ColumnLyapunov {
                    lyapunov: l,
                    stderr: None,
                    period: Some(period),
                });
                self.done = true;
            }
        }
        while !self.done {
            if self.next >= kept.len() {
                self.done = true;
                break;
            }
            if !first && yielding.pause() {
                return false;
            }
            first = false;
            let i = self.next;
            self.next += 1;
            let next = kept.get(i + 1).copied().unwrap_or(col.theta_last);
            if let Ok((d, _)) = map_derivative(exact, kept[i], next) {
                // f′ = 0 exactly (a superstable point) would give −∞: it
                // is left out rather than let one point swamp the mean.
                let l = d.abs().ln();
                if l.is_finite() {
                    self.logs.push(l);
                }
            }
        }
        true
    }

    /// λ once [`LyapunovRun::advance`] has returned true (`None` before).
    pub fn result(&self) -> Option<ColumnLyapunov> {
        if !self.done {
            return None;
        }
        if self.settled.is_some() {
            return self.settled;
        }
        match mean_and_stderr(&self.logs) {
            (Some(lyapunov), stderr) => Some(ColumnLyapunov {
                lyapunov,
                stderr,
                period: None,
            }),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Params;
    use crate::sim::{SweepOptions, default_settings, fixed_point};

    fn column(theta_nu: f64, transient: usize, keep: usize) -> (Simulator, Column) {
        let params = Params {
            kappa: 18.95,
            gamma: 6.5,
            nu: 1e-3,
            theta_nu,
            omega: 50.0,
        };
        let settings = default_settings(1e-10);
        let opts = SweepOptions {
            transient,
            keep,
            map: crate::sim::MapChoice::Direct,
        };
        let sim = Simulator::new(params.with_theta_nu(theta_nu), settings).expect("valid");
        let col = Column::run(params, settings, theta_nu, theta_nu, &opts, &|| false);
        (sim, col)
    }

    #[test]
    fn a_fixed_point_column_has_the_exact_exponent_of_its_multiplier() {
        // Fig. 3b's parameters at θν = 0.9: a stable stick-slip fixed point.
        let (sim, col) = column(0.9, 300, 20);
        let got = column_lyapunov(&sim, &col).expect("computed");
        assert_eq!(got.period, Some(1));
        assert!(got.stderr.is_none());
        // Independently: the secant fixed point and its multiplier.
        let (_, m) = fixed_point(&sim, col.thetas[0], 1e-12)
            .expect("runs")
            .expect("found");
        assert!(m.abs() < 1.0);
        assert!(
            (got.lyapunov - m.abs().ln()).abs() < 1e-5,
            "{got:?} vs ln|{m}|"
        );
    }

    #[test]
    fn a_chaotic_column_averages_ln_slope_with_an_error_bar() {
        // The chaos preset (Fig. 3b at θν = 1.25): no period, λ > 0.
        let (sim, col) = column(1.25, 200, 64);
        let got = column_lyapunov(&sim, &col).expect("computed");
        assert_eq!(got.period, None);
        let se = got.stderr.expect("64 onsets: 8 batches of 8");
        assert!(got.lyapunov > 2.0 * se, "{got:?}");
        // The same mean, recomputed from each onset's own map slope.
        let logs: Vec<f64> = col
            .thetas
            .iter()
            .map(|&th| {
                let f = sim.map(th).expect("cycle");
                map_derivative(&sim, th, f).expect("slope").0.abs().ln()
            })
            .collect();
        let mean = logs.iter().sum::<f64>() / logs.len() as f64;
        assert!(
            (got.lyapunov - mean).abs() < 1e-9,
            "{} vs {mean}",
            got.lyapunov
        );
    }

    #[test]
    fn a_column_closing_in_slowly_on_a_long_cycle_has_its_exponent() {
        // Inside Fig. 3b's P24 window from θ₀ = 0.52: 1e-6 off the cycle
        // after 500 + 100 iterates, a period the contraction test does not
        // reach; 100 kept onsets are not whole periods, so their mean of
        // ln|f'| was -0.044 against the cycle's -0.0174.
        let tn = 1.2285714285714286;
        let (sim, _) = column(tn, 0, 0);
        let opts = SweepOptions {
            transient: 500,
            keep: 100,
            map: crate::sim::MapChoice::Direct,
        };
        let col = Column::run(*sim.params(), *sim.settings(), tn, 0.52, &opts, &|| false);
        let got = column_lyapunov(&sim, &col).expect("computed");
        assert_eq!((got.period, got.stderr), (Some(24), None), "{got:?}");
        // Independently: the P24 by Newton from the last onset, and
        // ln|m|/24 from its multiplier.
        let opts = CycleOptions::for_settings(sim.settings());
        let c = solve_counting(&sim, col.theta_last, 24, &opts, &mut (0, 0)).expect("P24");
        assert!(c.stable && c.minimal_period == 24, "{c:?}");
        let want = c.multiplier.abs().ln() / 24.0;
        assert!((got.lyapunov - want).abs() < 1e-6, "{got:?} vs {want}");
    }

    #[test]
    fn an_empty_column_has_none() {
        let (sim, mut col) = column(0.9, 5, 5);
        col.thetas.clear();
        assert_eq!(column_lyapunov(&sim, &col), None);
    }
}
