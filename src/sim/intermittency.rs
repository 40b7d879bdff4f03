//! Intermittency statistics of an orbit (the paper's Fig. 3a family, θν ≈
//! 1.4 at κ = 50): the orbit creeps for a while, then one large slip
//! re-injects it. From the slip sizes of the kept events (the transient
//! already dropped) this module gives
//!
//! - which slips are *large*: size ≥ [`LARGE_FRACTION`] × the largest size
//!   of the run. The slip distances are bimodal on the intermittent orbit
//!   (θν = 1.4): creep slips of ≈ 3e-3 that grow to at most ≈ 0.08 just
//!   before a re-injection, and large ones of 0.6–0.8; a quarter of the
//!   largest (≈ 0.2) sits in the gap, a factor ≈ 2.5 from either side;
//! - the *laminar lengths*: the number of creep slips between two
//!   consecutive large ones (the run before the first large slip and after
//!   the last one is cut off by the window and not counted);
//! - the slip-size distribution in logarithmic bins;
//! - the mean laminar length against the distance to a critical θν, with a
//!   least-squares slope on log–log axes to set beside type-I
//!   intermittency's ⟨ℓ⟩ ∝ |θν − θν_c|^(−1/2).

use super::stats::mean_and_stderr;

/// A slip is large when its size is at least this fraction of the largest.
pub const LARGE_FRACTION: f64 = 0.25;

/// Type-I intermittency's exponent: ⟨ℓ⟩ ∝ ε^(−1/2).
pub const TYPE_ONE_SLOPE: f64 = -0.5;

/// How far a fitted slope may lie from [`TYPE_ONE_SLOPE`] and still be said
/// to support it.
pub const SLOPE_TOLERANCE: f64 = 0.15;

