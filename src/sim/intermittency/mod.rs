//! Intermittency statistics of an orbit (the paper's Fig. 3a family, θν ≈
//! 1.4 at κ = 50): the block creeps for a while, its onsets drifting slowly
//! through the creep arc, then stick-slip slips re-inject it. A slip is
//! creep or stick-slip by where it starts, the model's own criterion
//! (creep on the part of C where γ² < A(θ) = κ cos²θ + sin²θ, i.e.
//! κ³x0² + y0² > γ²), never by its size. From the kept events (the
//! transient already dropped) this module gives
//!
//! - the *laminar lengths*: each run of consecutive creep slips between two
//!   stick-slip slips (the run before the first stick-slip slip and after
//!   the last one is cut off by the window and not counted; two stick-slip
//!   slips in a row enclose no laminar phase);
//! - the slip-size distribution in logarithmic bins (sizes are only
//!   described, never used to tell creep from stick-slip);
//! - [`channel`]: the passage time through the channel between f and the
//!   diagonal on the creep arc, computed from f itself, to set beside the
//!   mean laminar length;
//! - [`tangency`]: a tangency located by continuation (the fold of a
//!   periodic window's cycle), and the mean laminar length against the
//!   distance ε to it, fitted on log–log axes beside type-I
//!   intermittency's ⟨ℓ⟩ ∝ ε^(−1/2); where no tangency is found, no fit.

pub mod channel;
pub mod tangency;

pub use channel::{Passage, PassageRun, creep_interval, passage};
pub use tangency::{ScalePoint, Scaling, ScalingRun, Tangency, find_tangency, scaling};

use super::SlipEvent;
use super::stats::mean_and_stderr;
use crate::model::{OnsetCharacter, onset_character};

/// Type-I intermittency's exponent: ⟨ℓ⟩ ∝ ε^(−1/2).
pub const TYPE_ONE_SLOPE: f64 = -0.5;

/// How far a fitted slope may lie from [`TYPE_ONE_SLOPE`] and still be said
/// to support it.
pub const SLOPE_TOLERANCE: f64 = 0.15;

/// Whether each onset in `onsets` starts a creep slip (for κ and γ).
pub fn creep_flags(kappa: f64, gamma: f64, onsets: impl IntoIterator<Item = f64>) -> Vec<bool> {
    onsets
        .into_iter()
        .map(|th| onset_character(kappa, gamma, th) == OnsetCharacter::Creep)
        .collect()
}

/// The laminar lengths of a sequence of slips (`true` = creep): the length
/// of every run of consecutive creep slips that has a stick-slip slip on
/// both sides, in order.
pub fn laminar_lengths(creep: &[bool]) -> Vec<usize> {
    let mut out = Vec::new();
    // The creep run since the last stick-slip slip; `None` before the first.
    let mut run: Option<usize> = None;
    for &c in creep {
        if c {
            if let Some(n) = run.as_mut() {
                *n += 1;
            }
        } else {
            if let Some(n) = run.filter(|&n| n > 0) {
                out.push(n);
            }
            run = Some(0);
        }
    }
    out
}

/// How many slips are creep and how many stick-slip by the model's own
/// criterion: by where each starts, creep on the part of C where
/// γ² < A(θ) = κ cos²θ + sin²θ ([`crate::model::onset_character`]), not by
/// its size. Pure creep has only creep, pure stick-slip only stick-slip.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OnsetCounts {
    /// Slips starting on the creep arc.
    pub creep: usize,
    /// Slips starting on the stick-slip arc.
    pub stick_slip: usize,
}

impl OnsetCounts {
    /// The counts of slips starting at `onsets` for κ and γ.
    pub fn of(kappa: f64, gamma: f64, onsets: impl IntoIterator<Item = f64>) -> Self {
        Self::of_flags(&creep_flags(kappa, gamma, onsets))
    }

