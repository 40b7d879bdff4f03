//! Which attractor of one column of a parameter range is which of the
//! next: a *track* per attractor followed along the parameter, so that a
//! picture gives it one colour and one legend entry, and a birth or a
//! death is where a track starts or ends.
//!
//! Two attractors of neighbouring columns are one, continued, when each
//! lies in the other's basin (its cycle's points, or its cover's
//! stretches, in no other basin and in the other's at least once) and
//! their kinds can turn into each other as the parameter moves (see
//! [`may_continue`]); of such pairs the ones whose basins overlap most
//! pair up (each the other's best). Basins are unions of arc intervals,
//! so the overlap is exact; no distance in radians decides. A track goes
//! on through a supercritical flip (the born cycle lies round the fixed
//! point, in its basin, and the fixed point in the born cycle's), through
//! a cascade into chaos of as many bands and through band merging, and
//! ends where its attractor's next column has no partner: a fold, a
//! subcritical flip, a crisis (a window's cycle born in a fold out of
//! one-band chaos is a new track, and that chaos ends there).

use super::{Attractor, Found, Verdict};
use crate::model::wrap_angle;

/// One attractor followed along the parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    /// Its number, in the order tracks were started (a colour's index).
    pub id: usize,
    /// Its periods in the order met along the parameter (`None`: an
    /// aperiodic set), each once per run: [2, 1] for a P2 that halves
    /// into the fixed point.
    pub periods: Vec<Option<usize>>,
    /// The kind of each of those runs, as a legend names it ([`kind_name`]:
    /// "P2", "chaotic", "undecided").
    pub kinds: Vec<String>,
    /// Its legend name: the kinds it takes, in order ("P2 → P1",
    /// "chaotic"); a second track of the same name gets " (2)", and so on.
    pub label: String,
}

/// The tracks over a range's columns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Identities {
    pub tracks: Vec<Track>,
    /// Per column (in grid order), the track of each of its attractors;
    /// `None` for a column not (yet) computed or failed.
    pub of: Vec<Option<Vec<usize>>>,
}

impl Identities {
    /// Track `gone` is track `keep` continued (found so by the cycle's
    /// own continuation): its columns go to `keep`, and the tracks after
    /// it move down one, renamed.
    pub fn join(&mut self, keep: usize, gone: usize) {
        if keep == gone || gone >= self.tracks.len() || keep >= self.tracks.len() {
            return;
        }
        let moved = self.tracks.remove(gone);
        let keep = if keep > gone { keep - 1 } else { keep };
        for (p, k) in moved.periods.into_iter().zip(moved.kinds) {
            let t = &mut self.tracks[keep];
            if t.periods.last() != Some(&p) {
                t.periods.push(p);
                t.kinds.push(k);
            }
        }
        for of in self.of.iter_mut().flatten() {
            for id in of.iter_mut() {
                if *id == gone {
                    *id = keep;
                } else if *id > gone {
                    *id -= 1;
                }
            }
        }
        for (i, t) in self.tracks.iter_mut().enumerate() {
            t.id = i;
        }
        name_tracks(&mut self.tracks);
    }

    /// The track of column `c`'s attractor `a`.
    pub fn track(&self, c: usize, a: usize) -> Option<&Track> {
        let id = *self.of.get(c)?.as_ref()?.get(a)?;
        self.tracks.get(id)
    }
}

/// An attractor's kind as a legend names it: P1, P2, …, chaotic,
/// undecided.
pub fn kind_name(period: Option<usize>, verdict: &Verdict) -> String {
    match (period, verdict) {
        (Some(p), _) => format!("P{p}"),
        (None, Verdict::Chaotic) => "chaotic".into(),
        (None, _) => "undecided".into(),
    }
}

impl Found {
    /// The attractor whose basin holds the onset θ (any turn of it), or
    /// `None` on the basins' boundary or off the arc.
    pub fn basin_of(&self, theta: f64) -> Option<usize> {
        let psi = self.basins.first()?.from;
        let t = psi + wrap_angle(theta - psi);
        let i = self.basins.partition_point(|b| b.to < t);
        let b = self.basins.get(i)?;
        (b.from <= t).then_some(b.attractor)?
    }

