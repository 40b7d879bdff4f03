//! Every attractor and basin at one parameter point, from f itself with no
//! orbit budget (docs/attractors.md): set-oriented numerics on the
//! verified interpolant of f over the whole exit arc (Dellnitz–Junge's
//! subdivision, Ulam's method).
//!
//! 1. f is built over the arc as a verified interpolant (`arc`), with its
//!    error bound ε.
//! 2. The arc is covered by cells; a cell has an edge to every cell its
//!    image (the enclosure of f over it, widened by ε) meets (`graph`).
//! 3. The graph's closed strongly connected components hold the
//!    attractors. Each is subdivided until it is proved to be the
//!    trapping region of one stable cycle (a contraction of f^p over its
//!    clusters), or its cells reach the resolution asked for, or the cell
//!    budget runs out (`search`); so are the cells that reach more than one of them
//!    (the basin boundary).
//! 4. Then exact (`classify`, `verdict`): a cycle by Newton on the integrated map; a
//!    set that holds no stable cycle, by its invariant density on its
//!    cells (Ulam) and λ = ∫ ln|f'| dμ beside a long orbit's time average.
//!    Where the two disagree, or λ ≤ 0, it is not called chaotic.
//!
//! A cell's basin is the closed component every path from it ends in;
//! cells whose paths end in more than one are the basin boundary at that
//! resolution.

pub mod arc;
mod classify;
mod density;
pub mod events;
mod graph;
mod search;
pub mod tracks;
mod verdict;

pub use arc::{ArcBuild, ArcError, ArcMap};

/// The one orbit `attractors`' cost is measured against (benches, docs):
/// 400 transient + 128 kept iterates, the paper's budget.
pub const TRANSIENT: usize = 400;
pub const KEEP: usize = 128;

use graph::CellGraph;
use search::Search;
use verdict::classify_closed;

use super::{Layout, SimError, Simulator};

/// What the cell graph is asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellOptions {
    /// Equal cells the arc starts with.
    pub initial_cells: usize,
    /// The finest cell width subdivision goes to (radians).
    pub resolution: f64,
    /// The most cells in all. (The arc's interpolant has its own budget of
    /// map evaluations, fixed in `arc.rs`: no option sets it.)
    pub max_cells: usize,
    /// A chaotic set's invariant density (Ulam) and λ from it; without it
    /// (a diagram's column), λ from a shorter orbit.
    pub density: bool,
    /// The finest grid the density is computed on (cells over the set's
    /// hull), doubled up to from 4 096 until λ is steady.
    pub density_cells: usize,
}

impl CellOptions {
    /// For one column of a diagram or one cell of a grid: cells to 1e-5
    /// rad at most, no density.
    pub fn column() -> Self {
        CellOptions {
            initial_cells: 1024,
            resolution: 1e-5,
            max_cells: 8_192,
            density: false,
            ..CellOptions::default()
        }
    }
}

impl Default for CellOptions {
    fn default() -> Self {
        CellOptions {
            initial_cells: 1024,
            resolution: 1e-6,
            max_cells: 1 << 16,
            density: true,
            density_cells: 1 << 16,
        }
    }
}

/// How an attractor's label was decided.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// f^p contracts its closed set onto the cycle: the set holds nothing
    /// else.
    Proved,
    /// A stable cycle (Newton, |m| < 1) in a closed set that the
    /// resolution did not shrink onto it: another attractor may hide in
    /// the rest of the set.
    CycleInSet,
    /// λ > 0 from the density and from the orbit, and they agree.
    Chaotic,
    /// Neither: why, in words.
    Undecided(String),
}

/// The invariant density of a chaotic attractor, on equal bins.
#[derive(Clone, Debug, PartialEq)]
pub struct Density {
    pub from: f64,
    pub to: f64,
    /// Probabilities per bin, summing to 1.
    pub values: Vec<f64>,
}

