//! f over the whole exit arc, as the cell graph reads it: verified
//! interpolants (`sim::interpolant`) and the enclosure of f over any
//! interval, widened by the map's error ε there.
//!
//! Two tiers. The whole arc is built once to [`COARSE_TOL`] (f is smooth
//! at that scale almost everywhere: Fig. 3b's arc takes 5 pieces, where
//! 1e-9 takes 66 and 18 000 evaluations). Where the cell graph needs
//! cells narrower than about 100 ε, the stretch is built again to
//! [`FINE_TOL`] ([`ArcMap::sharpen`]) and its series replace the coarse
//! ones there.
//!
//! Everything here works in u = θ − ψ ∈ (−π/2, π/2), ψ the arc's centre,
//! where f is continuous between its jumps (θ' − ψ never wraps: every
//! iterate lies on the arc).
//!
//! The enclosure of a series piece over [s, t] is rigorous for the series:
//! with M₂ ≥ |f''| on the piece (from the coefficients, |T_k''| ≤
//! k²(k² − 1)/3), f is monotone on [s, t] when |f'(m)| > M₂ h/2 at the
//! midpoint m (h = t − s), and its range is then [f(s), f(t)]; otherwise
//! f(x) ∈ f(m) + f'(m)(x − m) ± M₂ h²/8. A stretch no series resolves (a
//! jump's bracket, a rough stretch, or the neighbourhood of a point where
//! f' is unbounded, which the builder leaves to integration) is sampled:
//! the one-sided values of its neighbours and integrated samples across
//! it, their hull widened by the largest difference between neighbouring
//! samples (a jump's bracket, 2e-10 wide: its two sides and its midpoint,
//! each on its own). Those are sampled, not bounded: docs/attractors.md
//! says so.

use std::f64::consts::FRAC_PI_2;

mod build;
mod nodes;

use crate::sim::interpolant::{InterpolantError, Layout, chebyshev};
use crate::sim::{SimError, Simulator};
use nodes::Node;

pub use build::{ArcBuild, Sharpening};

/// How far inside the arc's ends the cells start: at the ends the surface
/// moves along C. An image that falls into these strips is counted in
/// the nearest cell.
pub const EDGE: f64 = 1e-6;

/// The whole arc's interpolant tolerance (radians).
pub const COARSE_TOL: f64 = 1e-6;

/// A sharpened stretch's tolerance.
pub const FINE_TOL: f64 = 1e-9;

/// An interval [lo, hi] of u.
pub type Span = [f64; 2];

/// A piece as the enclosures use it.
#[derive(Clone, Debug)]
enum Part {
    Series {
        /// The series' interval (x = ±1 at its ends).
        a: f64,
        b: f64,
        /// The stretch of it this part covers.
        from: f64,
        to: f64,
        map: std::sync::Arc<[f64]>,
        derivative: std::sync::Arc<[f64]>,
        /// M₂ ≥ |f''(u)| on [a, b].
        curvature: f64,
        /// The error bound its images are widened by.
        eps: f64,
    },
    /// A stretch left to integration, enclosed from its nodes ([`nodes`]),
    /// increasing in u; `own` is the integrated map's error at a node,
    /// and `fine` says which simulator evaluates new ones.
    Sampled {
        from: f64,
        to: f64,
        nodes: Vec<Node>,
        own: f64,
        fine: bool,
    },
}

impl Part {
    fn from(&self) -> f64 {
        match self {
            Part::Series { from, .. } | Part::Sampled { from, .. } => *from,
        }
    }
    fn to(&self) -> f64 {
        match self {
            Part::Series { to, .. } | Part::Sampled { to, .. } => *to,
        }
    }
    /// The part restricted to [lo, hi] (which must meet it).
    fn clip(&self, lo: f64, hi: f64) -> Part {
        let mut p = self.clone();
        match &mut p {
            Part::Series { from, to, .. } | Part::Sampled { from, to, .. } => {
                *from = from.max(lo);
                *to = to.min(hi);
            }
        }
        p
    }
}

/// f over the arc, with enclosures (see the module's doc).
#[derive(Clone, Debug)]
pub struct ArcMap {
    sim: Simulator,
    psi: f64,
    parts: Vec<Part>,
    starts: Vec<f64>,
    /// The covered interval of u.
    pub lo: f64,
    pub hi: f64,
    /// The whole arc's build runs on this one: an adaptive method's
    /// tolerance loosened to [`COARSE_RTOL`] (its own error 1e-7 is a
    /// tenth of [`COARSE_TOL`]; 1.8× fewer steps than 1e-10).
    coarse: Simulator,
    /// The integrated map's own error (10× an adaptive method's
    /// tolerance, 1e-9 for the fixed-step methods), part of every ε:
    /// the coarse tier's and the sharpened one's.
    own: f64,
    own_coarse: f64,
    /// Stretches built to [`FINE_TOL`].
    sharp: Vec<Span>,
    /// Where the whole arc's interpolant put its pieces: a neighbouring
    /// column starts from it ([`ArcBuild::start_from`]).
    layout: Layout,
    /// Map evaluations and right-hand sides spent.
    pub spent: (u64, u64),
    /// The largest error the interpolants' checks measured.
    pub max_error: f64,
    /// Nodes added on the cell graph's demand, and whether their budget
    /// ran out.
    node_evaluations: usize,
    nodes_capped: bool,
}

