//! What the worker has sent for a job, one type per kind of job: the
//! trajectory with its slip events, the map iterates with their analysis,
//! the bifurcation columns, the work-precision rows (the phase grid's cells
//! are in `phase_data`). Which job is current, and its state, is the job
//! model's (`jobs`).

use super::jobs::Receive;
use crate::model::Params;
use crate::numerics::{Row, Subject};
use crate::sim::column_lyapunov::ColumnLyapunov;
use crate::sim::continuation::ContParam;
use crate::sim::{Period, Sample, SlipEvent};
use crate::worker::Update;

/// The most samples and events kept (a rolling window: an endless
/// trajectory keeps the newest; the view shows the last cycles only).
pub const MAX_SAMPLES: usize = 2_000_000;
pub const MAX_EVENTS: usize = 200_000;

/// The trajectory job's results.
#[derive(Clone, Debug, Default)]
pub struct TrajectoryData {
    pub samples: Vec<Sample>,
    pub events: Vec<SlipEvent>,
    /// The oldest samples or events were dropped to stay under the caps.
    pub truncated: bool,
}

/// The iterate job's results.
#[derive(Clone, Debug, Default)]
pub struct IterateData {
    pub thetas: Vec<f64>,
    /// Points (θ, f(θ)) of the map's graph over the orbit's window (NaN
    /// where a cycle failed), once the job has drawn it.
    pub graph: Vec<[f64; 2]>,
    /// f^k at the graph's θ for k = 2, 3, … (as many as were asked for and
    /// have arrived; NaN where a cycle failed).
    pub powers: Vec<Vec<f64>>,
    pub period: Option<Period>,
    pub lyapunov: Option<f64>,
    /// λ's standard error: `None` for a solved cycle (exact) or too few
    /// iterates.
    pub lyapunov_stderr: Option<f64>,
}

/// The sweep job's results: one slot per column of the final grid.
#[derive(Clone, Debug, Default)]
pub struct SweepData {
    /// The parameter varied along the diagram's axis.
    pub param: ContParam,
    /// Its range (values, both ends computed).
    pub from: f64,
    pub to: f64,
    pub columns: Vec<Option<Column>>,
    pub filled: usize,
    /// Bumped on every change, so views rebuild only when it moves.
    pub revision: u64,
}

/// One received column.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    /// The varied parameter's value (θν unless the diagram varies another).
    pub value: f64,
    pub thetas: Vec<f64>,
    pub coarse: bool,
    /// λ of the column ([`crate::sim::column_lyapunov`]), when computed.
    pub lyapunov: Option<ColumnLyapunov>,
    /// The attractor of each of `thetas` (0: the followed one); empty
    /// without seeds.
    pub attractor: Vec<u8>,
    /// With seeds, why the column's attractors could not be counted (the
    /// exit arc's cell graph could not be built): the column then holds
    /// the followed orbit alone, which is no count of one.
    pub uncounted: Option<String>,
}

impl SweepData {
    pub fn new(from: f64, to: f64, columns: usize) -> Self {
        SweepData {
            param: ContParam::ThetaNu,
            from,
            to,
            columns: vec![None; columns],
            filled: 0,
            revision: 0,
        }
    }

    /// How many points the diagram holds.
    pub fn points(&self) -> usize {
        self.columns.iter().flatten().map(|c| c.thetas.len()).sum()
    }
}

impl TrajectoryData {
    /// The index of the first sample of the last `keep` cycles.
    pub fn recent_start(&self, keep: usize) -> usize {
        if self.events.len() <= keep {
            return 0;
        }
        let t0 = self.events[self.events.len() - keep].onset_time;
        self.samples.partition_point(|s| s.t < t0 - 1e-12)
    }

    /// Appends streamed samples, dropping the oldest half past the cap.
    pub fn push_samples(&mut self, samples: Vec<Sample>) {
        if self.samples.len() + samples.len() > MAX_SAMPLES {
            // A rolling window: the oldest half goes, the view keeps
            // following the newest cycles.
            self.samples.drain(..self.samples.len() / 2);
            self.truncated = true;
        }
        self.samples.extend(samples);
    }

