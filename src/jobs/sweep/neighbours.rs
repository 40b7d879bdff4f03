//! A seeded diagram's neighbour pass: every attractor found at one column
//! is followed to its neighbours, in both directions, until it dies.
//!
//! A sweep follows one attractor from column to column, and its seeds
//! sample each column's basins; a branch whose basin the seeds miss at a
//! column (a narrow one, or few seeds) would be drawn only where the
//! seeds or the followed orbit happened to land on it. Once every column
//! is done, each column is checked against its two neighbours: a
//! neighbour's attractor that none of the column's own continues
//! (`SeededColumn::starts_from`) seeds an orbit at the column from its
//! last point, as a downward or upward sweep would continue it. What such
//! a seed finds that is new is confirmed at full accuracy as any seed's
//! is, the column is sent again with it, and its neighbours are checked
//! again.
//!
//! The pass runs as one worklist, in index order, under one lock, so that
//! it gives the same columns on every host and thread count: a column is
//! checked whole, and a neighbour's attractor is tried at a column once.

use std::collections::{BTreeSet, HashSet};

use crate::integrate::SolverSettings;
use crate::jobs::protocol::Update;
use crate::jobs::{Generation, JobError, Status};
use crate::model::Params;
use crate::sim::column_lyapunov::ColumnLyapunov;
use crate::sim::interpolant::MapUsed;
use crate::sim::seeded::SeededColumn;
use crate::sim::{SimError, SweepOptions};

/// A seeded column as sent, kept for the neighbour pass.
pub(super) struct SentColumn {
    pub coarse: bool,
    pub map: MapUsed,
    pub lyapunov: Option<ColumnLyapunov>,
    /// Right-hand-side evaluations of the followed column alone.
    pub rhs_evals: u64,
    pub seeded: SeededColumn,
}

impl SentColumn {
    /// The column's update.
    pub fn update(&self, generation: Generation, index: usize, theta_nu: f64) -> Update {
        Update::Column {
            generation,
            index,
            theta_nu,
            thetas: self.seeded.thetas.clone(),
            coarse: self.coarse,
            rhs_evals: self.rhs_evals + self.seeded.rhs_evals,
            map: self.map.clone(),
            lyapunov: self.lyapunov,
            attractor: self.seeded.attractor.clone(),
        }
    }
}

/// The pass's worklist.
#[derive(Default)]
pub(super) struct NeighbourPass {
    begun: bool,
    /// Columns to check against their neighbours, least index first.
    pending: BTreeSet<usize>,
    /// (column, neighbour, the neighbour's label) already tried.
    tried: HashSet<(usize, usize, usize)>,
}

/// What a step of the pass needs of the sweep.
pub(super) struct Sweep<'a> {
    pub params: Params,
    pub settings: SolverSettings,
    pub opts: &'a SweepOptions,
    pub grid: &'a [f64],
}

impl NeighbourPass {
    /// Checks the next column of the worklist against its neighbours
    /// (`columns`: each column as sent, `None` where it failed); an
    /// amended column is stored and returned with its index, for sending.
    /// `Done` once nothing is left to check.
    pub fn step(
        &mut self,
        sweep: &Sweep,
        columns: &mut [Option<SentColumn>],
        cancel: &dyn Fn() -> bool,
    ) -> Result<(Status, Option<usize>), JobError> {
        if !self.begun {
            self.begun = true;
            self.pending = (0..columns.len())
                .filter(|&i| columns[i].is_some())
                .collect();
        }
        let Some(i) = self.pending.pop_first() else {
            return Ok((Status::Done, None));
        };
        let params = sweep.params.with_theta_nu(sweep.grid[i]);
        let neighbours = [i.checked_sub(1), Some(i + 1).filter(|&j| j < columns.len())];
        let mut starts = vec![];
        let Some(mine) = &columns[i] else {
            return Ok((Status::Working, None));
        };
        for j in neighbours.into_iter().flatten() {
            if let Some(theirs) = &columns[j] {
                let tried = |label| !self.tried.insert((i, j, label));
                starts.extend(mine.seeded.starts_from(&theirs.seeded, &params, tried));
            }
        }
        let Some(mine) = &mut columns[i] else {
            return Ok((Status::Working, None));
        };
        let (settings, opts) = (sweep.settings, sweep.opts);
        match mine
            .seeded
            .extend_from(params, settings, &starts, opts, cancel)
        {
            Ok(true) => {
                self.pending.extend(neighbours.into_iter().flatten());
                Ok((Status::Working, Some(i)))
            }
            Err(SimError::Cancelled) => Err(JobError::Stop),
            // Failed seeds are left out, as the column's own are.
            Ok(false) | Err(_) => Ok((Status::Working, None)),
        }
    }
}
