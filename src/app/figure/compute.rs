//! A figure's data computed headless: the job model over the
//! single-threaded worker, pumped round after round of the window's own
//! `sync` until the view's jobs are done (the other lanes dropped unrun),
//! all at once ([`compute`]) or a time budget at a time ([`ComputeRun`]),
//! and resumed over the jobs of a run before (a played θν's next frame).

use std::time::Duration;

use super::super::jobs::{JobKind, JobState, Jobs, Shown};
use super::super::settings::{Layout, Settings, ViewKind};
use super::Figure;
use crate::jobs::{Lane, Shape};
use crate::worker::LocalWorker;

/// Rounds of the job model's sync before a figure gives up: each round
/// runs every job it sends to its end, and a view needs at most three
/// (trajectory, then the orbit analysis, then a measurement).
const MAX_ROUNDS: usize = 16;

/// Seconds of ui time between rounds: past every debounce of the job
/// model, so each round sends what the settings call for.
const ROUND_SECONDS: f64 = 10.0;

/// The lanes a figure's data comes from (every other lane's jobs are not
/// run): its view's, and its overlays'.
fn lanes(fig: &Figure) -> Vec<Lane> {
    let mut l = view_lanes(fig.view);
    if fig.overlays.branches {
        l.push(Lane::Continuation);
    }
    if fig.overlays.boundaries {
        l.push(Lane::Curves);
    }
    l
}

/// The lanes a view's data comes from: those of the kinds that feed it
/// (the window's slot table).
fn view_lanes(view: ViewKind) -> Vec<Lane> {
    let mut lanes = Vec::new();
    for k in JobKind::ALL
        .into_iter()
        .filter(|k| k.feeds().contains(&view))
    {
        if !lanes.contains(&k.lane()) {
            lanes.push(k.lane());
        }
    }
    lanes
}

/// The states of the jobs `fig` draws from: its view's and its overlays'.
fn states<'a>(jobs: &'a Jobs, fig: &Figure) -> Vec<&'a JobState> {
    let mut st = view_states(jobs, fig.view);
    if fig.overlays.branches {
        st.push(&jobs.branches.state);
    }
    if fig.overlays.boundaries {
        st.push(&jobs.curves.state);
    }
    st
}

/// The states of the jobs `view` draws from.
fn view_states(jobs: &Jobs, view: ViewKind) -> Vec<&JobState> {
    let orbit = [&jobs.trajectory.state, &jobs.iterate.state];
    match view {
        ViewKind::Bifurcation => vec![&jobs.sweep.state],
        ViewKind::Phase => vec![&jobs.phase.state],
        ViewKind::Basins => vec![&jobs.basins.state],
        ViewKind::ReturnMap => orbit.into_iter().chain([&jobs.map_basins.state]).collect(),
        ViewKind::Numerics => orbit.into_iter().chain([&jobs.numerics.state]).collect(),
        _ => orbit.to_vec(),
    }
}

/// The figure's settings: its view alone, as the tab.
pub(in crate::app) fn view_settings(fig: &Figure) -> Settings {
    let mut s = fig.settings.clone();
    s.layout = Layout::Tabs;
    s.tab = fig.view;
    // A picture for a document: anti-aliased.
    s.smooth_lines = Some(true);
    s
}

/// Computes what `fig`'s view shows, on this thread; the error says which
/// job failed and why.
pub fn compute(fig: &Figure) -> Result<Jobs, String> {
    let mut run = ComputeRun::new(fig);
    loop {
        if let Some(r) = run.advance(fig, Duration::from_secs(3600)) {
            return r;
        }
    }
}

/// [`compute`] a time budget at a time, for a host that wants its thread
/// back between them (the browser's Record): rounds of the window's
/// `sync`, each pumping its jobs to their end, with the same jobs and
/// results.
pub(in crate::app) struct ComputeRun {
    jobs: Option<Jobs>,
    settings: Settings,
    round: usize,
    /// Whether this round's `sync` was made (its jobs are then pumped).
    synced: bool,
    /// The job model's clock at the first round, seconds: a run resumed
    /// over the jobs of the one before goes on from its time (the
    /// debounces compare with the time of the last send).
    start: f64,
    /// Whether the diagram's sweep is waited for too, whatever the view
    /// (a played return map holds its axes at the diagram's θ).
    with_sweep: bool,
}

impl ComputeRun {
    pub(in crate::app) fn new(fig: &Figure) -> Self {
        Self::with_lanes(fig, false)
    }

