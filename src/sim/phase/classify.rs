//! One phase cell's classification (docs/phase.md): its iterates, from the
//! interpolant once built, and the tests that end it early (a settled
//! period, a slow contraction solved, λ beyond its error, a near repeat),
//! else the brute force's verdict on its whole budget.

use super::capture::Known;
use super::*;

mod exponent;
mod known;

use exponent::cycle_exponent;

/// The most map evaluations (iterates, a solve's steps, the
/// interpolant's samples) one [`Classifier::advance`] spends before it
/// gives its thread back: about 3 ms of the page's frame. An iterate or a
/// step of a solve is not cut, so a piece may end a little past it.
const PIECE_EVALUATIONS: u64 = 32;

/// A cell's iterates and tests in progress (see the module's doc), a
/// bounded piece of work a call, the same bit for bit however it is cut:
/// a test that needs a cycle solved waits for the solve, a map evaluation
/// a step ([`CycleSolve`]), and then the tests of that iterate run again
/// with its result.
pub(super) struct Classifier {
    run: CellRun,
    /// The next iterate's index.
    i: usize,
    /// The interpolant being built for the rest of the iterates.
    building: Option<StepperBuild>,
    /// Whether its build was begun (once: built or refused, the iterates
    /// go on).
    built: bool,
    stepper: Option<Stepper>,
    /// A solve a test waited for has ended: the tests run again, from
    /// that test ([`Self::resume`]).
    retest: bool,
    /// The test that waits for a solve (0: the period, 1: the contraction,
    /// 2: λ's near repeat); the tests before it have run.
    resume: usize,
    /// The iterates are spent: the budget's verdict is what is left.
    at_end: bool,
    /// A finished neighbour's cycle (a point moved onto this cell's exit
    /// arc, and its period), to be solved before the first iterate
    /// (`super::capture`).
    neighbour: Option<(f64, usize)>,
}

impl Classifier {
    pub(super) fn new(
        sim: Simulator,
        theta_start: f64,
        opts: PhaseOptions,
        neighbour: Option<(f64, usize)>,
    ) -> Self {
        Classifier {
            neighbour: neighbour.filter(|_| opts.early_exit),
            run: CellRun::new(sim, theta_start, opts),
            i: 0,
            building: None,
            built: false,
            stepper: None,
            retest: false,
            resume: 0,
            at_end: false,
        }
    }

    /// The simulator the cell runs on.
    pub(super) fn simulator(&self) -> &Simulator {
        &self.run.sim
    }

    /// The interpolant the cell's iterates came from, once built.
    pub(super) fn stepper(&self) -> Option<&Stepper> {
        self.stepper.as_ref()
    }

    /// Iterates and tests until the cell is classified (`true`) or about
    /// [`PIECE_EVALUATIONS`] map evaluations were spent (`false`: call
    /// again). `cancel` is polled every iterate and every solve's step.
    pub(super) fn advance(
        &mut self,
        cell: &mut PhaseCell,
        cancel: &dyn Fn() -> bool,
    ) -> Result<bool, SimError> {
        let from = self.run.evaluations(cell);
        let total = self.run.opts.transient + self.run.opts.keep;
        loop {
            if cancel() {
                return Err(SimError::Cancelled);
            }
            let classified = if let Some((seed, p)) = self.neighbour.take() {
                self.run.begin_known(seed, p);
                false
            } else if self.run.solving.is_some() {
                // One step of the solve a test waits for (before the
                // first iterate: the neighbour's cycle).
                self.retest |= self.run.solve_step(cell);
                if self.i == 0 && std::mem::take(&mut self.retest) {
                    self.run.take_known();
                }
                false
            } else if std::mem::take(&mut self.retest) {
                self.tests(cell)?
            } else if let Some(b) = self.building.take() {
                // The interpolant's construction, one piece a call.
                self.building = self.run.build_step(cell, b, &mut self.stepper);
                false
            } else if self.i >= total {
                self.at_end = true;
                self.tests(cell)?
            } else if !self.built
                && let Some(b) = self.run.switch_map(cell, self.i)
            {
                self.building = Some(b);
                self.built = true;
                false
            } else if self.run.iterate(cell, self.i, &mut self.stepper)? {
                self.i += 1;
                cell.theta_last = self.run.theta;
                self.run.solved.clear();
                self.tests(cell)?
            } else {
                // A piece of the interpolant's extension to θ.
                false
            };
            if classified {
                return Ok(true);
            }
            if self.run.evaluations(cell) - from >= PIECE_EVALUATIONS {
                return Ok(false);
            }
        }
    }

