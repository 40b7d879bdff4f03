//! What the worker sent for the phase diagram: one slot per cell of the
//! requested grid (row-major, row 0 = the lowest κ), filled as batches of
//! cells arrive.

use super::jobs::Receive;
use crate::worker::Update;
use std::collections::HashMap;

use crate::sim::phase::PhaseCell;
use crate::sim::theta_nu_grid;
use crate::worker::{GridCell, ListedAttractor};

/// The phase job's results.
#[derive(Clone, Debug, Default)]
pub struct PhaseData {
    /// θν range (columns) and κ range (rows) of the grid, ends included.
    pub theta_nu: (f64, f64),
    pub kappa: (f64, f64),
    pub columns: usize,
    pub rows: usize,
    /// `rows × columns` slots, row-major.
    pub cells: Vec<Option<PhaseCell>>,
    /// Whether each received cell came with the coarse lattice.
    pub coarse: Vec<bool>,
    pub filled: usize,
    /// The attractors of the multistable cells whose list came (by flat
    /// index): only those cells, each list at most `MAX_LISTED` long.
    pub listed: HashMap<usize, Vec<ListedAttractor>>,
    /// The last error the job reported (a failed cell, or bad input).
    pub error: Option<String>,
    /// Bumped on every change, so the view rebuilds only when it moves.
    pub revision: u64,
}

impl PhaseData {
    pub fn new(theta_nu: (f64, f64), kappa: (f64, f64), columns: usize, rows: usize) -> Self {
        PhaseData {
            theta_nu,
            kappa,
            columns,
            rows,
            cells: vec![None; rows * columns],
            coarse: vec![false; rows * columns],
            filled: 0,
            listed: HashMap::new(),
            error: None,
            revision: 0,
        }
    }

    /// The grid's θν values, as the worker computes them.
    pub fn theta_nus(&self) -> Vec<f64> {
        theta_nu_grid(self.theta_nu.0, self.theta_nu.1, self.columns)
    }

    /// The grid's κ values, as the worker computes them.
    pub fn kappas(&self) -> Vec<f64> {
        theta_nu_grid(self.kappa.0, self.kappa.1, self.rows)
    }

    /// The cell at (row, column), if it has arrived.
    pub fn cell(&self, row: usize, column: usize) -> Option<&PhaseCell> {
        if row >= self.rows || column >= self.columns {
            return None;
        }
        self.cells[row * self.columns + column].as_ref()
    }

    /// The listed attractors of the cell at (row, column), if any came.
    pub fn listed(&self, row: usize, column: usize) -> Option<&[ListedAttractor]> {
        if row >= self.rows || column >= self.columns {
            return None;
        }
        self.listed
            .get(&(row * self.columns + column))
            .map(Vec::as_slice)
    }

    /// Stores received cells (out-of-grid ones are ignored; a repeat
    /// replaces the cell without counting it twice).
    pub fn insert(&mut self, cells: Vec<GridCell>, coarse: bool) {
        for gc in cells {
            if gc.row >= self.rows || gc.column >= self.columns {
                continue;
            }
            let i = gc.row * self.columns + gc.column;
            if self.cells[i].is_none() {
                self.filled += 1;
            }
            self.cells[i] = Some(gc.cell);
            self.coarse[i] = coarse;
            if gc.listed.is_empty() {
                self.listed.remove(&i);
            } else {
                self.listed.insert(i, gc.listed);
            }
        }
        self.revision += 1;
    }

    /// Whether every cell has arrived.
    pub fn complete(&self) -> bool {
        self.rows * self.columns > 0 && self.filled == self.rows * self.columns
    }
}

impl Receive for PhaseData {
    fn receive(&mut self, u: Update) -> Option<Update> {
        match u {
            Update::PhaseCells { cells, coarse, .. } => {
                self.insert(cells, coarse);
                None
            }
            u => Some(u),
        }
    }
}
