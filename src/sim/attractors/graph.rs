//! The cell graph: cells covering the arc, each with an edge to every cell
//! its image meets; its strongly connected components (Tarjan's
//! algorithm, iterative), the closed (terminal) ones, what each cell can
//! reach, and subdivision.

use super::arc::{ArcMap, Image, Span};

/// Cells [bounds[i], bounds[i + 1]] of u, and their images.
#[derive(Clone, Debug)]
pub struct CellGraph {
    pub bounds: Vec<f64>,
    pub images: Vec<Image>,
    /// Successor ranges (inclusive), `ranges[starts[i]..starts[i + 1]]`.
    starts: Vec<u32>,
    ranges: Vec<(u32, u32)>,
    /// Proved traps: f maps the first span into the second, so a cell
    /// inside the first has its image clipped to the second.
    traps: Vec<(Span, Span)>,
    /// The cycles the traps were built round: (p, a point, in u).
    pub cycles: Vec<(usize, f64)>,
}

/// The components of a [`CellGraph`].
#[derive(Clone, Debug)]
pub struct Components {
    /// `comp[cell]`; components are numbered in the order Tarjan closes
    /// them, so a component's successors have smaller numbers.
    pub comp: Vec<u32>,
    pub count: usize,
    /// No edge leaves it.
    pub terminal: Vec<bool>,
    /// A path leads from it back to itself (more than one cell, or a cell
    /// whose image meets it): it may hold an invariant set.
    pub recurrent: Vec<bool>,
}

const UNSET: u32 = u32::MAX;

impl CellGraph {
    /// `n` equal cells over the covered interval.
    pub fn uniform(map: &ArcMap, n: usize) -> Self {
        let bounds: Vec<f64> = (0..=n)
            .map(|i| map.lo + (map.hi - map.lo) * i as f64 / n as f64)
            .collect();
        let images = bounds.windows(2).map(|w| map.image(w[0], w[1])).collect();
        let mut g = CellGraph {
            bounds,
            images,
            starts: Vec::new(),
            ranges: Vec::new(),
            traps: Vec::new(),
            cycles: Vec::new(),
        };
        g.link();
        g
    }

    pub fn len(&self) -> usize {
        self.images.len()
    }

    /// The cell holding u (the first or last beyond the ends).
    pub fn cell_of(&self, u: f64) -> usize {
        self.bounds
            .partition_point(|&b| b <= u)
            .saturating_sub(1)
            .min(self.len() - 1)
    }

    pub fn width(&self, i: usize) -> f64 {
        self.bounds[i + 1] - self.bounds[i]
    }

    pub fn mid(&self, i: usize) -> f64 {
        0.5 * (self.bounds[i] + self.bounds[i + 1])
    }

    /// The cells a span of u meets: (first, last).
    pub fn cells_of(&self, lo: f64, hi: f64) -> (usize, usize) {
        let a = self.cell_of(lo);
        // A span ending exactly on a bound does not meet the next cell.
        let mut b = self.cell_of(hi);
        if b > a && self.bounds[b] >= hi {
            b -= 1;
        }
        (a, b)
    }

    /// Edges from the images.
    fn link(&mut self) {
        self.starts.clear();
        self.ranges.clear();
        self.starts.push(0);
        for i in 0..self.images.len() {
            for sp in &self.images[i].spans {
                let (a, b) = self.cells_of(sp[0], sp[1]);
                self.ranges.push((a as u32, b as u32));
            }
            self.starts.push(self.ranges.len() as u32);
        }
    }

    /// The successor ranges of cell i.
    pub fn succ(&self, i: usize) -> &[(u32, u32)] {
        &self.ranges[self.starts[i] as usize..self.starts[i + 1] as usize]
    }

    /// Halves every marked cell (recomputing the halves' images) and
    /// relinks.
    pub fn subdivide(&mut self, map: &ArcMap, marked: &[bool]) {
        let n = self.len();
        let extra = marked.iter().filter(|&&m| m).count();
        let mut bounds = Vec::with_capacity(n + extra + 1);
        let mut images = Vec::with_capacity(n + extra);
        for i in 0..n {
            let (a, b) = (self.bounds[i], self.bounds[i + 1]);
            bounds.push(a);
            if marked[i] {
                let m = 0.5 * (a + b);
                images.push(self.image(map, a, m));
                images.push(self.image(map, m, b));
                bounds.push(m);
            } else {
                images.push(std::mem::take(&mut self.images[i]));
            }
        }
        bounds.push(self.bounds[n]);
        self.bounds = bounds;
        self.images = images;
        self.link();
    }

    /// The image of [a, b], clipped by a trap that holds it.
    fn image(&self, map: &ArcMap, a: f64, b: f64) -> Image {
        let mut im = map.image(a, b);
        if let Some((_, to)) = self
            .traps
            .iter()
            .find(|(from, _)| from[0] <= a && b <= from[1])
        {
            im.spans = im
                .spans
                .iter()
                .filter_map(|s| {
                    let (lo, hi) = (s[0].max(to[0]), s[1].min(to[1]));
                    (hi >= lo).then_some([lo, hi])
                })
                .collect();
        }
        im
    }