    /// The tests after the last iterate (or, at the end, the budget's
    /// verdict), from the one that waited for a solve if one did: whether
    /// the cell is classified. `false` too while a test waits for its
    /// solve.
    fn tests(&mut self, cell: &mut PhaseCell) -> Result<bool, SimError> {
        let run = &mut self.run;
        if self.at_end {
            run.finish(cell)?;
            return Ok(run.solving.is_none());
        }
        let i = self.i - 1;
        if !run.opts.early_exit {
            return Ok(false);
        }
        if self.resume == 0 && run.captured(cell) {
            return Ok(true);
        }
        if i + 1 < MIN_TRANSIENT {
            return Ok(false);
        }
        let from = std::mem::take(&mut self.resume);
        for test in from..3 {
            let classified = match test {
                0 => run.settled(cell)?,
                1 => run.contracting(cell, i),
                _ => run.chaotic(cell)?,
            };
            if classified {
                return Ok(true);
            }
            if run.solving.is_some() {
                self.resume = test;
                return Ok(false);
            }
        }
        Ok(false)
    }
}

/// A cell in progress: its iterates (all of them: the tests read the
/// transient's end), the kept iterates' ln|f'(θ)|, the next onset, and
/// what the tests have tried so far.
struct CellRun {
    sim: Simulator,
    opts: PhaseOptions,
    cycle_opts: CycleOptions,
    thetas: Vec<f64>,
    /// The period test on `thetas`: `settled_period`'s decisions at O(1)
    /// amortised cost an iterate.
    watch: Box<PeriodWatch>,
    logs: Vec<f64>,
    /// The next onset (after the last of `thetas`).
    theta: f64,
    /// Differences below this are the map's own error, not a contraction.
    noise: f64,
    solves: usize,
    next_solve: usize,
    /// A settled period whose cycle did not attract: the period test waits
    /// for the kept iterates (the Lyapunov exponent decides).
    unstable_seen: bool,
    /// The period of the last near repeat solved ([`near_period`]), so that
    /// a failed one is not solved again.
    near_tried: Option<usize>,
    /// Map and right-hand-side evaluations of solves not yet charged.
    spent: (u64, u64),
    /// The solve a test waits for: its seed and period, in progress.
    solving: Option<(f64, usize, CycleSolve)>,
    /// The solves done for the last iterate's tests (seed, period, result).
    solved: Vec<(f64, usize, Result<Cycle, CycleFailure>)>,
    /// The cycle the cell was found periodic on.
    cycle: Option<Vec<f64>>,
    /// The neighbour's cycle, solved here and attracting.
    known: Option<Known>,
}

impl CellRun {
    fn new(sim: Simulator, theta_start: f64, opts: PhaseOptions) -> Self {
        CellRun {
            sim,
            opts,
            cycle_opts: CycleOptions::for_classifier(sim.settings()),
            thetas: Vec::with_capacity(opts.transient + opts.keep),
            watch: Box::new(PeriodWatch::new(opts.period_tol)),
            logs: Vec::with_capacity(opts.keep),
            theta: theta_start,
            noise: 1e-2 * opts.period_tol,
            solves: 0,
            next_solve: MIN_TRANSIENT,
            unstable_seen: false,
            near_tried: None,
            spent: (0, 0),
            solving: None,
            solved: Vec::new(),
            cycle: None,
            known: None,
        }
    }

    /// The cell's map evaluations so far, the waiting solve's included.
    fn evaluations(&self, cell: &PhaseCell) -> u64 {
        cell.iterates + self.solving.as_ref().map_or(0, |s| s.2.spent().0)
    }