    /// The smallest kick out of attractor `a`'s basin: the distance from
    /// the attractor (its cycle's points, or its cover) to the nearest
    /// onset in no basin or in another's, with that stretch's width when
    /// it is boundary (where in it the basins part is not resolved): the
    /// true smallest kick lies in [kick, kick + width]. `None` where
    /// every other stretch of the arc is `a`'s (no kick leaves it).
    pub fn min_kick(&self, a: usize) -> Option<(f64, f64)> {
        let at = self.attractors.get(a)?;
        let psi = self.basins.first()?.from;
        let on_arc = |t: f64| psi + wrap_angle(t - psi);
        let stretches: Vec<(f64, f64)> = if at.period.is_some() || at.cover.is_empty() {
            at.points.iter().map(|&t| (on_arc(t), on_arc(t))).collect()
        } else {
            at.cover
                .iter()
                .map(|&(l, h)| (on_arc(l), on_arc(h)))
                .collect()
        };
        let others: Vec<&super::Basin> = self
            .basins
            .iter()
            .filter(|b| b.attractor != Some(a))
            .collect();
        let mut best: Option<(f64, f64)> = None;
        for (l, h) in stretches {
            let i = others.partition_point(|b| b.to <= l);
            // The nearest other stretch on the right (or one over this
            // point), and on the left.
            let right = others.get(i).map(|b| ((b.from - h).max(0.0), b));
            let left = i
                .checked_sub(1)
                .and_then(|k| others.get(k))
                .map(|b| ((l - b.to).max(0.0), b));
            for (d, b) in right.into_iter().chain(left) {
                let width = if b.attractor.is_none() {
                    b.to - b.from
                } else {
                    0.0
                };
                if best.is_none_or(|(x, _)| d < x) {
                    best = Some((d, width));
                }
            }
        }
        best
    }

    /// [`Found::min_kick`] in words, to the decimals the cells resolve:
    /// "0.08639 rad (the basin's edge within 2.2e-6 beyond)".
    pub fn kick_text(&self, a: usize) -> Option<String> {
        let (d, width) = self.min_kick(a)?;
        let known = width.max(self.resolution.finest);
        let decimals = (-known.log10()).floor().clamp(1.0, 8.0) as usize;
        Some(if width > 0.0 {
            format!("{d:.decimals$} rad (the basin's edge within {width:.1e} beyond)")
        } else {
            format!("{d:.decimals$} rad")
        })
    }

    /// The length of the onsets in attractor `a`'s basin here and in
    /// attractor `b`'s in `other` (both unions of intervals, sorted).
    fn basin_overlap(&self, a: usize, other: &Found, b: usize) -> f64 {
        let mine = self.basins.iter().filter(|x| x.attractor == Some(a));
        let theirs: Vec<_> = other
            .basins
            .iter()
            .filter(|x| x.attractor == Some(b))
            .collect();
        let mut sum = 0.0;
        let mut j = 0;
        for x in mine {
            while j < theirs.len() && theirs[j].to <= x.from {
                j += 1;
            }
            let mut k = j;
            while k < theirs.len() && theirs[k].from < x.to {
                sum += (x.to.min(theirs[k].to) - x.from.max(theirs[k].from)).max(0.0);
                k += 1;
            }
        }
        sum
    }
}

/// Where an attractor is, for the test of lying in a basin: a cycle's
/// points, else the middle of each stretch of its cover (at most 64).
fn marks(a: &Attractor) -> Vec<f64> {
    if a.period.is_some() || a.cover.is_empty() {
        return a.points.clone();
    }
    let step = a.cover.len().div_ceil(64);
    a.cover
        .iter()
        .step_by(step)
        .map(|&(l, h)| 0.5 * (l + h))
        .collect()
}

/// Whether attractor `x` (of some column) lies in attractor `a`'s basin
/// of `found`: no mark in another basin, one at least in `a`'s.
fn lies_in(x: &Attractor, found: &Found, a: usize) -> bool {
    let mut inside = false;
    for t in marks(x) {
        match found.basin_of(t) {
            Some(b) if b == a => inside = true,
            Some(_) => return false,
            None => {}
        }
    }
    inside
}

/// The bands of an aperiodic set: its cover's stretches, apart where a
/// gap is wider than the cells beside it.
fn bands(a: &Attractor) -> usize {
    let mut n = usize::from(!a.cover.is_empty());
    for w in a.cover.windows(2) {
        let gap = w[1].0 - w[0].1;
        if gap > (w[0].1 - w[0].0).max(w[1].1 - w[1].0) {
            n += 1;
        }
    }
    n
}

/// Whether attractor `a` of one column can turn into `b` of the next
/// with no birth or death between: a cycle into one of the same period,
/// or twice or half of it (a flip); a cycle of period p into chaos of k
/// bands, or back, only as a cascade does (p = k·2ⁿ, n ≥ 1: the P4 of a
/// cascade into two-band chaos, not the P3 a fold opens in one-band
/// chaos); chaos into chaos (band merging, widening).
fn may_continue(a: &Attractor, b: &Attractor) -> bool {
    let cascade =
        |p: usize, k: usize| k > 0 && p.is_multiple_of(k) && (p / k).is_power_of_two() && p > k;
    match (a.period, b.period) {
        (Some(p), Some(q)) => q == p || q == 2 * p || 2 * q == p,
        (Some(p), None) => cascade(p, bands(b)),
        (None, Some(q)) => cascade(q, bands(a)),
        (None, None) => true,
    }
}

