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
use super::protocol::{Timing, Update, WorkPrecisionSpec};
use super::{Job, JobError, Sink, Status, Stop, lock};
use crate::model::ParamError;
use crate::numerics::SamplePoint as Sample;
use crate::numerics::quick::{SLOW_ITERATE, combine};
use crate::numerics::sample::SampleBuild;
use crate::numerics::{Row, measure};
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
    /// The sample being built, until it is.
    build: Option<SampleBuild>,
    /// The sample once built.
    sample: Option<Vec<Sample>>,
    /// The next subject to measure.
    next: usize,
    /// The subject being measured, point by point.
    setting: Option<Setting>,
    pacer: Pacer,
    /// A method whose setting was too slow per iterate: its later (more
    /// expensive) settings are skipped, with the reason.
    too_slow: Vec<(&'static str, String)>,
}

/// A setting part-measured: the rows of its points so far, and the
/// fastest timing of the current point.
struct Setting {
    index: usize,
    rows: Vec<Row>,
    best: Option<Row>,
    /// Timings of the current point so far.
    timed: u32,
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
        let build = SampleBuild::new(&spec.attractors, spec.points);
        Ok(WorkPrecisionJob {
            spec,
            state: Mutex::new(Progress {
                build: Some(build),
                sample: None,
                next: 0,
                setting: None,
                pacer: Pacer::new(),
                too_slow: Vec::new(),
            }),
        })
    }

    /// Pieces of the sample until it is built (then sent, with how far its
    /// reference is from DP5(4) at 1e-13) or the host wants its thread
    /// back. `true` once built.
    fn build(&self, st: &mut Progress, sink: &dyn Sink) -> Result<bool, JobError> {
        let Some(build) = st.build.as_mut() else {
            return Ok(true);
        };
        let cancel = || sink.cycle();
        let sample = loop {
            match build.advance(&cancel) {
                None if sink.pause() => return Ok(false),
                None => {}
                Some(Err(SimError::Cancelled)) => return Err(Stop::Stale.into()),
                Some(Err(e)) => return Err(e.into()),
                Some(Ok(sample)) => break sample,
            }
        };
        st.build = None;
        let spread = sample
            .iter()
            .map(|s| s.reference_spread())
            .fold(0.0, f64::max);
        sink.send(Update::WorkPrecisionSample {
            generation: sink.generation(),
            points: sample.len(),
            reference_spread: spread,
        })?;
        st.sample = Some(sample);
        Ok(true)
    }

    /// How many timings a point takes, each how long, and whether a slow
    /// method's later settings are skipped. The window's timing is the
    /// fastest of a few: what the other lanes (or other programs) take of
    /// the cores only ever adds time.
    fn timing(&self, points: usize) -> (u32, Duration, bool) {
        match self.spec.timing {
            Timing::PerSetting(d) => (
                TIMING_REPEATS,
                d / points.max(1) as u32 / TIMING_REPEATS,
                true,
            ),
            Timing::PerPoint(d) => (1, d, false),
        }
    }

    /// Measures subject `setting.index` on `sample`, one timing of one
    /// point a piece, until it is measured (`true`: its row sent) or the
    /// host wants its thread back. A subject of a method found too slow is
    /// skipped, saying why.
    fn measure(
        &self,
        setting: &mut Setting,
        sample: &[Sample],
        st: &mut Progress,
        sink: &dyn Sink,
    ) -> Result<bool, JobError> {
        let generation = sink.generation();
        let subjects = &self.spec.subjects;
        let (index, total) = (setting.index, subjects.len());
        let subject = &subjects[index];
        let method = subject.method_name();
        if let Some((_, reason)) = st.too_slow.iter().find(|(m, _)| *m == method) {
            sink.send(Update::WorkPrecisionSkipped {
                generation,
                index,
                total,
                subject: *subject,
                reason: reason.clone(),
            })?;
            return Ok(true);
        }
        let (repeats, each, skips) = self.timing(sample.len());
        while let Some(sp) = sample.get(setting.rows.len()) {
            if sink.cycle() {
                return Err(Stop::Stale.into());
            }
            let r = measure(std::slice::from_ref(sp), subject, each);
            if setting
                .best
                .as_ref()
                .is_none_or(|b| r.median_us < b.median_us)
            {
                setting.best = Some(r);
            }
            setting.timed += 1;
            if setting.timed == repeats {
                setting.rows.extend(setting.best.take());
                setting.timed = 0;
            }
            if setting.rows.len() < sample.len() && sink.pause() {
                return Ok(false);
            }
        }
        let Some(row) = combine(&setting.rows) else {
            return Ok(true);
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
                lane: sink.lane(),
                fraction: (index + 1) as f64 / total.max(1) as f64,
                // The job times iterates on purpose: a rate is meaningless.
                iterates_per_second: 0.0,
            })?;
        }
        Ok(true)
    }
}

impl Job for WorkPrecisionJob {
    /// The sample first, then up to `width` settings, pausing between any
    /// two pieces when the host wants its thread back.
    fn step(&self, width: usize, sink: &dyn Sink) -> Result<Status, JobError> {
        let mut guard = lock(&self.state);
        let st = &mut *guard;
        if !self.build(st, sink)? {
            return Ok(Status::Working);
        }
        let Some(sample) = st.sample.take() else {
            return Ok(Status::Done);
        };
        let result = (|| {
            for _ in 0..width.max(1) {
                let mut setting = match st.setting.take() {
                    Some(s) => s,
                    None if st.next < self.spec.subjects.len() => {
                        st.next += 1;
                        Setting {
                            index: st.next - 1,
                            rows: Vec::with_capacity(sample.len()),
                            best: None,
                            timed: 0,
                        }
                    }
                    None => return Ok(Status::Done),
                };
                if !self.measure(&mut setting, &sample, st, sink)? {
                    st.setting = Some(setting);
                    return Ok(Status::Working);
                }
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
