//! What a closed set of cells holds: a cycle proved to attract the whole
//! set (a contraction of f^p), a stable cycle found in it, or a chaotic
//! attractor with its invariant density (`density`: Ulam's method)
//! and λ = ∫ ln|f'| dμ beside the time average of a long orbit.

use super::arc::{ArcMap, Span};
use super::graph::CellGraph;
use crate::sim::cycles::{CycleOptions, solve_counting};
use crate::sim::period::{PERIOD_MAX, settled_period};
use crate::sim::{Cycle, SimError, Simulator};

/// A closed set's cells as runs of neighbouring cells: (first, last).
pub fn clusters(cells: &[usize]) -> Vec<(usize, usize)> {
    let mut out: Vec<(usize, usize)> = Vec::new();
    for &c in cells {
        match out.last_mut() {
            Some(r) if r.1 + 1 == c => r.1 = c,
            _ => out.push((c, c)),
        }
    }
    out
}

/// A proof that a closed set is the trapping region of one cycle: its p
/// clusters are permuted cyclically by f (each cluster's image meets one
/// cluster only), and Π sup|f'| over them is below 1, so f^p contracts the
/// first cluster into itself and has exactly one fixed point there, which
/// attracts the whole set. Returns p, the contraction bound, and the
/// cycle solved on the series from the first cluster (u).
pub fn contraction(g: &CellGraph, map: &ArcMap, cells: &[usize]) -> Option<(usize, f64, f64)> {
    let runs = clusters(cells);
    let p = runs.len();
    if p > PERIOD_MAX {
        return None;
    }
    let which = |c: usize| runs.iter().position(|r| r.0 <= c && c <= r.1);
    let mut next = vec![usize::MAX; p];
    let mut bound = 1.0;
    for (k, &(a, b)) in runs.iter().enumerate() {
        let mut slope: f64 = 0.0;
        for i in a..=b {
            slope = slope.max(g.images[i].slope);
            for &(x, y) in g.succ(i) {
                for j in [x as usize, y as usize] {
                    let t = which(j)?;
                    if next[k] != usize::MAX && next[k] != t {
                        return None;
                    }
                    next[k] = t;
                }
            }
        }
        bound *= slope;
    }
    if !(bound < 1.0) {
        return None;
    }
    // One cycle through all clusters.
    let (mut k, mut steps) = (0, 0);
    loop {
        k = next[k];
        steps += 1;
        if k == 0 || steps > p {
            break;
        }
    }
    if k != 0 || steps != p {
        return None;
    }
    // Newton on the series for f^p(u) = u in the first cluster.
    let (lo, hi) = (g.bounds[runs[0].0], g.bounds[runs[0].1 + 1]);
    let mut u = 0.5 * (lo + hi);
    for _ in 0..60 {
        let (mut x, mut d) = (u, 1.0);
        for _ in 0..p {
            let (fx, dx) = map.eval(x)?;
            x = fx;
            d *= dx;
        }
        let step = (x - u) / (1.0 - d);
        u = (u + step).clamp(lo, hi);
        if step.abs() < 1e-15 {
            break;
        }
    }
    Some((p, bound, u))
}

/// The p-cycle through u (in θ − ψ) solved by Newton on the integrated map.
pub fn solve(sim: &Simulator, psi: f64, u: f64, p: usize, spent: &mut (u64, u64)) -> Option<Cycle> {
    let opts = CycleOptions::for_settings(sim.settings());
    solve_counting(sim, psi + u, p, &opts, spent).ok()
}

/// What a long orbit on the series shows.
#[derive(Clone, Debug)]
pub struct Orbit {
    /// The time average of ln|f'| and its batch-means standard error.
    pub lyapunov: f64,
    pub stderr: f64,
    /// The period it settled on, if it did (with its last point, u).
    pub settled: Option<(usize, f64)>,
    /// Its last point (u).
    pub last: f64,
    /// Its last [`TAIL`] points (u).
    pub tail: Vec<f64>,
}

/// Iterates dropped and kept by [`long_orbit`]: for `attractors`, and
/// for a diagram's column (no density; λ from the orbit alone).
pub const ORBIT: (usize, usize) = (1_000, 10_000);
pub const COLUMN_ORBIT: (usize, usize) = (300, 2_000);

/// The points an orbit keeps for drawing.
pub const TAIL: usize = 256;