/// One attractor.
#[derive(Clone, Debug, PartialEq)]
pub struct Attractor {
    /// The period, or `None` for an aperiodic set.
    pub period: Option<usize>,
    /// A cycle's points; an aperiodic set's smallest and largest θ.
    pub points: Vec<f64>,
    /// A cycle's multiplier.
    pub multiplier: Option<f64>,
    /// ln|m|/p for a cycle; the long orbit's time average otherwise.
    pub lyapunov: Option<f64>,
    /// The time average's batch-means standard error.
    pub lyapunov_stderr: Option<f64>,
    /// λ = ∫ ln|f'| dμ from the invariant density (aperiodic sets).
    pub lyapunov_from_density: Option<f64>,
    /// Its discretisation error: the largest change over the last two
    /// doublings of the density's grid.
    pub lyapunov_density_error: Option<f64>,
    pub density: Option<Density>,
    /// The basin's share of the arc's length.
    pub basin_fraction: f64,
    /// The closed set of cells, as intervals of θ.
    pub cover: Vec<(f64, f64)>,
    /// Points on it to draw: a cycle's points, or the last iterates of the
    /// orbit that told it.
    pub iterates: Vec<f64>,
    pub verdict: Verdict,
}

/// A stretch of the arc and the attractor it goes to (an index into
/// [`Found::attractors`]), or `None` where it reaches more than one at
/// this resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Basin {
    pub from: f64,
    pub to: f64,
    pub attractor: Option<usize>,
}

/// The cells' resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resolution {
    /// The finest and the widest cell.
    pub finest: f64,
    pub widest: f64,
    /// The map's error bound ε the images are widened by.
    pub eps: f64,
    pub cells: usize,
    /// Whether the cell budget stopped subdivision before the resolution
    /// asked for was reached where it was wanted.
    pub budget_hit: bool,
    /// Whether the budget of nodes added where no series resolves f
    /// ([`arc::NODE_EVALUATIONS`]) stopped a refinement there.
    pub nodes_capped: bool,
}

/// Everything at one point.
#[derive(Clone, Debug, PartialEq)]
pub struct Found {
    pub attractors: Vec<Attractor>,
    pub basins: Vec<Basin>,
    pub resolution: Resolution,
    /// The share of the arc in no single basin.
    pub boundary_fraction: f64,
    /// The part of that share where f could not be enclosed (cells over
    /// nodes that fail the enclosure test: `arc::nodes`), so that it is
    /// boundary whatever the resolution.
    pub unenclosed_fraction: f64,
    /// Map evaluations (the interpolant's and Newton's) and right-hand
    /// sides.
    pub map_evaluations: u64,
    /// Where f's interpolant over the arc put its pieces: a neighbouring
    /// column's run starts from it ([`AttractorsRun::starting_from`]).
    pub layout: Layout,
}

/// Every attractor and basin at `sim`'s parameters (see the module's doc).
pub fn attractors(
    sim: &Simulator,
    opts: &CellOptions,
    cancel: &dyn Fn() -> bool,
) -> Result<Found, AttractorError> {
    let mut run = AttractorsRun::new(sim, opts);
    loop {
        if let Some(done) = run.advance(cancel) {
            return done;
        }
    }
}

/// The loosest tolerance the cell graph integrates at: its enclosures
/// are widened by 10 × the tolerance, and a cell is made no narrower than
/// 100 of those, so at a looser one (the window's Auto setting for where
/// a diagram's dots land, 1e-5 to 1e-4) the cells could not shrink onto
/// a cycle at all.
pub const GRAPH_RTOL: f64 = 1e-10;

/// `sim` with an adaptive method's tolerance tightened to
/// [`GRAPH_RTOL`] where it is looser (the parameters and method kept).
pub fn graph_simulator(sim: &Simulator) -> Simulator {
    let mut s = *sim.settings();
    if !s.method.is_adaptive() || s.rtol <= GRAPH_RTOL {
        return *sim;
    }
    s.atol *= GRAPH_RTOL / s.rtol;
    s.rtol = GRAPH_RTOL;
    Simulator::new(*sim.params(), s).unwrap_or(*sim)
}