/// The most nodes the cell graph may add to the stretches left to
/// integration ([`ArcMap::add_nodes`]).
pub const NODE_EVALUATIONS: usize = 20_000;

/// The two nodes round u (the first or last two beyond the ends).
fn around(nodes: &[Node], u: f64) -> Option<(&Node, &Node)> {
    if nodes.len() < 2 {
        return None;
    }
    let k = nodes
        .partition_point(|n| n.u <= u)
        .clamp(1, nodes.len() - 1);
    Some((&nodes[k - 1], &nodes[k]))
}

/// A cell's image and the bound on |f'| over it.
#[derive(Clone, Debug, Default)]
pub struct Image {
    /// Disjoint spans of u, increasing.
    pub spans: Vec<Span>,
    /// max |f'| over the cell (infinite where it holds a sampled stretch).
    pub slope: f64,
    /// The largest ε its spans were widened by.
    pub eps: f64,
    /// Where one series covers the cell: f at its ends and f' at its
    /// midpoint (Ulam's chain reads them instead of evaluating again).
    pub series: Option<SeriesValues>,
    /// Part of the cell lies between nodes that enclose nothing
    /// (`arc::nodes`): its image is the whole arc.
    pub open: bool,
}

/// f at a cell's ends and f' at its midpoint, from one series.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeriesValues {
    pub ends: [f64; 2],
    pub mid_slope: f64,
}

/// The adaptive methods' tolerance for the whole arc's build (the
/// user's, where tighter, is kept for sharpened stretches and Newton).
pub const COARSE_RTOL: f64 = 1e-8;

/// The most map evaluations the whole arc's build may take; past it, what
/// is unresolved is sampled.
const COARSE_EVALUATIONS: usize = 6_000;

impl ArcMap {
    /// Builds f over the arc less [`EDGE`] at each end to [`COARSE_TOL`],
    /// all at once ([`ArcBuild`] in pieces).
    pub fn build(sim: &Simulator) -> Result<Self, ArcError> {
        let mut build = ArcBuild::start(sim)?;
        while !build.advance()? {}
        Ok(build.finish())
    }

    /// The map with no parts yet, and the coarse tier's simulator.
    fn empty(sim: &Simulator) -> Result<Self, ArcError> {
        let psi = crate::model::exit_arc(sim.params().kappa, sim.params().theta_nu).0;
        let settings = sim.settings();
        let own_of = |s: &crate::integrate::SolverSettings| {
            if s.method.is_adaptive() {
                10.0 * s.rtol
            } else {
                1e-9
            }
        };
        let mut loose = *settings;
        if loose.method.is_adaptive() && loose.rtol < COARSE_RTOL {
            loose.atol *= COARSE_RTOL / loose.rtol;
            loose.rtol = COARSE_RTOL;
        }
        let coarse = Simulator::new(*sim.params(), loose)?;
        Ok(ArcMap {
            sim: *sim,
            coarse,
            own: own_of(settings),
            own_coarse: own_of(&loose),
            psi,
            parts: Vec::new(),
            starts: Vec::new(),
            lo: -FRAC_PI_2 + EDGE,
            hi: FRAC_PI_2 - EDGE,
            sharp: Vec::new(),
            spent: (0, 0),
            layout: Layout::default(),
            max_error: 0.0,
            node_evaluations: 0,
            nodes_capped: false,
        })
    }

    /// Builds [lo, hi] again to [`FINE_TOL`] (within `max_evaluations`),
    /// its parts replacing the coarse ones there, all at once
    /// ([`Self::sharpen_start`] in pieces). Whether anything was sharpened
    /// (a stretch already sharp is left alone).
    pub fn sharpen(&mut self, lo: f64, hi: f64, max_evaluations: usize) -> Result<bool, ArcError> {
        let Some(mut s) = self.sharpen_start(lo, hi, max_evaluations)? else {
            return Ok(false);
        };
        while !self.sharpen_step(&mut s)? {}
        Ok(true)
    }

    /// Whether [lo, hi] was sharpened already.
    pub fn is_sharp(&self, lo: f64, hi: f64) -> bool {
        let (lo, hi) = (lo.max(self.lo), hi.min(self.hi));
        self.sharp.iter().any(|s| s[0] <= lo && hi <= s[1])
    }

