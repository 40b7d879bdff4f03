//! Seeded columns (docs/attractors.md): besides the attractor a sweep
//! follows from its neighbour, every attractor at the column's θν from the
//! exit arc's cell graph (`super::attractors`, `CellOptions::column()`),
//! with no orbit budget. Where attractors coexist (hysteresis), a seeded
//! diagram shows every branch.
//!
//! The followed column's attractor is the one whose basin holds its last
//! onset; the others are drawn from their points (a cycle's p points, or
//! the last iterates of the orbit that told a chaotic set). Attractors the
//! graph leaves undecided are neither drawn nor counted.

use super::attractors::{Attractor, AttractorError, CellOptions, Verdict, attractors};
use super::{Column, SimError, Simulator};
use crate::integrate::SolverSettings;
use crate::model::{Params, wrap_angle};

/// The most `--seeds` may be (any N > 0 turns the cell graph on; the
/// number is kept so that old command lines and sessions still run).
pub const MAX_SEEDS: usize = 256;

/// The most further attractors a column draws (all are counted).
pub const MAX_OTHERS: usize = 8;

/// A column of a seeded diagram: the followed column's points and every
/// other attractor's, each point labelled with its attractor.
#[derive(Clone, Debug, PartialEq)]
pub struct SeededColumn {
    /// The followed column's kept iterates, then each further attractor's
    /// points (a cycle's p points, or a chaotic set's last iterates).
    pub thetas: Vec<f64>,
    /// `attractor[i]` labels `thetas[i]`: 0 is the followed attractor,
    /// 1, 2, … the others along the arc.
    pub attractor: Vec<u8>,
    /// How many distinct attractors (0 if the followed column is empty).
    pub count: usize,
    /// Map evaluations the cell graph cost.
    pub rhs_evals: u64,
    /// Why the other attractors were not counted: the exit arc's cell
    /// graph could not be built (the column is then the followed one alone).
    pub uncounted: Option<String>,
}

/// The followed column `followed` at θν of `params` with every other
/// attractor the cell graph finds there (see the module's doc); at most
/// `keep` points each. With `seeds` = 0 it is the followed column alone,
/// labelled 0.
pub fn seeded_column(
    params: Params,
    settings: SolverSettings,
    followed: &Column,
    seeds: usize,
    keep: usize,
    cancel: &dyn Fn() -> bool,
) -> Result<SeededColumn, SimError> {
    let mut col = SeededColumn {
        thetas: followed.thetas.clone(),
        attractor: vec![0; followed.thetas.len()],
        count: usize::from(!followed.thetas.is_empty()),
        rhs_evals: 0,
        uncounted: None,
    };
    if seeds == 0 || followed.thetas.is_empty() {
        return Ok(col);
    }
    let sim = Simulator::new(params, settings)?;
    let found = match attractors(&sim, &CellOptions::column(), cancel) {
        Ok(f) => f,
        Err(AttractorError::Sim(e)) => return Err(e),
        // No graph (the arc's map could not be built): the column alone,
        // and why, so that no count claims what was not looked at.
        Err(AttractorError::Arc(e)) => {
            col.uncounted = Some(e.to_string());
            return Ok(col);
        }
    };
    col.rhs_evals = found.map_evaluations;
    let mine = found.basin_of(followed.theta_last);
    let others = found
        .attractors
        .iter()
        .enumerate()
        .filter(|&(i, a)| Some(i) != mine && !matches!(a.verdict, Verdict::Undecided(_)));
    for (label, (_, a)) in (1u8..).zip(others) {
        let points = drawn(a, keep);
        col.attractor
            .extend(std::iter::repeat_n(label, points.len()));
        col.thetas.extend(points);
        col.count += 1;
    }
    Ok(col)
}

/// An attractor's points as a diagram draws them: at most `keep`, in
/// (−π, π].
fn drawn(a: &Attractor, keep: usize) -> Vec<f64> {
    let n = a.iterates.len();
    a.iterates[n.saturating_sub(keep.max(1))..]
        .iter()
        .map(|&t| wrap_angle(t))
        .collect()
}