/// [`attractors`] one piece at a time, so that a host on a slice of time
/// (the browser's) can stop between two and go on later with the same
/// result bit for bit. The pieces: the interpolant of f over the arc (in
/// pieces of a few ms: [`ArcBuild`]), each level of subdivision (`cancel` polled before it), each closed set's
/// verdict, and the basins.
pub struct AttractorsRun {
    sim: Simulator,
    opts: CellOptions,
    /// A neighbouring column's interpolant layout to start f's from.
    layout: Option<Layout>,
    stage: Stage,
}

enum Stage {
    Start,
    Arc(Box<ArcBuild>),
    Search(Box<Search>),
    Classify(Box<Classifying>),
    Done,
}

/// The search's outcome, its closed sets judged one at a time.
struct Classifying {
    search: Search,
    closed: Vec<search::Closed>,
    comps: graph::Components,
    labels: Vec<Option<usize>>,
    known: Vec<classify::Orbit>,
    found: Vec<Attractor>,
    /// A chaotic set's density in progress.
    pending: Option<Box<verdict::Pending>>,
}

impl Attractor {
    /// Its stability in words, the same in the command line, the window
    /// and the figures' CSV: a cycle's multiplier to six decimals (Newton
    /// at the graph's 1e-10), a chaotic set's λ from the density and from
    /// an orbit, each to the digits its error allows (`+-`).
    pub fn stability(&self) -> String {
        use crate::text::with_error;
        let err = |e: Option<f64>| e.unwrap_or(f64::INFINITY);
        match (
            self.period,
            self.multiplier,
            self.lyapunov,
            self.lyapunov_from_density,
        ) {
            (Some(_), Some(m), _, _) => format!("multiplier {m:.6}"),
            (_, _, Some(l), Some(d)) => format!(
                "lyapunov {} from the density, {} from an orbit",
                with_error(d, err(self.lyapunov_density_error)),
                with_error(l, err(self.lyapunov_stderr)),
            ),
            (_, _, Some(l), None) => {
                format!(
                    "lyapunov {} from an orbit",
                    with_error(l, err(self.lyapunov_stderr))
                )
            }
            _ => "no exponent".into(),
        }
    }
}

impl AttractorsRun {
    /// The search at `sim`'s parameters, nothing computed.
    pub fn new(sim: &Simulator, opts: &CellOptions) -> Self {
        AttractorsRun {
            sim: graph_simulator(sim),
            opts: *opts,
            layout: None,
            stage: Stage::Start,
        }
    }

    /// The run with f's interpolant started from `layout`, a neighbouring
    /// column's ([`Found::layout`]): its pieces are where the build starts,
    /// and each is settled and checked as in a build from nothing
    /// (`InterpolantBuild::start_from`), so the guarantees are the same
    /// and only the work changes.
    pub fn starting_from(mut self, layout: Option<Layout>) -> Self {
        self.layout = layout;
        self
    }

    /// One piece and `None`, or, once done, what was found.
    pub fn advance(&mut self, cancel: &dyn Fn() -> bool) -> Option<Result<Found, AttractorError>> {
        match self.piece(cancel) {
            Ok(None) => None,
            Ok(Some(found)) => {
                self.stage = Stage::Done;
                Some(Ok(found))
            }
            Err(e) => {
                self.stage = Stage::Done;
                Some(Err(e))
            }
        }
    }

