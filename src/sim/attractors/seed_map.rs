//! The map the seeds of [`super::attractors`] iterate: verified
//! interpolants over neighbourhoods of the attractors found so far, and
//! direct integration everywhere else. Once the first orbit has shown where
//! an attractor lies, the seeds that fall towards it cost a few direct
//! iterates each and then tens of nanoseconds an iterate; so 64 seeds cost
//! a small multiple of one orbit instead of 64 orbits.
//!
//! A neighbourhood's interpolant is built as wide as a bounded number of
//! map evaluations allows (wider catches the seeds sooner, but may take in
//! a jump of f that is expensive to resolve): 0.3 rad each side of the
//! attractor's hull, then 0.1, 0.03 and 0.01, each try capped at
//! [`BUILD_CAP`]. A chaotic set's neighbourhoods are tried only where they
//! at least double its hull, and to a looser tolerance ([`SET_MAP_TOL`]);
//! where all are refused (a wide set whose hull holds a jump of f, as the
//! intermittent one's), the hull alone is tried, capped at what the
//! remaining seeds would otherwise integrate.
//!
//! Seeds that linger far from every series (creep, whose fixed point draws
//! them in at 1 % an iterate) get a patch where they are: once they have
//! integrated as many iterates as a try may cost, one interpolant at the
//! first width is tried around the next one's onset. A refused patch costs
//! at most what was integrated since the last (docs/attractors.md gives
//! what they save at the creep preset).

use std::f64::consts::FRAC_PI_2;

use crate::model::{exit_arc, wrap_angle};
use crate::sim::interpolant::{InterpolantOptions, MapInterpolant};
use crate::sim::period::{PERIOD_MAX, contraction, settled_period};
use crate::sim::seeded::SEED_MAP_TOL;
use crate::sim::{SimError, Simulator};

/// The widths (radians each side of an attractor's hull) a neighbourhood's
/// interpolant is tried at, widest first.
const WIDTHS: [f64; 4] = [0.3, 0.1, 0.03, 0.01];

/// The most map evaluations one try may take (a refusal costs at most this).
const BUILD_CAP: usize = 160;

/// A loose map's widths and cap ([`SeedMap::loose`]): its seeds stop as
/// soon as they close in on a known attractor, so a neighbourhood pays
/// only where it is cheap (measured on the Fig. 4 grid: the accurate
/// map's widths and cap cost the seeds a third more there).
const LOOSE_WIDTHS: [f64; 2] = [0.1, 0.01];
/// See [`LOOSE_WIDTHS`].
const LOOSE_CAP: usize = 100;

/// The map for the seeds.
pub(crate) struct SeedMap<'s> {
    sim: &'s Simulator,
    psi: f64,
    iopts: InterpolantOptions,
    /// The widths a neighbourhood is tried at, and each try's cap.
    widths: &'static [f64],
    cap: usize,
    interps: Vec<MapInterpolant>,
    /// Iterates integrated since the last patch was tried ([`Self::next`]).
    since_try: usize,
    /// Iterates integrated directly.
    pub direct: usize,
    /// Map evaluations the interpolants took, refused tries included.
    pub evaluations: usize,
    /// Right-hand-side evaluations of both.
    pub rhs_evals: u64,
}

impl<'s> SeedMap<'s> {
    /// The map of `sim` (the seeds' loose map,
    /// `super::super::seeded::seed_simulator`) over [`WIDTHS`]:
    /// `attractors`'s, whose seeds run their whole budget unless they close
    /// in on a known attractor, so wide neighbourhoods pay.
    pub fn wide(sim: &'s Simulator) -> Self {
        Self::with(sim, &WIDTHS, BUILD_CAP)
    }

    /// As [`Self::wide`] over [`LOOSE_WIDTHS`]: a seeded column's or
    /// cell's, at every column of a diagram.
    pub fn loose(sim: &'s Simulator) -> Self {
        Self::with(sim, &LOOSE_WIDTHS, LOOSE_CAP)
    }

    /// Its interpolants to [`SEED_MAP_TOL`], or ten times the map's own
    /// tolerance where that is looser.
    fn with(sim: &'s Simulator, widths: &'static [f64], cap: usize) -> Self {
        let p = sim.params();
        let tol = SEED_MAP_TOL.max(10.0 * sim.settings().rtol);
        SeedMap {
            sim,
            widths,
            cap,
            psi: exit_arc(p.kappa, p.theta_nu).0,
            iopts: InterpolantOptions {
                tol,
                ..InterpolantOptions::for_settings(sim.settings())
            },
            interps: Vec::new(),
            since_try: 0,
            direct: 0,
            evaluations: 0,
            rhs_evals: 0,
        }
    }

