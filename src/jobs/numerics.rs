//! The work-precision job: the window's Numerics view (a small sample of
//! the current attractor) and `oneblock work-precision` (the committed
//! sample, or one attractor given). Its first unit builds the sample with
//! its reference; each later unit measures one setting point by point
//! (`numerics::measure` on one point, combined by `numerics::quick::combine`),
//! polling its sink before every point, as the other jobs poll before every
//! slip cycle.

use std::sync::Mutex;
use std::time::Duration;

use super::orbit::Pacer;
use super::protocol::{Lane, Timing, Update, WorkPrecisionSpec};
use super::{Job, JobError, Sink, Status, Stop, lock};
use crate::model::ParamError;
use crate::numerics::SamplePoint as Sample;
use crate::numerics::quick::{SLOW_ITERATE, combine};
use crate::numerics::{Row, build_sample_until, measure};
use crate::sim::SimError;

/// Timings of each point in a re-measure, of which the fastest is kept.
pub const TIMING_REPEATS: u32 = 3;

/// The longest timing a job accepts per setting (a run of 57 settings stays
/// under a few minutes even at the limit) …
pub const MAX_TIME_PER_SETTING: Duration = Duration::from_secs(2);
/// … and per point.
pub const MAX_TIME_PER_POINT: Duration = Duration::from_secs(10);
/// The longest reference transient a job accepts.
pub const MAX_TRANSIENT: usize = 100_000;
/// The most points a job takes per attractor.
pub const MAX_POINTS: usize = 10_000;

fn invalid(name: &'static str, value: f64, range: &'static str) -> JobError {
    SimError::from(ParamError::new(name, value, range)).into()
}

/// A work-precision measurement in progress.
pub(crate) struct WorkPrecisionJob {
    spec: WorkPrecisionSpec,
    state: Mutex<Progress>,
}

/// How far a measurement is.
struct Progress {
    /// The sample once built.
    sample: Option<Vec<Sample>>,
    /// The next subject to measure.
    next: usize,
    pacer: Pacer,
    /// A method whose setting was too slow per iterate: its later (more
    /// expensive) settings are skipped, with the reason.
    too_slow: Vec<(&'static str, String)>,
}

impl WorkPrecisionJob {
    pub fn new(spec: WorkPrecisionSpec) -> Result<Self, JobError> {
        if !(1..=MAX_POINTS).contains(&spec.points) {
            return Err(invalid(
                "points",
                spec.points as f64,
                "must lie in [1, 10000]",
            ));
        }
        if spec.attractors.is_empty() {
            return Err(invalid("attractors", 0.0, "must be at least 1"));
        }
        for a in &spec.attractors {
            if a.transient > MAX_TRANSIENT {
                let range = "must lie in [0, 100000]";
                return Err(invalid("transient", a.transient as f64, range));
            }
            a.params.validate().map_err(SimError::from)?;
        }
        match spec.timing {
            Timing::PerSetting(d) if d > MAX_TIME_PER_SETTING => {
                let range = "must lie in [0, 2] seconds";
                return Err(invalid("time_per_setting", d.as_secs_f64(), range));
            }
            Timing::PerPoint(d) if d > MAX_TIME_PER_POINT => {
                let range = "must lie in [0, 10] seconds";
                return Err(invalid("time_per_point", d.as_secs_f64(), range));
            }
            _ => {}
        }
        Ok(WorkPrecisionJob {
            spec,
            state: Mutex::new(Progress {
                sample: None,
                next: 0,
                pacer: Pacer::new(),
                too_slow: Vec::new(),
            }),
        })
    }

    /// The sample with its reference, and how far that reference is from
    /// DP5(4) at 1e-13.
    fn build(&self, sink: &dyn Sink) -> Result<Vec<Sample>, JobError> {
        let s = &self.spec;
        let sample = build_sample_until(&s.attractors, s.points, &|| sink.cycle())?;
        let spread = sample
            .iter()
            .map(|s| s.reference_spread())
            .fold(0.0, f64::max);
        sink.send(Update::WorkPrecisionSample {
            generation: sink.generation(),
            points: sample.len(),
            reference_spread: spread,
        })?;
        Ok(sample)
    }

    /// Measures subject `index` on `sample` (or skips it, saying why).
    fn measure_one(
        &self,
        index: usize,
        sample: &[Sample],
        st: &mut Progress,
        sink: &dyn Sink,
    ) -> Result<(), JobError> {
        let generation = sink.generation();
        let subjects = &self.spec.subjects;
        let (subject, total) = (&subjects[index], subjects.len());
        let method = subject.method_name();
        if let Some((_, reason)) = st.too_slow.iter().find(|(m, _)| *m == method) {
            sink.send(Update::WorkPrecisionSkipped {
                generation,
                index,
                total,
                subject: *subject,
                reason: reason.clone(),
            })?;
            return Ok(());
        }
        // The window's timing is the fastest of a few: what the other lanes
        // (or other programs) take of the cores only ever adds time.
        let (repeats, each, skips) = match self.spec.timing {
            Timing::PerSetting(d) => (
                TIMING_REPEATS,
                d / sample.len().max(1) as u32 / TIMING_REPEATS,
                true,
            ),
            Timing::PerPoint(d) => (1, d, false),
        };
        let mut rows: Vec<Row> = Vec::with_capacity(sample.len());
        for sp in sample {
            let mut best: Option<Row> = None;
            for _ in 0..repeats {
                if sink.cycle() {
                    return Err(Stop::Stale.into());
                }
                let r = measure(std::slice::from_ref(sp), subject, each);
                if best.as_ref().is_none_or(|b| r.median_us < b.median_us) {
                    best = Some(r);
                }
            }
            rows.extend(best);
        }
        let Some(row) = combine(&rows) else {
            return Ok(());
        };
        if skips && row.median_us > SLOW_ITERATE.as_secs_f64() * 1e6 {
            let (kind, setting) = subject.setting();
            st.too_slow.push((
                method,
                format!(
                    "{method} at {kind} {setting:e} already took {:.1} ms per iterate \
                     (limit {} ms)",
                    row.median_us * 1e-3,
                    SLOW_ITERATE.as_millis()
                ),
            ));
        }
        sink.send(Update::WorkPrecisionRow {
            generation,
            index,
            total,
            row,
        })?;
        if st.pacer.due() {
            sink.send(Update::Progress {
                generation,
                lane: Lane::Numerics,
                fraction: (index + 1) as f64 / total.max(1) as f64,
                // The job times iterates on purpose: a rate is meaningless.
                iterates_per_second: 0.0,
            })?;
        }
        Ok(())
    }
}

impl Job for WorkPrecisionJob {
    /// The sample first, then up to `width` settings.
    fn step(&self, width: usize, sink: &dyn Sink) -> Result<Status, JobError> {
        let mut st = lock(&self.state);
        let sample = match st.sample.take() {
            Some(s) => s,
            None => {
                let s = self.build(sink)?;
                st.sample = Some(s);
                return Ok(Status::Working);
            }
        };
        let result = (|| {
            for _ in 0..width.max(1) {
                if st.next >= self.spec.subjects.len() {
                    return Ok(Status::Done);
                }
                let index = st.next;
                st.next += 1;
                self.measure_one(index, &sample, &mut st, sink)?;
            }
            Ok(if st.next >= self.spec.subjects.len() {
                Status::Done
            } else {
                Status::Working
            })
        })();
        st.sample = Some(sample);
        result
    }
}