    /// The p-cycle from `seed` a test asks for: its result if it was
    /// solved for this iterate's tests; else the solve is begun (unless
    /// another is under way) and the test must wait (`None`).
    fn solve(&mut self, seed: f64, p: usize) -> Option<Result<Cycle, CycleFailure>> {
        let done = self
            .solved
            .iter()
            .find(|(s, q, _)| s.to_bits() == seed.to_bits() && *q == p);
        if let Some((_, _, r)) = done {
            return Some(r.clone());
        }
        if self.solving.is_none() {
            match CycleSolve::start(&self.sim, seed, p, &self.cycle_opts) {
                Ok(s) => self.solving = Some((seed, p, s)),
                Err(e) => {
                    self.solved.push((seed, p, Err(e.clone())));
                    return Some(Err(e));
                }
            }
        }
        None
    }

    /// One step (a map evaluation) of the waiting solve; whether it ended,
    /// its result kept for the tests and its cost charged to the cell.
    fn solve_step(&mut self, cell: &mut PhaseCell) -> bool {
        let Some((seed, p, mut s)) = self.solving.take() else {
            return false;
        };
        let Some(r) = s.advance(&self.sim) else {
            self.solving = Some((seed, p, s));
            return false;
        };
        let (maps, rhs) = s.spent();
        cell.iterates += maps;
        cell.rhs_evals += rhs;
        self.solved.push((seed, p, r));
        true
    }

    /// Adds the solves' cost to the cell's.
    fn charge(&mut self, cell: &mut PhaseCell) {
        cell.iterates += self.spent.0;
        cell.rhs_evals += self.spent.1;
        self.spent = (0, 0);
    }

    /// The cell is periodic: `cycle`'s period, its onsets' character and
    /// the exponent `lyapunov`.
    fn periodic(&mut self, cell: &mut PhaseCell, cycle: &[f64], lyapunov: f64) {
        self.cycle = Some(cycle.to_vec());
        let p = self.sim.params();
        cell.class = CellClass::Periodic(cycle.len());
        cell.regime = AttractorRegime::of(p.kappa, p.gamma, cycle);
        cell.lyapunov = Some(lyapunov);
    }

    /// At iterate `i`, the interpolant's build over the recent iterates
    /// when the cell's direct part ends and enough iterates are left (a
    /// refusal at once is recorded in the cell).
    fn switch_map(&mut self, cell: &mut PhaseCell, i: usize) -> Option<StepperBuild> {
        let total = self.opts.transient + self.opts.keep;
        let switch = self.opts.transient.clamp(MIN_DIRECT, DIRECT_PART);
        if i != switch
            || !self
                .opts
                .map
                .interpolates_beyond(total - i, INTERPOLANT_LEFT)
        {
            return None;
        }
        let iopts = InterpolantOptions {
            max_evaluations: evaluation_budget(total - i),
            ..InterpolantOptions::for_settings(self.sim.settings())
        };
        let recent = &self.thetas[self.thetas.len().saturating_sub(300)..];
        match StepperBuild::over(&self.sim, recent, iopts) {
            Ok(b) => Some(b),
            Err(e) => {
                cell.map = MapUsed::Refused(e.to_string());
                None
            }
        }
    }

    /// One piece of the interpolant's build: the build to go on with, or,
    /// once it is over (built, into `stepper`, or refused, in the cell),
    /// `None`, its cost charged.
    fn build_step(
        &mut self,
        cell: &mut PhaseCell,
        mut b: StepperBuild,
        stepper: &mut Option<Stepper>,
    ) -> Option<StepperBuild> {
        let outcome = b.advance();
        if matches!(outcome, Ok(false)) {
            return Some(b);
        }
        let (n, rhs) = b.spent();
        self.spent.0 += n;
        self.spent.1 += rhs;
        match outcome {
            Ok(_) => *stepper = Some(b.finish()),
            Err(e) => cell.map = MapUsed::Refused(e.to_string()),
        }
        self.charge(cell);
        None
    }