    /// The counts of slips flagged creep (`true`) or stick-slip.
    pub fn of_flags(creep: &[bool]) -> Self {
        let n = creep.iter().filter(|c| **c).count();
        OnsetCounts {
            creep: n,
            stick_slip: creep.len() - n,
        }
    }

    /// "N creep, M stick-slip".
    pub fn describe(&self) -> String {
        format!("{} creep, {} stick-slip", self.creep, self.stick_slip)
    }
}
/// (length, how many laminar phases had it), by increasing length.
pub fn length_counts(lengths: &[usize]) -> Vec<(usize, usize)> {
    let mut sorted = lengths.to_vec();
    sorted.sort_unstable();
    let mut out: Vec<(usize, usize)> = Vec::new();
    for l in sorted {
        match out.last_mut() {
            Some((k, c)) if *k == l => *c += 1,
            _ => out.push((l, 1)),
        }
    }
    out
}

/// One bin of a histogram: `[lo, hi)` (the last bin includes `hi`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bin {
    pub lo: f64,
    pub hi: f64,
    pub count: usize,
}

/// Sizes whose log10 spread is below this (a ratio of 1.01) are binned as
/// one size by [`log_histogram`].
pub const MIN_LOG_SPAN: f64 = 0.004_3;

/// The positive finite `xs` in `bins` bins of equal width in log10 between
/// their smallest and largest value; empty when there is none.
pub fn log_histogram(xs: &[f64], bins: usize) -> Vec<Bin> {
    let pos: Vec<f64> = xs
        .iter()
        .copied()
        .filter(|x| x.is_finite() && *x > 0.0)
        .collect();
    if pos.is_empty() || bins == 0 {
        return Vec::new();
    }
    let lo = pos.iter().copied().fold(f64::INFINITY, f64::min).log10();
    let hi = pos
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max)
        .log10();
    // Sizes that differ by less than 1 % (one value, or a periodic orbit's
    // sizes still converging in their last digits) are one size: one bin
    // a tenth of a decade wide, not their rounding spread over every bin.
    let (lo, hi, bins) = if hi - lo < MIN_LOG_SPAN {
        let mid = 0.5 * (lo + hi);
        (mid - 0.05, mid + 0.05, 1)
    } else {
        (lo, hi, bins)
    };
    let w = (hi - lo) / bins as f64;
    let mut counts = vec![0usize; bins];
    for x in pos {
        let i = ((x.log10() - lo) / w) as usize;
        counts[i.min(bins - 1)] += 1;
    }
    counts
        .into_iter()
        .enumerate()
        .map(|(i, count)| Bin {
            lo: 10f64.powf(lo + i as f64 * w),
            hi: 10f64.powf(lo + (i + 1) as f64 * w),
            count,
        })
        .collect()
}

/// The statistics of one orbit's kept slips.
#[derive(Clone, Debug, PartialEq)]
pub struct Intermittency {
    /// Creep and stick-slip slips, by where each starts.
    pub onsets: OnsetCounts,
    /// Every complete laminar phase's length (creep slips), in order.
    pub laminar: Vec<usize>,
    /// Their mean and its standard error by batch means (`None` without
    /// any; the error also below 16 phases).
    pub mean_laminar: Option<f64>,
    pub mean_laminar_stderr: Option<f64>,
    /// The slip-size distribution in logarithmic bins.
    pub sizes: Vec<Bin>,
}

/// Bins of the slip-size distribution.
pub const SIZE_BINS: usize = 30;

/// The fewest complete laminar phases, and their least mean length, for an
/// orbit to be called intermittent: a creep/stick-slip alternation has
/// phases of length 1, a periodic orbit the same length over and over.
pub const MIN_PHASES: usize = 3;
pub const MIN_MEAN_LENGTH: f64 = 2.0;

/// The longest repeat period of the laminar lengths [`Regime`] looks for.
pub const MAX_REPEAT: usize = 16;

