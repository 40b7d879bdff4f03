//! Which attractor of one θν column is which of the next: an identity
//! (a *track*) per attractor followed along θν, so that a picture gives it
//! one colour and one legend entry. A cycle is matched to a cycle of the
//! same period in the previous column by its nearest points; an aperiodic
//! set to one whose cover overlaps its own. Whatever finds no partner (a
//! new attractor, or a cycle across a doubling) starts a new track.

use crate::sim::attractors::{Attractor, Found, Verdict};

/// The farthest a cycle's points may move between neighbouring columns
/// and still be the same cycle (radians; its sorted points, the largest
/// move).
pub const MAX_CYCLE_MOVE: f64 = 0.25;

/// One attractor followed along θν.
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    /// Its number, in the order tracks were started (a colour's index).
    pub id: usize,
    /// Its period, `None` for an aperiodic set.
    pub period: Option<usize>,
    /// Its legend name: P1, P2, …, chaotic, undecided; a second track of
    /// the same name gets " (2)", and so on.
    pub label: String,
}

/// The tracks over a diagram's columns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Identities {
    pub tracks: Vec<Track>,
    /// Per column (in grid order), the track of each of its attractors;
    /// `None` for a column not (yet) computed or failed.
    pub of: Vec<Option<Vec<usize>>>,
}

impl Identities {
    /// The track of column `c`'s attractor `a`.
    pub fn track(&self, c: usize, a: usize) -> Option<&Track> {
        let id = *self.of.get(c)?.as_ref()?.get(a)?;
        self.tracks.get(id)
    }
}

/// The name a new track of `a` starts from.
fn base_label(a: &Attractor) -> String {
    match (a.period, &a.verdict) {
        (Some(p), _) => format!("P{p}"),
        (None, Verdict::Chaotic) => "chaotic".into(),
        (None, _) => "undecided".into(),
    }
}

/// The θ extent of an attractor: its cover's, or its points'.
fn extent(a: &Attractor) -> (f64, f64) {
    let xs = a
        .cover
        .iter()
        .flat_map(|&(l, h)| [l, h])
        .chain(a.points.iter().copied());
    xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
        (l.min(x), h.max(x))
    })
}

/// How far `b` (this column's) is from `a` (the previous column's), or
/// `None` if they cannot be one attractor.
pub fn distance(a: &Attractor, b: &Attractor) -> Option<f64> {
    match (a.period, b.period) {
        (Some(p), Some(q)) if p == q => {
            let sorted = |x: &Attractor| {
                let mut v = x.points.clone();
                v.sort_by(f64::total_cmp);
                v
            };
            let (u, v) = (sorted(a), sorted(b));
            let d = u
                .iter()
                .zip(&v)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            (u.len() == v.len() && d <= MAX_CYCLE_MOVE).then_some(d)
        }
        (None, None) => {
            let ((l0, h0), (l1, h1)) = (extent(a), extent(b));
            let overlap = h0.min(h1) - l0.max(l1);
            // Overlapping covers; the larger the overlap, the nearer.
            (overlap >= 0.0).then(|| 1.0 / (1.0 + overlap))
        }
        _ => None,
    }
}

/// The tracks of `columns` (in grid order; `None`: not computed or failed).
pub fn identify(columns: &[Option<&Found>]) -> Identities {
    let mut ids = Identities::default();
    let mut prev: Option<(&Found, Vec<usize>)> = None;
    for col in columns {
        let Some(found) = col else {
            ids.of.push(None);
            continue;
        };
        let now = &found.attractors;
        let mut mine: Vec<Option<usize>> = vec![None; now.len()];
        if let Some((pf, ptracks)) = &prev {
            let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
            for (i, a) in pf.attractors.iter().enumerate() {
                for (j, b) in now.iter().enumerate() {
                    if let Some(d) = distance(a, b) {
                        pairs.push((d, i, j));
                    }
                }
            }
            pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
            let mut taken = vec![false; pf.attractors.len()];
            for (_, i, j) in pairs {
                if !taken[i] && mine[j].is_none() {
                    taken[i] = true;
                    mine[j] = Some(ptracks[i]);
                }
            }
        }
        let tracks: Vec<usize> = mine
            .into_iter()
            .zip(now)
            .map(|(m, a)| m.unwrap_or_else(|| new_track(&mut ids.tracks, a)))
            .collect();
        ids.of.push(Some(tracks.clone()));
        prev = Some((found, tracks));
    }
    ids
}

/// Starts a track for `a`, named apart from the tracks before it.
fn new_track(tracks: &mut Vec<Track>, a: &Attractor) -> usize {
    let base = base_label(a);
    let same = tracks
        .iter()
        .filter(|t| t.label == base || t.label.starts_with(&format!("{base} (")))
        .count();
    let label = if same == 0 {
        base
    } else {
        format!("{base} ({})", same + 1)
    };
    let id = tracks.len();
    tracks.push(Track {
        id,
        period: a.period,
        label,
    });
    id
}