    /// Appends one slip event, dropping the oldest half past the cap.
    pub fn push_event(&mut self, event: SlipEvent) {
        if self.events.len() >= MAX_EVENTS {
            self.events.drain(..MAX_EVENTS / 2);
            self.truncated = true;
        }
        self.events.push(event);
    }
}

impl SweepData {
    /// Stores a received column (one outside the grid is ignored; a repeat
    /// replaces the column without counting it twice).
    pub fn insert(&mut self, index: usize, column: Column) {
        if let Some(slot) = self.columns.get_mut(index) {
            if slot.is_none() {
                self.filled += 1;
            }
            *slot = Some(column);
            self.revision += 1;
        }
    }
}

/// A work-precision measurement on the current parameters (the Numerics
/// view) and what it has sent.
#[derive(Clone, Debug, Default)]
pub struct WorkPrecisionData {
    /// The parameters it measures on.
    pub params: Option<Params>,
    /// Rows in the order of the job's settings.
    pub rows: Vec<Row>,
    /// Settings it skipped, each with the reason.
    pub skipped: Vec<String>,
    /// Settings in the job (rows + skipped when done).
    pub total: usize,
    /// Points of its sample, and how far its reference is from the check.
    pub points: usize,
    pub reference_spread: Option<f64>,
    /// The machine's one-minute load average and core count when the run
    /// started (Linux; `None` elsewhere).
    pub load: Option<(f64, usize)>,
    /// The error it reported, naming the parameter.
    pub error: Option<String>,
}

impl WorkPrecisionData {
    /// A new measurement on `params` of `total` settings.
    pub fn new(params: Params, total: usize) -> Self {
        WorkPrecisionData {
            params: Some(params),
            total,
            ..Default::default()
        }
    }

    /// Whether the cores were busy with other work when the run started,
    /// so that its wall times are inflated: a load average above half the
    /// cores beyond the one the measurement takes.
    pub fn loaded(&self) -> bool {
        self.load
            .is_some_and(|(l, cores)| l > 1.0 + 0.5 * cores.saturating_sub(1) as f64)
    }

    /// Settings measured or skipped so far.
    pub fn done(&self) -> usize {
        self.rows.len() + self.skipped.len()
    }

    /// Records a skipped setting with its reason.
    pub fn skip(&mut self, total: usize, subject: Subject, reason: &str) {
        self.total = total;
        let (kind, value) = subject.setting();
        self.skipped.push(format!(
            "{} {kind} {value:e}: {reason}",
            subject.method_name()
        ));
    }
}

/// The one-minute load average and the number of cores (Linux's
/// `/proc/loadavg`; `None` where it cannot be read).
pub fn load_average() -> Option<(f64, usize)> {
    let text = std::fs::read_to_string("/proc/loadavg").ok()?;
    let l: f64 = text.split_whitespace().next()?.parse().ok()?;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    l.is_finite().then_some((l, cores))
}

impl Receive for SweepData {
    fn receive(&mut self, u: Update) -> Option<Update> {
        match u {
            Update::Column {
                index,
                value,
                thetas,
                coarse,
                lyapunov,
                attractor,
                uncounted,
                ..
            } => {
                let column = Column {
                    value,
                    thetas,
                    coarse,
                    lyapunov,
                    attractor,
                    uncounted,
                };
                self.insert(index, column);
                None
            }
            u => Some(u),
        }
    }
}

impl Receive for WorkPrecisionData {
    fn receive(&mut self, u: Update) -> Option<Update> {
        match u {
            Update::WorkPrecisionSample {
                points,
                reference_spread,
                ..
            } => {
                self.points = points;
                self.reference_spread = Some(reference_spread);
            }
            Update::WorkPrecisionRow { total, row, .. } => {
                self.total = total;
                self.rows.push(row);
            }
            Update::WorkPrecisionSkipped {
                total,
                subject,
                reason,
                ..
            } => self.skip(total, subject, &reason),
            u => return Some(u),
        }
        None
    }
}
