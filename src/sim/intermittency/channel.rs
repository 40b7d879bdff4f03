//! The passage time through the channel between f and the diagonal on the
//! creep arc, computed from f itself.
//!
//! A laminar phase is a run of creep slips: the onsets drift through the
//! creep arc by g(θ) = f(θ) − θ per slip, small there (the creep slips
//! barely move the block), until one lands past the arc's end and the
//! stick-slip slips that follow re-inject the orbit. Where g keeps one sign
//! on the arc, the arc is an open channel between f and the diagonal and
//! the time to cross it from θ_in is the continuous approximation
//!
//!   T(θ_in) = ∫ dθ / g(θ)   from θ_in to the arc's exit end,
//!
//! in iterates of f (type-I intermittency's passage time, which near a
//! tangency of f with the diagonal grows as ε^(−1/2)). A run entering at
//! θ_in holds the onsets reached at times 0, 1, 2, … before T, that is
//! ⌈T⌉ creep slips: the estimate of a laminar length. The entries θ_in are
//! computed from f too: the last creep onset of a run lies within one step
//! g of the exit end; [`ENTRIES`] such onsets, spread evenly over that step
//! (the assumption: the orbit's phase there is uniform), are mapped on by
//! f until they land back in the channel. The estimate is the mean of ⌈T⌉
//! over those entries (the mean of T itself is kept beside it: it falls
//! about half a slip short, and below 1 where a run is a single slip).
//!
//! g is sampled at the midpoints of [`CELLS`] equal cells of the arc and
//! 1/g taken constant on each (the midpoint rule; the ends of the arc are
//! never evaluated, so an arc that ends on the exit arc's edge is fine).

use crate::model::{is_on_exit_arc, onset_character, wrap_angle};
use crate::sim::{SimError, Simulator};
use std::f64::consts::{FRAC_PI_2, PI};

/// Cells g is sampled on.
pub const CELLS: usize = 64;
/// Last creep onsets mapped on to find where the orbit re-enters.
pub const ENTRIES: usize = 32;
/// The most iterates outside the channel before an exit counts as not
/// coming back.
pub const MAX_RETURN: usize = 64;

/// The connected part of the creep arc on the exit arc that holds the
/// creep onset `near`, as (lo, hi) with lo < near < hi (unwrapped about
/// `near`); `None` when `near` is no creep onset on the exit arc.
pub fn creep_interval(kappa: f64, gamma: f64, theta_nu: f64, near: f64) -> Option<(f64, f64)> {
    if !near.is_finite()
        || !is_on_exit_arc(kappa, theta_nu, near)
        || onset_character(kappa, gamma, near) != crate::model::OnsetCharacter::Creep
    {
        return None;
    }
    // A(θ) − γ² = (κ − 1) cos²θ + 1 − γ² changes sign where
    // cos²θ = (γ² − 1)/(κ − 1); the exit arc ends at ψ ± π/2. Between two
    // neighbouring boundaries nothing changes.
    let mut bounds = Vec::with_capacity(24);
    let r = (gamma * gamma - 1.0) / (kappa - 1.0);
    if r.is_finite() && r > 0.0 && r < 1.0 {
        let t1 = r.sqrt().acos();
        bounds.extend([t1, -t1]);
    }
    let (psi, _) = crate::model::exit_arc(kappa, theta_nu);
    bounds.push(psi + FRAC_PI_2);
    let mut lo = f64::NEG_INFINITY;
    let mut hi = f64::INFINITY;
    for b in bounds {
        for k in -4..=4 {
            let c = b + k as f64 * PI;
            if c < near {
                lo = lo.max(c);
            } else if c > near {
                hi = hi.min(c);
            }
        }
    }
    (lo.is_finite() && hi.is_finite()).then_some((lo, hi))
}

/// The passage through the creep channel, or why there is none.
#[derive(Clone, Debug, PartialEq)]
pub enum Passage {
    /// No creep onset on the exit arc to start from.
    NoChannel,
    /// f − θ changes sign on the creep arc, near `theta`: f meets the
    /// diagonal there (a fixed point), so the channel is closed.
    Closed { theta: f64 },
    /// None of the exits came back to the creep arc within [`MAX_RETURN`]
    /// iterates.
    NoReturn,
    /// The channel is open.
    Open(ChannelPassage),
}

/// An open channel and the passage time through it.
#[derive(Clone, Debug, PartialEq)]
pub struct ChannelPassage {
    /// The creep arc's ends (unwrapped about the onset asked for).
    pub lo: f64,
    pub hi: f64,
    /// The narrowest gap |f(θ) − θ| over the arc's cells, and where.
    pub narrowest: f64,
    pub at: f64,
    /// The mean number of creep slips a passage holds, ⌈T⌉ over the
    /// entries, T = ∫dθ/(f(θ) − θ) from the entry to the exit end.
    pub mean: f64,
    /// The mean of T itself, in iterates of f.
    pub mean_time: f64,
    /// How many of the [`ENTRIES`] exits came back (the mean's sample).
    pub entries: usize,
}

