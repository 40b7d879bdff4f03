//! `orbit --stats`: the kept events' intermittency statistics as CSV,
//! with the creep channel's passage time and, with `--scaling`, the mean
//! laminar length against the distance to a tangency located by
//! continuation (`sim::intermittency`).

use crate::sim::intermittency::{Intermittency, Scaling, passage, scaling};
use crate::sim::{Orbit, SimError, Simulator};

/// The statistics file: laminar phases as runs of creep slips (by where
/// each slip starts), the channel passage beside their mean, the verdict,
/// then the rows. `source` ends the laminar line (where the sizes came
/// from); `scan` (with `--scaling`) runs the tangency scan, polled to stop.
pub(super) fn stats_text(
    sim: &Simulator,
    orbit: &Orbit,
    source: &str,
    scan: Option<&dyn Fn() -> bool>,
) -> Result<String, SimError> {
    let p = *sim.params();
    let (st, first_creep) = Intermittency::of_events(p.kappa, p.gamma, &orbit.events);
    let mut notes = Vec::new();
    match first_creep {
        Some(th) => {
            let pass = passage(sim, th, &|| scan.is_some_and(|s| s()))?;
            let mean = st
                .mean_laminar
                .map_or("no complete laminar phase".into(), |m| {
                    format!("mean laminar length {m:.1}")
                });
            notes.push(format!("{mean}; {}", pass.describe()));
        }
        None => notes.push("no creep slip: no creep channel to pass".into()),
    }
    if let Some(stop) = scan {
        notes.extend(scaling_notes(&scaling(p, *sim.settings(), stop)?));
    }
    Ok(st.csv("slip_distance", source, &notes))
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
