//! `orbit --stats`: the kept events' intermittency statistics as CSV,
//! with the creep channel's passage time and, with `--scaling`, the mean
//! laminar length against the distance to a tangency located by
//! continuation (`sim::intermittency`), both run as the Events view's
//! jobs.

use super::CliError;
use super::run_control::{Limits, Progress, run_job};
use crate::jobs::{PassageSpec, ScanSpec, Spec, Update};
use crate::sim::intermittency::{Intermittency, Scaling};
use crate::sim::{Orbit, Simulator};

/// The statistics file: laminar phases as runs of creep slips (by where
/// each slip starts), the channel passage beside their mean, the verdict,
/// then the rows. `source` ends the laminar line (where the sizes came
/// from). The passage and (with `--scaling`) the tangency scan are the
/// Events view's jobs, stopped by `limits`.
pub(super) fn stats_text(
    sim: &Simulator,
    orbit: &Orbit,
    source: &str,
    scan: bool,
    limits: &Limits,
) -> Result<String, CliError> {
    let (params, settings) = (*sim.params(), *sim.settings());
    let (st, first_creep) = Intermittency::of_events(params.kappa, params.gamma, &orbit.events);
    let mut notes = Vec::new();
    match first_creep {
        Some(near) => {
            let spec = PassageSpec {
                params,
                settings,
                near,
            };
            let pass = answer("passage", spec.into(), limits, |u| match u {
                Update::Passage { passage, .. } => Some(passage),
                _ => None,
            })?;
            let mean = st
                .mean_laminar
                .map_or("no complete laminar phase".into(), |m| {
                    format!("mean laminar length {m:.1}")
                });
            notes.push(format!("{mean}; {}", pass.describe()));
        }
        None => notes.push("no creep slip: no creep channel to pass".into()),
    }
    if scan {
        let spec = ScanSpec { params, settings };
        let scaling = answer("tangency scan", spec.into(), limits, |u| match u {
            Update::Scan { scaling, .. } => Some(scaling),
            _ => None,
        })?;
        notes.extend(scaling_notes(&scaling));
    }
    Ok(st.csv("slip_distance", source, &notes))
}

/// The answer `pick` finds among the updates of the job of `spec` (the
/// `what` of `orbit --stats`).
fn answer<T>(
    what: &'static str,
    spec: Spec,
    limits: &Limits,
    pick: impl Fn(Update) -> Option<T>,
) -> Result<T, CliError> {
    let progress = Progress::new("orbit --stats", what, 1);
    let updates = run_job("orbit", spec, 1, &progress, limits)?;
    updates
        .into_iter()
        .find_map(pick)
        .ok_or_else(|| CliError::Failed(format!("orbit: the {what} job ended without its answer")))
}

/// The scan's `#` lines: the tangency, one line per distance, the verdict.
fn scaling_notes(sc: &Scaling) -> Vec<String> {
    let mut out = Vec::new();
    if let Scaling::Fitted {
        tangency: t,
        points,
        ..
    } = sc
    {
        out.push(format!(
            "tangency: fold of the P{} cycle at theta-nu = {} (theta = {}, multiplier {}), \
             found from the window at theta-nu = {}",
            t.period, t.theta_nu, t.theta, t.multiplier, t.window
        ));
        for q in points {
            let opt = |v: Option<f64>| v.map_or("none".to_string(), |v| format!("{v:.2}"));
            out.push(format!(
                "eps = {:.3e} (theta-nu = {:.6}): {} laminar phases, mean laminar length {} +- {}, channel passage {}",
                q.eps,
                q.theta_nu,
                q.phases,
                opt(q.mean),
                opt(q.stderr),
                opt(q.passage)
            ));
        }
    }
    out.push(format!("type-I scaling: {}", sc.describe()));
    out
}