impl Passage {
    /// A few words: "channel passage ≈ 24.1 slips (f − θ ≥ 0.015 at θ = 0.05)".
    pub fn describe(&self) -> String {
        match self {
            Passage::NoChannel => "no creep onset to start a channel from".into(),
            Passage::Closed { theta } => format!(
                "no open channel: f meets the diagonal on the creep arc near theta = {theta:.4}"
            ),
            Passage::NoReturn => format!(
                "no channel passage: no exit comes back to the creep arc within {MAX_RETURN} slips"
            ),
            Passage::Open(c) => format!(
                "channel passage {:.1} slips (ceil of T = integral of dtheta/(f - theta) over \
                 the creep arc [{:.4}, {:.4}] from {} re-entries, mean T {:.2}; f - theta >= \
                 {:.2e}, at theta = {:.4})",
                c.mean, c.lo, c.hi, c.entries, c.mean_time, c.narrowest, c.at
            ),
        }
    }

    /// The mean passage time, when the channel is open.
    pub fn mean(&self) -> Option<f64> {
        match self {
            Passage::Open(c) => Some(c.mean),
            _ => None,
        }
    }
}

/// The passage time through the creep channel holding the creep onset
/// `near` at `sim`'s parameters (see the module notes). About
/// [`CELLS`] + 8·[`ENTRIES`] map evaluations; `cancel` is polled at each.
pub fn passage(sim: &Simulator, near: f64, cancel: &dyn Fn() -> bool) -> Result<Passage, SimError> {
    let mut run = PassageRun::new(sim, near);
    loop {
        if let Some(r) = run.advance(sim, cancel) {
            return r;
        }
    }
}

/// [`passage`] one map evaluation at a time, so that a host on a slice of
/// time (the browser's) can stop between two and go on later: the same
/// evaluations in the same order, so the same result bit for bit.
pub struct PassageRun {
    near: f64,
    /// The channel (`None`: there is none) and its cells' width.
    channel: Option<(f64, f64)>,
    w: f64,
    /// g at the cells' midpoints computed so far.
    g: Vec<f64>,
    /// Once g is complete: the entry being followed, where it is (`None`
    /// before its first evaluation) and the returns made from it.
    entry: usize,
    x: Option<f64>,
    returns: usize,
    times: Vec<f64>,
}

impl PassageRun {
    /// The passage for the creep onset `near`, nothing evaluated yet.
    pub fn new(sim: &Simulator, near: f64) -> Self {
        let p = *sim.params();
        let channel = creep_interval(p.kappa, p.gamma, p.theta_nu, near);
        PassageRun {
            near,
            channel,
            w: channel.map_or(0.0, |(lo, hi)| (hi - lo) / CELLS as f64),
            g: Vec::with_capacity(CELLS),
            entry: 0,
            x: None,
            returns: 0,
            times: Vec::with_capacity(ENTRIES),
        }
    }

    /// One map evaluation (`cancel` polled before it), then `None` while
    /// the passage goes on, or its result. `sim` must be the simulator it
    /// was made with; a run that has answered is not advanced again.
    pub fn advance(
        &mut self,
        sim: &Simulator,
        cancel: &dyn Fn() -> bool,
    ) -> Option<Result<Passage, SimError>> {
        let Some((lo, hi)) = self.channel else {
            return Some(Ok(Passage::NoChannel));
        };
        let f = |th: f64| -> Result<f64, SimError> {
            if cancel() {
                return Err(SimError::Cancelled);
            }
            sim.map(wrap_angle(th))
        };
        if self.g.len() < CELLS {
            let m = lo + (self.g.len() as f64 + 0.5) * self.w;
            match f(m) {
                Ok(v) => self.g.push(wrap_angle(v - wrap_angle(m))),
                Err(e) => return Some(Err(e)),
            }
            return (self.g.len() == CELLS).then(|| self.closed()).flatten();
        }
        if self.entry < ENTRIES {
            // A failed evaluation drops the entry; a cancel ends the whole.
            let at = self.x.unwrap_or_else(|| self.last_onset(lo, hi));
            match f(at) {
                Err(SimError::Cancelled) => return Some(Err(SimError::Cancelled)),
                Err(_) => self.next_entry(),
                Ok(y) => self.landed(y, lo, hi),
            }
        }
        (self.entry == ENTRIES).then(|| Ok(self.open(lo, hi)))
    }

    /// Once g is complete: the channel is closed where g changes sign.
    fn closed(&self) -> Option<Result<Passage, SimError>> {
        let (lo, g, w) = (self.channel?.0, &self.g, self.w);
        let i = (1..CELLS).find(|&i| (g[i] > 0.0) != (g[i - 1] > 0.0))?;
        // The zero of g between the two midpoints, by linear interpolation.
        let (m0, g0, g1) = (lo + (i as f64 - 0.5) * w, g[i - 1], g[i]);
        Some(Ok(Passage::Closed {
            theta: wrap_angle(m0 + w * g0 / (g0 - g1)),
        }))
    }

