//! A finished cell told again from the exit arc's cell graph
//! (`sim::attractors`, docs/attractors.md), with no orbit budget: an
//! undecided cell (a drift too slow, or a transient too long, for its
//! iterates) takes the class of the attractor whose basin holds its last
//! onset; with seeds, the cell counts the attractors the graph decides,
//! and a cycle the graph solved there is the cell's class whatever the
//! orbit said.

use super::{CellClass, PhaseCell};
use crate::sim::SimError;
use crate::sim::attractors::{AttractorError, Found, Verdict};

/// Tells `cell` again from the cell graph `found` at `params` (see the
/// module's doc); `count` also sets [`PhaseCell::attractors`]. A graph that
/// could not be built leaves the cell as it was, uncounted with the reason
/// in [`PhaseCell::uncounted`] when `count`; a cancel fails it. What was
/// found, when counted.
pub(super) fn tell(
    cell: &mut PhaseCell,
    found: Result<Found, AttractorError>,
    count: bool,
) -> Option<Found> {
    let found = match found {
        Ok(f) => f,
        Err(AttractorError::Sim(SimError::Cancelled)) => {
            cell.class = CellClass::Failed;
            cell.error = Some(SimError::Cancelled);
            return None;
        }
        Err(e) => {
            if count {
                cell.uncounted = Some(e.to_string());
            }
            return None;
        }
    };
    cell.iterates += found.map_evaluations;
    let decided = |v: &Verdict| !matches!(v, Verdict::Undecided(_));
    if count {
        let n = found
            .attractors
            .iter()
            .filter(|a| decided(&a.verdict))
            .count();
        cell.attractors = Some(n.max(1));
    }
    // The graph's attractor for the orbit's last onset: an undecided cell
    // takes it; with every attractor asked for (`count`), a cycle the
    // graph solved (proved, or found in its set) overrides the orbit's
    // class too: 400 + 128 iterates may not outlast a transient chaos
    // (κ = 38, θν = 1.5: a proved P12 the orbit called chaos). A chaotic
    // verdict of the graph's column (itself an orbit's) never overrides a
    // cycle the orbit settled on.
    let graph_cycle = |a: &crate::sim::attractors::Attractor| {
        matches!(a.verdict, Verdict::Proved | Verdict::CycleInSet)
    };
    if let Some(a) = found
        .basin_of(cell.theta_last)
        .and_then(|a| found.attractors.get(a))
        && decided(&a.verdict)
        && (cell.class == CellClass::Undecided || (count && graph_cycle(a)))
    {
        cell.class = match a.period {
            Some(p) => CellClass::Periodic(p),
            None => CellClass::Chaos,
        };
        cell.lyapunov = a.lyapunov;
        cell.lyapunov_stderr = a.lyapunov_stderr.filter(|_| a.period.is_none());
    }
    count.then_some(found)
}