    fn piece(&mut self, cancel: &dyn Fn() -> bool) -> Result<Option<Found>, AttractorError> {
        match std::mem::replace(&mut self.stage, Stage::Done) {
            Stage::Start => {
                let build = ArcBuild::start_from(&self.sim, self.layout.as_ref())?;
                self.stage = Stage::Arc(Box::new(build));
            }
            // Not polled for a cancel: `cancel` counts as a cycle on the
            // hosts, and the first level polls it.
            Stage::Arc(mut build) => {
                if !build.advance()? {
                    self.stage = Stage::Arc(build);
                    return Ok(None);
                }
                let map = build.finish();
                let g = CellGraph::uniform(&map, self.opts.initial_cells.max(2));
                self.stage = Stage::Search(Box::new(Search::new(self.sim, self.opts, map, g)));
            }
            Stage::Search(mut search) => {
                // Polled once a level (not in a closed set's decision).
                if !search.deciding() && cancel() {
                    return Err(AttractorError::Sim(SimError::Cancelled));
                }
                match search.level()? {
                    None => self.stage = Stage::Search(search),
                    Some((closed, comps, labels)) => {
                        let known = search.settled.drain(..).map(|(_, o)| o).collect();
                        let found = Vec::with_capacity(closed.len());
                        self.stage = Stage::Classify(Box::new(Classifying {
                            search: *search,
                            closed,
                            comps,
                            labels,
                            known,
                            found,
                            pending: None,
                        }));
                    }
                }
            }
            Stage::Classify(mut c) => {
                if let Some(mut p) = c.pending.take() {
                    match p.run.advance(&c.search.map, 0) {
                        Some(d) => c.found.push(p.finish(d)),
                        None => c.pending = Some(p),
                    }
                    self.stage = Stage::Classify(c);
                    return Ok(None);
                }
                let Some(k) = c.closed.get(c.found.len()) else {
                    return Ok(Some(c.conclude()));
                };
                let s = &mut c.search;
                let judged = classify_closed(
                    &self.sim,
                    &s.map,
                    &s.g,
                    k,
                    &c.known,
                    &self.opts,
                    &mut s.spent,
                )?;
                match judged {
                    verdict::Judged::Done(a) => c.found.push(*a),
                    verdict::Judged::Density(p) => c.pending = Some(p),
                }
                self.stage = Stage::Classify(c);
            }
            Stage::Done => {}
        }
        Ok(None)
    }
}

impl Classifying {
    /// The basins, and everything found.
    fn conclude(self) -> Found {
        let Classifying {
            search,
            comps,
            labels,
            mut found,
            ..
        } = self;
        let Search {
            map,
            g,
            spent,
            budget_hit,
            ..
        } = search;
        let (basins, boundary_fraction, unenclosed_fraction) =
            basins(&g, &map, &comps, &labels, &mut found);
        let widths = (0..g.len()).map(|i| g.width(i));
        let (finest, widest) =
            widths.fold((f64::INFINITY, 0.0_f64), |(a, b), w| (a.min(w), b.max(w)));
        Found {
            attractors: found,
            basins,
            resolution: Resolution {
                finest,
                widest,
                eps: map.eps(),
                cells: g.len(),
                budget_hit,
                nodes_capped: map.nodes_capped(),
            },
            boundary_fraction,
            unenclosed_fraction,
            map_evaluations: map.spent.0 + spent.0,
            layout: map.layout().clone(),
        }
    }
}

/// The basins along the arc (runs of cells with one reachable closed set),
/// the boundary's share and the part of it not enclosed; sets each
/// attractor's basin fraction.
fn basins(
    g: &CellGraph,
    map: &ArcMap,
    comps: &graph::Components,
    labels: &[Option<usize>],
    found: &mut [Attractor],
) -> (Vec<Basin>, f64, f64) {
    let reach = g.reach(comps, labels);
    let mut unenclosed = 0.0;
    let psi = map.psi();
    let total = map.hi - map.lo;
    let mut basins: Vec<Basin> = Vec::new();
    let mut share = vec![0.0; found.len()];
    let mut boundary = 0.0;
    for v in 0..g.len() {
        let m = reach[comps.comp[v] as usize];
        let a = (m.count_ones() == 1).then(|| m.trailing_zeros() as usize);
        match a {
            Some(a) if a < share.len() => share[a] += g.width(v),
            _ => {
                boundary += g.width(v);
                if g.images[v].open {
                    unenclosed += g.width(v);
                }
            }
        }
        let (from, to) = (psi + g.bounds[v], psi + g.bounds[v + 1]);
        match basins.last_mut() {
            Some(b) if b.attractor == a => b.to = to,
            _ => basins.push(Basin {
                from,
                to,
                attractor: a,
            }),
        }
    }
    for (a, s) in found.iter_mut().zip(&share) {
        a.basin_fraction = s / total;
    }
    (basins, boundary / total, unenclosed / total)
}

/// Why the attractors could not be found.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AttractorError {
    #[error("f could not be built over the exit arc: {0}")]
    Arc(#[from] ArcError),
    #[error("{0}")]
    Sim(#[from] SimError),
}