/// Which of `now`'s attractors continue which of `prev`'s: `mine[j]` is
/// the index in `prev` of `now`'s attractor `j`'s partner.
fn partners(prev: &Found, now: &Found) -> Vec<Option<usize>> {
    let (n, m) = (prev.attractors.len(), now.attractors.len());
    let mut weight = vec![vec![None; m]; n];
    for (i, a) in prev.attractors.iter().enumerate() {
        for (j, b) in now.attractors.iter().enumerate() {
            if may_continue(a, b) && lies_in(b, prev, i) && lies_in(a, now, j) {
                weight[i][j] = Some(prev.basin_overlap(i, now, j));
            }
        }
    }
    let best_of_row = |i: usize| {
        (0..m)
            .filter_map(|j| weight[i][j].map(|w| (w, j)))
            .max_by(|x, y| x.0.total_cmp(&y.0))
            .map(|x| x.1)
    };
    let best_of_column = |j: usize| {
        (0..n)
            .filter_map(|i| weight[i][j].map(|w| (w, i)))
            .max_by(|x, y| x.0.total_cmp(&y.0))
            .map(|x| x.1)
    };
    (0..m)
        .map(|j| best_of_column(j).filter(|&i| best_of_row(i) == Some(j)))
        .collect()
}

/// The tracks of `columns` (in grid order; `None`: not computed or
/// failed, which the tracks step over).
pub fn identify(columns: &[Option<&Found>]) -> Identities {
    let mut ids = Identities::default();
    let mut prev: Option<(&Found, Vec<usize>)> = None;
    for col in columns {
        let Some(found) = col else {
            ids.of.push(None);
            continue;
        };
        let mine = match &prev {
            Some((pf, ptracks)) => partners(pf, found)
                .into_iter()
                .map(|p| p.map(|i| ptracks[i]))
                .collect(),
            None => vec![None; found.attractors.len()],
        };
        let tracks: Vec<usize> = mine
            .into_iter()
            .zip(&found.attractors)
            .map(|(m, a)| {
                let id = m.unwrap_or_else(|| {
                    ids.tracks.push(Track {
                        id: ids.tracks.len(),
                        periods: Vec::new(),
                        kinds: Vec::new(),
                        label: String::new(),
                    });
                    ids.tracks.len() - 1
                });
                let t = &mut ids.tracks[id];
                if t.periods.last() != Some(&a.period) {
                    t.periods.push(a.period);
                    t.kinds.push(kind_name(a.period, &a.verdict));
                }
                id
            })
            .collect();
        ids.of.push(Some(tracks.clone()));
        prev = Some((found, tracks));
    }
    name_tracks(&mut ids.tracks);
    ids
}

