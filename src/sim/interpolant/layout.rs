//! A build started from a neighbour's [`Layout`]
//! (`InterpolantBuild::start_from`): the pieces it begins with.

use super::Layout;
use super::build::Pending;

/// How far to either side of a neighbour's jump (or rough stretch) its
/// series pieces are kept off: a jump that moved less is found in a piece
/// of its own, at a few dozen evaluations; one that moved more is found
/// as in a build from nothing, in the series piece it moved into.
const GUARD: f64 = 2e-3;

/// Series narrower than this in a neighbour's layout are not kept: they
/// are the cascade of halvings towards a jump, or a point where f' is
/// unbounded, which moves with the parameters; consecutive ones are
/// merged and resolved as in a build from nothing, so that a cascade
/// left behind by a jump that moved does not cost its evaluations again
/// column after column.
const NARROW: f64 = 0.03;

/// The pieces a build over [a, b] starts with, from a neighbour's layout:
/// its series where they were, each to be sampled at once as finely as it
/// was; a guard piece reaching [`GUARD`] beyond each of its stretches
/// left to integration (the series beside it cut back, or swallowed when
/// little of them is left); its narrow series merged ([`NARROW`]); the
/// layout clipped to [a, b] and any gap filled. Empty when the layout
/// does not meet [a, b].
pub(super) fn from_layout(a: f64, b: f64, layout: &Layout) -> Vec<Pending> {
    // (from, to, first sampling, a guard).
    let mut cuts: Vec<(f64, f64, usize, bool)> = Vec::new();
    let mut pos = a;
    let push =
        |cuts: &mut Vec<(f64, f64, usize, bool)>, lo: f64, hi: f64, first: usize, guard: bool| {
            match cuts.last_mut() {
                Some(last) if first == 0 && !guard && last.2 == 0 && !last.3 => last.1 = hi,
                _ => cuts.push((lo, hi, first, guard)),
            }
        };
    for &(pa, pb, n) in &layout.0 {
        let guard = n == 0;
        let (lo, hi) = if guard {
            (pa - GUARD, pb + GUARD)
        } else {
            (pa, pb)
        };
        let (mut lo, hi) = (lo.max(a), hi.min(b));
        if !(hi > lo && hi > pos) {
            continue;
        }
        while guard && let Some(last) = cuts.last_mut().filter(|l| lo < l.1) {
            let swallow = lo - last.0 < GUARD;
            if swallow {
                lo = lo.min(last.0);
                cuts.pop();
            } else {
                last.1 = lo;
            }
            pos = lo;
            if !swallow {
                break;
            }
        }
        let lo = lo.max(pos);
        if lo > pos {
            push(&mut cuts, pos, lo, 0, false);
        }
        let first = if guard || hi - lo < NARROW { 0 } else { n };
        push(&mut cuts, lo, hi, first, guard);
        pos = hi;
    }
    if !cuts.is_empty() && pos < b {
        push(&mut cuts, pos, b, 0, false);
    }
    cuts.into_iter()
        .map(|(lo, hi, first, _)| {
            let mut p = Pending::new(lo, hi);
            p.first = first;
            p
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::{GUARD, Layout, from_layout};

    /// The pieces' ends and first samplings.
    fn cut(a: f64, b: f64, layout: &[(f64, f64, usize)]) -> Vec<(f64, f64, usize)> {
        from_layout(a, b, &Layout(layout.to_vec()))
            .iter()
            .map(|p| (p.a, p.b, p.first))
            .collect()
    }

    /// Whether `pieces` tile [a, b] in order with no gap or overlap.
    fn tiles(a: f64, b: f64, pieces: &[(f64, f64, usize)]) -> bool {
        !pieces.is_empty()
            && pieces[0].0 == a
            && pieces[pieces.len() - 1].1 == b
            && pieces.windows(2).all(|w| w[0].1 == w[1].0)
            && pieces.iter().all(|p| p.1 > p.0)
    }

    #[test]
    fn series_are_kept_with_their_sampling_and_the_interval_is_tiled() {
        let p = cut(
            -1.5,
            1.5,
            &[(-1.5, 0.0, 129), (0.0, 0.75, 33), (0.75, 1.5, 65)],
        );
        assert_eq!(p, [(-1.5, 0.0, 129), (0.0, 0.75, 33), (0.75, 1.5, 65)]);
        // A narrower interval: clipped; a wider one: its ends filled.
        let p = cut(-1.0, 1.0, &[(-1.5, 0.0, 129), (0.0, 1.5, 33)]);
        assert_eq!(p, [(-1.0, 0.0, 129), (0.0, 1.0, 33)]);
        let p = cut(-1.5, 1.5, &[(-1.0, 1.0, 65)]);
        assert_eq!(p, [(-1.5, -1.0, 0), (-1.0, 1.0, 65), (1.0, 1.5, 0)]);
        assert!(cut(-1.5, 1.5, &[]).is_empty());
        assert!(cut(0.0, 1.0, &[(2.0, 3.0, 33)]).is_empty());
    }

    #[test]
    fn a_jump_gets_a_guard_piece_and_narrow_series_merge() {
        let j = 0.3;
        let layout = [
            (-1.5, 0.0, 129),
            (0.0, 0.25, 33),
            (0.25, j - 1e-3, 33),
            (j - 1e-3, j, 33),
            (j, j + 2e-10, 0),
            (j + 2e-10, j + 1e-3, 33),
            (j + 1e-3, 0.5, 33),
            (0.5, 1.5, 129),
        ];
        let p = cut(-1.5, 1.5, &layout);
        assert!(tiles(-1.5, 1.5, &p), "{p:?}");
        // The guard holds the jump with GUARD to spare each side, and is
        // sampled from the first sampling on.
        let g = p.iter().find(|q| q.0 <= j && j + 2e-10 <= q.1).unwrap();
        assert!(g.0 <= j - GUARD && g.1 >= j + 2e-10 + GUARD, "{g:?}");
        assert_eq!(g.2, 0);
        // The wide series keep their sampling; nothing narrower than the
        // guard is left beside it.
        assert_eq!(p[0], (-1.5, 0.0, 129));
        assert_eq!(p[p.len() - 1], (0.5, 1.5, 129));
        assert!(p.iter().all(|q| q.1 - q.0 >= GUARD), "{p:?}");
    }
}
