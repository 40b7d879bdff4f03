//! The construction of a [`MapInterpolant`], in bounded pieces
//! ([`InterpolantBuild`]): sampling in lanes, the decay test, splitting at
//! jumps or in the middle, and the check at independent points (the
//! module's doc in `sim::interpolant` says how they fit).

use super::chebyshev;
use super::{
    CHECKS, FIELDS, InterpolantError, InterpolantOptions, JUMP_WIDTH, Layout, MIN_PIECE,
    MapInterpolant, Piece, SAMPLINGS, Sample, Verification, clenshaw_fields,
};
use crate::model::{exit_arc, wrap_angle};
use crate::sim::{Simulator, cycles_in_lanes};

/// A piece being resolved: its ends and its samples so far.
#[derive(Debug)]
pub(super) struct Pending {
    pub(super) a: f64,
    pub(super) b: f64,
    samples: Vec<Sample>,
    /// The sampling to start with (a neighbour's layout: [`Layout`]), 0
    /// for the first of [`SAMPLINGS`].
    pub(super) first: usize,
}

impl Pending {
    pub(super) fn new(a: f64, b: f64) -> Self {
        Pending {
            a,
            b,
            samples: Vec::new(),
            first: 0,
        }
    }
}

/// The most map evaluations one [`MapInterpolant::advance`] samples (in
/// lanes, bitwise as alone, so the chunks do not change a sample): about
/// 3 ms of the page's frame.
const CHUNK: usize = 64;

/// An interval being resolved into verified pieces, round by round: each
/// round samples every pending piece further, settles each (a series, more
/// points, or a split), and checks the series it made.
#[derive(Debug)]
pub(super) struct Resolve {
    /// The interval's left end (where a refusal points if nothing pends).
    a: f64,
    budget: usize,
    pending: Vec<Pending>,
    /// Pieces done and checked, in the order they were.
    verified: Vec<Piece>,
    stage: Stage,
}

/// Where a round is.
#[derive(Debug)]
enum Stage {
    /// Between rounds: the budgets are tested and the next points planned.
    Head,
    /// The round's points `us`, `wanted` of them per pending piece, the
    /// first `got.len()` sampled.
    Sampling {
        us: Vec<f64>,
        wanted: Vec<usize>,
        got: Vec<Sample>,
    },
    /// The sampled pieces settled one by one into series (`done`, to be
    /// checked) and pieces for the next round.
    Settling {
        sampled: std::vec::IntoIter<Pending>,
        done: Vec<Piece>,
        next: Vec<Pending>,
    },
    /// The round's series checked one by one.
    Checking { fresh: std::vec::IntoIter<Piece> },
}

impl Resolve {
    pub(super) fn new(a: f64, b: f64, budget: usize) -> Self {
        Resolve {
            a,
            budget,
            pending: vec![Pending::new(a, b)],
            verified: Vec::new(),
            stage: Stage::Head,
        }
    }
}

/// A construction of f in progress ([`MapInterpolant::build`] and
/// [`MapInterpolant::build_lenient`] run one to its end), one bounded piece
/// of work a call: a caller that must give its thread back (the page's
/// frame) pauses between any two.
#[derive(Debug)]
pub struct InterpolantBuild {
    me: MapInterpolant,
    resolve: Resolve,
    done: Option<Vec<Piece>>,
}

impl InterpolantBuild {
    /// A build of f over [lo, hi] (radians, on the exit arc), `lenient` as
    /// [`MapInterpolant::build_lenient`]; refused at once for bad options
    /// or an interval off the arc.
    pub fn start(
        sim: &Simulator,
        lo: f64,
        hi: f64,
        opts: InterpolantOptions,
        lenient: bool,
    ) -> Result<Self, InterpolantError> {
        if !(opts.tol > 0.0 && opts.max_pieces >= 1) {
            return Err(InterpolantError::Options(
                "tol must be > 0 and max_pieces >= 1",
            ));
        }
        let p = sim.params();
        let (psi, _) = exit_arc(p.kappa, p.theta_nu);
        let me = MapInterpolant {
            sim: *sim,
            psi,
            opts,
            pieces: Vec::new(),
            starts: Vec::new(),
            verification: Verification::default(),
            evaluations: 0,
            rhs_evals: 0,
            lenient,
        };
        let (a, b) = me.check_interval(lo, hi)?;
        Ok(InterpolantBuild {
            me,
            resolve: Resolve::new(a, b, opts.max_pieces),
            done: None,
        })
    }