    /// Where the whole arc's interpolant put its pieces (the coarse
    /// tier's: sharpened stretches are rebuilt where a column needs them).
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The arc's centre ψ (u = θ − ψ).
    pub fn psi(&self) -> f64 {
        self.psi
    }

    /// The coarse ε (the whole arc's).
    pub fn eps(&self) -> f64 {
        COARSE_TOL + self.own_coarse
    }

    /// ε at u.
    pub fn eps_at(&self, u: f64) -> f64 {
        match &self.parts[self.index(u)] {
            Part::Series { eps, .. } => *eps,
            Part::Sampled { own, .. } => *own,
        }
    }

    /// f(u) and f'(u) from the series, or between two nodes with slopes
    /// (cubic Hermite); `None` next to a node without one.
    pub fn eval(&self, u: f64) -> Option<(f64, f64)> {
        match &self.parts[self.index(u)] {
            Part::Series {
                a,
                b,
                map,
                derivative,
                ..
            } => {
                let x = ((2.0 * u - a - b) / (b - a)).clamp(-1.0, 1.0);
                Some((
                    chebyshev::clenshaw(map, x),
                    chebyshev::clenshaw(derivative, x),
                ))
            }
            Part::Sampled { nodes, .. } => {
                let (p, q) = around(nodes, u)?;
                (p.d.is_finite() && q.d.is_finite()).then(|| nodes::hermite(p, q, u))
            }
        }
    }

    /// f(u) and f'(u) anywhere: [`Self::eval`], or next to a node without
    /// a slope the chord between the neighbouring nodes (for orbits that
    /// only classify; cycles are solved on the integrated map).
    pub fn eval_any(&self, u: f64) -> (f64, f64) {
        if let Some(v) = self.eval(u) {
            return v;
        }
        match &self.parts[self.index(u)] {
            Part::Sampled { nodes, .. } => match around(nodes, u) {
                Some((p, q)) => nodes::hermite(p, q, u),
                None => (u, 1.0),
            },
            Part::Series { .. } => (u, 1.0),
        }
    }

    /// Nodes at each of `us` that lies inside a stretch left to
    /// integration (not a jump's bracket) and is not a node already, so
    /// that cells bounded there are enclosed by their own nodes: the
    /// refinement the cell graph asks for where it subdivides. At most
    /// [`NODE_EVALUATIONS`] in all; whether any was added.
    pub fn add_nodes(&mut self, us: &[f64]) -> Result<bool, ArcError> {
        let mut added = false;
        let psi = self.psi;
        for &u in us {
            if self.node_evaluations >= NODE_EVALUATIONS {
                self.nodes_capped = true;
                break;
            }
            let i = self.index(u);
            let Part::Sampled {
                from,
                to,
                nodes,
                fine,
                ..
            } = &self.parts[i]
            else {
                continue;
            };
            if !(u > *from && u < *to) || *to - *from < 1e-8 {
                continue;
            }
            let k = nodes.partition_point(|n| n.u < u);
            let near = |j: usize| {
                nodes
                    .get(j)
                    .is_some_and(|n: &Node| (n.u - u).abs() <= 1e-15)
            };
            if near(k) || (k > 0 && near(k - 1)) {
                continue;
            }
            let sim = if *fine { self.sim } else { self.coarse };
            let node = Node::at(&sim, psi, u, &mut self.spent)?;
            self.node_evaluations += 1;
            if let Part::Sampled { nodes, .. } = &mut self.parts[i] {
                nodes.insert(k, node);
            }
            added = true;
        }
        Ok(added)
    }

    /// Whether the nodes' budget stopped a refinement.
    pub fn nodes_capped(&self) -> bool {
        self.nodes_capped
    }

    /// The part holding u (the nearest at the ends).
    fn index(&self, u: f64) -> usize {
        self.starts
            .partition_point(|&s| s <= u)
            .saturating_sub(1)
            .min(self.parts.len() - 1)
    }

    /// The image of [s, t] (s < t, inside the covered interval): the
    /// enclosure of f, widened by ε, and max |f'| there.
    pub fn image(&self, s: f64, t: f64) -> Image {
        let mut out = Image::default();
        let mut i = self.index(s);
        let mut parts = 0;
        while i < self.parts.len() {
            let part = &self.parts[i];
            let (a, b) = (part.from(), part.to());
            if a >= t {
                break;
            }
            let (ps, pt) = (s.max(a), t.min(b));
            if pt > ps {
                out.series = enclose(part, ps, pt, &mut out);
                parts += 1;
            }
            i += 1;
        }
        if parts != 1 {
            out.series = None;
        }
        out.spans.sort_by(|x, y| x[0].total_cmp(&y[0]));
        let mut merged: Vec<Span> = Vec::with_capacity(out.spans.len());
        for sp in out.spans {
            match merged.last_mut() {
                Some(m) if sp[0] <= m[1] => m[1] = m[1].max(sp[1]),
                _ => merged.push(sp),
            }
        }
        out.spans = merged;
        out
    }
}