/// The large-slip threshold of `sizes`: [`LARGE_FRACTION`] of the largest
/// finite size, or `None` when there is no positive finite size.
pub fn large_threshold(sizes: &[f64]) -> Option<f64> {
    let max = sizes
        .iter()
        .copied()
        .filter(|s| s.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    (max > 0.0).then_some(LARGE_FRACTION * max)
}

/// The laminar lengths of `sizes` for a large-slip `threshold`: the number
/// of slips below it between each two consecutive slips at or above it.
pub fn laminar_lengths(sizes: &[f64], threshold: f64) -> Vec<usize> {
    let mut out = Vec::new();
    let mut run: Option<usize> = None;
    for &s in sizes {
        if s >= threshold {
            if let Some(n) = run {
                out.push(n);
            }
            run = Some(0);
        } else if let Some(n) = run.as_mut() {
            *n += 1;
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
        use crate::model::{OnsetCharacter, onset_character};
        let mut c = OnsetCounts {
            creep: 0,
            stick_slip: 0,
        };
        for th in onsets {
            match onset_character(kappa, gamma, th) {
                OnsetCharacter::Creep => c.creep += 1,
                OnsetCharacter::StickSlip => c.stick_slip += 1,
            }
        }
        c
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
    /// The large-slip threshold used (same unit as the sizes).
    pub threshold: f64,
    /// Slips at or above the threshold, and below it.
    pub large: usize,
    pub creep: usize,
    /// Every complete laminar phase's length, in order.
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
/// orbit to be called intermittent: a creep fixed point has phases of
/// length 0, a creep/slip alternation of 1, a periodic orbit the same
/// length over and over.
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
    /// Every slip is large: no creep between them (stick-slip, periodic
    /// or chaotic).
    NoCreep,
    /// Every slip is a creep slip but one or none: no laminar phase ends.
    NoLargeSlips,
    /// Fewer than [`MIN_PHASES`] complete laminar phases in the window.
    TooFewPhases,
    /// Large slips with at most a creep slip or two between them (mean
    /// laminar length below [`MIN_MEAN_LENGTH`]).
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
            Regime::NoCreep => {
                "not intermittent: every slip is large, no small slips between them".into()
            }
            Regime::NoLargeSlips => {
                "not intermittent: no large slips between the small ones".into()
            }
            Regime::TooFewPhases => {
                format!("too few laminar phases to tell (under {MIN_PHASES}): keep more events")
            }
            Regime::Alternating => format!(
                "not intermittent: large slips with under {MIN_MEAN_LENGTH} creep slips between them"
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
}

impl Intermittency {
    /// The statistics of `sizes` (the transient already dropped), with the
    /// threshold [`large_threshold`] unless one is given.
    pub fn of(sizes: &[f64], threshold: Option<f64>) -> Option<Intermittency> {
        let threshold = threshold.or_else(|| large_threshold(sizes))?;
        let laminar = laminar_lengths(sizes, threshold);
        let large = sizes.iter().filter(|s| **s >= threshold).count();
        let ls: Vec<f64> = laminar.iter().map(|&l| l as f64).collect();
        let (mean, err) = mean_and_stderr(&ls);
        Some(Intermittency {
            threshold,
            large,
            creep: sizes.len() - large,
            laminar,
            mean_laminar: mean,
            mean_laminar_stderr: err,
            sizes: log_histogram(sizes, SIZE_BINS),
        })
    }

    /// Whether these slips are intermittent, and if not, why.
    pub fn regime(&self) -> Regime {
        if self.creep == 0 {
            return Regime::NoCreep;
        }
        if self.large < 2 {
            return Regime::NoLargeSlips;
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

    /// The statistics as CSV: `#` lines with the summary, then
    /// `statistic,lo,hi,count` rows: `laminar_length` (lo = hi = the
    /// length) and `slip_size` (the bin's ends).
    pub fn csv(&self, measure: &str) -> String {
        use std::fmt::Write as _;
        let mut s = String::new();
        let opt = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
        writeln!(
            s,
            "# large slip: {measure} >= {} ({LARGE_FRACTION} x the largest); \
             {} large, {} small; {} complete laminar phases, mean length {} +- {}",
            self.threshold,
            self.large,
            self.creep,
            self.laminar.len(),
            opt(self.mean_laminar),
            opt(self.mean_laminar_stderr),
        )
        .ok();
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

/// The mean laminar length against the distance to the critical θν.
#[derive(Clone, Debug, PartialEq)]
pub struct Scaling {
    /// The lower end of the intermittent window below the θν scanned from,
    /// to within [`CRITICAL_RESOLUTION`].
    pub theta_nu_c: f64,
    /// (θν − θν_c, mean laminar length), by decreasing distance.
    pub points: Vec<(f64, f64)>,
    /// The least-squares slope and intercept on log–log axes.
    pub fit: Option<(f64, f64)>,
}

impl Scaling {
    /// Whether the points support type-I intermittency's slope −1/2.
    pub fn supports_type_one(&self) -> bool {
        self.fit.is_some_and(|(s, _)| supports_type_one(s))
    }
}

/// How finely [`scaling`] locates θν_c, in radians.
pub const CRITICAL_RESOLUTION: f64 = 1e-3;
/// How far below the θν scanned from [`scaling`] looks for θν_c.
pub const SCAN_SPAN: f64 = 0.4;
/// Distances from θν_c [`scaling`] measures at: (θν − θν_c)·2^−k.
pub const SCAN_POINTS: usize = 7;

/// Whether the orbit at `theta_nu` is intermittent ([`Regime`]), with its
/// mean laminar length.
fn intermittent_at(
    params: crate::model::Params,
    settings: crate::integrate::SolverSettings,
    theta_nu: f64,
    cancel: &dyn Fn() -> bool,
) -> Result<Option<f64>, super::SimError> {
    let p = crate::model::Params { theta_nu, ..params };
    let sim = super::Simulator::new(p, settings)?;
    let opts = super::OrbitOptions {
        transient: 300,
        keep: 2000,
        lyapunov: false,
        period_tol: 1e-6,
    };
    let orbit = sim.orbit(theta_nu, &opts, cancel)?;
    let sizes: Vec<f64> = orbit.events.iter().map(|e| e.slip_distance).collect();
    Ok(Intermittency::of(&sizes, None)
        .filter(|st| st.regime().is_intermittent())
        .and_then(|st| st.mean_laminar))
}

/// The mean laminar length against θν − θν_c below `params.theta_nu`: θν_c
/// is found by bisection between θν − [`SCAN_SPAN`] (not intermittent)
/// and θν (intermittent), then [`SCAN_POINTS`] orbits measure the mean
/// laminar length at θν_c + (θν − θν_c)·2^−k. `None` when θν is not
/// intermittent or the window has no lower end in the span. Each orbit
/// keeps 2000 iterates after 300; `cancel` stops the scan.
pub fn scaling(
    params: crate::model::Params,
    settings: crate::integrate::SolverSettings,
    cancel: &dyn Fn() -> bool,
) -> Result<Option<Scaling>, super::SimError> {
    let top = params.theta_nu;
    if intermittent_at(params, settings, top, cancel)?.is_none() {
        return Ok(None);
    }
    let mut lo = (top - SCAN_SPAN).max(1e-3);
    if intermittent_at(params, settings, lo, cancel)?.is_some() {
        return Ok(None);
    }
    let mut hi = top;
    while hi - lo > CRITICAL_RESOLUTION {
        let mid = 0.5 * (lo + hi);
        if intermittent_at(params, settings, mid, cancel)?.is_some() {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let theta_nu_c = 0.5 * (lo + hi);
    let mut points = Vec::new();
    for k in 0..SCAN_POINTS {
        let eps = (top - theta_nu_c) * 0.5f64.powi(k as i32);
        if eps < 2.0 * CRITICAL_RESOLUTION {
            break;
        }
        if let Some(m) = intermittent_at(params, settings, theta_nu_c + eps, cancel)? {
            points.push((eps, m));
        }
    }
    let fit = log_log_fit(&points);
    Ok(Some(Scaling {
        theta_nu_c,
        points,
        fit,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ends_of_the_window_are_not_laminar_phases() {
        let s = [0.1, 1.0, 0.1, 0.1, 1.0, 1.0, 0.1];
        assert_eq!(laminar_lengths(&s, 0.5), vec![2, 0]);
        assert!(laminar_lengths(&[0.1, 0.2], 0.5).is_empty());
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