/// The smallest q ≤ [`MAX_REPEAT`] with `ls[i] == ls[i + q]` for every i,
/// when the sequence holds at least three repeats of it.
pub fn repeat_period(ls: &[usize]) -> Option<usize> {
    (1..=MAX_REPEAT)
        .take_while(|q| 3 * q <= ls.len())
        .find(|&q| ls.iter().zip(&ls[q..]).all(|(a, b)| a == b))
}

/// What the kept slips say about intermittency.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Regime {
    /// Every slip is stick-slip: no creep between them (periodic or
    /// chaotic stick-slip).
    NoCreep,
    /// Every slip is creep but one or none: no laminar phase ends.
    NoStickSlip,
    /// Fewer than [`MIN_PHASES`] complete laminar phases in the window.
    TooFewPhases,
    /// Stick-slip slips with at most a creep slip or two between them
    /// (mean laminar length below [`MIN_MEAN_LENGTH`]).
    Alternating,
    /// The laminar lengths repeat with a short period (`every` phases; the
    /// first length `first`): a periodic orbit.
    Periodic { every: usize, first: usize },
    /// Laminar phases of varying length, long on average.
    Intermittent,
}

impl Regime {
    /// Whether the laminar statistics mean something.
    pub fn is_intermittent(self) -> bool {
        self == Regime::Intermittent
    }

    /// A few words for a summary line.
    pub fn describe(self) -> String {
        match self {
            Regime::NoCreep => "not intermittent: every slip is stick-slip, no creep".into(),
            Regime::NoStickSlip => {
                "not intermittent: every slip is creep, no stick-slip slips end a laminar phase"
                    .into()
            }
            Regime::TooFewPhases => {
                format!("too few laminar phases to tell (under {MIN_PHASES}): keep more events")
            }
            Regime::Alternating => format!(
                "not intermittent: stick-slip slips with under {MIN_MEAN_LENGTH} creep slips between them"
            ),
            Regime::Periodic { every: 1, first } => {
                format!("not intermittent: periodic, every laminar phase {first} creep slips long")
            }
            Regime::Periodic { every, .. } => {
                format!(
                    "not intermittent: periodic, the laminar lengths repeat every {every} phases"
                )
            }
            Regime::Intermittent => "intermittent".into(),
        }
    }

    /// Why an orbit is not intermittent, in a few words.
    pub fn short_reason(self) -> &'static str {
        match self {
            Regime::NoCreep => "not intermittent: no creep",
            Regime::NoStickSlip => "not intermittent: all creep",
            Regime::TooFewPhases => "too few laminar phases",
            Regime::Alternating => "not intermittent: alternating",
            Regime::Periodic { .. } => "not intermittent: periodic",
            Regime::Intermittent => "intermittent",
        }
    }
}

impl Intermittency {
    /// The statistics of an orbit's slips `events` at κ and γ, told by
    /// where each starts and sized by its slip distance, and where the
    /// first creep slip starts (the creep channel's entry, for the
    /// passage), if there is one.
    pub fn of_events(kappa: f64, gamma: f64, events: &[SlipEvent]) -> (Intermittency, Option<f64>) {
        let creep = creep_flags(kappa, gamma, events.iter().map(|e| e.theta));
        let sizes: Vec<f64> = events.iter().map(|e| e.slip_distance).collect();
        let first_creep = events
            .iter()
            .zip(&creep)
            .find(|(_, c)| **c)
            .map(|(e, _)| e.theta);
        (Intermittency::of(&creep, &sizes), first_creep)
    }

    /// The statistics of slips flagged creep (`true`) or stick-slip by
    /// where each starts, with their `sizes` (the transient already
    /// dropped; the two slices in step).
    pub fn of(creep: &[bool], sizes: &[f64]) -> Intermittency {
        let laminar = laminar_lengths(creep);
        let ls: Vec<f64> = laminar.iter().map(|&l| l as f64).collect();
        let (mean, err) = mean_and_stderr(&ls);
        Intermittency {
            onsets: OnsetCounts::of_flags(creep),
            laminar,
            mean_laminar: mean,
            mean_laminar_stderr: err,
            sizes: log_histogram(sizes, SIZE_BINS),
        }
    }

