//! A figure of data computed elsewhere: `oneblock phase --png` draws the
//! grid it has just computed (and the curves of `--boundaries`) through
//! the figure's own code, on a job model whose phase and curves slots hold
//! them, done, and that runs no job.

use super::super::backend::Recorder;
use super::super::branches::CurveData;
use super::super::jobs::{JobState, Jobs};
use super::super::phase_data::PhaseData;
use crate::sim::continuation::Curve;
use crate::sim::phase::PhaseCell;
use crate::worker::GridCell;

/// The jobs of a phase figure holding `grid` (rows of κ over `kappa`,
/// each of columns of θν over `theta_nu`, ends included) and `curves`
/// in (θν, κ), as the window's Phase job and Boundaries would.
pub fn phase_jobs(
    grid: &[Vec<PhaseCell>],
    theta_nu: (f64, f64),
    kappa: (f64, f64),
    curves: Vec<Curve>,
) -> Jobs {
    let rows = grid.len();
    let columns = grid.first().map_or(0, Vec::len);
    let mut data = PhaseData::new(theta_nu, kappa, columns, rows);
    let cells = grid
        .iter()
        .enumerate()
        .flat_map(|(row, r)| {
            r.iter().enumerate().map(move |(column, cell)| GridCell {
                row,
                column,
                cell: cell.clone(),
                listed: Vec::new(),
            })
        })
        .collect();
    data.insert(cells, false);
    // Nothing is sent: the recorder only keeps what would be.
    let mut jobs = Jobs::new(Box::new(Recorder::new()));
    jobs.phase.data = data;
    jobs.phase.state = JobState::Done;
    if !curves.is_empty() {
        jobs.curves.data = CurveData { curves };
        jobs.curves.state = JobState::Done;
    }
    jobs
}
