//! A chaotic attractor's invariant density by Ulam's method on a uniform
//! grid over its hull, and λ = ∫ ln|f'| dμ from it, refined until it is
//! stable, with its discretisation error.
//!
//! Cell i sends to cell j the share of it that f, linear between the
//! cell's ends, maps into j; μ is the stationary vector of that chain (a
//! lazy chain, so that a density cycling over bands converges), and λ =
//! Σ μᵢ ⟨ln|f'|⟩ᵢ with ⟨ln|f'|⟩ᵢ the exact mean of ln|ℓ| over the cell for
//! ℓ the line through f' at its ends (finite where f' vanishes inside).
//!
//! Ulam's λ converges as the cells shrink, but neither monotonically nor at
//! a known rate where λ is small (a weakly chaotic set spends long
//! stretches near unstable cycles, which the chain's diffusion smears). So
//! the grid is doubled from [`FIRST`] cells up to the most asked for, and
//! λ is reported at the finest grid with the largest change over the last
//! two doublings as its discretisation error.

use super::ArcMap;

/// The first grid.
const FIRST: usize = 4096;

/// Power iterations at most per grid.
const ITERATIONS: usize = 20_000;

/// λ from the density, its discretisation error and the density on the
/// finest grid.
#[derive(Clone, Debug, PartialEq)]
pub struct DensityLambda {
    pub lambda: f64,
    pub error: f64,
    /// μ per cell of the finest grid over [lo, hi] (in u).
    pub mu: Vec<f64>,
    /// Each grid's (cells, λ), coarse to fine.
    pub levels: Vec<(usize, f64)>,
}

/// λ from the density on the closed set `cover` (intervals of u,
/// increasing): grids over its hull from [`FIRST`] cells doubled up to
/// `most`, each keeping the cells that meet the cover, until two
/// doublings in a row change λ by less than `target`. Computed a bounded
/// piece at a time (f at a chunk of a grid's bounds, a grid's chain
/// built, or some power iterations), so that a host on a slice of time
/// (the page's frame) can pause between any two with the same result bit
/// for bit.
pub struct DensityRun {
    cover: Vec<(f64, f64)>,
    lo: f64,
    hi: f64,
    most: usize,
    target: f64,
    /// The grid being computed: its cells, and f and f' at its bounds so
    /// far.
    n: usize,
    ends: Vec<(f64, f64)>,
    /// The coarser grid's bounds and density.
    coarse_ends: Vec<(f64, f64)>,
    coarse_mu: Option<Vec<f64>>,
    chain: Option<Chain>,
    levels: Vec<(usize, f64)>,
}

/// A grid's chain and its power iteration in progress.
struct Chain {
    starts: Vec<usize>,
    entries: Vec<(u32, f64)>,
    logs: Vec<f64>,
    mu: Vec<f64>,
    next: Vec<f64>,
    done: usize,
}

/// Bounds evaluated, or chain entries updated, in one piece.
const PIECE_WORK: usize = 1 << 18;

impl DensityRun {
    pub fn new(cover: &[(f64, f64)], most: usize, target: f64) -> Self {
        DensityRun {
            cover: cover.to_vec(),
            lo: cover[0].0,
            hi: cover[cover.len() - 1].1,
            most: most.max(FIRST),
            target,
            n: FIRST,
            ends: Vec::new(),
            coarse_ends: Vec::new(),
            coarse_mu: None,
            chain: None,
            levels: Vec::new(),
        }
    }

    /// One piece of about `work` units at most ([`PIECE_WORK`] when
    /// smaller is asked); the result once done.
    pub fn advance(&mut self, map: &ArcMap, work: usize) -> Option<DensityLambda> {
        let work = work.max(PIECE_WORK);
        let n = self.n;
        if self.ends.len() <= n {
            // f and f' at the grid's bounds: the coarser grid's are every
            // other one.
            let end = (self.ends.len() + work / 64).min(n + 1);
            for i in self.ends.len()..end {
                let e = match self.coarse_ends.get(i / 2).filter(|_| i % 2 == 0) {
                    Some(&e) => e,
                    None => map.eval_any(self.lo + (self.hi - self.lo) * i as f64 / n as f64),
                };
                self.ends.push(e);
            }
            return None;
        }
        let Some(chain) = self.chain.as_mut() else {
            self.chain = Some(self.build());
            return None;
        };
        let steps = (work / (chain.entries.len() + n).max(1)).max(1);
        if !chain.iterate(steps) {
            return None;
        }
        let chain = self.chain.take()?;
        let lambda = chain.mu.iter().zip(&chain.logs).map(|(m, l)| m * l).sum();
        self.levels.push((n, lambda));
        self.coarse_mu = Some(chain.mu);
        self.coarse_ends = std::mem::take(&mut self.ends);
        let k = self.levels.len();
        let steady = k >= 3
            && (self.levels[k - 1].1 - self.levels[k - 2].1).abs() < self.target
            && (self.levels[k - 2].1 - self.levels[k - 3].1).abs() < self.target;
        if !steady && n * 2 <= self.most {
            self.n *= 2;
            return None;
        }
        let levels = std::mem::take(&mut self.levels);
        let k = levels.len();
        let error = (1..k)
            .rev()
            .take(2)
            .map(|i| (levels[i].1 - levels[i - 1].1).abs())
            .fold(0.0_f64, f64::max);
        Some(DensityLambda {
            lambda: levels[k - 1].1,
            // One grid alone says nothing of its error.
            error: if k > 1 { error } else { f64::INFINITY },
            mu: self.coarse_mu.take().unwrap_or_default(),
            levels,
        })
    }