    /// Iterate `i`: from the interpolant if there is one, else integrated;
    /// past the transient with f'(θ) too. False, with nothing iterated,
    /// after a piece of the interpolant's extension to θ (asked again, it
    /// goes on).
    fn iterate(
        &mut self,
        cell: &mut PhaseCell,
        i: usize,
        stepper: &mut Option<Stepper>,
    ) -> Result<bool, SimError> {
        let kept = i >= self.opts.transient;
        if let Some(st) = stepper.as_mut() {
            // The same iterate from the series: f'(θ) from it too.
            let next = if kept {
                st.next_with_derivative_piece(self.theta)?.map(|(next, d)| {
                    self.logs.push(d.abs().ln());
                    next
                })
            } else {
                st.next_piece(self.theta)?
            };
            let (n, rhs) = st.take_cost();
            cell.iterates += n;
            cell.rhs_evals += rhs;
            let Some(next) = next else {
                return Ok(false);
            };
            self.thetas.push(self.theta);
            self.theta = next;
            return Ok(true);
        }
        self.thetas.push(self.theta);
        // Past the transient f'(θ) is needed too: it rides along the
        // iterate's own integration (the variational equations), so it
        // adds evaluations, not iterates (two where f has no derivative
        // and the secant stands in).
        let ev = if kept {
            let (ev, d, n) = cycle_with_derivative(&self.sim, self.theta, 0.0)?;
            cell.rhs_evals += n;
            self.logs.push(d.abs().ln());
            ev
        } else {
            self.sim.cycle(self.theta, 0.0, None)?
        };
        cell.iterates += 1;
        cell.rhs_evals += ev.rhs_evals;
        self.theta = self.sim.next_onset(&ev);
        Ok(true)
    }

    /// The period test: whether the iterates have settled on a period whose
    /// cycle attracts (the cell is then periodic).
    fn settled(&mut self, cell: &mut PhaseCell) -> Result<bool, SimError> {
        let test = !(self.unstable_seen && self.logs.is_empty()) && self.thetas.len() >= MIN_WINDOW;
        let Some(p) = test
            .then(|| self.watch.settled(&self.thetas, self.thetas.len()))
            .flatten()
        else {
            return Ok(false);
        };
        // The cycle solved from the next onset gives the exponent ln|m|/p;
        // if it cannot be solved, the mean of ln|f'| on its last p
        // iterates does.
        let Some(solved) = self.solve(self.theta, p) else {
            return Ok(false);
        };
        let solved = solved.ok().filter(|c| c.minimal_period == p);
        let (lc, points) = match solved {
            Some(c) => {
                // The solve started from the next onset: its point 0 is
                // where the next cell continues.
                cell.theta_last = c.points[0];
                (c.lyapunov(), c.points)
            }
            None => {
                let (sim, thetas, logs) = (&self.sim, &self.thetas, &self.logs);
                let lc = cycle_exponent(cell, sim, thetas, self.theta, logs, p)?;
                (lc, thetas[thetas.len() - p..].to_vec())
            }
        };
        if lc < 0.0 {
            self.periodic(cell, &points, lc);
            return Ok(true);
        }
        // Repeats within the tolerance but does not attract: not a periodic
        // attractor (e.g. 2^n tiny chaotic bands under a loose tolerance).
        // Let the Lyapunov exponent decide.
        self.unstable_seen = true;
        Ok(false)
    }

    /// Contracting onto a cycle, but slowly: the cycle is solved instead of
    /// waited for; whether it was, and confirmed (the cell is then
    /// periodic).
    fn contracting(&mut self, cell: &mut PhaseCell, i: usize) -> bool {
        if self.solves >= MAX_SOLVES || i + 1 < self.next_solve || self.unstable_seen {
            return false;
        }
        // `contraction` and the confirmation read the last 4p + 1 values,
        // p ≤ 16: a copy of those, not of the whole orbit.
        let from = self
            .thetas
            .len()
            .saturating_sub(4 * CONTRACTION_PERIOD_MAX + 1);
        let mut seq = self.thetas[from..].to_vec();
        seq.push(self.theta);
        let Some(c) = contraction(&seq, self.noise) else {
            return false;
        };
        let Some(solved) = self.solve(c.limit, c.period) else {
            return false;
        };
        let confirmed = solved.ok().filter(|cy| confirms(cy, &seq, &c, self.noise));
        if let Some(cycle) = confirmed {
            cell.theta_last = cycle.points[0];
            self.periodic(cell, &cycle.points, cycle.lyapunov());
            return true;
        }
        self.solves += 1;
        self.next_solve = i + 1 + SOLVE_COOLDOWN;
        false
    }

