//! The one period detector every consumer uses (orbits, the phase grid, the
//! sweeps, the window's iterates), and the test that an orbit is contracting
//! onto a cycle too slowly to wait for, so that the cycle is solved instead
//! (`super::cycles`). [`PeriodWatch`] makes the same decisions as
//! [`settled_period`] for a growing sequence, at O(1) amortised cost a
//! value.

use crate::model::wrap_angle;

mod watch;

pub use watch::{PeriodWatch, WINDOW_MAX};

/// The longest period looked for.
pub const PERIOD_MAX: usize = 64;

/// The window a period is accepted on, at least: max(3p, this) values (or
/// all of them in a shorter sequence).
pub const MIN_WINDOW: usize = 24;

/// A divisor q of a candidate period whose residual is within this factor of
/// the tolerance means the orbit is still converging onto period q.
pub const DIVISOR_MARGIN: f64 = 10.0;

/// How far the last `w` values of `thetas` are from repeating with period p:
/// the largest distance (as angles) of a value from the one a whole number
/// of periods before it at the window's start. `None` if fewer than `w`
/// values, or a window shorter than one period.
pub fn period_residual(thetas: &[f64], p: usize, w: usize) -> Option<f64> {
    let n = thetas.len();
    if n < w || w < p || p == 0 {
        return None;
    }
    let s = n - w;
    Some(
        (s + p..n)
            .map(|i| wrap_angle(thetas[i] - thetas[s + (i - s) % p]).abs())
            .fold(0.0, f64::max),
    )
}

/// The window period p is tested on in a sequence of `n` values:
/// max(3p, [`MIN_WINDOW`]), or all `n` values when fewer; `None` when that
/// does not show the repeat twice (fewer than 2p values).
pub fn period_window(p: usize, n: usize) -> Option<usize> {
    let w = (3 * p).max(MIN_WINDOW).min(n);
    (w >= 2 * p).then_some(w)
}

/// The longest period a sequence of `n` values can reveal.
pub fn longest_testable(n: usize) -> usize {
    PERIOD_MAX.min(n / 2)
}

/// The smallest period p ≤ 64 that the end of `thetas` has settled on: on
/// its window ([`period_window`]), the residual of p ([`period_residual`])
/// is ≤ `tol`, and that of every proper divisor q of p is above
/// [`DIVISOR_MARGIN`]·`tol`.
///
/// Comparing with the window's start (not with the previous period) makes a
/// slow drift fail. The divisor margin is there because an orbit converging
/// onto a fixed point passes the test of a multiple of its period first (its
/// lag across the window is shorter): with multiplier −0.77 the period-2
/// residual is about the distance d to the fixed point while the period-1
/// residual is 1.77 d; such an orbit is given more iterates instead.
pub fn settled_period(thetas: &[f64], tol: f64) -> Option<usize> {
    let n = thetas.len();
    (1..=longest_testable(n)).find(|&p| {
        let Some(w) = period_window(p, n) else {
            return false;
        };
        match period_residual(thetas, p, w) {
            Some(r) if r <= tol => (1..p)
                .filter(|q| p.is_multiple_of(*q))
                .all(|q| period_residual(thetas, q, w).is_some_and(|rq| rq > DIVISOR_MARGIN * tol)),
            _ => false,
        }
    })
}

/// The longest period whose slow approach is looked for: four whole periods
/// of geometric contraction must be seen, and long cycles close to a
/// bifurcation are rare enough to be left to the period test.
pub const CONTRACTION_PERIOD_MAX: usize = 16;

/// An orbit contracting geometrically onto a p-cycle: every p-th difference
/// shrinks by `ratio` (the cycle's multiplier, estimated), towards `limit`
/// (Aitken's Δ² from the newest value).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contraction {
    pub period: usize,
    pub ratio: f64,
    pub limit: f64,
}

