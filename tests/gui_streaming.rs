//! What the worker streams reaches the window: trajectory chunks, slips
//! and diagram columns land in the job model, every view draws with them,
//! and an update of an older generation is dropped.
#![cfg(feature = "gui")]

use crate::window;

use oneblock::app::jobs::JobState;
use oneblock::app::{Layout, Recorder, Settings, ViewKind};
use oneblock::sim::{Phase, Sample};
use oneblock::worker::Spec;
use oneblock::worker::{Command, Update};
use window::{event, harness};

#[test]
fn streamed_results_reach_every_view_and_stale_ones_are_dropped() {
    let rec = Recorder::new();
    let mut h = harness(&rec, Settings::default());
    h.run_steps(2);
    let (traj_gen, sweep_gen) = {
        let cmds = rec.commands();
        let t = cmds.iter().find_map(|c| match c {
            Command::Run {
                generation,
                spec: Spec::Trajectory(..),
            } => Some(*generation),
            _ => None,
        });
        let s = cmds.iter().find_map(|c| match c {
            Command::Run {
                generation,
                spec: Spec::Sweep(spec),
            } => Some((*generation, spec.axis.steps)),
            _ => None,
        });
        (t.expect("trajectory"), s.expect("sweep"))
    };
    // A stale update (older generation) is dropped.
    rec.push(Update::Slip {
        generation: 0,
        event: event(0.5, 0.2, 0.0),
    });
    // A trajectory: 5 cycles of a small loop.
    for c in 0..5 {
        let t0 = c as f64 * 103.0;
        let samples: Vec<Sample> = (0..60)
            .map(|i| {
                let s = i as f64 / 59.0;
                Sample {
                    t: t0 + 3.0 * s,
                    x: 0.05 * (6.0 * s).cos(),
                    y: 0.5 - s,
                    u: 0.0,
                    w: -0.3,
                    phase: if s < 0.4 { Phase::Accel } else { Phase::Decel },
                }
            })
            .chain([Sample {
                t: t0 + 103.0,
                x: 0.05,
                y: 0.5,
                u: 0.0,
                w: 0.0,
                phase: Phase::Stick,
            }])
            .collect();
        rec.push(Update::TrajectoryChunk {
            generation: traj_gen,
            samples,
        });
        rec.push(Update::Slip {
            generation: traj_gen,
            event: event(0.5, 0.2, t0),
        });
    }
    let (g, n) = sweep_gen;
    for i in 0..n {
        rec.push(Update::Column {
            generation: g,
            index: i,
            value: i as f64 / (n - 1) as f64 * std::f64::consts::FRAC_PI_2,
            thetas: (0..200)
                .map(|k| 0.1 + 0.001 * (k % 7) as f64 + i as f64 * 1e-3)
                .collect(),
            coarse: i % 8 == 0,
            rhs_evals: 0,
            map: Default::default(),
            lyapunov: None,
            attractor: vec![],
            uncounted: None,
        });
    }
    rec.push(Update::Finished {
        generation: g,
        lane: oneblock::worker::Lane::Sweep,
        outcome: oneblock::worker::Outcome::Completed,
    });
    h.run_steps(2);
    {
        let j = &h.state().jobs;
        assert_eq!(j.stale_dropped, 1);
        assert_eq!(j.trajectory.data.events.len(), 5);
        assert_eq!(j.sweep.data.filled, n);
        assert_eq!(j.sweep.state, JobState::Done);
        assert_eq!(j.sweep.data.points(), 200 * n);
    }
    // Every view draws with data in it.
    for v in ViewKind::ALL {
        h.state_mut().settings.layout = Layout::Tabs;
        h.state_mut().settings.tab = v;
        h.run_steps(2);
    }
}