    /// Whether the channel is crossed upwards (g > 0 on it).
    fn up(&self) -> bool {
        self.g[0] > 0.0
    }

    /// The current entry's last creep onset: [`ENTRIES`] of them spread
    /// over the last step g before the exit end.
    fn last_onset(&self, lo: f64, hi: f64) -> f64 {
        let g = &self.g;
        let (exit, step) = if self.up() {
            (hi, g[g.len() - 1])
        } else {
            (lo, g[0])
        };
        let span = step.abs().min(hi - lo);
        exit - span.copysign(step) * (self.entry as f64 + 0.5) / ENTRIES as f64
    }

    /// `y` in the channel, unwrapped about the onset asked for.
    fn inside(&self, y: f64, lo: f64, hi: f64) -> Option<f64> {
        let u = self.near + wrap_angle(y - self.near);
        (u > lo && u < hi).then_some(u)
    }

    /// Where the current entry's orbit landed: an onset still in the
    /// channel was no run's last; back in it, its passage time is kept;
    /// outside, it goes on up to [`MAX_RETURN`] iterates.
    fn landed(&mut self, y: f64, lo: f64, hi: f64) {
        let first = self.x.is_none();
        match self.inside(y, lo, hi) {
            Some(_) if first => self.next_entry(),
            Some(u) => {
                self.times
                    .push(time_to_exit(&self.g, lo, self.w, u, self.up()));
                self.next_entry();
            }
            None if first => self.x = Some(y),
            None => {
                self.returns += 1;
                if self.returns == MAX_RETURN {
                    self.next_entry();
                } else {
                    self.x = Some(y);
                }
            }
        }
    }

    fn next_entry(&mut self) {
        self.entry += 1;
        self.x = None;
        self.returns = 0;
    }

    /// The answer once every entry has been followed.
    fn open(&self, lo: f64, hi: f64) -> Passage {
        let times = &self.times;
        if times.is_empty() {
            return Passage::NoReturn;
        }
        let (k, narrowest) =
            self.g
                .iter()
                .map(|v| v.abs())
                .enumerate()
                .fold(
                    (0, f64::INFINITY),
                    |a, (i, v)| if v < a.1 { (i, v) } else { a },
                );
        Passage::Open(ChannelPassage {
            lo,
            hi,
            narrowest,
            at: wrap_angle(lo + (k as f64 + 0.5) * self.w),
            mean: times.iter().map(|t| t.ceil()).sum::<f64>() / times.len() as f64,
            mean_time: times.iter().sum::<f64>() / times.len() as f64,
            entries: times.len(),
        })
    }
}

/// ∫ dθ/|g| from `u` to the exit end (`hi` when `up`), 1/g constant on each
/// cell of width `w` from `lo`.
fn time_to_exit(g: &[f64], lo: f64, w: f64, u: f64, up: bool) -> f64 {
    let i0 = (((u - lo) / w) as usize).min(g.len() - 1);
    let cell_lo = lo + i0 as f64 * w;
    if up {
        let part = (cell_lo + w - u) / g[i0].abs();
        part + g[i0 + 1..].iter().map(|v| w / v.abs()).sum::<f64>()
    } else {
        let part = (u - cell_lo) / g[i0].abs();
        part + g[..i0].iter().map(|v| w / v.abs()).sum::<f64>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_creep_interval_ends_at_the_critical_angles_and_the_exit_arc() {
        // κ = 50, γ = 6.5: θc = 0.4090 (docs/model.md).
        let (lo, hi) = creep_interval(50.0, 6.5, 1.4, 0.1).expect("creep at 0.1");
        assert!(
            (hi - 0.4090).abs() < 1e-4 && (lo + 0.4090).abs() < 1e-4,
            "{lo} {hi}"
        );
        assert!(creep_interval(50.0, 6.5, 1.4, 0.6).is_none());
        // Pure creep: the whole exit arc, of width π.
        let (lo, hi) = creep_interval(3.0, 0.5, 0.3, 0.3).expect("creep");
        assert!((hi - lo - PI).abs() < 1e-12);
    }

    #[test]
    fn the_passage_integral_of_a_constant_gap_is_length_over_gap() {
        let g = vec![0.01; 10];
        // Cells of 0.05 from 0: from 0.125 to 0.5 at 0.01 per iterate.
        assert!((time_to_exit(&g, 0.0, 0.05, 0.125, true) - 37.5).abs() < 1e-9);
        assert!((time_to_exit(&g, 0.0, 0.05, 0.125, false) - 12.5).abs() < 1e-9);
    }
}