/// Each track's label: its kinds in order, a second of the same name
/// numbered " (2)", and so on.
fn name_tracks(tracks: &mut [Track]) {
    let mut seen: Vec<String> = Vec::new();
    for t in tracks.iter_mut() {
        let base = t.kinds.join(" → ");
        let same = seen.iter().filter(|s| **s == base).count();
        t.label = if same == 0 {
            base.clone()
        } else {
            format!("{base} ({})", same + 1)
        };
        seen.push(base);
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Basin, Resolution};
    use super::*;

    fn cycle(points: &[f64]) -> Attractor {
        Attractor {
            period: Some(points.len()),
            points: points.to_vec(),
            multiplier: Some(0.5),
            lyapunov: None,
            lyapunov_stderr: None,
            lyapunov_from_density: None,
            lyapunov_density_error: None,
            density: None,
            basin_fraction: 0.0,
            cover: Vec::new(),
            iterates: points.to_vec(),
            verdict: Verdict::Proved,
        }
    }

    /// A column: its attractors and the basins as (from, to, which).
    fn column(attractors: Vec<Attractor>, basins: &[(f64, f64, Option<usize>)]) -> Found {
        Found {
            attractors,
            basins: basins
                .iter()
                .map(|&(from, to, attractor)| Basin {
                    from,
                    to,
                    attractor,
                })
                .collect(),
            resolution: Resolution {
                finest: 1e-6,
                widest: 1e-3,
                eps: 1e-9,
                cells: 100,
                budget_hit: false,
                nodes_capped: false,
            },
            boundary_fraction: 0.0,
            unenclosed_fraction: 0.0,
            map_evaluations: 0,
            layout: Default::default(),
        }
    }

    #[test]
    fn a_flip_continues_the_track_and_a_fold_starts_one() {
        // A fixed point at 0.5 owning [0, 1]; then a P2 round it; then a
        // second fixed point born at 0.9 in its own basin [0.8, 1].
        let c0 = column(vec![cycle(&[0.5])], &[(0.0, 1.0, Some(0))]);
        let c1 = column(vec![cycle(&[0.45, 0.55])], &[(0.0, 1.0, Some(0))]);
        let c2 = column(
            vec![cycle(&[0.44, 0.56]), cycle(&[0.9])],
            &[(0.0, 0.79, Some(0)), (0.79, 0.8, None), (0.8, 1.0, Some(1))],
        );
        let ids = identify(&[Some(&c0), Some(&c1), None, Some(&c2)]);
        assert_eq!(ids.tracks.len(), 2);
        assert_eq!(ids.tracks[0].periods, [Some(1), Some(2)]);
        assert_eq!(ids.tracks[0].label, "P1 → P2");
        assert_eq!(ids.tracks[1].label, "P1");
        assert_eq!(ids.of[3], Some(vec![0, 1]));
        assert_eq!(ids.of[2], None);
    }

    #[test]
    fn an_attractor_that_dies_hands_its_basin_on_without_its_track() {
        // Two fixed points; the one at 0.2 with the larger basin dies, and
        // the one at 0.8 takes its whole basin: a new owner, not the dead
        // one's continuation (it never lay in that basin).
        let c0 = column(
            vec![cycle(&[0.2]), cycle(&[0.8])],
            &[(0.0, 0.7, Some(0)), (0.7, 1.0, Some(1))],
        );
        let c1 = column(vec![cycle(&[0.8])], &[(0.0, 1.0, Some(0))]);
        let ids = identify(&[Some(&c0), Some(&c1)]);
        assert_eq!(ids.of[1], Some(vec![1]));
        assert_eq!(ids.tracks.len(), 2);
        assert_eq!(ids.tracks[1].label, "P1 (2)");
    }

    /// A chaotic set over the stretches `bands`, each cut in cells 0.01
    /// wide.
    fn chaos(bands: &[(f64, f64)]) -> Attractor {
        let cover: Vec<(f64, f64)> = bands
            .iter()
            .flat_map(|&(l, h)| {
                let n = ((h - l) / 0.01).round() as usize;
                (0..n).map(move |k| (l + 0.01 * k as f64, l + 0.01 * (k + 1) as f64))
            })
            .collect();
        Attractor {
            period: None,
            points: vec![bands[0].0, bands[bands.len() - 1].1],
            multiplier: None,
            cover,
            verdict: Verdict::Chaotic,
            ..cycle(&[0.0])
        }
    }

    #[test]
    fn a_cascade_goes_on_into_chaos_and_a_window_born_in_a_fold_does_not() {
        let whole = [(0.0, 1.0, Some(0))];
        let p4 = column(vec![cycle(&[0.2, 0.3, 0.7, 0.8])], &whole);
        let two_bands = column(vec![chaos(&[(0.15, 0.35), (0.65, 0.85)])], &whole);
        let one_band = column(vec![chaos(&[(0.1, 0.9)])], &whole);
        let p3 = column(vec![cycle(&[0.2, 0.5, 0.8])], &whole);
        let ids = identify(&[Some(&p4), Some(&two_bands), Some(&one_band), Some(&p3)]);
        assert_eq!(bands(&two_bands.attractors[0]), 2);
        assert_eq!(
            ids.of,
            [Some(vec![0]), Some(vec![0]), Some(vec![0]), Some(vec![1])]
        );
        assert_eq!(ids.tracks[0].label, "P4 → chaotic");
        assert_eq!(ids.tracks[1].label, "P3");
    }

    #[test]
    fn the_basin_of_an_onset_is_read_off_the_sorted_intervals() {
        let c = column(
            vec![cycle(&[0.2]), cycle(&[0.8])],
            &[(0.0, 0.5, Some(0)), (0.5, 0.6, None), (0.6, 1.0, Some(1))],
        );
        assert_eq!(c.basin_of(0.1), Some(0));
        assert_eq!(c.basin_of(0.55), None);
        assert_eq!(c.basin_of(0.7), Some(1));
        assert_eq!(c.basin_of(0.7 + std::f64::consts::TAU), Some(1));
        assert_eq!(c.basin_of(1.5), None);
        assert!((c.basin_overlap(1, &c, 1) - 0.4).abs() < 1e-15);
        assert_eq!(c.basin_overlap(0, &c, 1), 0.0);
    }
}
