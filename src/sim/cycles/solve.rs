//! Newton's solve of a p-cycle one map evaluation at a time, so that a host
//! on a slice of time (the browser's) can stop between two and go on later
//! with the same iterates, bit for bit. [`super::solve_counting`] runs it
//! to its end in one go.

use super::{CycleFailure, CycleOptions, MAX_STEP, Pass, finish};
use crate::model::wrap_angle;
use crate::sim::analysis::central_difference;
use crate::sim::period::PERIOD_MAX;
use crate::sim::{Cycle, SimError, Simulator};

/// One pass round a candidate cycle in progress: p iterates from `theta`
/// with the exact f'(θᵢ) at each ([`Simulator::cycle_slope`]: one map
/// evaluation carrying its tangent along θ). Where f has no derivative (a
/// restart, an onset at the arc's edge, a tangential event) the slope of a
/// central difference keeps Newton going, and the pass is marked: a cycle
/// through such a point is refused.
pub(super) struct Walk {
    theta: f64,
    th: f64,
    multiplier: f64,
    points: Vec<f64>,
    restarted: bool,
}

impl Walk {
    pub(super) fn new(theta: f64, p: usize) -> Self {
        Walk {
            theta,
            th: theta,
            multiplier: 1.0,
            points: Vec::with_capacity(p),
            restarted: false,
        }
    }

    /// One iterate of the pass; true once it has all `p`.
    pub(super) fn step(
        &mut self,
        sim: &Simulator,
        p: usize,
        spent: &mut (u64, u64),
    ) -> Result<bool, SimError> {
        let th = self.th;
        self.points.push(th);
        let (ev, d, extra) = sim.cycle_slope(th, 0.0)?;
        spent.0 += 1;
        spent.1 += ev.rhs_evals + extra;
        let slope = match d {
            Ok(d) => d,
            Err(_) => {
                self.restarted = true;
                let (d, n) = central_difference(sim, th, ev.theta_next)?;
                spent.0 += 2;
                spent.1 += n;
                d
            }
        };
        self.multiplier *= slope;
        self.restarted |= ev.restarted;
        self.th = sim.next_onset(&ev);
        Ok(self.points.len() >= p)
    }

    /// The complete pass: g = wrap(f^p(θ) − θ), its multiplier and points.
    pub(super) fn finish(self) -> Pass {
        Pass {
            g: wrap_angle(self.th - self.theta),
            multiplier: self.multiplier,
            points: self.points,
            restarted: self.restarted,
        }
    }
}

/// The Newton step being tried from the current iterate, halved while it
/// fails (see the module notes of [`super`]).
#[derive(Clone, Copy)]
struct Trial {
    /// The step, and the iterate it leads to.
    step: f64,
    y: f64,
    /// Halvings done so far.
    halvings: usize,
    /// The last trial that integrated but did not shrink |g|: its step, g.
    last: Option<(f64, f64)>,
    /// g'(x) = m − 1 and the Newton step |g/g'| at the current iterate.
    slope: f64,
    newton: f64,
}

/// Newton's solve of f^p(θ) = θ in progress ([`CycleSolve::advance`]).
pub struct CycleSolve {
    p: usize,
    opts: CycleOptions,
    /// Map and right-hand-side evaluations spent so far.
    spent: (u64, u64),
    /// The current iterate and its complete pass (`None` until the first
    /// pass is done).
    x: f64,
    e: Option<Pass>,
    iterations: usize,
    /// The pass being walked: the first, or a trial's.
    walk: Walk,
    trial: Option<Trial>,
    ended: bool,
}

impl CycleSolve {
    /// A solve from `seed`, nothing evaluated yet; refused at once for a
    /// period outside [1, PERIOD_MAX] or a seed off the exit arc.
    pub fn start(
        sim: &Simulator,
        seed: f64,
        p: usize,
        opts: &CycleOptions,
    ) -> Result<Self, CycleFailure> {
        if !(1..=PERIOD_MAX).contains(&p) {
            return Err(CycleFailure::BadPeriod(p));
        }
        if sim.check_onset(seed).is_err() {
            return Err(CycleFailure::SeedOffArc { theta: seed });
        }
        Ok(CycleSolve {
            p,
            opts: *opts,
            spent: (0, 0),
            x: seed,
            e: None,
            iterations: 0,
            walk: Walk::new(seed, p),
            trial: None,
            ended: false,
        })
    }

    /// Map and right-hand-side evaluations spent so far (all of the
    /// solve's once it has ended, whether it succeeded or not).
    pub fn spent(&self) -> (u64, u64) {
        self.spent
    }