    /// Whether these slips are intermittent, and if not, why.
    pub fn regime(&self) -> Regime {
        if self.onsets.creep == 0 {
            return Regime::NoCreep;
        }
        if self.onsets.stick_slip < 2 {
            return Regime::NoStickSlip;
        }
        if self.laminar.len() < MIN_PHASES {
            return Regime::TooFewPhases;
        }
        if self.mean_laminar.is_none_or(|m| m < MIN_MEAN_LENGTH) {
            return Regime::Alternating;
        }
        match repeat_period(&self.laminar) {
            Some(every) => Regime::Periodic {
                every,
                first: self.laminar[0],
            },
            None => Regime::Intermittent,
        }
    }

    /// The statistics as CSV: `#` lines with the summary (the laminar line
    /// ends with `source`, then one line per `notes` entry, then the
    /// verdict), then `statistic,lo,hi,count` rows: `laminar_length`
    /// (lo = hi = the length) and `slip_size` (the bin's ends).
    pub fn csv(&self, measure: &str, source: &str, notes: &[String]) -> String {
        use std::fmt::Write as _;
        let mut s = String::new();
        let opt = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
        writeln!(
            s,
            "# {}: by where each slip starts (creep where gamma^2 < kappa cos^2 theta + sin^2 theta)",
            self.onsets.describe()
        )
        .ok();
        writeln!(
            s,
            "# laminar phase: a run of creep slips between two stick-slip slips; \
             {} complete laminar phases, mean length {} +- {}; size: {measure}{source}",
            self.laminar.len(),
            opt(self.mean_laminar),
            opt(self.mean_laminar_stderr),
        )
        .ok();
        for n in notes {
            writeln!(s, "# {n}").ok();
        }
        writeln!(s, "# {}", self.regime().describe()).ok();
        s.push_str("statistic,lo,hi,count\n");
        for (l, c) in length_counts(&self.laminar) {
            writeln!(s, "laminar_length,{l},{l},{c}").ok();
        }
        for b in &self.sizes {
            writeln!(s, "slip_size,{},{},{}", b.lo, b.hi, b.count).ok();
        }
        s
    }
}

/// The least-squares line through (log10 x, log10 y) of the points with
/// positive finite coordinates: (slope, intercept), or `None` with fewer
/// than three such points or no spread in x.
pub fn log_log_fit(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.log10(), y.log10()))
        .collect();
    if pts.len() < 3 {
        return None;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    Some((slope, my - slope * mx))
}

/// Whether a fitted slope supports type-I intermittency.
pub fn supports_type_one(slope: f64) -> bool {
    (slope - TYPE_ONE_SLOPE).abs() <= SLOPE_TOLERANCE
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ends_of_the_window_are_not_laminar_phases() {
        let (c, s) = (true, false);
        // A creep run cut by the window's start, phases of 2 and 1, two
        // stick-slip slips in a row (no phase), a run cut by its end.
        let seq = [c, c, s, c, c, s, c, s, s, c, c];
        assert_eq!(laminar_lengths(&seq), vec![2, 1]);
        assert!(laminar_lengths(&[c, c, c]).is_empty());
        assert!(laminar_lengths(&[s, s, s]).is_empty());
    }

    #[test]
    fn log_bins_cover_the_values_once() {
        let xs = [1e-3, 2e-3, 1e-2, 0.5, 0.8, 0.0, f64::NAN];
        let b = log_histogram(&xs, 6);
        assert_eq!(b.iter().map(|b| b.count).sum::<usize>(), 5);
        assert!((b[0].lo - 1e-3).abs() < 1e-15);
        assert!((b[5].hi - 0.8).abs() < 1e-12);
        for w in b.windows(2) {
            assert!((w[0].hi - w[1].lo).abs() < 1e-12 * w[1].lo);
        }
    }
}
