//! The plans of the laned jobs: in which order a progressive diagram's
//! items are computed, and which earlier item each one continues from.
//!
//! A plan is fixed before any work starts, so the diagram does not depend on
//! thread timing, and a test can recompute every item with the core alone
//! (each item starts from its parent's last onset through `column_start`).
//! Both plans have a coarse pass over the whole range first, then refine by
//! bisection level by level, so that the picture sharpens evenly.

use std::ops::Range;

/// One column of a sweep plan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlannedColumn {
    /// Position in the final grid (0 … columns−1).
    pub index: usize,
    /// The column whose last onset this one starts from (`None`: θ = θν).
    pub parent: Option<usize>,
    /// Whether it belongs to the coarse pass.
    pub coarse: bool,
    /// 0 for the coarse pass, then the bisection level of the fill-in.
    pub level: u32,
}

/// The order and the starting neighbours of a progressive sweep of
/// `columns` columns with a coarse pass of `coarse` columns (at least the
/// two ends, at most `columns`) in `chains` chains. The coarse columns come first (chain
/// heads, then each chain's second column, …), then the fill-in by level
/// and position. Every index appears exactly once, and every parent comes
/// before its child.
pub fn sweep_plan(columns: usize, coarse: usize, chains: usize) -> Vec<PlannedColumn> {
    if columns == 0 {
        return vec![];
    }
    // At least both ends (a single column when that is all there is).
    let m = coarse.clamp(2, columns.max(2)).min(columns);
    // Spread with both ends included; a step of (n−1)/(m−1) ≥ 1 keeps the
    // rounded indices distinct.
    let idx: Vec<usize> = if m == 1 {
        vec![0]
    } else {
        (0..m)
            .map(|k| ((k * (columns - 1)) as f64 / (m - 1) as f64).round() as usize)
            .collect()
    };
    let chains = chains.clamp(1, m);
    let mut chain_of = Vec::with_capacity(m);
    for c in 0..chains {
        let (lo, hi) = (c * m / chains, (c + 1) * m / chains);
        chain_of.push((lo, hi));
    }
    let mut plan = Vec::with_capacity(columns);
    let longest = chain_of.iter().map(|(lo, hi)| hi - lo).max().unwrap_or(0);
    for pos in 0..longest {
        for &(lo, hi) in &chain_of {
            let k = lo + pos;
            if k < hi {
                plan.push(PlannedColumn {
                    index: idx[k],
                    parent: (pos > 0).then(|| idx[k - 1]),
                    coarse: true,
                    level: 0,
                });
            }
        }
    }
    let mut fill = Vec::with_capacity(columns - m);
    fn bisect(a: usize, b: usize, level: u32, out: &mut Vec<PlannedColumn>) {
        if b - a < 2 {
            return;
        }
        let mid = (a + b) / 2;
        let parent = if mid - a <= b - mid { a } else { b };
        out.push(PlannedColumn {
            index: mid,
            parent: Some(parent),
            coarse: false,
            level,
        });
        bisect(a, mid, level + 1, out);
        bisect(mid, b, level + 1, out);
    }
    for w in idx.windows(2) {
        bisect(w[0], w[1], 1, &mut fill);
    }
    fill.sort_by_key(|p| (p.level, p.index));
    plan.extend(fill);
    plan
}

/// One cell of a phase plan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlannedCell {
    /// κ row (0 … rows−1).
    pub row: usize,
    /// θν column (0 … columns−1).
    pub column: usize,
    /// The (row, column) whose last onset this cell starts from (`None`:
    /// θ = θν).
    pub parent: Option<(usize, usize)>,
    /// Whether it belongs to the coarse lattice.
    pub coarse: bool,
    /// 0 for the coarse lattice, then the bisection level of the refinement.
    pub level: u32,
}