    /// As [`Self::start`], from a neighbour's layout (at nearby
    /// parameters): its pieces are where this build starts, each sampled
    /// at once as finely as it was there; from there every piece is
    /// settled and checked as in a build from nothing, split where it
    /// fails. A layout that does not meet [lo, hi] starts from nothing.
    pub fn start_from(
        sim: &Simulator,
        lo: f64,
        hi: f64,
        opts: InterpolantOptions,
        lenient: bool,
        layout: &Layout,
    ) -> Result<Self, InterpolantError> {
        let mut build = Self::start(sim, lo, hi, opts, lenient)?;
        let r = &mut build.resolve;
        let (a, b) = (r.pending[0].a, r.pending[0].b);
        let pieces = super::layout::from_layout(a, b, layout);
        if !pieces.is_empty() {
            r.pending = pieces;
        }
        Ok(build)
    }

    /// One piece of the work (a few ms at most); whether the build is done.
    /// An error refuses the build, and it must not be advanced again.
    pub fn advance(&mut self) -> Result<bool, InterpolantError> {
        if self.done.is_none() {
            self.done = self.me.advance(&mut self.resolve)?;
        }
        Ok(self.done.is_some())
    }

    /// Map evaluations and right-hand-side evaluations spent so far.
    pub fn spent(&self) -> (u64, u64) {
        (self.me.evaluations as u64, self.me.rhs_evals)
    }

    /// The build run to its end, all at once; what it spent is added to
    /// `spent`, also when it is refused.
    pub fn run_counting(
        mut self,
        spent: &mut (u64, u64),
    ) -> Result<MapInterpolant, InterpolantError> {
        let done = loop {
            match self.advance() {
                Ok(true) => break Ok(()),
                Ok(false) => {}
                Err(e) => break Err(e),
            }
        };
        let (evaluations, rhs) = self.spent();
        spent.0 += evaluations;
        spent.1 += rhs;
        done.map(|()| self.finish())
    }

    /// The interpolant, once [`Self::advance`] has said the build is done.
    pub fn finish(mut self) -> MapInterpolant {
        let pieces = self.done.take().expect("finish follows a done advance");
        self.me.insert(pieces);
        self.me
    }
}

impl MapInterpolant {
    /// The samples of the events at the onsets u + ψ, computed in lanes.
    fn sample(&mut self, us: &[f64]) -> Result<Vec<Sample>, InterpolantError> {
        let tasks: Vec<_> = us.iter().map(|u| (&self.sim, self.psi + u, 0.0)).collect();
        self.evaluations += tasks.len();
        let psi = self.psi;
        let mut rhs = 0;
        let out = cycles_in_lanes(&tasks)
            .into_iter()
            .map(|r| {
                let e = r?;
                rhs += e.rhs_evals;
                Ok((
                    [
                        wrap_angle(e.theta_next - psi),
                        0.0,
                        e.stop_x,
                        e.stop_y,
                        e.accel_duration,
                        e.slip_duration,
                        e.peak_vr,
                        e.stick_duration,
                    ],
                    e.restarted,
                ))
            })
            .collect();
        self.rhs_evals += rhs;
        out
    }

