//! [`settled_period`] for a sequence that grows one value at a time, at
//! O(1) amortised cost per value instead of a residual over every
//! candidate period's window (Σ 2p ≈ 4 000 angle differences) at each.
//!
//! A period p can pass only where it can have happened: its residual
//! compares every value of its window with the value a whole number of
//! periods before it at the window's start, so a residual within `tol`
//! needs every p-difference |θᵢ − θᵢ₋ₚ| in the window within 2·`tol`
//! (both are within `tol` of the same value). One p-difference above that
//! (plus rounding) keeps p from passing until the window has moved past
//! it: max(3p, 24) − p more values. The watch keeps, for each p, the
//! length from which p can pass again, in a calendar of due lengths, and
//! looks at a p-difference only when p is due: on a chaotic orbit one
//! difference per due p, about 1.5 a value in all. A p whose window holds
//! no such difference is tested exactly, by [`settled_period`]'s own
//! residuals, smallest first, so the decisions are [`settled_period`]'s
//! (`tests` compares the two on orbits of the map).

use super::{DIVISOR_MARGIN, MIN_WINDOW, PERIOD_MAX, longest_testable, period_residual};
use super::{period_window, settled_period};
use crate::model::wrap_angle;

/// Values a period's window holds at most: max(3p, [`MIN_WINDOW`]) for
/// p ≤ [`PERIOD_MAX`]. [`settled_period`] reads no further back.
pub const WINDOW_MAX: usize = 3 * PERIOD_MAX;
const _: () = assert!(WINDOW_MAX >= MIN_WINDOW);

/// Slots of the calendar: more than the furthest a p is ever put off
/// (max(3p, 24) − p + 1 ≤ 129 lengths).
const SLOTS: usize = 256;

/// Beyond this size (radians) an angle's rounding errors are not known to
/// fit the filter's margin: a window holding one is tested in full.
const LARGE: f64 = 64.0;

/// The filter's allowance for rounding on top of 2·tol: the residuals and
/// the p-difference are each a difference of two angles within
/// [`LARGE`] and one reduction by 2π, off by a few ulps of 2·LARGE
/// (≈ 3e-14) each.
const ROUNDING: f64 = 1e-12;

/// [`settled_period`] of a growing sequence, incrementally (see the
/// module's comment). The sequence may only grow: the values it held at
/// one call are the same at the next. About 2.6 KB: box it where what
/// holds it is moved about.
#[derive(Clone, Debug)]
pub struct PeriodWatch {
    tol: f64,
    /// The largest p-difference consistent with a residual within `tol`.
    bound: f64,
    /// `due[n % SLOTS]`: bit p − 1 set when p is to be looked at once the
    /// sequence has n values.
    due: [u64; SLOTS],
    /// For each p (index p − 1): the p-differences of values before this
    /// index have been looked at (or were too old to matter).
    seen: [usize; PERIOD_MAX],
    /// The length at the last call (the calendar is cleared up to it).
    last: usize,
    /// Values before this index were checked for [`LARGE`] ones.
    scanned: usize,
    /// One past the newest index of a value beyond [`LARGE`] (or not
    /// finite), 0 if none.
    large_end: usize,
    /// The answer at length `last` (a second call at one length repeats it).
    answer: Option<usize>,
}

impl PeriodWatch {
    /// A watch with the tolerance of [`settled_period`]'s `tol`.
    pub fn new(tol: f64) -> Self {
        let mut due = [0u64; SLOTS];
        // p is first testable with 2p values.
        for p in 1..=PERIOD_MAX {
            due[(2 * p) % SLOTS] |= 1 << (p - 1);
        }
        PeriodWatch {
            tol,
            bound: 2.0 * tol + ROUNDING,
            due,
            seen: [0; PERIOD_MAX],
            last: 0,
            scanned: 0,
            large_end: 0,
            answer: None,
        }
    }