    /// One map evaluation (one slip cycle with its slope), then whatever
    /// Newton decides from it: `None` while the solve goes on, its result
    /// once it has ended. `sim` must be the simulator it started with. A
    /// solve that has ended is not advanced again (it says so).
    pub fn advance(&mut self, sim: &Simulator) -> Option<Result<Cycle, CycleFailure>> {
        if self.ended {
            return Some(Err(CycleFailure::NoConvergence {
                iterations: self.iterations,
                residual: f64::NAN,
            }));
        }
        let walked = match self.walk.step(sim, self.p, &mut self.spent) {
            Ok(false) => return None,
            Ok(true) => Ok(std::mem::replace(&mut self.walk, Walk::new(0.0, 0)).finish()),
            Err(e) => Err(e),
        };
        let out = match (&self.e, self.trial) {
            // The first pass: a failure fails the solve.
            (None, _) => match walked {
                Ok(pass) => {
                    self.e = Some(pass);
                    self.newton(sim)
                }
                Err(e) => Some(Err(e.into())),
            },
            (Some(e), Some(mut t)) => match walked {
                Ok(ey) if ey.g.abs() < e.g.abs() => {
                    self.x = t.y;
                    self.e = Some(ey);
                    self.iterations += 1;
                    self.newton(sim)
                }
                // A trial that fails to integrate is treated as a step
                // too long: halve it.
                other => {
                    if let Ok(ey) = other {
                        t.last = Some((t.step, ey.g));
                    }
                    t.step *= 0.5;
                    t.halvings += 1;
                    self.next_trial(sim, t)
                }
            },
            (Some(_), None) => Some(Err(CycleFailure::NoConvergence {
                iterations: self.iterations,
                residual: f64::NAN,
            })),
        };
        self.ended = out.is_some();
        out
    }

    /// At a new iterate with its pass: converged, out of steps, or the
    /// first trial of the next Newton step.
    fn newton(&mut self, sim: &Simulator) -> Option<Result<Cycle, CycleFailure>> {
        let e = self.e.as_ref()?;
        let iterations = self.iterations;
        if !(e.g.is_finite() && e.multiplier.is_finite()) {
            return Some(Err(CycleFailure::NoConvergence {
                iterations,
                residual: e.g.abs(),
            }));
        }
        let slope = e.multiplier - 1.0;
        let newton = (e.g / slope).abs();
        if newton <= self.opts.tol {
            return Some(self.finish(newton));
        }
        if iterations == self.opts.max_iter {
            if e.g.abs() <= self.opts.floor {
                return Some(self.finish(newton));
            }
            return Some(Err(CycleFailure::NoConvergence {
                iterations,
                residual: e.g.abs(),
            }));
        }
        let full = if slope != 0.0 { -e.g / slope } else { MAX_STEP };
        let trial = Trial {
            step: full.clamp(-MAX_STEP, MAX_STEP),
            y: self.x,
            halvings: 0,
            last: None,
            slope,
            newton,
        };
        self.next_trial(sim, trial)
    }

    /// Starts the pass of the first trial, from `t` on, whose iterate is
    /// on the exit arc (halving past those that are not); when no halving
    /// is left, the solve ends.
    fn next_trial(&mut self, sim: &Simulator, mut t: Trial) -> Option<Result<Cycle, CycleFailure>> {
        while t.halvings <= self.opts.max_halvings {
            let y = wrap_angle(self.x + t.step);
            if sim.check_onset(y).is_ok() {
                t.y = y;
                self.trial = Some(t);
                self.walk = Walk::new(y, self.p);
                return None;
            }
            t.step *= 0.5;
            t.halvings += 1;
        }
        self.trial = None;
        let g = self.e.as_ref()?.g;
        // No step shrinks a residual already at the map's own error:
        // Newton has gone as far as the map allows.
        if g.abs() <= self.opts.floor {
            return Some(self.finish(t.newton));
        }
        // The smallest step still did not shrink |g|. If g moved far more
        // than its slope allows over that step, f jumps between x and
        // x + step; otherwise Newton has stalled at the map's own error.
        let jumped = t.last.is_some_and(|(s, gy)| {
            (wrap_angle(gy - g) - t.slope * s).abs()
                > 1e-6 + 1e2 * ((t.slope * s).abs() + self.opts.floor)
        });
        Some(Err(if jumped {
            CycleFailure::Discontinuity { theta: self.x }
        } else {
            CycleFailure::NoConvergence {
                iterations: self.iterations,
                residual: g.abs(),
            }
        }))
    }

    /// The solved cycle at the current iterate.
    fn finish(&mut self, newton: f64) -> Result<Cycle, CycleFailure> {
        match self.e.take() {
            Some(e) => finish(
                e,
                self.x,
                self.p,
                &self.opts,
                self.iterations,
                newton,
                &self.spent,
                (0, 0),
            ),
            None => Err(CycleFailure::NoConvergence {
                iterations: self.iterations,
                residual: f64::NAN,
            }),
        }
    }
}
