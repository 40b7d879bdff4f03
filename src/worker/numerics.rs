//! The numerics lane: one work-precision job at a time, on the current
//! parameters' attractor (the app's Numerics panel). It builds a small
//! sample with its reference, then measures each setting point by point
//! (`numerics::measure` on one point, combined by `numerics::quick::combine`)
//! so that it polls its generation before every point, like the other lanes
//! poll before every slip cycle.

use std::time::Duration;

use super::Shared;
use super::gate::{Gate, Stop};
use super::orbit::{JobError, Pacer, run_guarded};
use super::protocol::{Command, Generation, Lane, Update};
use crate::model::{ParamError, Params};
use crate::numerics::quick::{MAX_QUICK_POINTS, SLOW_ITERATE, combine, current_attractor};
use crate::numerics::{Row, Subject, build_sample_until, measure};
use crate::sim::SimError;

/// Timings of each point in a re-measure, of which the fastest is kept.
pub const TIMING_REPEATS: u32 = 3;

/// The longest timing a job accepts per setting (a run of 57 settings stays
/// under a few minutes even at the limit).
pub const MAX_TIME_PER_SETTING: Duration = Duration::from_secs(2);
/// The longest reference transient a job accepts.
pub const MAX_TRANSIENT: usize = 100_000;

/// Runs one numerics-lane command.
pub(crate) fn run(shared: &Shared, cmd: Command) {
    if let Command::WorkPrecision { generation, spec } = cmd {
        let job = Job { shared, generation };
        run_guarded(&shared.numerics, generation, || {
            job.run(
                spec.params,
                spec.theta0,
                spec.transient,
                spec.points,
                spec.time_per_setting,
                &spec.subjects,
            )
        });
    }
}

struct Job<'a> {
    shared: &'a Shared,
    generation: Generation,
}

fn invalid(name: &'static str, value: f64, range: &'static str) -> JobError {
    SimError::from(ParamError::new(name, value, range)).into()
}

impl Job<'_> {
    fn gate(&self) -> &Gate {
        &self.shared.numerics
    }

    /// True when the job must stop (counted as a cycle, as the other lanes
    /// count theirs, so tests can bound the work done after a stop).
    fn stale(&self) -> bool {
        self.shared.stats.poll(self.gate(), self.generation)
    }

    fn send(&self, u: Update) -> Result<(), JobError> {
        Ok(self.gate().send(self.generation, u)?)
    }

    fn run(
        &self,
        params: Params,
        theta0: Option<f64>,
        transient: usize,
        points: usize,
        time_per_setting: Duration,
        subjects: &[Subject],
    ) -> Result<(), JobError> {
        let generation = self.generation;
        if !(1..=MAX_QUICK_POINTS).contains(&points) {
            return Err(invalid("points", points as f64, "must lie in [1, 64]"));
        }
        if transient > MAX_TRANSIENT {
            return Err(invalid(
                "transient",
                transient as f64,
                "must lie in [0, 100000]",
            ));
        }
        if time_per_setting > MAX_TIME_PER_SETTING {
            return Err(invalid(
                "time_per_setting",
                time_per_setting.as_secs_f64(),
                "must lie in [0, 2] seconds",
            ));
        }
        let attractor = current_attractor(params, theta0, transient);
        let sample = build_sample_until(&[attractor], points, &|| self.stale())?;
        let spread = sample
            .iter()
            .map(|s| s.reference_spread())
            .fold(0.0, f64::max);
        self.send(Update::WorkPrecisionSample {
            generation,
            points: sample.len(),
            reference_spread: spread,
        })?;
        let per_point = time_per_setting / sample.len().max(1) as u32;
        let total = subjects.len();
        let mut pacer = Pacer::new();
        // A method whose setting was too slow per iterate: its later
        // (more expensive) settings are skipped, with the reason.
        let mut too_slow: Vec<(&'static str, String)> = Vec::new();
        for (index, subject) in subjects.iter().enumerate() {
            let method = subject.method_name();
            if let Some((_, reason)) = too_slow.iter().find(|(m, _)| *m == method) {
                self.send(Update::WorkPrecisionSkipped {
                    generation,
                    index,
                    total,
                    subject: *subject,
                    reason: reason.clone(),
                })?;
                continue;
            }
            let mut rows: Vec<Row> = Vec::with_capacity(sample.len());
            for sp in &sample {
                // The fastest of a few timings: what the other lanes (or
                // other programs) take of the cores only ever adds time.
                let mut best: Option<Row> = None;
                for _ in 0..TIMING_REPEATS {
                    if self.stale() {
                        return Err(Stop::Stale.into());
                    }
                    let r = measure(
                        std::slice::from_ref(sp),
                        subject,
                        per_point / TIMING_REPEATS,
                    );
                    if best.as_ref().is_none_or(|b| r.median_us < b.median_us) {
                        best = Some(r);
                    }
                }
                rows.extend(best);
            }
            let Some(row) = combine(&rows) else {
                continue;
            };
            if row.median_us > SLOW_ITERATE.as_secs_f64() * 1e6 {
                let (kind, setting) = subject.setting();
                too_slow.push((
                    method,
                    format!(
                        "{method} at {kind} {setting:e} already took {:.1} ms per iterate \
                         (limit {} ms)",
                        row.median_us * 1e-3,
                        SLOW_ITERATE.as_millis()
                    ),
                ));
            }
            self.send(Update::WorkPrecisionRow {
                generation,
                index,
                total,
                row,
            })?;
            if pacer.due() {
                self.send(Update::Progress {
                    generation,
                    lane: Lane::Numerics,
                    fraction: (index + 1) as f64 / total.max(1) as f64,
                    // The job times iterates on purpose: a rate is meaningless.
                    iterates_per_second: 0.0,
                })?;
            }
        }
        Ok(())
    }
}