    /// The next onset after θ: from a verified series where one covers θ,
    /// integrated otherwise.
    pub fn next(&mut self, theta: f64) -> Result<f64, SimError> {
        if let Some(next) = self.interps.iter().find_map(|i| i.map(theta)) {
            return Ok(next);
        }
        if self.since_try >= self.cap {
            // The seeds linger away from every series: a patch where they
            // are, paid for by the integrated iterates it may save.
            self.since_try = 0;
            let tol = self.iopts.tol;
            self.try_width(theta, theta, self.widths[0], self.cap, tol);
            if let Some(next) = self.interps.last().and_then(|i| i.map(theta)) {
                return Ok(next);
            }
        }
        self.since_try += 1;
        self.direct += 1;
        let ev = self.sim.cycle(theta, 0.0, None)?;
        self.rhs_evals += ev.rhs_evals;
        Ok(self.sim.next_onset(&ev))
    }

    /// Adds an interpolant over a neighbourhood of a cycle's point `theta`,
    /// as wide as its widths and cap allow (the widest that is built);
    /// nothing when every try is refused (seeds then integrate there).
    pub fn cover_point(&mut self, theta: f64) {
        let (widths, cap, tol) = (self.widths, self.cap, self.iopts.tol);
        for &w in widths {
            if self.try_width(theta, theta, w, cap, tol) {
                return;
            }
        }
    }

    /// Adds an interpolant over a chaotic set's interval [lo, hi], to
    /// [`SET_MAP_TOL`]: a neighbourhood as wide as its widths allow where
    /// one at least doubles the interval (a narrow band), else the interval
    /// alone, with `worth` evaluations at most (a wide set's interval may
    /// hold a jump of f and rough stretches); nothing when every try is
    /// refused.
    pub fn cover_set(&mut self, lo: f64, hi: f64, worth: usize) {
        let (a, b) = (wrap_angle(lo - self.psi), wrap_angle(hi - self.psi));
        if !(a <= b) {
            return;
        }
        let tol = SET_MAP_TOL.max(self.iopts.tol);
        let (widths, cap) = (self.widths, self.cap);
        let tries = widths.iter().filter(|&&w| w >= b - a).map(|&w| (w, cap));
        for (w, cap) in tries.chain([(1e-3, worth)]) {
            if self.try_width(lo, hi, w, cap, tol) {
                return;
            }
        }
    }

    /// Adds an interpolant to `tol` over [lo − w, hi + w] (θ, kept inside
    /// the arc), at most `cap` map evaluations; whether it was built.
    fn try_width(&mut self, lo: f64, hi: f64, w: f64, cap: usize, tol: f64) -> bool {
        let edge = FRAC_PI_2 - 1e-6;
        let (lo, hi) = (wrap_angle(lo - self.psi), wrap_angle(hi - self.psi));
        let (a, b) = ((lo - w).max(-edge), (hi + w).min(edge));
        if a >= b || cap == 0 {
            return false;
        }
        let opts = InterpolantOptions {
            max_evaluations: cap,
            tol,
            ..self.iopts
        };
        let mut spent = (0, 0);
        let (from, to) = (self.psi + a, self.psi + b);
        let built = MapInterpolant::build_counting(self.sim, from, to, opts, &mut spent);
        self.evaluations += spent.0 as usize;
        self.rhs_evals += spent.1;
        built.map(|i| self.interps.push(i)).is_ok()
    }
}

/// The error in θ' allowed for an interpolant over a chaotic set's
/// interval ([`SeedMap::cover_set`]). A seed there is only told whether
/// it stays in the interval (or closes in on a cycle to 1e-3), and its
/// orbit is chaotic: errors of 1e-4 change nothing it is told. At the
/// seeds' 1e-5 the intermittent preset's interval took 2 755 evaluations
/// (tries at the loose map's own noise), at 1e-4 545.
pub(crate) const SET_MAP_TOL: f64 = 1e-4;

/// What a seed's orbit on [`SeedMap`] came to.
pub(crate) enum Fell {
    /// It closes in on the known cycle of this index ([`closes_in`]).
    Known(usize),
    /// It has wandered inside the known chaotic set of this index (its
    /// interval) for [`SET_STAY`] iterates without settling.
    InSet(usize),
    /// Its iterates repeat with a period: these are its last p.
    Repeats(Vec<f64>),
    /// They did not: its kept iterates and the onset after them.
    Wanders(Vec<f64>, f64),
}