    /// One bounded piece of `r`'s work: at most [`CHUNK`] of a round's
    /// samples, or one pending piece settled (a jump bracketed), or one
    /// piece checked. The pieces once every one is verified.
    pub(super) fn advance(
        &mut self,
        r: &mut Resolve,
    ) -> Result<Option<Vec<Piece>>, InterpolantError> {
        match std::mem::replace(&mut r.stage, Stage::Head) {
            Stage::Head => {
                if r.pending.is_empty() {
                    return Ok(Some(std::mem::take(&mut r.verified)));
                }
                if self.over_budget(r)? {
                    return Ok(Some(std::mem::take(&mut r.verified)));
                }
                // Every pending piece's next points, in one round of lanes.
                let (us, wanted) = next_points(&r.pending);
                let got = Vec::with_capacity(us.len());
                r.stage = Stage::Sampling { us, wanted, got };
            }
            Stage::Sampling { us, wanted, got } => {
                r.stage = self.sample_round(r, us, wanted, got)?
            }
            Stage::Settling {
                mut sampled,
                mut done,
                mut next,
            } => match sampled.next() {
                Some(p) => {
                    self.settle(p, &mut done, &mut next)?;
                    r.stage = Stage::Settling {
                        sampled,
                        done,
                        next,
                    };
                }
                None => {
                    r.pending = next;
                    r.stage = Stage::Checking {
                        fresh: done.into_iter(),
                    };
                }
            },
            // The check at independent points, of the pieces this round
            // made: one that fails it is split and resolved again.
            Stage::Checking { mut fresh } => {
                if let Some(piece) = fresh.next() {
                    if self.check(&piece)? {
                        r.verified.push(piece);
                    } else {
                        let (pa, pb) = piece.ends();
                        let m = 0.5 * (pa + pb);
                        for (a, b) in [(pa, m), (m, pb)] {
                            r.pending.push(Pending::new(a, b));
                        }
                    }
                    r.stage = Stage::Checking { fresh };
                }
            }
        }
        Ok(None)
    }

    /// At most [`CHUNK`] more of a round's points `us` sampled (`got` so
    /// far); once all are, the pending pieces take their samples and are
    /// to be settled.
    fn sample_round(
        &mut self,
        r: &mut Resolve,
        us: Vec<f64>,
        wanted: Vec<usize>,
        mut got: Vec<Sample>,
    ) -> Result<Stage, InterpolantError> {
        let from = got.len();
        let to = us.len().min(from + CHUNK);
        got.extend(self.sample(&us[from..to])?);
        if to < us.len() {
            return Ok(Stage::Sampling { us, wanted, got });
        }
        let mut fresh = got.into_iter();
        let sampled: Vec<Pending> = std::mem::take(&mut r.pending)
            .into_iter()
            .zip(wanted)
            .map(|(mut p, count)| {
                let new: Vec<Sample> = fresh.by_ref().take(count).collect();
                p.samples = interleave(std::mem::take(&mut p.samples), new);
                p
            })
            .collect();
        Ok(Stage::Settling {
            sampled: sampled.into_iter(),
            done: Vec::new(),
            next: Vec::new(),
        })
    }

    /// At the head of a round: whether the budgets are spent. A lenient
    /// build then leaves what is pending to direct integration; a strict
    /// one is refused.
    fn over_budget(&mut self, r: &mut Resolve) -> Result<bool, InterpolantError> {
        let next_batch: usize = r
            .pending
            .iter()
            .map(|p| next_sampling(p.samples.len()) - p.samples.len())
            .sum();
        let evaluations = self.evaluations.saturating_add(next_batch) > self.opts.max_evaluations;
        let pieces = r.pending.len() + r.verified.len() > r.budget;
        if (evaluations || pieces) && self.lenient {
            let left = r
                .pending
                .drain(..)
                .map(|p| Piece::Direct { a: p.a, b: p.b });
            r.verified.extend(left);
            return Ok(true);
        }
        if evaluations {
            return Err(InterpolantError::OverBudget {
                tol: self.opts.tol,
                max_evaluations: self.opts.max_evaluations,
                near: self.psi + 0.5 * (r.pending[0].a + r.pending[0].b),
            });
        }
        if pieces {
            let narrowest = r
                .pending
                .iter()
                .min_by(|x, y| (x.b - x.a).total_cmp(&(y.b - y.a)))
                .map_or(r.a, |p| 0.5 * (p.a + p.b));
            return Err(InterpolantError::Unresolved {
                tol: self.opts.tol,
                max_pieces: self.opts.max_pieces,
                near: self.psi + narrowest,
            });
        }
        Ok(false)
    }