    /// `settled_period(seq, tol)` for the sequence `seq` of `n` values,
    /// given its end `recent`: its last min(n, [`WINDOW_MAX`]) values at
    /// least, the last of them `seq[n − 1]`.
    pub fn settled(&mut self, recent: &[f64], n: usize) -> Option<usize> {
        debug_assert!(recent.len() >= n.min(WINDOW_MAX) && recent.len() <= n);
        debug_assert!(n >= self.last, "the sequence only grows");
        if n == self.last {
            return self.answer;
        }
        let base = n - recent.len();
        self.scan_large(recent, base, n);
        let due = self.take_due(n);
        if self.large_end > 0 && n < self.large_end + WINDOW_MAX {
            // Put off nothing: the p due now are looked at again next time.
            self.due[(n + 1) % SLOTS] |= due;
            self.answer = settled_period(recent, self.tol);
            return self.answer;
        }
        let mut candidates = 0u64;
        let mut bits = due;
        while bits != 0 {
            let p = bits.trailing_zeros() as usize + 1;
            bits &= bits - 1;
            match self.newest_violation(recent, base, n, p) {
                Some(i) => {
                    // Blocked while i and i − p are both in p's window.
                    let again = i + p_window(p) - p + 1;
                    self.due[again % SLOTS] |= 1 << (p - 1);
                }
                None => {
                    candidates |= 1 << (p - 1);
                    self.due[(n + 1) % SLOTS] |= 1 << (p - 1);
                }
            }
        }
        self.answer = self.first_passing(recent, n, candidates);
        self.answer
    }

    /// Notes the newest value beyond [`LARGE`] among those new since the
    /// last call.
    fn scan_large(&mut self, recent: &[f64], base: usize, n: usize) {
        for i in self.scanned.max(base)..n {
            if !(recent[i - base].abs() <= LARGE) {
                self.large_end = i + 1;
            }
        }
        self.scanned = n;
    }

    /// The p due by length `n`, taken off the calendar.
    fn take_due(&mut self, n: usize) -> u64 {
        let mut due = 0;
        for len in (self.last + 1).max(n.saturating_sub(SLOTS - 1))..=n {
            due |= std::mem::take(&mut self.due[len % SLOTS]);
        }
        self.last = n;
        due
    }

    /// The newest index i in p's window at length n (at least 2p, so
    /// p is testable) whose p-difference is above the bound, looked for
    /// among the indices not looked at before, newest first.
    fn newest_violation(
        &mut self,
        recent: &[f64],
        base: usize,
        n: usize,
        p: usize,
    ) -> Option<usize> {
        let w = period_window(p, n)?;
        let from = (n - w + p).max(self.seen[p - 1]);
        self.seen[p - 1] = n;
        let at = |i: usize| recent[i - base];
        (from..n)
            .rev()
            .find(|&i| wrap_angle(at(i) - at(i - p)).abs() > self.bound)
    }

    /// The smallest p among `candidates` (bit p − 1) that
    /// [`settled_period`] accepts.
    fn first_passing(&self, recent: &[f64], n: usize, mut candidates: u64) -> Option<usize> {
        while candidates != 0 {
            let p = candidates.trailing_zeros() as usize + 1;
            candidates &= candidates - 1;
            if p > longest_testable(n) {
                continue;
            }
            let Some(w) = period_window(p, n) else {
                continue;
            };
            let passes = period_residual(recent, p, w).is_some_and(|r| r <= self.tol)
                && (1..p).filter(|q| p.is_multiple_of(*q)).all(|q| {
                    period_residual(recent, q, w).is_some_and(|rq| rq > DIVISOR_MARGIN * self.tol)
                });
            if passes {
                return Some(p);
            }
        }
        None
    }
}

/// The window p is tested on once the sequence is long enough.
fn p_window(p: usize) -> usize {
    (3 * p).max(MIN_WINDOW)
}

#[cfg(test)]
mod tests;