/// The level of each index 0 … n−1 along one axis: 0 for the coarse
/// indices (about every `stride`-th, both ends included, spread evenly),
/// then the bisection depth between them.
fn axis_levels(n: usize, stride: usize) -> Vec<u32> {
    let mut level = vec![u32::MAX; n];
    if n == 0 {
        return level;
    }
    let m = if n == 1 {
        1
    } else {
        ((n - 1).div_ceil(stride.max(1)) + 1).min(n)
    };
    // A step of (n−1)/(m−1) ≥ 1 keeps the rounded indices distinct.
    let idx: Vec<usize> = if m == 1 {
        vec![0]
    } else {
        (0..m)
            .map(|k| ((k * (n - 1)) as f64 / (m - 1) as f64).round() as usize)
            .collect()
    };
    for &i in &idx {
        level[i] = 0;
    }
    fn bisect(a: usize, b: usize, depth: u32, level: &mut [u32]) {
        if b - a < 2 {
            return;
        }
        let mid = (a + b) / 2;
        level[mid] = depth;
        bisect(a, mid, depth + 1, level);
        bisect(mid, b, depth + 1, level);
    }
    for w in idx.windows(2) {
        bisect(w[0], w[1], 1, &mut level);
    }
    level
}

/// The order and starting neighbours of a progressive phase diagram of
/// `rows` × `columns` cells with a coarse lattice of about every `stride`-th
/// row and column (see the module's doc). Every cell appears exactly once,
/// coarse cells first, levels never decrease, and every parent comes before
/// its child.
pub fn phase_plan(rows: usize, columns: usize, stride: usize) -> Vec<PlannedCell> {
    let lr = axis_levels(rows, stride);
    let lc = axis_levels(columns, stride);
    let level = |r: usize, c: usize| lr[r].max(lc[c]);
    let mut plan = Vec::with_capacity(rows * columns);
    for r in 0..rows {
        for c in 0..columns {
            let l = level(r, c);
            // Earlier in the order (level, row, column), on the same row:
            // to the left anything of level ≤ l, to the right only lower.
            let left = (0..c).rev().find(|&k| level(r, k) <= l);
            let right = if l == 0 {
                None
            } else {
                (c + 1..columns).find(|&k| level(r, k) < l)
            };
            let in_row = match (left, right) {
                (Some(a), Some(b)) => Some(if c - a <= b - c { a } else { b }),
                (a, b) => a.or(b),
            };
            let parent = match in_row {
                Some(k) => Some((r, k)),
                // A coarse row's first cell starts from θν, as in phase_row.
                None if l == 0 => None,
                None => {
                    let below = (0..r).rev().find(|&k| level(k, c) <= l);
                    let above = (r + 1..rows).find(|&k| level(k, c) < l);
                    match (below, above) {
                        (Some(a), Some(b)) => Some(if r - a <= b - r { a } else { b }),
                        (a, b) => a.or(b),
                    }
                    .map(|k| (k, c))
                }
            };
            plan.push(PlannedCell {
                row: r,
                column: c,
                parent,
                coarse: l == 0,
                level: l,
            });
        }
    }
    plan.sort_by_key(|p| (p.level, p.row, p.column));
    plan
}

/// The side of a phase plan's blocks, in cells: a cell's neighbour is
/// always in its own block, so a block's cells are the same whichever
/// other blocks are computed with it (`oneblock phase --shard`).
pub const PHASE_BLOCK: usize = 32;

/// The blocks of a `rows` × `columns` grid, row-major: each one's rows
/// and columns (at most [`PHASE_BLOCK`] of each; the last in a row or
/// column of blocks may be narrower).
pub fn phase_blocks(rows: usize, columns: usize) -> Vec<(Range<usize>, Range<usize>)> {
    let spans = |n: usize| -> Vec<Range<usize>> {
        (0..n.div_ceil(PHASE_BLOCK))
            .map(|b| b * PHASE_BLOCK..((b + 1) * PHASE_BLOCK).min(n))
            .collect()
    };
    let (rs, cs) = (spans(rows), spans(columns));
    rs.iter()
        .flat_map(|r| cs.iter().map(move |c| (r.clone(), c.clone())))
        .collect()
}

/// The blocks of shard `k` of `n` (1 ≤ k ≤ n ≤ `blocks`): a run of whole
/// blocks, in the order of [`phase_blocks`], the shards as even as they
/// can be.
pub fn shard_blocks(blocks: usize, k: usize, n: usize) -> Range<usize> {
    (k - 1) * blocks / n..k * blocks / n
}