/// Whether the end of `seq` contracts geometrically onto a cycle, for the
/// smallest p ≤ [`CONTRACTION_PERIOD_MAX`] that does: the last four
/// p-differences are all above `noise` (below it the map's own error would
/// decide the ratios), their three ratios agree within 5 % with |ratio| in
/// [0.5, 1) (slow: a faster approach settles by itself in a few periods; a
/// chaotic orbit's ratios do not agree), and the extrapolated limit is
/// within 0.1 rad.
///
/// An orbit slowly closing in on a 2p-cycle has p-ratios near −1 that may
/// agree as well (the cycle's two halves alternate, the approach is a small
/// change on top). A true p-contraction of ratio r ≈ −1 has 2p-ratios r²;
/// where the 2p-differences contract with another ratio, the orbit is
/// closing in on the 2p-cycle, and p is passed over for it.
pub fn contraction(seq: &[f64], noise: f64) -> Option<Contraction> {
    (1..=CONTRACTION_PERIOD_MAX).find_map(|p| {
        let c = contraction_at(seq, p, noise)?;
        let r2 = c.ratio * c.ratio;
        let doubled = c.ratio < -0.8
            && contraction_at(seq, 2 * p, noise).is_some_and(|d| (d.ratio - r2).abs() > 0.05 * r2);
        (!doubled).then_some(c)
    })
}

/// [`contraction`]'s test at the period p alone.
fn contraction_at(seq: &[f64], p: usize, noise: f64) -> Option<Contraction> {
    let m = seq.len();
    if m < 4 * p + 1 {
        return None;
    }
    let last = m - 1;
    // d[0] is the newest difference.
    let d: [f64; 4] =
        std::array::from_fn(|k| wrap_angle(seq[last - k * p] - seq[last - (k + 1) * p]));
    if d.iter().any(|x| x.abs() <= noise) {
        return None;
    }
    let r: [f64; 3] = std::array::from_fn(|k| d[k] / d[k + 1]);
    let r0 = r[0];
    let consistent = r.iter().all(|x| (x - r0).abs() <= 0.05 * r0.abs());
    if !consistent || !(0.5..1.0).contains(&r0.abs()) {
        return None;
    }
    let jump = d[0] * r0 / (1.0 - r0);
    (jump.abs() < 0.1).then(|| Contraction {
        period: p,
        ratio: r0,
        limit: wrap_angle(seq[last] + jump),
    })
}

/// How near (radians) a slowly contracting orbit's p-differences must
/// have come to 0 to be taken for closing in on a p-cycle ([`closing_in`]).
pub const CLOSING: f64 = 1e-4;