/// How near a known cycle's point an orbit must come, closing in over
/// four periods, to be counted as falling onto it: far inside the
/// neighbourhood where the cycle's linearisation governs the approach
/// (coexisting attractors here lie tenths of a radian apart).
const CLOSE: f64 = 1e-3;

/// Whether the end of `seq` closes in on the p-cycle `points`: its newest
/// value within [`CLOSE`] of a point of it, and its distance from that
/// point, one period at a time, shrinking over the last four periods (the
/// approach of a stable cycle in its linear regime).
fn closes_in(seq: &[f64], points: &[f64]) -> bool {
    let (n, p) = (seq.len(), points.len());
    if p == 0 || n < 4 * p + 1 {
        return false;
    }
    let last = seq[n - 1];
    let gap = |x: f64, y: f64| wrap_angle(x - y).abs();
    let Some(&target) = points
        .iter()
        .min_by(|x, y| gap(last, **x).total_cmp(&gap(last, **y)))
    else {
        return false;
    };
    let e: Vec<f64> = (0..4).map(|k| gap(seq[n - 1 - k * p], target)).collect();
    e[0] < CLOSE && e[0] < e[1] && e[1] < e[2] && e[2] < e[3]
}

/// How many iterates in a row a seed wanders inside a known chaotic set's
/// interval, neither closing in on a cycle nor repeating, before it is
/// counted as reaching that set (as its kept iterates' interval would
/// overlap the set's): as long as the longest period told apart.
pub(crate) const SET_STAY: usize = PERIOD_MAX;

/// What a seed's orbit is told against: the stable cycles and chaotic sets
/// (intervals [lo, hi]) known so far.
#[derive(Clone, Copy, Default)]
pub(crate) struct Known<'k> {
    pub cycles: &'k [&'k [f64]],
    pub sets: &'k [(f64, f64)],
}

impl SeedMap<'_> {
    /// The seed's orbit from θ0, `transient` + `keep` iterates at most: it
    /// stops once it closes in on one of the stable cycles `known`, once it
    /// has stayed in one of its chaotic sets ([`SET_STAY`]), or once its
    /// last iterates repeat with a period (to `rep_tol`).
    pub fn fall(
        &mut self,
        theta0: f64,
        (transient, keep): (usize, usize),
        rep_tol: f64,
        known: Known,
        cancel: &dyn Fn() -> bool,
    ) -> Result<Fell, SimError> {
        let window = 3 * PERIOD_MAX;
        let mut recent = Vec::with_capacity(2 * window);
        let mut kept = Vec::with_capacity(keep.min(1 << 16));
        let mut stay = vec![0usize; known.sets.len()];
        let mut theta = theta0;
        for i in 0..transient.saturating_add(keep) {
            if i % 64 == 0 && cancel() {
                return Err(SimError::Cancelled);
            }
            if i >= transient {
                kept.push(theta);
            }
            for (n, &(lo, hi)) in stay.iter_mut().zip(known.sets) {
                *n = if (lo..=hi).contains(&theta) {
                    *n + 1
                } else {
                    0
                };
            }
            if let Some(k) = stay.iter().position(|&n| n >= SET_STAY) {
                // Not while it contracts slowly onto a cycle inside the set.
                if contraction(&recent, rep_tol).is_none() {
                    return Ok(Fell::InSet(k));
                }
                stay[k] = 0;
            }
            if recent.len() == 2 * window {
                recent.drain(..window);
            }
            recent.push(theta);
            if i % 8 == 7 {
                if let Some(k) = known.cycles.iter().position(|c| closes_in(&recent, c)) {
                    return Ok(Fell::Known(k));
                }
                // The full period test only once the newest value repeats
                // one of the last PERIOD_MAX (a cheap test chaos fails).
                let n = recent.len();
                let repeats = (1..=PERIOD_MAX.min(n - 1))
                    .any(|p| wrap_angle(recent[n - 1] - recent[n - 1 - p]).abs() <= rep_tol);
                if repeats && let Some(p) = settled_period(&recent, rep_tol) {
                    return Ok(Fell::Repeats(recent[n - p..].to_vec()));
                }
            }
            theta = self.next(theta)?;
        }
        Ok(Fell::Wanders(kept, theta))
    }
}

/// The least and greatest of `thetas` (an orbit's hull).
pub(crate) fn hull(thetas: &[f64]) -> (f64, f64) {
    let lo = thetas.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = thetas.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (lo, hi)
}