/// [`phase_plan`] over the blocks `which` of [`phase_blocks`] (all of them
/// for the whole grid): each block planned on its own, every parent in
/// its child's block, the blocks' cells merged by level, then row and
/// column, so that the whole grid sharpens evenly.
pub fn block_plan(
    rows: usize,
    columns: usize,
    stride: usize,
    which: Range<usize>,
) -> Vec<PlannedCell> {
    let blocks = phase_blocks(rows, columns);
    let mut plan = Vec::new();
    for (r, c) in &blocks[which.start.min(blocks.len())..which.end.min(blocks.len())] {
        let moved = |(row, column): (usize, usize)| (row + r.start, column + c.start);
        plan.extend(phase_plan(r.len(), c.len(), stride).into_iter().map(|p| {
            let (row, column) = moved((p.row, p.column));
            PlannedCell {
                row,
                column,
                parent: p.parent.map(moved),
                ..p
            }
        }));
    }
    plan.sort_by_key(|p| (p.level, p.row, p.column));
    plan
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    fn check_sweep_plan(columns: usize, coarse: usize, chains: usize) {
        let plan = sweep_plan(columns, coarse, chains);
        assert_eq!(plan.len(), columns, "{columns} {coarse} {chains}");
        let idx: HashSet<usize> = plan.iter().map(|p| p.index).collect();
        assert_eq!(idx.len(), columns, "each column once");
        assert!(idx.iter().all(|&i| i < columns));
        let m = coarse.clamp(2, columns.max(2)).min(columns);
        assert!(plan[..m].iter().all(|p| p.coarse && p.level == 0));
        assert!(plan[m..].iter().all(|p| !p.coarse && p.level > 0));
        // The coarse pass spans the range: both ends, even gaps.
        let mut c: Vec<usize> = plan[..m].iter().map(|p| p.index).collect();
        c.sort();
        assert_eq!(c[0], 0);
        if m > 1 {
            assert_eq!(c[m - 1], columns - 1);
            let gaps: Vec<usize> = c.windows(2).map(|w| w[1] - w[0]).collect();
            let (lo, hi) = (
                gaps.iter().min().expect("gaps"),
                gaps.iter().max().expect("gaps"),
            );
            assert!(hi - lo <= 1, "even coarse gaps {gaps:?}");
        }
        // Parents come earlier, and are the nearest earlier column.
        let pos: Vec<usize> = {
            let mut v = vec![0; columns];
            for (k, p) in plan.iter().enumerate() {
                v[p.index] = k;
            }
            v
        };
        let heads = plan.iter().filter(|p| p.parent.is_none()).count();
        assert_eq!(heads, chains.clamp(1, m));
        for (k, p) in plan.iter().enumerate() {
            if let Some(q) = p.parent {
                assert!(pos[q] < k);
                let d = q.abs_diff(p.index);
                let nearer = plan[..k]
                    .iter()
                    .filter(|e| e.coarse || !p.coarse)
                    .map(|e| e.index.abs_diff(p.index))
                    .min()
                    .expect("a parent exists, so an earlier column does");
                if !p.coarse {
                    assert_eq!(d, nearer, "column {} continues from the nearest", p.index);
                }
            }
        }
        // Levels do not decrease.
        assert!(plan.windows(2).all(|w| w[0].level <= w[1].level));
    }

    #[test]
    fn plans_cover_every_column_once_coarse_first() {
        for columns in [1, 2, 3, 7, 10, 64, 65, 100, 400] {
            for coarse in [1, 2, 5, 8, 64, 1000] {
                for chains in [1, 2, 3] {
                    check_sweep_plan(columns, coarse, chains);
                }
            }
        }
        assert!(sweep_plan(0, 8, 2).is_empty());
    }

    fn check_phase_plan(rows: usize, columns: usize, stride: usize) {
        let plan = phase_plan(rows, columns, stride);
        let what = format!("{rows} x {columns} stride {stride}");
        assert_eq!(plan.len(), rows * columns, "{what}");
        let cells: HashSet<(usize, usize)> = plan.iter().map(|p| (p.row, p.column)).collect();
        assert_eq!(cells.len(), rows * columns, "each cell once: {what}");
        let n_coarse = plan.iter().filter(|p| p.coarse).count();
        assert!(plan[..n_coarse].iter().all(|p| p.coarse && p.level == 0));
        assert!(plan[n_coarse..].iter().all(|p| !p.coarse && p.level > 0));
        assert!(plan.windows(2).all(|w| w[0].level <= w[1].level), "{what}");
        // The coarse lattice holds the four corners and spans evenly.
        for corner in [
            (0, 0),
            (0, columns - 1),
            (rows - 1, 0),
            (rows - 1, columns - 1),
        ] {
            assert!(
                plan[..n_coarse].iter().any(|p| (p.row, p.column) == corner),
                "{what}: corner {corner:?}"
            );
        }
        let mut coarse_cols: Vec<usize> = plan[..n_coarse]
            .iter()
            .filter(|p| p.row == 0)
            .map(|p| p.column)
            .collect();
        coarse_cols.sort();
        let gaps: Vec<usize> = coarse_cols.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(gaps.iter().all(|&g| g <= stride), "{what}: {gaps:?}");
        // Parents come earlier; coarse parents are the left neighbour in the
        // row; a refinement cell's parent is in its row or column.
        let mut pos = vec![0; rows * columns];
        for (k, p) in plan.iter().enumerate() {
            pos[p.row * columns + p.column] = k;
        }
        for (k, p) in plan.iter().enumerate() {
            match p.parent {
                None => assert!(p.coarse, "{what}: {p:?} has no parent"),
                Some((r, c)) => {
                    assert!(pos[r * columns + c] < k, "{what}: {p:?}");
                    assert!(r == p.row || c == p.column, "{what}: {p:?}");
                    if p.coarse {
                        assert!(r == p.row && c < p.column, "{what}: {p:?}");
                    }
                    if r == p.row {
                        // The nearest earlier cell of the row.
                        let d = c.abs_diff(p.column);
                        let nearer = plan[..k]
                            .iter()
                            .filter(|e| e.row == p.row && e.column.abs_diff(p.column) < d)
                            .count();
                        assert_eq!(nearer, 0, "{what}: {p:?}");
                    } else {
                        // Only when the row had nothing computed before it.
                        assert!(!plan[..k].iter().any(|e| e.row == p.row), "{what}: {p:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn plans_cover_every_cell_once_coarse_first() {
        for rows in [1, 2, 3, 5, 9, 30] {
            for columns in [1, 2, 4, 7, 30, 61] {
                for stride in [1, 2, 4] {
                    check_phase_plan(rows, columns, stride);
                }
            }
        }
        // 30 x 30 at stride 4: a 9 x 9 coarse lattice.
        let plan = phase_plan(30, 30, 4);
        assert_eq!(plan.iter().filter(|p| p.coarse).count(), 81);
    }

    #[test]
    fn block_plans_keep_every_parent_in_its_block_and_shards_partition_them() {
        let (rows, columns) = (70, 45);
        let blocks = phase_blocks(rows, columns);
        assert_eq!(blocks.len(), 3 * 2);
        let block_of = |r: usize, c: usize| {
            blocks
                .iter()
                .position(|(br, bc)| br.contains(&r) && bc.contains(&c))
                .expect("a block")
        };
        let plan = block_plan(rows, columns, 8, 0..blocks.len());
        assert_eq!(plan.len(), rows * columns);
        assert!(plan.windows(2).all(|w| w[0].level <= w[1].level));
        for p in &plan {
            if let Some((r, c)) = p.parent {
                assert_eq!(block_of(r, c), block_of(p.row, p.column), "{p:?}");
            }
        }
        // A shard's plan is the whole plan's cells of its blocks, with the
        // same parents; the shards cover every cell once.
        let mut seen = HashSet::new();
        for k in 1..=4 {
            let which = shard_blocks(blocks.len(), k, 4);
            let part = block_plan(rows, columns, 8, which.clone());
            for p in &part {
                assert!(which.contains(&block_of(p.row, p.column)));
                assert!(plan.contains(p));
                assert!(seen.insert((p.row, p.column)));
            }
        }
        assert_eq!(seen.len(), rows * columns);
        // One block: the plain plan.
        assert_eq!(block_plan(20, 30, 8, 0..1), phase_plan(20, 30, 8));
    }
}