    /// What becomes of a sampled pending piece: a series (to be checked),
    /// more points, or a split.
    fn settle(
        &mut self,
        p: Pending,
        done: &mut Vec<Piece>,
        next: &mut Vec<Pending>,
    ) -> Result<(), InterpolantError> {
        let n = p.samples.len();
        let restarts = p.samples.iter().any(|s| s.1);
        if !restarts && let Some(piece) = self.series(p.a, p.b, &p.samples) {
            done.push(piece);
            return Ok(());
        }
        if n < SAMPLINGS[SAMPLINGS.len() - 1] && !restarts {
            next.push(p);
            return Ok(());
        }
        // A loose tolerance leaves wider stretches to integration: a seed
        // lands in one rarely, and resolving it would cost the most.
        if p.b - p.a < MIN_PIECE.max(100.0 * self.opts.tol) {
            done.push(Piece::Direct { a: p.a, b: p.b });
            return Ok(());
        }
        let x = chebyshev::points(n);
        let at = |j: usize| 0.5 * (p.a + p.b) + 0.5 * (p.b - p.a) * x[j];
        // A jump: one gap between neighbouring samples holds a quarter of
        // the variation, or the restart flag changes there.
        let gaps: Vec<f64> = p
            .samples
            .windows(2)
            .map(|w| {
                let flag = if w[0].1 != w[1].1 { 1.0 } else { 0.0 };
                (w[1].0[0] - w[0].0[0]).abs() + flag
            })
            .collect();
        let total: f64 = gaps.iter().sum();
        let (j, &largest) = gaps
            .iter()
            .enumerate()
            .max_by(|x, y| x.1.total_cmp(y.1))
            .unwrap_or((0, &0.0));
        let mut halves = Vec::new();
        if largest > 0.25 * total && largest > 1e3 * self.opts.tol {
            // Samples run from b down to a.
            let (jl, jr) =
                self.bracket_jump((at(j + 1), p.samples[j + 1]), (at(j), p.samples[j]))?;
            done.push(Piece::Direct { a: jl, b: jr });
            halves.extend([(p.a, jl), (jr, p.b)]);
        } else {
            let m = 0.5 * (p.a + p.b);
            halves.extend([(p.a, m), (m, p.b)]);
        }
        for (a, b) in halves {
            if b > a {
                next.push(Pending::new(a, b));
            }
        }
        Ok(())
    }

    /// Narrows [l, r] (in θ − ψ, with their samples) around the jump to
    /// [`JUMP_WIDTH`], keeping the half across which θ' changes most (or
    /// the restart flag changes).
    fn bracket_jump(
        &mut self,
        mut l: (f64, Sample),
        mut r: (f64, Sample),
    ) -> Result<(f64, f64), InterpolantError> {
        let change =
            |x: &Sample, y: &Sample| (x.0[0] - y.0[0]).abs() + if x.1 != y.1 { 10.0 } else { 0.0 };
        while r.0 - l.0 > JUMP_WIDTH {
            let m = 0.5 * (l.0 + r.0);
            if m <= l.0 || m >= r.0 {
                break;
            }
            let sm = self.sample(&[m])?[0];
            if change(&l.1, &sm) >= change(&sm, &r.1) {
                r = (m, sm);
            } else {
                l = (m, sm);
            }
        }
        Ok((l.0, r.0))
    }