/// Adds the enclosure of `part` over [s, t] to `out`; a series' values
/// at s and t and its slope at the midpoint.
fn enclose(part: &Part, s: f64, t: f64, out: &mut Image) -> Option<SeriesValues> {
    match part {
        Part::Series {
            a,
            b,
            map,
            derivative,
            curvature,
            eps,
            ..
        } => {
            let x = |u: f64| ((2.0 * u - a - b) / (b - a)).clamp(-1.0, 1.0);
            let h = t - s;
            let m = 0.5 * (s + t);
            let (fs, ft) = (
                chebyshev::clenshaw(map, x(s)),
                chebyshev::clenshaw(map, x(t)),
            );
            let dm = chebyshev::clenshaw(derivative, x(m));
            let (lo, hi) = if dm.abs() > 0.5 * curvature * h {
                (fs.min(ft), fs.max(ft))
            } else {
                let fm = chebyshev::clenshaw(map, x(m));
                let r = 0.5 * dm.abs() * h + 0.125 * curvature * h * h;
                (fm - r, fm + r)
            };
            out.spans.push([lo - eps, hi + eps]);
            out.slope = out.slope.max(dm.abs() + 0.5 * curvature * h);
            out.eps = out.eps.max(*eps);
            Some(SeriesValues {
                ends: [fs, ft],
                mid_slope: dm,
            })
        }
        Part::Sampled {
            from,
            to,
            nodes,
            own,
            ..
        } if to - from < 1e-8 || nodes.len() < 2 => {
            // A jump's bracket: the hull of its sides' values and its
            // midpoint's, widened by their spread.
            let (lo, hi) = nodes
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), n| {
                    (l.min(n.f), h.max(n.f))
                });
            let d = hi - lo;
            out.spans.push([lo - d - own, hi + d + own]);
            out.slope = f64::INFINITY;
            out.eps = out.eps.max(*own);
            None
        }
        Part::Sampled { nodes, own, .. } => {
            enclose_nodes(nodes, *own, s, t, out);
            None
        }
    }
}

/// Adds the enclosure from `nodes` (each value within `own`) over [s, t]
/// to `out`: the whole arc where an interval between them is open.
fn enclose_nodes(nodes: &[Node], own: f64, s: f64, t: f64, out: &mut Image) {
    let k = nodes.partition_point(|x| x.u <= s).saturating_sub(1);
    let (mut lo, mut hi, mut slope) = (f64::INFINITY, f64::NEG_INFINITY, 0.0_f64);
    let mut open = nodes.len() < 2;
    for w in nodes[k..].windows(2) {
        if w[0].u >= t {
            break;
        }
        let (ps, pt) = (s.max(w[0].u), t.min(w[1].u));
        match nodes::between(&w[0], &w[1], ps.min(pt), pt.max(ps), own) {
            Some((l, h, d)) => {
                lo = lo.min(l);
                hi = hi.max(h);
                slope = slope.max(d);
            }
            None => open = true,
        }
    }
    if open || !(lo <= hi) {
        // Nothing is known of f here: every cell is reachable.
        out.spans.push([-FRAC_PI_2, FRAC_PI_2]);
        out.slope = f64::INFINITY;
        out.open = true;
    } else {
        out.spans.push([lo, hi]);
        out.slope = out.slope.max(slope);
    }
    out.eps = out.eps.max(own);
}

/// A series' value at u on [a, b].
fn series_at(map: &[f64], a: f64, b: f64, u: f64) -> f64 {
    chebyshev::clenshaw(map, ((2.0 * u - a - b) / (b - a)).clamp(-1.0, 1.0))
}

/// M₂ ≥ max |f''| on [a, b] for f = Σ c_k T_k(x(u)): |T_k''| ≤
/// k²(k² − 1)/3 on [−1, 1], and dx/du = 2/(b − a).
fn curvature_bound(c: &[f64], a: f64, b: f64) -> f64 {
    let s = 2.0 / (b - a);
    let sum: f64 = c
        .iter()
        .enumerate()
        .map(|(k, ck)| {
            let k = k as f64;
            ck.abs() * k * k * (k * k - 1.0) / 3.0
        })
        .sum();
    sum * s * s
}

/// Why f could not be built over the arc.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ArcError {
    #[error("{0}")]
    Interpolant(#[from] InterpolantError),
    #[error("{0}")]
    Sim(#[from] SimError),
}
