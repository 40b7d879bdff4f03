//! A sweep's columns on lanes: several columns' slips stepped together on
//! one thread, each column pausable between two cycles for a host that
//! wants its thread back.

use super::{Column, ColumnRun, SweepOptions, Yield};
use crate::sim::{LANES, SimError, Simulator, run_lanes};

/// One column for [`run_columns`]: its simulator (θν in its parameters, or
/// why it could not be made) and where its orbit starts, or the paused run
/// it resumes.
pub struct ColumnJob<'s> {
    pub sim: Result<&'s Simulator, SimError>,
    pub theta_nu: f64,
    pub start: f64,
    /// The neighbour's slow cycle's period ([`Handover`]).
    pub slow_period: Option<usize>,
    /// A column paused part-way by an earlier [`run_columns`], continued
    /// from where it stopped (`start` and `slow_period` are then unused).
    pub resume: Option<PausedColumn>,
}

/// A column stopped between two slip cycles (or two map evaluations of a
/// cycle solve) because its host wanted the thread back ([`run_columns`]'s
/// `pause`). Resumed, it goes on exactly as if it had not stopped: the same
/// cycles, bit for bit.
pub struct PausedColumn(ColumnRun);

/// How a column left its lane: finished, or paused to be resumed later.
pub enum LaneEnd {
    Finished(Column),
    Paused(PausedColumn),
}

/// Runs columns on the lanes of [`run_lanes`] (several columns' slips
/// stepped together on this thread, each column's orbit bitwise what
/// [`Column::run`] gives). `next(lane, ended)` is called with `None`
/// once per lane for its first column, then with each column the lane
/// finishes or pauses, and returns the lane's next column or `None` to
/// retire it. `cancel` is polled once a cycle in each lane; a cancelled
/// column is handed to `next` with `SimError::Cancelled`. `yielding` is
/// asked before each cycle (or heavy piece) of an unfinished column that
/// has run at least one cycle in this call (so every call moves on), and
/// between two map evaluations of a cycle solve: when it says stop, the
/// column is handed to `next` as [`LaneEnd::Paused`] instead of going on.
pub fn run_columns<'s>(
    opts: &SweepOptions,
    cancel: &dyn Fn() -> bool,
    yielding: &dyn Yield,
    mut next: impl FnMut(usize, Option<LaneEnd>) -> Option<ColumnJob<'s>>,
) {
    let mut current: [Option<(&'s Simulator, ColumnRun)>; LANES] = std::array::from_fn(|_| None);
    let mut moved = [false; LANES];
    run_lanes(|lane, result| {
        let mut ended = None;
        if let (Some((sim, run)), Some(r)) = (&mut current[lane], result) {
            run.take(sim, r);
            moved[lane] = true;
        }
        loop {
            if let Some((sim, run)) = &mut current[lane] {
                let stop = || yielding.pause() || (run.heavy_due() && yielding.defer_heavy());
                // A cycle solve goes on one map evaluation at a time and
                // pauses between two like the cycles do.
                if !run.done && ((moved[lane] && stop()) || !run.heavy_step(sim, yielding, cancel))
                {
                    ended = current[lane]
                        .take()
                        .map(|(_, run)| LaneEnd::Paused(PausedColumn(run)));
                } else if let Some(theta) = run.next_onset(sim, cancel) {
                    return Some((*sim, theta, 0.0));
                } else {
                    ended = current[lane]
                        .take()
                        .map(|(_, run)| LaneEnd::Finished(run.finish()));
                }
            }
            let job = next(lane, ended.take())?;
            moved[lane] = false;
            match (job.sim, job.resume) {
                (Ok(sim), Some(PausedColumn(run))) => current[lane] = Some((sim, run)),
                (Ok(sim), None) => {
                    let run = ColumnRun::new(sim, job.start, job.slow_period, opts);
                    current[lane] = Some((sim, run));
                }
                (Err(e), _) => {
                    ended = Some(LaneEnd::Finished(Column::failed(
                        job.theta_nu,
                        job.start,
                        e,
                    )));
                }
            }
        }
    });
}