    /// The series of [a, b] from its samples at `points(n)`, when every
    /// quantity is resolved.
    fn series(&self, a: f64, b: f64, samples: &[Sample]) -> Option<Piece> {
        let n = samples.len();
        let column = |f: usize| -> Vec<f64> { samples.iter().map(|s| s.0[f]).collect() };
        let c0 = chebyshev::coefficients(&column(0));
        if !chebyshev::resolved(&c0, self.opts.tol) {
            return None;
        }
        let mut table = vec![[0.0; FIELDS]; n];
        let mut d = chebyshev::derivative(&c0);
        let scale = 2.0 / (b - a);
        d.iter_mut().for_each(|x| *x *= scale);
        for k in 0..n {
            table[k][0] = c0[k];
            table[k][1] = d.get(k).copied().unwrap_or(0.0);
        }
        for f in 2..FIELDS {
            let c = chebyshev::coefficients(&column(f));
            for k in 0..n {
                table[k][f] = c[k];
            }
        }
        let cycle: Vec<f64> = table.iter().map(|c| c[5] + c[7]).collect();
        let big = samples
            .iter()
            .fold(1.0_f64, |m, s| m.max((s.0[5] + s.0[7]).abs()));
        Some(Piece::Series {
            a,
            b,
            map: chebyshev::chop(&c0, self.opts.tol),
            cycle: chebyshev::chop(&cycle, 1e-12 * big),
            table,
        })
    }

    /// Compares a piece with the direct map at [`CHECKS`]; says whether θ'
    /// is within the tolerance there, and records the errors of the pieces
    /// that pass.
    fn check(&mut self, piece: &Piece) -> Result<bool, InterpolantError> {
        let Piece::Series {
            a, b, map, table, ..
        } = piece
        else {
            return Ok(true);
        };
        let us: Vec<f64> = CHECKS.iter().map(|f| a + f * (b - a)).collect();
        let direct = self.sample(&us)?;
        let (mut ok, mut worst, mut worst_event) = (true, 0.0_f64, 0.0_f64);
        for (u, (s, restarted)) in us.iter().zip(direct) {
            let x = (2.0 * u - a - b) / (b - a);
            let v = clenshaw_fields(table, x);
            let map_err = (chebyshev::clenshaw(map, x) - s[0]).abs();
            let mut ev_err: f64 = 0.0;
            for f in 2..FIELDS {
                ev_err = ev_err.max((v[f] - s[f]).abs() / s[f].abs().max(1.0));
            }
            worst = worst.max(map_err);
            worst_event = worst_event.max(ev_err);
            ok &= !restarted && map_err <= self.opts.tol;
        }
        let vf = &mut self.verification;
        if ok {
            vf.points += CHECKS.len();
            vf.max_map_error = vf.max_map_error.max(worst);
            vf.max_event_error = vf.max_event_error.max(worst_event);
        } else {
            vf.failed += 1;
        }
        Ok(ok)
    }
}

/// The next number of points for a piece with `have` samples.
fn next_sampling(have: usize) -> usize {
    SAMPLINGS
        .iter()
        .copied()
        .find(|&n| n > have)
        .unwrap_or(SAMPLINGS[SAMPLINGS.len() - 1])
}

/// The samples at `points(2n − 1)` from those at `points(n)` (the even
/// indices) and the new ones (the odd).
fn interleave(old: Vec<Sample>, new: Vec<Sample>) -> Vec<Sample> {
    if old.is_empty() {
        return new;
    }
    let mut out = Vec::with_capacity(old.len() + new.len());
    let mut new = new.into_iter();
    for (i, s) in old.into_iter().enumerate() {
        if i > 0
            && let Some(m) = new.next()
        {
            out.push(m);
        }
        out.push(s);
    }
    out
}

/// The next points of every pending piece (its first sampling, or the
/// points that refine it), in order, and how many each piece wants.
fn next_points(pending: &[Pending]) -> (Vec<f64>, Vec<usize>) {
    let mut us = Vec::new();
    let mut wanted = Vec::new();
    for p in pending {
        let n = match p.samples.len() {
            0 if SAMPLINGS.contains(&p.first) => p.first,
            have => next_sampling(have),
        };
        let x = chebyshev::points(n);
        let new: Vec<usize> = if p.samples.is_empty() {
            (0..n).collect()
        } else {
            (1..n).step_by(2).collect()
        };
        for &j in &new {
            us.push(0.5 * (p.a + p.b) + 0.5 * (p.b - p.a) * x[j]);
        }
        wanted.push(new.len());
    }
    (us, wanted)
}
