//! Sampling the block's path for display and export: at a settable spacing
//! in time from the dense output (not at every integrator step), plus the
//! exact phase boundaries. A stick phase is a straight line at the surface
//! velocity, so only its two ends are recorded.

use serde::{Deserialize, Serialize};

use crate::integrate::{Dense, State};

/// Which mode the block is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Phase {
    Stick,
    Accel,
    Decel,
}

impl Phase {
    pub fn name(self) -> &'static str {
        match self {
            Phase::Stick => "stick",
            Phase::Accel => "accel",
            Phase::Decel => "decel",
        }
    }
}

/// One point of the path: time, position, lab velocity (u, w), phase.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    pub t: f64,
    pub x: f64,
    pub y: f64,
    pub u: f64,
    pub w: f64,
    pub phase: Phase,
}

/// Collects samples of the slips at a fixed spacing in time.
#[derive(Clone, Debug)]
pub struct Sampler {
    spacing: f64,
    next_t: f64,
    pub samples: Vec<Sample>,
    /// The most samples held at once (`usize::MAX`: no cap).
    limit: usize,
    /// Samples refused because the cap was reached.
    dropped: u64,
}

impl Sampler {
    /// Samples every `spacing` time units during slips (spacing > 0).
    pub fn new(spacing: f64) -> Self {
        Sampler {
            spacing: spacing.max(1e-9),
            next_t: 0.0,
            samples: Vec::new(),
            limit: usize::MAX,
            dropped: 0,
        }
    }

    /// As `new`, holding at most `limit` samples at once: the samples past
    /// it are not stored but counted ([`Sampler::dropped`]), so that memory
    /// stays bounded whatever the spacing and the slips' lengths.
    pub fn with_limit(spacing: f64, limit: usize) -> Self {
        Sampler {
            limit,
            ..Sampler::new(spacing)
        }
    }

    /// Holds at most `limit` samples at once from now on.
    pub fn set_limit(&mut self, limit: usize) {
        self.limit = limit;
    }

    /// How many samples the cap of [`Sampler::with_limit`] refused.
    pub fn dropped(&self) -> u64 {
        self.dropped
    }

    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// Takes the samples collected so far, leaving the sampler empty.
    pub fn take(&mut self) -> Vec<Sample> {
        std::mem::take(&mut self.samples)
    }

    /// Records a position with lab velocity `vel`.
    pub fn push(&mut self, t: f64, p: [f64; 2], vel: [f64; 2], phase: Phase) {
        if self.samples.len() >= self.limit {
            self.dropped += 1;
            return;
        }
        self.samples.push(Sample {
            t,
            x: p[0],
            y: p[1],
            u: vel[0],
            w: vel[1],
            phase,
        });
    }

    /// Records a slip state (x, y, v_r) at time t, V being the surface velocity.
    pub fn push_state(&mut self, t: f64, s: &State, v: [f64; 2], phase: Phase) {
        self.push(t, [s[0], s[1]], [s[2] + v[0], s[3] + v[1]], phase);
    }

    pub(crate) fn start_slip(&mut self, t_abs: f64, s: &State, v: [f64; 2]) {
        self.push_state(t_abs, s, v, Phase::Accel);
        self.next_t = t_abs + self.spacing;
    }

    /// Samples the step `d` up to local time `t_end` (slip started at `t_abs`).
    pub(crate) fn sample_step(
        &mut self,
        t_abs: f64,
        d: &Dense,
        t_end: f64,
        phase: Phase,
        v: [f64; 2],
    ) {
        self.sample_step_with(t_abs, d, t_end, phase, v, |s| *s);
    }

    /// As `sample_step`, for a dense output whose state `slip_state` turns
    /// into (x, y, v_r).
    pub(crate) fn sample_step_with(
        &mut self,
        t_abs: f64,
        d: &Dense,
        t_end: f64,
        phase: Phase,
        v: [f64; 2],
        slip_state: impl Fn(&State) -> State,
    ) {
        while self.next_t <= t_abs + t_end {
            let s = slip_state(&d.at(self.next_t - t_abs));
            self.push_state(self.next_t, &s, v, phase);
            self.next_t += self.spacing;
        }
    }

    /// Where the samples stand, to go back to with `rewind`.
    pub(crate) fn mark(&self) -> (usize, f64) {
        (self.samples.len(), self.next_t)
    }

    /// Drops the samples taken since `mark`.
    pub(crate) fn rewind(&mut self, mark: (usize, f64)) {
        self.samples.truncate(mark.0);
        self.next_t = mark.1;
    }
}