    /// Adds a proved trap (f maps `from` into `to`): cells are split at
    /// `from`'s ends, and the images of the cells inside it clipped.
    pub fn add_trap(&mut self, map: &ArcMap, from: Span, to: Span) {
        self.traps.push((from, to));
        for x in from {
            let i = self.cell_of(x);
            let (a, b) = (self.bounds[i], self.bounds[i + 1]);
            if x > a && x < b {
                self.bounds.insert(i + 1, x);
                self.images[i] = Image::default();
                self.images.insert(i + 1, Image::default());
                self.images[i] = self.image(map, a, x);
                self.images[i + 1] = self.image(map, x, b);
            }
        }
        let (a, b) = self.cells_of(from[0], from[1]);
        for i in a..=b {
            self.images[i] = self.image(map, self.bounds[i], self.bounds[i + 1]);
        }
        self.link();
    }

    /// Whether cell i lies inside a trap.
    pub fn trapped(&self, i: usize) -> bool {
        let (a, b) = (self.bounds[i], self.bounds[i + 1]);
        self.traps.iter().any(|(f, _)| f[0] <= a && b <= f[1])
    }

    /// The cycle whose trap holds every one of `cells` and which has a
    /// point among them, if one does. A set inside traps but holding no
    /// cycle's point is not given one (it is judged as any other closed
    /// set is): no label without its cycle.
    pub fn trap_cycle(&self, cells: &[usize]) -> Option<(usize, f64)> {
        if !cells.iter().all(|&i| self.trapped(i)) {
            return None;
        }
        let (lo, hi) = (
            self.bounds[cells[0]],
            self.bounds[cells[cells.len() - 1] + 1],
        );
        self.cycles.iter().copied().find(|&(_, u)| {
            // A point of the cycle among the cells.
            lo <= u && u <= hi
        })
    }

    /// Recomputes the images of the cells meeting [lo, hi] (after the map
    /// was sharpened there) and relinks.
    pub fn refresh(&mut self, map: &ArcMap, lo: f64, hi: f64) {
        let (a, b) = self.cells_of(lo, hi);
        for i in a..=b {
            self.images[i] = self.image(map, self.bounds[i], self.bounds[i + 1]);
        }
        self.link();
    }

    /// The strongly connected components and which are closed.
    pub fn components(&self) -> Components {
        let mut t = Tarjan::new(self, None);
        for root in 0..self.len() {
            if t.index[root] == UNSET {
                t.from(root);
            }
        }
        let (comp, count) = (t.comp, t.count as usize);
        let mut terminal = vec![true; count];
        let mut recurrent = vec![false; count];
        let mut size = vec![0u32; count];
        for v in 0..self.len() {
            let c = comp[v];
            size[c as usize] += 1;
            let succ = self.succ(v);
            if succ
                .iter()
                .any(|&(a, b)| (a..=b).any(|w| comp[w as usize] != c))
            {
                terminal[c as usize] = false;
            }
            if succ
                .iter()
                .any(|&(a, b)| a as usize <= v && v <= b as usize)
            {
                recurrent[c as usize] = true;
            }
        }
        for (r, &n) in recurrent.iter_mut().zip(&size) {
            *r |= n > 1;
        }
        Components {
            comp,
            count,
            terminal,
            recurrent,
        }
    }

    /// The closed components among `cells` (sorted) only: a subset of the
    /// graph that no edge leaves (the cells of closed components, after
    /// subdivision) holds all the closed components there are in it.
    pub fn closed_within(&self, cells: &[usize]) -> Vec<Vec<usize>> {
        let mut member = vec![false; self.len()];
        for &c in cells {
            member[c] = true;
        }
        let mut t = Tarjan::new(self, Some(&member));
        for &root in cells {
            if t.index[root] == UNSET {
                t.from(root);
            }
        }
        let count = t.count as usize;
        let mut terminal = vec![true; count];
        let mut members: Vec<Vec<usize>> = vec![Vec::new(); count];
        for &v in cells {
            let c = t.comp[v];
            members[c as usize].push(v);
            let leaves = self
                .succ(v)
                .iter()
                .any(|&(a, b)| (a..=b).any(|w| !member[w as usize] || t.comp[w as usize] != c));
            if leaves {
                terminal[c as usize] = false;
            }
        }
        members
            .into_iter()
            .zip(terminal)
            .filter_map(|(m, t)| t.then_some(m))
            .collect()
    }

    /// For every component, the set of closed components (by their number
    /// in `labels`, a bit each, the 64th meaning "one of the rest") it can
    /// reach; `labels[c]` is `Some(k)` for the closed component c.
    pub fn reach(&self, comps: &Components, labels: &[Option<usize>]) -> Vec<u64> {
        let mut by_comp: Vec<Vec<u32>> = vec![Vec::new(); comps.count];
        for (v, &c) in comps.comp.iter().enumerate() {
            by_comp[c as usize].push(v as u32);
        }
        let mut reach = vec![0u64; comps.count];
        // Successors close first: increasing numbers are a topological
        // order from the sinks up.
        for c in 0..comps.count {
            let mut m = labels[c].map_or(0, |k| 1u64 << k.min(63));
            for &v in &by_comp[c] {
                for &(a, b) in self.succ(v as usize) {
                    for w in a..=b {
                        let cw = comps.comp[w as usize] as usize;
                        if cw != c {
                            m |= reach[cw];
                        }
                    }
                }
            }
            reach[c] = m;
        }
        reach
    }
}

