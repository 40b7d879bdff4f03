//! "What am I looking at": one paragraph per view, shown by the "?" in the
//! view's title bar, and the guided tour's steps. The text lives here only;
//! docs/gui.md carries the same paragraphs between generated markers, which
//! a test compares with this file (`tests/docs_help.rs`), so the two cannot
//! drift.

use super::settings::ViewKind;

/// The Basins view's paragraph.
const BASINS_HELP: &str = "Every attractor of the map and its basin, at each pull direction θν (one column): \
     the whole exit arc of slip onsets θ₀ (up) is coloured by the attractor an orbit \
     from there ends on, the same colour for the same attractor from column to column \
     (P1, P2, …, chaotic); grey is the basin boundary, where the cells cannot tell at \
     their resolution. Nothing is iterated for a budget: f is built over the arc as a \
     verified interpolant, the arc is covered by cells, and the attractors are the \
     closed sets of the graph of where each cell maps (oneblock attractors). Below, the \
     basin fractions stacked against θν: where two colours share a column, two \
     attractors coexist (hysteresis). Once every column is in, the marks on top say where \
     an attractor is born, dies or changes its period, and why: a fold, a flip, a border \
     of f or a crisis, located by continuation to 1e-10 or by bisection on the cells \
     (oneblock attractors --param); hover a mark or a basin to read it in a sentence. \
     Drag a box to zoom; click a column to list its attractors.";

/// The Bifurcation view's paragraph.
const BIFURCATION_HELP: &str = "A bifurcation diagram: for each pull direction θν (one column), the slip onsets θ \
     the orbit settles on after a transient. One point per column is a stable fixed \
     point (one slip repeating), two a period-2 cycle, and so on; a smear is chaos. \
     Each column starts from its neighbour's last onset, so the diagram follows one \
     attractor. The strip under it is the Lyapunov exponent λ of each column: below 0 \
     the orbit is periodic, λ = 0 where a period doubles, above 0 in chaos. With every \
     attractor on, the exit arc's cell graph shows the other attractors too \
     (magenta), where two coexist (hysteresis). Births & deaths (a θν diagram) marks \
     where each attractor is born or dies, and why (fold, flip, border collision, \
     crisis), located to 1e-8 by the Basins job over the diagram's range: the events \
     oneblock attractors --param theta-nu prints for the same columns, each a dashed \
     line with its mark at the top, named in the legend and read in a sentence on \
     hover. Find bifurcations marks each doubling \
     supercritical (a stable cycle of twice the period is born) or subcritical (an \
     unstable one: the attractor jumps), and lists a cascade's ratios δ_n, which tend \
     to Feigenbaum's 4.669. \"Diagram in\" varies κ, γ, ν or Ω instead of θν, the \
     others held at the sliders' values (κ, ν and Ω on a log axis).";

/// What view `v` shows and how it is computed, in one paragraph.
pub fn view_help(v: ViewKind) -> &'static str {
    match v {
        ViewKind::Plane => {
            "The block's path in the plane of its position (x, y), coloured by phase: blue while \
             it sticks to the moving surface and is carried along the pull direction θν (the \
             arrow), vermilion and orange while it slips. A slip starts when the spring force \
             reaches the friction threshold, on the curve C (κ²x² + y² = 1); the angle θ of that \
             onset point is what the return map iterates. In the mixed regime the critical \
             ellipse marks where a slip can begin to creep instead."
        }
        ViewKind::Block => {
            "The paper's Fig. 1a animated: the block on the moving surface, held by two springs \
             of stiffness k_x and k_y (κ = k_x/k_y), with the spring force and the friction \
             drawn as arrows. The motion is the computed trajectory: the stick phases, which last \
             hundreds to thousands of time units, are fast-forwarded, and the slips play at the \
             chosen speed."
        }
        ViewKind::Bifurcation => BIFURCATION_HELP,
        ViewKind::ReturnMap => {
            "The return map θ' = f(θ): where the next slip starts as a function of where this \
             one started, computed by integrating one stick-slip cycle per point. The orbit's \
             iterates sit on its graph; the cobweb (orange) follows them: up to the graph, \
             across to the diagonal θ' = θ, up again. A fixed point is where f crosses the \
             diagonal, stable when |f'| < 1. The Lyapunov exponent λ is the average of \
             ln|f'(θ)| along the orbit (exactly ln|m|/p on a solved p-cycle of multiplier m). \
             Tick f(θ) − θ where f hugs the diagonal (creep)."
        }
        ViewKind::Events => {
            "Every slip event of the trajectory: its size over time, the distribution of sizes \
             on log axes, and the laminar phases. A slip is creep or stick-slip by where it \
             starts (creep where γ² < κ cos²θ + sin²θ); a laminar phase is a run of creep slips \
             between two stick-slip slips, and its mean length stands beside the passage time \
             through the channel between f and the diagonal on the creep arc, computed from f. \
             Type-I scaling, mean length growing like ε^(−1/2), is fitted on demand only against \
             a tangency located by continuation (the fold of a periodic window's cycle), ε the \
             distance to it; where none is found, the view says so."
        }
        ViewKind::Numerics => {
            "The work-precision chart: for each integrator and tolerance, the error of the map \
             f(θ), one stick-slip cycle, against what it cost, measured on a fixed sample of \
             orbit points against a reference integration. The setting each view uses is marked: \
             Auto picks the cheapest one accurate enough for what the view can show."
        }
        ViewKind::Phase => {
            "The paper's Fig. 4: over a grid of pull directions θν and stiffness ratios κ, the \
             class of the attractor the map settles on: a fixed point, a period-p cycle, chaos \
             (λ > 0), or undecided. Each cell iterates the map, detects its period and, if none, \
             computes λ. With every attractor on, each cell also counts its attractors from the \
             exit arc's cell graph; a white square marks a cell with more than one (multistable), \
             and a click on it lists them: period or chaotic, multiplier or λ, basin fraction. \
             Boundaries follows the period-doubling curves FP to P2 and P2 to P4, and the fixed \
             point's fold curves (dashed), by continuation, to the precision of the solver \
             rather than of the grid, and marks the generalised flips, where a doubling turns \
             from supercritical to subcritical."
        }
        ViewKind::Basins => BASINS_HELP,
        ViewKind::TimeSeries => {
            "The last cycles against time: the position x(t) and y(t), the slip speed |v_r| (the \
             block's speed relative to the surface, 0 while it sticks) and the elastic energy \
             (κx² + y²)/2, coloured by phase, over bands shading the stick phases (blue) and \
             the slips (orange). Drag or scroll to zoom in time: a slip lasting a few time units \
             between stick phases of hundreds opens up, and creep's tiny slips show as spikes \
             of |v_r|."
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_view_has_one_paragraph() {
        for v in ViewKind::ALL {
            let t = view_help(v);
            assert!(t.len() > 200 && !t.contains('\n'), "{v:?}");
        }
    }
}