    /// The chain of the grid whose bounds are computed, its iteration
    /// started from the coarser grid's density.
    fn build(&self) -> Chain {
        let (starts, entries, logs, inside) =
            ulam_chain((self.lo, self.hi, &self.cover), &self.ends);
        let n = inside.len();
        let members = inside.iter().filter(|&&x| x).count().max(1);
        let mu: Vec<f64> = match &self.coarse_mu {
            Some(w) if 2 * w.len() == n => (0..n)
                .map(|i| if inside[i] { 0.5 * w[i / 2] } else { 0.0 })
                .collect(),
            _ => inside
                .iter()
                .map(|&x| if x { 1.0 / members as f64 } else { 0.0 })
                .collect(),
        };
        Chain {
            starts,
            entries,
            logs,
            next: vec![0.0; n],
            mu,
            done: 0,
        }
    }
}

/// The mean of ln|ℓ| over a cell for ℓ linear from `a` to `b`.
fn log_mean(a: f64, b: f64) -> f64 {
    let big = a.abs().max(b.abs());
    if !(big > 0.0) {
        return 1e-300_f64.ln();
    }
    if (b - a).abs() <= 1e-9 * big {
        return (0.5 * (a + b)).abs().max(1e-300).ln();
    }
    let prim = |y: f64| if y == 0.0 { 0.0 } else { y * y.abs().ln() - y };
    (prim(b) - prim(a)) / (b - a)
}

/// A chain as rows `entries[starts[i]..starts[i + 1]]`, each cell's mean
/// of ln|f'|, and which cells meet the cover.
type Rows = (Vec<usize>, Vec<(u32, f64)>, Vec<f64>, Vec<bool>);

/// Ulam's chain on equal cells over [lo, hi] (f and f' at their bounds,
/// `ends`), those meeting `cover`.
fn ulam_chain((lo, hi, cover): (f64, f64, &[(f64, f64)]), ends: &[(f64, f64)]) -> Rows {
    let n = ends.len() - 1;
    let h = (hi - lo) / n as f64;
    let cell = |v: f64| (((v - lo) / h).floor().max(0.0) as usize).min(n - 1);
    let mut inside = vec![false; n];
    for &(a, b) in cover {
        inside[cell(a)..=cell(b)].iter_mut().for_each(|x| *x = true);
    }
    let mut starts = Vec::with_capacity(n + 1);
    let mut entries: Vec<(u32, f64)> = Vec::with_capacity(4 * n);
    let mut logs = Vec::with_capacity(n);
    for i in 0..n {
        starts.push(entries.len());
        let ((fs, ds), (ft, dt)) = (ends[i], ends[i + 1]);
        logs.push(log_mean(ds, dt));
        if !inside[i] {
            continue;
        }
        let (a, b) = (fs.min(ft), fs.max(ft));
        let start = entries.len();
        if b - a <= 1e-15 {
            entries.push((cell(a) as u32, 1.0));
        } else {
            for j in cell(a)..=cell(b) {
                let (x0, x1) = (lo + h * j as f64, lo + h * (j + 1) as f64);
                let ov = (x1.min(b) - x0.max(a)).max(0.0);
                if ov > 0.0 && inside[j] {
                    entries.push((j as u32, ov / (b - a)));
                }
            }
        }
        // Mass the linear model sends off the set (it should not):
        // renormalise what stays.
        let row = &mut entries[start..];
        let total: f64 = row.iter().map(|x| x.1).sum();
        if total > 0.0 {
            row.iter_mut().for_each(|x| x.1 /= total);
        }
    }
    starts.push(entries.len());
    (starts, entries, logs, inside)
}

impl Chain {
    /// At most `steps` power iterations of the lazy chain; whether μ is
    /// stationary (or the iterations' cap is reached).
    fn iterate(&mut self, steps: usize) -> bool {
        let n = self.mu.len();
        let end = self.done.saturating_add(steps).min(ITERATIONS);
        while self.done < end {
            let k = self.done;
            self.done += 1;
            let (mu, next) = (&mut self.mu, &mut self.next);
            next.iter_mut()
                .zip(mu.iter())
                .for_each(|(x, m)| *x = 0.5 * m);
            for i in 0..n {
                let m = 0.5 * mu[i];
                for &(j, w) in &self.entries[self.starts[i]..self.starts[i + 1]] {
                    next[j as usize] += m * w;
                }
            }
            let s: f64 = next.iter().sum();
            let diff: f64 = if k % 8 == 7 {
                next.iter()
                    .zip(mu.iter())
                    .map(|(a, b)| (a / s - b).abs())
                    .sum()
            } else {
                1.0
            };
            mu.iter_mut().zip(next.iter()).for_each(|(m, x)| *m = x / s);
            if diff < 1e-11 {
                return true;
            }
        }
        self.done >= ITERATIONS
    }
}

#[cfg(test)]
mod tests {
    use super::log_mean;

    #[test]
    fn log_mean_is_the_integral_mean() {
        // ∫_{-1}^{2} ln|x| dx / 3, by the primitive x ln|x| − x.
        let exact = ((2.0 * 2f64.ln() - 2.0) - (1.0)) / 3.0;
        assert!((log_mean(-1.0, 2.0) - exact).abs() < 1e-12);
        assert!((log_mean(3.0, 3.0) - 3f64.ln()).abs() < 1e-12);
    }
}