/// Tarjan's algorithm without recursion: a frame per cell being visited,
/// (cell, range index, next cell in that range).
struct Tarjan<'a> {
    g: &'a CellGraph,
    /// Only these cells (and edges between them) when restricted.
    member: Option<&'a [bool]>,
    index: Vec<u32>,
    low: Vec<u32>,
    on_stack: Vec<bool>,
    comp: Vec<u32>,
    stack: Vec<u32>,
    call: Vec<(u32, u32, u32)>,
    counter: u32,
    count: u32,
}

impl<'a> Tarjan<'a> {
    fn new(g: &'a CellGraph, member: Option<&'a [bool]>) -> Self {
        let n = g.len();
        Tarjan {
            g,
            member,
            index: vec![UNSET; n],
            low: vec![0; n],
            on_stack: vec![false; n],
            comp: vec![UNSET; n],
            stack: Vec::new(),
            call: Vec::new(),
            counter: 0,
            count: 0,
        }
    }

    fn enter(&mut self, v: usize) {
        self.index[v] = self.counter;
        self.low[v] = self.counter;
        self.counter += 1;
        self.stack.push(v as u32);
        self.on_stack[v] = true;
        let r = self.g.starts[v];
        let first = self.g.ranges.get(r as usize).map_or(0, |x| x.0);
        self.call.push((v as u32, r, first));
    }

    /// The next successor of the top frame's cell, if any is left.
    fn next(&mut self) -> Option<usize> {
        let g = self.g;
        let (v, r, j) = self.call.last_mut()?;
        let end = g.starts[*v as usize + 1];
        while *r < end {
            if *j <= g.ranges[*r as usize].1 {
                *j += 1;
                let w = *j as usize - 1;
                if self.member.is_none_or(|m| m[w]) {
                    return Some(w);
                }
                continue;
            }
            *r += 1;
            if *r < end {
                *j = g.ranges[*r as usize].0;
            }
        }
        None
    }

    /// Every component reachable from `root`.
    fn from(&mut self, root: usize) {
        self.enter(root);
        while let Some(&(v, _, _)) = self.call.last() {
            let v = v as usize;
            match self.next() {
                Some(w) if self.index[w] == UNSET => self.enter(w),
                Some(w) => {
                    if self.on_stack[w] {
                        self.low[v] = self.low[v].min(self.index[w]);
                    }
                }
                None => self.close(v),
            }
        }
    }

    /// The top frame's cell is done: pass its low link up, and pop its
    /// component if it is the root of one.
    fn close(&mut self, v: usize) {
        self.call.pop();
        if let Some(&(p, _, _)) = self.call.last() {
            let p = p as usize;
            self.low[p] = self.low[p].min(self.low[v]);
        }
        if self.low[v] == self.index[v] {
            while let Some(w) = self.stack.pop() {
                self.on_stack[w as usize] = false;
                self.comp[w as usize] = self.count;
                if w as usize == v {
                    break;
                }
            }
            self.count += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A graph from explicit successor ranges, without a map.
    fn graph(succ: &[&[(u32, u32)]]) -> CellGraph {
        let n = succ.len();
        let mut starts = vec![0];
        let mut ranges = Vec::new();
        for s in succ {
            ranges.extend_from_slice(s);
            starts.push(ranges.len() as u32);
        }
        CellGraph {
            bounds: (0..=n).map(|i| i as f64).collect(),
            images: vec![Image::default(); n],
            starts,
            ranges,
            traps: Vec::new(),
            cycles: Vec::new(),
        }
    }

    #[test]
    fn closed_components_are_the_sinks_of_the_condensation() {
        // 0 → 1 → 2 ↔ 3 (closed); 4 → 4 (closed); 5 → {0, 4}.
        let g = graph(&[
            &[(1, 1)],
            &[(2, 2)],
            &[(3, 3)],
            &[(2, 2)],
            &[(4, 4)],
            &[(0, 0), (4, 4)],
        ]);
        let c = g.components();
        assert_eq!(c.comp[2], c.comp[3]);
        let closed: Vec<usize> = (0..6).filter(|&v| c.terminal[c.comp[v] as usize]).collect();
        assert_eq!(closed, vec![2, 3, 4]);
        let mut labels = vec![None; c.count];
        labels[c.comp[2] as usize] = Some(0);
        labels[c.comp[4] as usize] = Some(1);
        let r = g.reach(&c, &labels);
        assert_eq!(r[c.comp[0] as usize], 0b01);
        assert_eq!(r[c.comp[5] as usize], 0b11);
        assert_eq!(r[c.comp[4] as usize], 0b10);
    }
}