/// An orbit of the series from u: `lengths.0` iterates dropped, then
/// `lengths.1` with ln|f'| (in a sampled stretch, from the line between
/// its samples), all at once ([`LongOrbit`] in pieces).
pub fn long_orbit(map: &ArcMap, u: f64, lengths: (usize, usize)) -> Result<Orbit, SimError> {
    let mut run = LongOrbit::new(u, lengths);
    loop {
        if let Some(o) = run.advance(map, usize::MAX) {
            return Ok(o);
        }
    }
}

/// Batches of the kept iterates, for λ's standard error.
const BATCHES: usize = 20;

/// A [`long_orbit`] in progress.
pub struct LongOrbit {
    u: f64,
    dropped: usize,
    per: usize,
    /// Iterates done (dropped ones included).
    done: usize,
    sum: f64,
    means: Vec<f64>,
    tail: Vec<f64>,
}

impl LongOrbit {
    pub fn new(u: f64, lengths: (usize, usize)) -> Self {
        LongOrbit {
            u,
            dropped: lengths.0,
            per: (lengths.1 / BATCHES).max(TAIL),
            done: 0,
            sum: 0.0,
            means: Vec::with_capacity(BATCHES),
            tail: Vec::with_capacity(TAIL),
        }
    }

    /// At most `most` iterates more; the orbit once all are done.
    pub fn advance(&mut self, map: &ArcMap, most: usize) -> Option<Orbit> {
        let total = self.dropped + BATCHES * self.per;
        let end = total.min(self.done.saturating_add(most));
        while self.done < end {
            let (fu, d) = map.eval_any(self.u);
            let k = self.done;
            self.done += 1;
            if k < self.dropped {
                self.u = fu;
                continue;
            }
            let (b, i) = ((k - self.dropped) / self.per, (k - self.dropped) % self.per);
            self.sum += d.abs().max(1e-300).ln();
            self.u = fu;
            if b == BATCHES - 1 && i >= self.per - TAIL {
                self.tail.push(self.u);
            }
            if i == self.per - 1 {
                self.means.push(self.sum / self.per as f64);
                self.sum = 0.0;
            }
        }
        (self.done == total).then(|| self.orbit())
    }

    fn orbit(&mut self) -> Orbit {
        let means = &self.means;
        let mean = means.iter().sum::<f64>() / BATCHES as f64;
        let var = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (BATCHES - 1) as f64;
        let tail = std::mem::take(&mut self.tail);
        let settled = settled_period(&tail, 1e-9).map(|p| (p, self.u));
        Orbit {
            lyapunov: mean,
            stderr: (var / BATCHES as f64).sqrt(),
            settled,
            last: self.u,
            tail,
        }
    }
}

/// A trap round a stable cycle (its points in u): intervals I_j = x_j ±
/// r_j with f(I_j) ⊂ I_{j+1} (I_p = I_0) and Π sup_{I_j}|f'| < 1, so that
/// f^p contracts I_0 into itself: the cycle is the one attractor in the
/// I_j. Found by growing r_0 from what ε alone demands. Returns the pairs
/// (I_j, I_{j+1}).
pub fn trap(map: &ArcMap, xs: &[f64]) -> Option<Vec<(Span, Span)>> {
    let p = xs.len();
    let run = |r0: f64| -> Option<(Vec<f64>, f64)> {
        let mut r = Vec::with_capacity(p + 1);
        r.push(r0);
        let mut product = 1.0;
        for j in 0..p {
            let (x, rj) = (xs[j], r[j]);
            let im = map.image(x - rj, x + rj);
            if im.spans.len() != 1 || !im.slope.is_finite() {
                return None;
            }
            product *= im.slope;
            let next = xs[(j + 1) % p];
            let s = im.spans[0];
            if !(s[0] <= next && next <= s[1]) {
                return None;
            }
            r.push((next - s[0]).max(s[1] - next));
        }
        Some((r, product))
    };
    let (r, _) = run(1e-13)?;
    let mut r0 = (4.0 * r[p]).max(1e-10);
    while r0 < 0.05 {
        let (r, product) = run(r0)?;
        if r[p] <= r0 && product < 1.0 {
            return Some(
                (0..p)
                    .map(|j| {
                        let k = (j + 1) % p;
                        let to = if k == 0 { r0 } else { r[k] };
                        ([xs[j] - r[j], xs[j] + r[j]], [xs[k] - to, xs[k] + to])
                    })
                    .collect(),
            );
        }
        r0 *= 2.0;
    }
    None
}