    /// A run that also computes the diagram's sweep (`with_sweep`), on a
    /// job model of its own.
    pub(in crate::app) fn with_lanes(fig: &Figure, with_sweep: bool) -> Self {
        let mut needed = lanes(fig);
        if with_sweep {
            needed.push(Lane::Sweep);
        }
        let skip = Lane::ALL
            .into_iter()
            .filter(|l| !needed.contains(l))
            .collect();
        // LANES columns stepped together (the same columns, faster per cycle).
        let worker = LocalWorker::new(Shape::default(), crate::sim::LANES);
        // Natively, a parallel job (the diagram, the grid, the Basins
        // columns) takes every core, as the command line's do.
        #[cfg(not(target_arch = "wasm32"))]
        let worker =
            worker.with_threads(std::thread::available_parallelism().map_or(1, |n| n.get()));
        let mut jobs = Jobs::new(Box::new(worker.skipping(skip)));
        if let Some(session) = &fig.session {
            // Bound to the session's settings: the first sync clears them
            // if the figure's flags changed what they depend on.
            let zoom = session.bifurcation_zoom.last().map(|z| z.theta_nu);
            let diagram = super::super::jobs::continuation_range(&session.settings, zoom);
            jobs.restore(&session.settings, diagram, session.results.clone());
        }
        ComputeRun {
            jobs: Some(jobs),
            settings: view_settings(fig),
            round: 0,
            synced: false,
            start: 0.0,
            with_sweep,
        }
    }

    /// A run over `jobs` (a run's answer before, whose clock ended at
    /// `start`) for `fig`'s settings: what changed restarts as in the
    /// window, the rest is kept (the diagram, when only θν moved).
    pub(in crate::app) fn resume(jobs: Jobs, fig: &Figure, start: f64, with_sweep: bool) -> Self {
        ComputeRun {
            jobs: Some(jobs),
            settings: view_settings(fig),
            round: 0,
            synced: false,
            start,
            with_sweep,
        }
    }

    /// The job model's clock at the next round, seconds.
    pub(in crate::app) fn clock(&self) -> f64 {
        self.start + (self.round + 1) as f64 * ROUND_SECONDS
    }

    /// Pumps the jobs for about `budget`; then `None` while work remains,
    /// else the view's data (or why it failed). `fig` is the one it was
    /// made for; a run that has answered is not advanced again.
    pub(in crate::app) fn advance(
        &mut self,
        fig: &Figure,
        budget: Duration,
    ) -> Option<Result<Jobs, String>> {
        let (s, jobs) = (&self.settings, self.jobs.as_mut()?);
        if self.round == MAX_ROUNDS {
            return Some(Err(format!(
                "the {} view's data did not arrive after {MAX_ROUNDS} rounds",
                fig.view.key()
            )));
        }
        if !self.synced {
            let shown = Shown {
                now: self.start + self.round as f64 * ROUND_SECONDS,
                sweep_zoom: fig.sweep_zoom(),
                phase: fig.view == ViewKind::Phase,
            };
            jobs.sync(s, shown);
            self.synced = true;
        }
        if jobs.pump(budget) || jobs.receive() {
            return None;
        }
        if let Some(m) = states(jobs, fig).iter().find_map(|st| match st {
            JobState::Failed(m) => Some(m.clone()),
            _ => None,
        }) {
            return Some(Err(format!("the simulation failed: {m}")));
        }
        let orbit_done = jobs.trajectory.state == JobState::Done
            && !matches!(jobs.iterate.state, JobState::Running | JobState::Idle);
        if fig.view == ViewKind::Numerics && orbit_done && !jobs.numerics.issued() {
            // Measured on the attractor, as the window does.
            jobs.start_work_precision(s);
            return None;
        }
        if start_overlays(jobs, s, fig) {
            return None;
        }
        let sweep_done = !self.with_sweep || jobs.sweep.state == JobState::Done;
        if sweep_done && states(jobs, fig).iter().all(|st| **st == JobState::Done) {
            return self.jobs.take().map(Ok);
        }
        self.round += 1;
        self.synced = false;
        None
    }
}

/// Starts the overlays `fig` asks for that are neither started nor kept
/// by its session (a kept result of other parameters was cleared, its
/// slot idle again), as the window's buttons do: "Find bifurcations" over
/// the diagram's θν range, "Boundaries" over the phase diagram's box.
/// Whether one was started.
fn start_overlays(jobs: &mut Jobs, s: &Settings, fig: &Figure) -> bool {
    if fig.overlays.branches && jobs.branches.state == JobState::Idle {
        let range = super::super::jobs::continuation_range(s, fig.sweep_zoom());
        jobs.find_bifurcations(s, range);
        return true;
    }
    if fig.overlays.boundaries && jobs.curves.state == JobState::Idle {
        jobs.compute_boundaries(s);
        return true;
    }
    false
}