    /// Every [`LYAPUNOV_EVERY`] kept iterates from [`LYAPUNOV_MIN`]: whether
    /// λ exceeds `sigmas` standard errors (the cell is then chaotic, unless
    /// its iterates nearly repeat on a cycle that attracts).
    fn chaotic(&mut self, cell: &mut PhaseCell) -> Result<bool, SimError> {
        let k = self.logs.len();
        if k < LYAPUNOV_MIN || !k.is_multiple_of(LYAPUNOV_EVERY) {
            return Ok(false);
        }
        let (l, se) = mean_and_stderr(&self.logs);
        let (Some(l), Some(se)) = (l, se) else {
            return Ok(false);
        };
        if l - self.opts.sigmas * se <= 0.0 {
            return Ok(false);
        }
        if self.near_cycle(cell)? {
            return Ok(true);
        }
        if self.solving.is_some() {
            // The near repeat's solve first.
            return Ok(false);
        }
        let p = self.sim.params();
        cell.class = CellClass::Chaos;
        cell.lyapunov = Some(l);
        cell.lyapunov_stderr = Some(se);
        cell.regime = AttractorRegime::of(p.kappa, p.gamma, &self.thetas[self.opts.transient..]);
        Ok(true)
    }

    /// The cycle the iterates nearly repeat on, if it attracts
    /// ([`NearRepeat`]): the cell is then periodic. One solve per period.
    fn near_cycle(&mut self, cell: &mut PhaseCell) -> Result<bool, SimError> {
        let from = self.thetas.len().saturating_sub(2 * CONTRACTION_PERIOD_MAX);
        let mut seq = self.thetas[from..].to_vec();
        seq.push(self.theta);
        let Some(near) = NearRepeat::of(&seq) else {
            return Ok(false);
        };
        if self.near_tried == Some(near.period) {
            return Ok(false);
        }
        let Some(solved) = self.solve(near.seed, near.period) else {
            return Ok(false);
        };
        self.near_tried = Some(near.period);
        let Some(c) = solved.ok().filter(|c| near.accepts(c)) else {
            return Ok(false);
        };
        cell.theta_last = c.points[0];
        self.periodic(cell, &c.points, c.lyapunov());
        Ok(true)
    }

    /// The budget is spent without an early answer: the brute force's
    /// period on the kept iterates, a near repeat's cycle, or λ decides.
    fn finish(&mut self, cell: &mut PhaseCell) -> Result<(), SimError> {
        let opts = self.opts;
        let kept_from = opts.transient.min(self.thetas.len());
        if !opts.early_exit && self.brute_force_period(cell, kept_from) {
            return Ok(());
        }
        let (l, se) = mean_and_stderr(&self.logs);
        let chaos = matches!((l, se), (Some(l), Some(se)) if l - opts.sigmas * se > 0.0);
        // Not chaotic (or not yet tested as such): a cycle the orbit nearly
        // repeats on may be what it is slowly reaching.
        if opts.early_exit && !chaos && self.near_cycle(cell)? || self.solving.is_some() {
            return Ok(());
        }
        let p = self.sim.params();
        cell.lyapunov = l;
        cell.lyapunov_stderr = se;
        cell.regime = AttractorRegime::of(p.kappa, p.gamma, &self.thetas[kept_from..]);
        cell.class = if chaos {
            CellClass::Chaos
        } else {
            CellClass::Undecided
        };
        Ok(())
    }

    /// The brute force's period: found on the kept iterates as `oneblock
    /// orbit` finds it (the cell is then periodic).
    fn brute_force_period(&mut self, cell: &mut PhaseCell, kept_from: usize) -> bool {
        let kept = &self.thetas[kept_from..];
        let s = self.sim.settle(
            kept,
            self.theta,
            mean_and_stderr(&self.logs),
            self.opts.period_tol,
            &mut self.spent,
        );
        self.charge(cell);
        if let Some(c) = s.cycle {
            self.periodic(cell, &c.points, c.lyapunov());
            return true;
        }
        if let crate::sim::Period::Periodic(p) = s.period
            && self.logs.len() >= p
        {
            let lc = self.logs[self.logs.len() - p..].iter().sum::<f64>() / p as f64;
            if lc < 0.0 {
                let cycle = self.thetas[self.thetas.len() - p..].to_vec();
                self.periodic(cell, &cycle, lc);
                return true;
            }
        }
        false
    }
}
