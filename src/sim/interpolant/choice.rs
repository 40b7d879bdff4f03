//! How a run evaluates the map: every iterate integrated, or the verified
//! interpolant where it serves ([`MapChoice`]).

/// How an orbit evaluates the map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapChoice {
    /// Every iterate integrated.
    Direct,
    /// The verified interpolant, with direct integration where it has no
    /// verified series.
    Interpolant,
    /// The interpolant from [`MapChoice::AUTO_ITERATES`] iterates on, direct
    /// below.
    Auto,
}

impl MapChoice {
    /// From this many iterates (transient + kept) on, `Auto` builds the
    /// interpolant: its construction (a few hundred to a few thousand map
    /// evaluations) is then a small part of the run.
    pub const AUTO_ITERATES: usize = 20_000;

    /// The kept points from which `Auto` continues a bifurcation column
    /// that has not settled on the interpolant: on Fig. 3b's chaotic
    /// columns its construction costs about 3 300 map evaluations (a
    /// refusal up to its cap, twice the kept points), so that 5000 points
    /// cost about what integrating them does and more points cost less.
    pub const AUTO_COLUMN_KEEP: usize = 5000;

    /// Whether a run of `iterates` iterates uses the interpolant.
    pub fn interpolates(self, iterates: usize) -> bool {
        match self {
            MapChoice::Direct => false,
            MapChoice::Interpolant => true,
            MapChoice::Auto => iterates >= Self::AUTO_ITERATES,
        }
    }

    /// Whether a run with `iterates` still to go after its direct part uses
    /// the interpolant, when `Auto` needs at least `threshold` of them.
    pub fn interpolates_beyond(self, iterates: usize, threshold: usize) -> bool {
        match self {
            MapChoice::Direct => false,
            MapChoice::Interpolant => iterates > 0,
            MapChoice::Auto => iterates >= threshold,
        }
    }
}