/// The p-cycle that `thetas` (kept iterates) close in on, if they do: for
/// the least p ≤ [`PERIOD_MAX`] with three periods' worth of kept
/// iterates, the largest p-difference over each of the last three periods
/// shrinks period by period (ratio r < 0.95 both times) and the last is
/// under [`CLOSING`]. Its
/// points are the last period's, extrapolated to the limit (each moved by
/// its last p-difference times r/(1 − r)), in the order of the last p of
/// `thetas`. A slowly settling column (Fig. 3b's P24 at θν ≈ 1.2286,
/// multiplier 0.66, still 1e-6 off after 600 iterates) is then that cycle,
/// not a chaotic set (`sim::seeded`), and its λ the cycle's
/// (`sim::column_lyapunov`); chaos never shrinks so for three periods
/// under 1e-4. Unlike [`contraction`] it needs no agreeing ratios, and
/// reaches periods up to [`PERIOD_MAX`].
pub fn closing_in(thetas: &[f64]) -> Option<Vec<f64>> {
    let n = thetas.len();
    let step = |i: usize, p: usize| wrap_angle(thetas[i] - thetas[i - p]);
    (1..=PERIOD_MAX.min(n / 4)).find_map(|p| {
        let widest = |k: usize| {
            let end = n - k * p;
            (end - p..end).map(|i| step(i, p).abs()).fold(0.0, f64::max)
        };
        let (e0, e1, e2) = (widest(0), widest(1), widest(2));
        let (r1, r2) = (e0 / e1, e1 / e2);
        if !(e0 < CLOSING && r1 < 0.95 && r2 < 0.95) {
            return None;
        }
        let r = r1.max(r2);
        let limit = (n - p..n).map(|i| thetas[i] + step(i, p) * r / (1.0 - r));
        Some(limit.collect())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_smallest_period() {
        let p3: Vec<f64> = (0..60).map(|i| [0.1, 0.5, -0.2][i % 3]).collect();
        assert_eq!(settled_period(&p3, 1e-6), Some(3));
        let fixed = vec![0.3; 10];
        assert_eq!(settled_period(&fixed, 1e-12), Some(1));
        let chaos: Vec<f64> = (0..200).map(|i| (i as f64 * 1.234567).sin()).collect();
        assert_eq!(settled_period(&chaos, 1e-6), None);
        // Across the ±π seam a fixed point is still a fixed point.
        let seam = vec![
            std::f64::consts::PI - 1e-12,
            -std::f64::consts::PI + 1e-12,
            std::f64::consts::PI,
        ];
        assert_eq!(settled_period(&seam, 1e-9), Some(1));
        assert_eq!(longest_testable(10), 5);
    }

    #[test]
    fn settled_period_needs_a_whole_window_without_drift() {
        let p3: Vec<f64> = (0..40).map(|i| [0.1, 0.5, -0.2][i % 3]).collect();
        assert_eq!(settled_period(&p3, 1e-9), Some(3));
        assert_eq!(settled_period(&p3[..5], 1e-9), None);
        // A fixed point approached with multiplier −0.99: the period-2 test
        // between neighbours passes long before the orbit has settled, the
        // drift test does not.
        let mut x = 1e-5;
        let flip: Vec<f64> = (0..40)
            .map(|_| {
                x *= -0.99;
                0.3 + x
            })
            .collect();
        assert_eq!(settled_period(&flip, 1e-6), None);
        let drift: Vec<f64> = (0..40).map(|i| 0.3 + 1e-7 * i as f64).collect();
        assert_eq!(settled_period(&drift, 1e-6), None);
        assert_eq!(settled_period(&drift, 1e-5), Some(1));
        // Converging with multiplier −0.77: period 2 passes before period 1
        // does, but period 1 is within the divisor margin, so wait.
        let alt = |n: usize| -> Vec<f64> {
            let mut x = 5e-6;
            (0..n)
                .map(|_| {
                    x *= -0.77;
                    0.3 + x
                })
                .collect()
        };
        assert_eq!(
            period_residual(&alt(40), 2, 24).map(|r| r <= 1e-7),
            Some(true)
        );
        assert_eq!(settled_period(&alt(40), 1e-7), None);
        assert_eq!(settled_period(&alt(60), 1e-7), Some(1));
    }

    #[test]
    fn contraction_sees_a_slow_geometric_approach_only() {
        // Multiplier 0.999 towards 0.4: Aitken's limit is the fixed point.
        let seq: Vec<f64> = (0..12).map(|i| 0.4 + 1e-2 * 0.999f64.powi(i)).collect();
        let c = contraction(&seq, 1e-9).expect("a clean geometric approach");
        assert_eq!(c.period, 1);
        assert!((c.ratio - 0.999).abs() < 1e-9, "{}", c.ratio);
        assert!((c.limit - 0.4).abs() < 1e-10, "{}", c.limit);
        // A flip (multiplier −0.98) is period 1 too.
        let flip: Vec<f64> = (0..12).map(|i| 0.4 + 1e-3 * (-0.98f64).powi(i)).collect();
        assert_eq!(contraction(&flip, 1e-9).map(|c| c.period), Some(1));
        // A period-2 orbit approached slowly: its 1-differences do not
        // contract (ratio ≈ −1 but growing in size is refused) and the
        // 2-differences do.
        let p2: Vec<f64> = (0..20)
            .map(|i| [0.1, 0.5][i % 2] + 1e-3 * 0.9f64.powi(i as i32 / 2))
            .collect();
        assert_eq!(contraction(&p2, 1e-9).map(|c| c.period), Some(2));
        // Closing in on a 2-cycle near its own flip (multiplier −0.9985,
        // as at Fig. 3b's θν = 1.1929): the 1-ratios are all near −0.99
        // and agree, but the 2-ratios are −0.9985, not their square.
        let p2flip: Vec<f64> = (0..40)
            .map(|i| [0.3684, 0.4637][i % 2] + 1e-3 * (-0.9985f64).powi(i as i32 / 2))
            .collect();
        let c = contraction(&p2flip, 1e-9).expect("a slow approach");
        assert_eq!(c.period, 2, "{c:?}");
        assert!((c.ratio + 0.9985).abs() < 1e-9, "{c:?}");
        let flip: Vec<f64> = (0..40).map(|i| 0.4 + 1e-3 * (-0.98f64).powi(i)).collect();
        assert_eq!(contraction(&flip, 1e-9).map(|c| c.period), Some(1));
        // A fast approach settles by itself; chaos is not geometric; the
        // map's noise is not a contraction.
        let fast: Vec<f64> = (0..12).map(|i| 0.4 + 1e-2 * 0.1f64.powi(i)).collect();
        assert_eq!(contraction(&fast, 1e-30), None);
        let ch: Vec<f64> = (0..40).map(|i| (i as f64 * 1.234567).sin()).collect();
        assert_eq!(contraction(&ch, 1e-9), None);
        let flat: Vec<f64> = (0..12).map(|i| 0.4 + 1e-12 * 0.9f64.powi(i)).collect();
        assert_eq!(contraction(&flat, 1e-10), None);
    }
}

/// The residual of a near repeat, relative to the spread of the window it
/// is measured on, below which an orbit is worth solving as a p-cycle.
pub const NEAR_REPEAT: f64 = 0.05;

/// The period p ≤ [`CONTRACTION_PERIOD_MAX`] with which the end of
/// `thetas` nearly repeats, when it does: the smallest p whose residual
/// ([`period_residual`] on the last 2·16 values) is within twice the
/// least of all and below [`NEAR_REPEAT`] times the window's spread. An
/// orbit drifting slowly along a cycle (leaving an unstable fixed point
/// just past a flip, or approaching a cycle with multiplier near 1) nearly
/// repeats long before it settles, and neither [`settled_period`] nor
/// [`contraction`] accepts it; a chaotic orbit has no such p.
pub fn near_period(thetas: &[f64]) -> Option<usize> {
    let w = 2 * CONTRACTION_PERIOD_MAX;
    let n = thetas.len();
    if n < w {
        return None;
    }
    let window = &thetas[n - w..];
    let lo = window.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = window.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let spread = hi - lo;
    if !(spread > 0.0) {
        return None;
    }
    let residuals: Vec<f64> = (1..=CONTRACTION_PERIOD_MAX)
        .map(|p| period_residual(thetas, p, w).unwrap_or(f64::INFINITY))
        .collect();
    let least = residuals.iter().copied().fold(f64::INFINITY, f64::min);
    if !(least <= NEAR_REPEAT * spread) {
        return None;
    }
    (1..=CONTRACTION_PERIOD_MAX).find(|&p| residuals[p - 1] <= 2.0 * least)
}

#[cfg(test)]
mod near_tests {
    use super::*;

    #[test]
    fn a_slowly_growing_two_cycle_nearly_repeats_with_period_two() {
        // Leaving a fixed point at 0.3 with multiplier −1.003.
        let thetas: Vec<f64> = (0..200)
            .map(|i| 0.3 + 1e-4 * 1.003f64.powi(i) * if i % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        assert_eq!(near_period(&thetas), Some(2));
        assert_eq!(settled_period(&thetas, 1e-6), None);
    }

    #[test]
    fn the_logistic_maps_chaos_does_not() {
        let mut x = 0.3;
        let thetas: Vec<f64> = (0..200)
            .map(|_| {
                x = 4.0 * x * (1.0 - x);
                x
            })
            .collect();
        assert_eq!(near_period(&thetas), None);
    }
}
