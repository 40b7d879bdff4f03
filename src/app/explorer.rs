//! The window: settings, the data the worker sent, the views, and the
//! plumbing between them. It can be built with any [`Backend`] and stepped
//! without a window (`logic_step` then `show`), which is how the kittest
//! tests drive it.

use eframe::egui;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

use egui::{Color32, Context, Key, KeyboardShortcut, Modifiers, Rect, RichText, Ui};

use super::accuracy::{AccuracyMode, JobKind, job_estimates};
use super::backend::Backend;
use super::bifurcation::{BifAction, BifurcationView};
use super::block::BlockView;
use super::controls::{Actions, Controls};
use super::data::{Data, JobState};
use super::events::EventsView;
use super::export;
use super::numerics_view::{NumericsAction, NumericsView};
use super::phase_job::{PhaseJob, PhaseKey, PhaseStep};
use super::phase_view::{PhaseAction, PhaseView};
use super::plane::PlaneView;
use super::return_map::ReturnMapView;
use super::screenshot::{Saved, Shots, fresh_path};
use super::settings::{Layout, Settings, SweepKey, View};
use super::style;
use crate::integrate::SolverSettings;
use crate::model::Params;
use crate::numerics::quick::{
    QUICK_POINTS, QUICK_TIME_PER_SETTING, QUICK_TRANSIENT, quick_subjects,
};
use crate::worker::{
    Axis, Command, Generation, IterateSpec, Lane, PhaseSpec, SweepSpec, TrajectorySpec,
    WorkPrecisionSpec,
};

/// A generation never issued: a job that waits for its turn.
const NO_GENERATION: Generation = Generation::MAX;

/// Time between two orbit restarts while a slider is dragged (seconds).
const ORBIT_DEBOUNCE: f64 = 0.04;
/// Quiet time after the last change before a sweep restarts (seconds).
const SWEEP_DEBOUNCE: f64 = 0.25;
/// Sample spacing of trajectories, in time units.
pub const SAMPLE_SPACING: f64 = 0.02;
/// Map iterates dropped and kept by the orbit analysis.
pub const ITERATE_TRANSIENT: usize = 1000;
pub const ITERATE_KEEP: usize = 300;

/// A scripted run: wait for the views, optionally measure frame times,
/// take one screenshot, close.
pub struct Script {
    pub path: PathBuf,
    pub timeout: Duration,
    /// Cycles the trajectory must have before the picture is taken.
    pub min_cycles: usize,
    /// Measure frame times for this long with a trajectory streaming.
    pub measure: Option<Duration>,
    /// Where the result goes: the saved path, or why it failed.
    pub outcome: Arc<Mutex<Option<Result<String, String>>>>,
    started: Option<Instant>,
    stage: Stage,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Stage {
    Waiting,
    /// Diagram full, trajectory done: the idle repaint cost.
    MeasuringIdle(Instant),
    /// Then with a trajectory streaming without end.
    Measuring(Instant),
    /// Then slider-to-picture: θν moved (the n-th time) at this instant;
    /// waiting for the first slip of the new trajectory on screen.
    Latency(u32, Instant, Generation),
    Settling(u32),
    Shooting,
    Closing,
}

impl Script {
    pub fn new(path: PathBuf, timeout: Duration, measure: Option<Duration>) -> Self {
        Script {
            path,
            timeout,
            min_cycles: 12,
            measure,
            outcome: Arc::new(Mutex::new(None)),
            started: None,
            stage: Stage::Waiting,
        }
    }
}

/// Frame-time bookkeeping (`--frame-stats`).
#[derive(Default)]
pub struct FrameStats {
    pub enabled: bool,
    last: Option<Instant>,
    recording: bool,
    /// Intervals between frames, in milliseconds, with a trajectory streaming.
    pub intervals: Vec<f32>,
    /// The same with nothing streaming (diagram full, trajectory done).
    pub idle: Vec<f32>,
    /// From a θν change to the frame showing the new trajectory's first slip, ms.
    pub latency: Vec<f32>,
    streaming: bool,
    /// CPU time eframe reports per frame, in milliseconds.
    pub cpu: Vec<f32>,
    /// Points in the diagram and samples received while recording.
    pub points: usize,
    pub samples_at_start: usize,
    pub samples_at_end: usize,
}

fn median(v: &[f32]) -> Option<f32> {
    if v.is_empty() {
        return None;
    }
    let mut s = v.to_vec();
    s.sort_by(f32::total_cmp);
    Some(s[s.len() / 2])
}

fn percentile(v: &[f32], q: f32) -> Option<f32> {
    if v.is_empty() {
        return None;
    }
    let mut s = v.to_vec();
    s.sort_by(f32::total_cmp);
    Some(s[((s.len() - 1) as f32 * q) as usize])
}

impl FrameStats {
    fn tick(&mut self) {
        let now = Instant::now();
        if let Some(l) = self.last
            && self.recording
        {
            let ms = (now - l).as_secs_f32() * 1e3;
            if self.streaming {
                self.intervals.push(ms);
            } else {
                self.idle.push(ms);
            }
        }
        self.last = Some(now);
    }

    /// One line for the terminal and docs.
    pub fn report(&self) -> String {
        let idle = match median(&self.idle) {
            Some(m) => format!(
                "frame-stats: idle (diagram full, trajectory done): median frame time {m:.1} ms \
                 (p90 {:.1} ms) over {} frames\n",
                percentile(&self.idle, 0.9).unwrap_or(m),
                self.idle.len()
            ),
            None => String::new(),
        };
        let streaming = match median(&self.intervals) {
            None => "frame-stats: no frames recorded".into(),
            Some(m) => format!(
                "frame-stats: streaming: median frame time {m:.1} ms (p90 {:.1} ms) over {} frames; \
                 median CPU per frame {}; diagram {} points; trajectory streaming {} → {} samples",
                percentile(&self.intervals, 0.9).unwrap_or(m),
                self.intervals.len(),
                median(&self.cpu).map_or("n/a".into(), |c| format!("{c:.1} ms")),
                self.points,
                self.samples_at_start,
                self.samples_at_end,
            ),
        };
        let latency = match median(&self.latency) {
            Some(m) => format!(
                "\nframe-stats: slider to picture (θν change to the frame showing the new \
                 trajectory's first slip): median {m:.0} ms, max {:.0} ms over {} changes",
                self.latency.iter().copied().fold(0.0, f32::max),
                self.latency.len()
            ),
            None => String::new(),
        };
        format!("{idle}{streaming}{latency}")
    }
}

/// The explorer app.
pub struct Explorer {
    pub settings: Settings,
    pub data: Data,
    pub controls: Controls,
    backend: Box<dyn Backend>,
    next_generation: Generation,
    /// What the running jobs were started with: the parameters, and the
    /// trajectory's and the map iterates' solver settings.
    sent_orbit: Option<(Params, SolverSettings, SolverSettings)>,
    sent_sweep: Option<(SweepKey, Option<(f64, f64)>)>,
    last_orbit_send: f64,
    sweep_changed_at: Option<f64>,
    /// Count of commands sent (tests, status).
    pub sent_count: usize,
    /// The orbit analysis waits for the trajectory (the worker's orbit lane
    /// runs one job at a time; a new job there cancels the running one):
    /// the trajectory's generation and what to iterate once it is done.
    pending_iterate: Option<(Generation, Params, SolverSettings)>,
    pub plane: PlaneView,
    pub block: BlockView,
    pub bifurcation: BifurcationView,
    pub return_map: ReturnMapView,
    pub events: EventsView,
    pub numerics: NumericsView,
    pub phase: PhaseView,
    /// When the phase grid runs (only while its view is shown).
    pub phase_job: PhaseJob,
    pub shots: Shots,
    pub script: Option<Script>,
    pub stats: FrameStats,
    /// Whether `save` writes the settings (not in scripted runs).
    pub persist: bool,
    view_rects: HashMap<View, Rect>,
    applied_style: Option<(f32, bool)>,
    /// Keep the orbit lane streaming indefinitely (frame-time measurement).
    stream_forever: bool,
    now: f64,
    /// Where the frame-time report goes when the window closes.
    pub stats_sink: Option<Arc<Mutex<Option<String>>>>,
}

impl Explorer {
    /// A window over `backend`, showing `settings`.
    pub fn new(backend: Box<dyn Backend>, mut settings: Settings) -> Self {
        if settings.params.validate().is_err() || settings.custom_solver().validate().is_err() {
            settings = Settings::default();
        }
        settings.columns = settings.columns.clamp(20, 2000);
        if settings.tiled.is_empty() {
            settings.tiled = Settings::default().tiled;
        }
        settings.keep_cycles = settings.keep_cycles.clamp(1, 1000);
        settings.phase = std::mem::take(&mut settings.phase).sanitised();
        Explorer {
            settings,
            data: Data {
                // No phase grid yet: generation 0 must not look like one.
                phase_gen: NO_GENERATION,
                ..Data::default()
            },
            controls: Controls::new(),
            backend,
            next_generation: 1,
            sent_orbit: None,
            sent_sweep: None,
            last_orbit_send: f64::NEG_INFINITY,
            sweep_changed_at: None,
            sent_count: 0,
            pending_iterate: None,
            plane: PlaneView::default(),
            block: BlockView::default(),
            bifurcation: BifurcationView::default(),
            return_map: ReturnMapView,
            events: EventsView,
            numerics: NumericsView::default(),
            phase: PhaseView::default(),
            phase_job: PhaseJob::default(),
            shots: Shots::default(),
            script: None,
            stats: FrameStats::default(),
            persist: true,
            view_rects: HashMap::new(),
            applied_style: None,
            stream_forever: false,
            now: 0.0,
            stats_sink: None,
        }
    }

    fn generation(&mut self) -> Generation {
        let g = self.next_generation;
        self.next_generation += 1;
        g
    }

    fn send(&mut self, cmd: Command) {
        self.sent_count += 1;
        if !self.backend.send(cmd) {
            self.data.last_error = Some("the simulation worker is not running".into());
        }
    }

    /// Starts the trajectory and the orbit analysis for the current parameters.
    pub fn restart_orbit(&mut self) {
        let params = self.settings.params;
        let solver = self.settings.solver_for(JobKind::Trajectory);
        let iterate_solver = self.settings.solver_for(JobKind::Iterate);
        let g = self.generation();
        self.data.start_trajectory(g);
        let cycles = if self.stream_forever {
            None
        } else {
            Some(self.settings.trajectory_cycles)
        };
        self.send(Command::Trajectory {
            generation: g,
            spec: TrajectorySpec {
                params,
                settings: solver,
                theta0: None,
                spacing: SAMPLE_SPACING,
                cycles,
            },
        });
        self.pending_iterate = (!self.stream_forever).then_some((g, params, iterate_solver));
        // The analysis shows "computing" until its job starts.
        self.data.start_iterate(NO_GENERATION);
        self.sent_orbit = Some((params, solver, iterate_solver));
        self.last_orbit_send = self.now;
    }

    /// Once the trajectory is done, analyses the orbit from where it ended
    /// (already on the attractor, so a short transient suffices).
    fn chain_iterate(&mut self) {
        let Some((g, params, solver)) = self.pending_iterate else {
            return;
        };
        if self.data.trajectory_gen != g {
            self.pending_iterate = None;
            return;
        }
        let (theta0, transient) = match &self.data.trajectory.state {
            JobState::Done => (
                self.data.trajectory.events.last().map(|e| e.theta_next),
                if self.data.trajectory.events.is_empty() {
                    ITERATE_TRANSIENT
                } else {
                    ITERATE_TRANSIENT / 10
                },
            ),
            JobState::Failed(m) => {
                self.pending_iterate = None;
                self.data.iterate.state = JobState::Failed(m.clone());
                return;
            }
            JobState::Cancelled => {
                self.pending_iterate = None;
                return;
            }
            _ => return,
        };
        self.pending_iterate = None;
        let g = self.generation();
        self.data.start_iterate(g);
        self.send(Command::Iterate {
            generation: g,
            spec: IterateSpec {
                params,
                settings: solver,
                theta0,
                transient,
                keep: ITERATE_KEEP,
            },
        });
    }

    /// Starts the bifurcation sweep over the current zoom range.
    pub fn restart_sweep(&mut self) {
        let s = &self.settings;
        let key = s.sweep_key();
        let zoom = self.bifurcation.theta_nu_range();
        let (from, to) = zoom.unwrap_or_else(|| s.sweep_range());
        let params = s.params;
        let (columns, transient, keep) = (s.columns, s.sweep_transient, s.sweep_keep);
        let solver = s.solver_for(JobKind::Sweep);
        let g = self.generation();
        self.data.start_sweep(g, from, to, columns);
        self.send(Command::Sweep {
            generation: g,
            spec: SweepSpec {
                params,
                settings: solver,
                theta_nu: Axis::new(from, to, columns),
                transient,
                keep,
            },
        });
        self.sent_sweep = Some((key, zoom));
        self.sweep_changed_at = None;
    }

    /// Measures work against precision on the current parameters (the
    /// Numerics view), on the worker's numerics lane.
    pub fn start_work_precision(&mut self) {
        let params = self.settings.params;
        // The orbit analysis's last point, if it is of these parameters, is
        // on the attractor already: the reference needs a short transient.
        let theta0 = match self.sent_orbit {
            Some((p, ..)) if p == params => self.data.iterate.thetas.last().copied(),
            _ => None,
        };
        let transient = if theta0.is_some() {
            20
        } else {
            QUICK_TRANSIENT
        };
        let subjects = quick_subjects();
        let g = self.generation();
        self.numerics.run.start(g, params, subjects.len());
        self.send(Command::WorkPrecision {
            generation: g,
            spec: WorkPrecisionSpec {
                params,
                theta0,
                transient,
                points: QUICK_POINTS,
                time_per_setting: QUICK_TIME_PER_SETTING,
                subjects,
            },
        });
    }

    /// Stops the Numerics view's measurement.
    pub fn stop_work_precision(&mut self) {
        let g = self.generation();
        self.numerics.run.stop(g);
        self.send(Command::Cancel {
            generation: g,
            lane: Some(Lane::Numerics),
        });
    }

    /// Starts the phase diagram over the current range with the sliders'
    /// γ, ν, Ω and solver.
    pub fn restart_phase(&mut self) {
        let key = PhaseKey::of(&self.settings);
        let (params, solver) = (
            self.settings.params,
            self.settings.solver_for(JobKind::Phase),
        );
        let g = self.generation();
        let (columns, rows) = key.steps;
        self.data
            .start_phase(g, key.range.theta_nu, key.range.kappa, columns, rows);
        self.send(Command::Phase {
            generation: g,
            spec: PhaseSpec {
                params,
                settings: solver,
                theta_nu: Axis::new(key.range.theta_nu.0, key.range.theta_nu.1, columns),
                kappa: Axis::new(key.range.kappa.0, key.range.kappa.1, rows),
                transient: key.transient,
                keep: key.keep,
            },
        });
        self.phase_job.started(key);
    }

    fn cancel_phase(&mut self) {
        let g = self.generation();
        self.send(Command::Cancel {
            generation: g,
            lane: Some(Lane::Phase),
        });
        if self.data.phase.state == JobState::Running {
            self.data.phase.state = JobState::Cancelled;
        }
    }

    /// Whether `v` is on screen (as a tab or a tile).
    pub fn shows(&self, v: View) -> bool {
        match self.settings.layout {
            Layout::Tabs => self.settings.tab == v,
            Layout::Tiles => self.settings.tiled.contains(&v),
        }
    }

    /// Starts, restarts or pauses the phase grid (see `phase_job`).
    fn sync_phase(&mut self, ctx: &Context) {
        let key = PhaseKey::of(&self.settings);
        let visible = self.shows(View::Phase);
        let running = self.data.phase.state == JobState::Running;
        match self.phase_job.step(key, visible, running, self.now) {
            PhaseStep::Start => self.restart_phase(),
            PhaseStep::Cancel => self.cancel_phase(),
            PhaseStep::WaitFor(s) => ctx.request_repaint_after(Duration::from_secs_f64(s)),
            PhaseStep::Nothing => {}
        }
    }

    fn phase_action(&mut self, a: PhaseAction) {
        match a {
            PhaseAction::SetPoint { theta_nu, kappa } => {
                let p = &mut self.settings.params;
                (p.theta_nu, p.kappa) = (theta_nu, kappa);
                if !(0.0..=std::f64::consts::FRAC_PI_2).contains(&theta_nu) {
                    self.settings.full_circle = true;
                }
            }
            PhaseAction::Compute => {
                self.restart_phase();
                self.phase_job.pinned = true;
            }
            PhaseAction::Stop => {
                self.cancel_phase();
                self.phase_job.stop();
            }
        }
    }

    /// Sends whatever the settings now call for: a new orbit at once (at
    /// most every 40 ms while dragging), a new sweep once κ, γ, ν, Ω or the
    /// solver have been still for 250 ms.
    pub fn sync_jobs(&mut self, ctx: &Context) {
        let orbit_now = Some((
            self.settings.params,
            self.settings.solver_for(JobKind::Trajectory),
            self.settings.solver_for(JobKind::Iterate),
        ));
        if self.sent_orbit != orbit_now {
            let wait = self.last_orbit_send + ORBIT_DEBOUNCE - self.now;
            if wait <= 0.0 || self.sent_orbit.is_none() {
                self.restart_orbit();
            } else {
                ctx.request_repaint_after(Duration::from_secs_f64(wait));
            }
        }
        let sweep_now = (self.settings.sweep_key(), self.bifurcation.theta_nu_range());
        match &self.sent_sweep {
            None => self.restart_sweep(),
            Some(sent) if *sent != sweep_now => {
                let zoom_only = sent.0 == sweep_now.0;
                if self.settings.full_circle != sent.0.full_circle
                    || (!zoom_only && sent.1.is_some())
                {
                    // A new parameter set or range: the zoom's θ box no longer applies.
                    if !zoom_only {
                        self.bifurcation.zoom.clear();
                        self.bifurcation.invalidate();
                    }
                }
                let changed_at = *self.sweep_changed_at.get_or_insert(self.now);
                if zoom_only || self.now - changed_at >= SWEEP_DEBOUNCE {
                    self.restart_sweep();
                } else {
                    ctx.request_repaint_after(Duration::from_secs_f64(
                        SWEEP_DEBOUNCE - (self.now - changed_at),
                    ));
                }
            }
            _ => {}
        }
        self.sync_phase(ctx);
    }

    /// Sends everything pending now (tests; the end of a scripted wait).
    pub fn flush(&mut self, ctx: &Context) {
        self.now += SWEEP_DEBOUNCE + ORBIT_DEBOUNCE;
        self.sync_jobs(ctx);
    }

    /// The non-drawing half of a frame: drain the worker, restart jobs,
    /// collect saved files, drive a scripted run.
    /// Tells the window it runs on a software OpenGL rasteriser (see
    /// `Settings::smooth_lines`).
    pub fn set_software_gl(&mut self, software: bool) {
        self.controls.software_gl = software;
    }

    pub fn logic_step(&mut self, ctx: &Context) {
        let smooth = self.settings.smooth_lines_on(self.controls.software_gl);
        if ctx.tessellation_options(|o| o.feathering) != smooth {
            ctx.tessellation_options_mut(|o| o.feathering = smooth);
        }
        self.now = ctx.input(|i| i.time);
        let mut n = 0;
        while let Some(u) = self.backend.try_recv() {
            // The Numerics view keeps its own job's updates.
            if let Some(u) = self.numerics.run.apply(u) {
                self.data.apply(u);
            }
            n += 1;
            if n > 20_000 {
                ctx.request_repaint();
                break;
            }
        }
        self.chain_iterate();
        self.sync_jobs(ctx);
        self.shots.poll(self.now);
        if self.shots.in_flight > 0 || !self.shots.toasts.is_empty() {
            ctx.request_repaint_after(Duration::from_millis(100));
        }
        if self.script.is_some() {
            self.script_step(ctx);
        }
        if self.stats.enabled {
            ctx.request_repaint();
        }
    }

    fn script_step(&mut self, ctx: &Context) {
        let Some(mut sc) = self.script.take() else {
            return;
        };
        let start = *sc.started.get_or_insert_with(Instant::now);
        ctx.request_repaint();
        let finish = |sc: &Script, r: Result<String, String>| {
            *sc.outcome.lock().unwrap_or_else(PoisonError::into_inner) = Some(r);
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        };
        match sc.stage {
            Stage::Waiting => {
                let shows_phase = self.shows(View::Phase);
                let failed = [
                    &self.data.sweep.state,
                    &self.data.trajectory.state,
                    &self.data.iterate.state,
                ]
                .into_iter()
                .chain(shows_phase.then_some(&self.data.phase.state))
                .find_map(|s| match s {
                    JobState::Failed(m) => Some(m.clone()),
                    _ => None,
                });
                if let Some(failed) = failed {
                    finish(&sc, Err(format!("the simulation failed: {failed}")));
                    sc.stage = Stage::Closing;
                } else if self.data.complete(sc.min_cycles)
                    && self.numerics_settled()
                    && (!shows_phase || self.data.phase.state == JobState::Done)
                {
                    if sc.measure.is_some() {
                        self.stats.enabled = true;
                        self.stats.recording = true;
                        self.stats.streaming = false;
                        sc.stage = Stage::MeasuringIdle(Instant::now() + Duration::from_secs(3));
                    } else {
                        sc.stage = Stage::Settling(0);
                    }
                } else if start.elapsed() > sc.timeout {
                    let msg = format!(
                        "timed out after {:.0} s waiting for the views: trajectory {} cycles ({:?}), \
                         orbit analysis {:?}, diagram {}/{} columns ({:?})",
                        sc.timeout.as_secs_f64(),
                        self.data.trajectory.events.len(),
                        self.data.trajectory.state,
                        self.data.iterate.state,
                        self.data.sweep.filled,
                        self.data.sweep.columns.len(),
                        self.data.sweep.state,
                    );
                    finish(&sc, Err(msg));
                    sc.stage = Stage::Closing;
                }
            }
            Stage::MeasuringIdle(until) => {
                if Instant::now() >= until {
                    // A trajectory streaming without end over a full diagram.
                    self.stream_forever = true;
                    self.restart_orbit();
                    self.stats.streaming = true;
                    self.stats.samples_at_start = 0;
                    let d = sc.measure.unwrap_or(Duration::from_secs(5));
                    sc.stage = Stage::Measuring(Instant::now() + d);
                }
            }
            Stage::Measuring(until) => {
                if Instant::now() >= until {
                    self.stats.recording = false;
                    self.stats.points = self.data.sweep.points();
                    self.stats.samples_at_end = self.data.trajectory.samples.len();
                    self.stream_forever = false;
                    self.settings.params.theta_nu += 0.01;
                    sc.stage = Stage::Latency(0, Instant::now(), self.data.trajectory_gen);
                }
            }
            Stage::Latency(n, since, before) => {
                // Logic runs before drawing: a slip here is on this frame.
                if self.data.trajectory_gen > before && !self.data.trajectory.events.is_empty() {
                    self.stats.latency.push(since.elapsed().as_secs_f32() * 1e3);
                    if n + 1 >= 10 {
                        sc.stage = Stage::Settling(0);
                    } else {
                        self.settings.params.theta_nu += if n % 2 == 0 { -0.01 } else { 0.01 };
                        sc.stage = Stage::Latency(n + 1, Instant::now(), self.data.trajectory_gen);
                    }
                } else if since.elapsed() > Duration::from_secs(10) {
                    sc.stage = Stage::Settling(0);
                }
            }
            Stage::Settling(n) => {
                // A few frames so plots settle their bounds and textures upload.
                if n >= 4 {
                    self.shots.request(ctx, sc.path.clone(), None);
                    sc.stage = Stage::Shooting;
                } else {
                    sc.stage = Stage::Settling(n + 1);
                }
            }
            Stage::Shooting => {
                if let Some(r) = self.shots.finished.pop() {
                    let r = match r {
                        Saved::Ok(p) => Ok(p.display().to_string()),
                        Saved::Failed(e) => Err(format!("screenshot failed: {e}")),
                    };
                    finish(&sc, r);
                    sc.stage = Stage::Closing;
                } else if start.elapsed() > sc.timeout + Duration::from_secs(30) {
                    finish(&sc, Err("the window never delivered the screenshot".into()));
                    sc.stage = Stage::Closing;
                }
            }
            Stage::Closing => {}
        }
        self.script = Some(sc);
    }

    /// For a scripted run: whether the Numerics view, if shown, has its
    /// measurement on the current parameters (started here once the orbit
    /// analysis is done, so that it starts on the attractor). A failed or
    /// stopped run counts as settled: the picture shows its error.
    fn numerics_settled(&mut self) -> bool {
        let shown = match self.settings.layout {
            Layout::Tabs => self.settings.tab == View::Numerics,
            Layout::Tiles => self.settings.tiled.contains(&View::Numerics),
        };
        if !shown {
            return true;
        }
        if self.numerics.run.generation.is_none() {
            self.start_work_precision();
        }
        self.numerics.run.state != JobState::Running
    }

    /// Records one frame for `--frame-stats` (eframe's CPU time if known).
    pub fn record_frame(&mut self, cpu_seconds: Option<f32>) {
        if !self.stats.enabled {
            return;
        }
        self.stats.tick();
        if let Some(c) = cpu_seconds
            && self.stats.recording
        {
            self.stats.cpu.push(c * 1e3);
        }
    }

    fn apply_style(&mut self, ctx: &Context) {
        let want = (self.settings.font_scale, self.settings.dark);
        if self.applied_style == Some(want) {
            return;
        }
        ctx.set_theme(if want.1 {
            egui::Theme::Dark
        } else {
            egui::Theme::Light
        });
        let base = egui::Style::default().text_styles;
        let scale = want.0.clamp(0.5, 3.0);
        ctx.all_styles_mut(|s| {
            for (ts, font) in s.text_styles.iter_mut() {
                if let Some(b) = base.get(ts) {
                    font.size = b.size * scale;
                }
            }
        });
        self.applied_style = Some(want);
    }

    fn shortcuts(&mut self, ctx: &Context) -> Actions {
        let mut a = Actions::default();
        let save = KeyboardShortcut::new(Modifiers::COMMAND, Key::S);
        if ctx.input_mut(|i| i.consume_shortcut(&save)) {
            a.screenshot = true;
        }
        if ctx.egui_wants_keyboard_input() {
            return a;
        }
        let tabs = [
            Key::Num1,
            Key::Num2,
            Key::Num3,
            Key::Num4,
            Key::Num5,
            Key::Num6,
            Key::Num7,
        ];
        for (k, v) in tabs.into_iter().zip(View::ALL) {
            if ctx.input(|i| i.key_pressed(k)) {
                self.settings.layout = Layout::Tabs;
                self.settings.tab = v;
            }
        }
        if ctx.input(|i| i.key_pressed(Key::T)) {
            self.settings.layout = match self.settings.layout {
                Layout::Tabs => Layout::Tiles,
                Layout::Tiles => Layout::Tabs,
            };
        }
        if ctx.input(|i| i.key_pressed(Key::Space)) {
            self.block.playing = !self.block.playing;
        }
        if ctx.input(|i| i.key_pressed(Key::R)) {
            a.restart = true;
        }
        let (left, right, shift) = ctx.input(|i| {
            (
                i.key_pressed(Key::ArrowLeft),
                i.key_pressed(Key::ArrowRight),
                i.modifiers.shift,
            )
        });
        if left || right {
            let step = if shift { 0.05 } else { 0.005 };
            let (lo, hi) = self.settings.sweep_range();
            let tn = self.settings.params.theta_nu + if right { step } else { -step };
            self.settings.params.theta_nu = tn.clamp(lo, hi);
        }
        a
    }

    /// Says with what accuracy an exported trajectory or its events were
    /// computed: under Auto that is the (x, y) view's, far coarser than the
    /// command line's default, and a CSV does not show it.
    fn accuracy_note(&mut self, what: &str) {
        if self.settings.accuracy != AccuracyMode::Auto {
            return;
        }
        let Some(e) = job_estimates(&self.settings)
            .into_iter()
            .find(|e| e.job == JobKind::Trajectory)
        else {
            return;
        };
        let msg = format!(
            "The {what} was computed at Auto's trajectory accuracy ({}); pick Custom, or \
             use `oneblock orbit` / `trajectory` (tol 1e-10), for a tighter one.",
            e.text()
        );
        self.shots.toast(msg, false, self.now);
    }

    fn handle_actions(&mut self, a: Actions, ctx: &Context) {
        if a.screenshot {
            let path = fresh_path(&self.settings.save_dir, "window", "png");
            self.shots.request(ctx, path, None);
        }
        let dir = self.settings.save_dir.clone();
        if a.export_events {
            if self.data.trajectory.events.is_empty() {
                self.shots
                    .toast("No events to export yet".into(), true, self.now);
            } else {
                let csv = export::events_csv(&self.data.trajectory.events);
                self.shots
                    .write(fresh_path(&dir, "events", "csv"), csv.into_bytes());
                self.accuracy_note("events");
            }
        }
        if a.export_trajectory {
            if self.data.trajectory.samples.is_empty() {
                self.shots
                    .toast("No trajectory to export yet".into(), true, self.now);
            } else {
                let csv = export::trajectory_csv(&self.data.trajectory.samples);
                self.shots
                    .write(fresh_path(&dir, "trajectory", "csv"), csv.into_bytes());
                self.accuracy_note("trajectory");
            }
        }
        if a.export_bifurcation {
            if self.data.sweep.filled == 0 {
                self.shots
                    .toast("No diagram columns to export yet".into(), true, self.now);
            } else {
                let csv = export::bifurcation_csv(&self.data.sweep);
                self.shots
                    .write(fresh_path(&dir, "bifurcation", "csv"), csv.into_bytes());
            }
        }
        if a.export_phase {
            if self.data.phase.filled == 0 {
                self.shots.toast(
                    "No phase-diagram cells to export yet".into(),
                    true,
                    self.now,
                );
            } else {
                let csv = export::phase_csv(&self.data.phase);
                self.shots
                    .write(fresh_path(&dir, "phase", "csv"), csv.into_bytes());
            }
        }
        if a.reset_defaults {
            let dir = std::mem::take(&mut self.settings.save_dir);
            self.settings = Settings {
                save_dir: dir,
                ..Settings::default()
            };
            self.controls.resync();
            self.bifurcation.zoom.clear();
            self.bifurcation.invalidate();
        }
        if a.restart {
            self.restart_orbit();
        }
    }

    /// The whole window.
    pub fn show(&mut self, ui: &mut Ui) {
        let ctx = ui.ctx().clone();
        self.now = ctx.input(|i| i.time);
        self.apply_style(&ctx);
        let mut actions = self.shortcuts(&ctx);

        // No fills on the panels either (see the central panel below).
        let bare = egui::Frame::side_top_panel(ui.style()).fill(egui::Color32::TRANSPARENT);
        egui::Panel::top("top").frame(bare).show(ui, |ui| {
            ui.horizontal_wrapped(|ui| {
                ui.label(
                    RichText::new("oneblock")
                        .strong()
                        .size(ui.text_style_height(&egui::TextStyle::Heading)),
                );
                ui.separator();
                ui.selectable_value(&mut self.settings.layout, Layout::Tiles, "Tiles")
                    .on_hover_text("Several views at once (T toggles)");
                ui.selectable_value(&mut self.settings.layout, Layout::Tabs, "Tabs")
                    .on_hover_text("One view, full size (keys 1–7)");
                ui.separator();
                match self.settings.layout {
                    Layout::Tabs => {
                        for v in View::ALL {
                            ui.selectable_value(&mut self.settings.tab, v, v.title());
                        }
                    }
                    Layout::Tiles => {
                        ui.label("tiles:");
                        for v in View::ALL {
                            let mut on = self.settings.tiled.contains(&v);
                            if ui.checkbox(&mut on, v.title()).changed() {
                                if on {
                                    self.settings.tiled.push(v);
                                    self.settings
                                        .tiled
                                        .sort_by_key(|x| View::ALL.iter().position(|y| y == x));
                                } else if self.settings.tiled.len() > 1 {
                                    self.settings.tiled.retain(|x| *x != v);
                                }
                            }
                        }
                    }
                }
            });
        });

        egui::Panel::bottom("status")
            .frame(bare)
            .show(ui, |ui| self.status_ui(ui));

        egui::Panel::left("controls")
            .frame(bare)
            .resizable(true)
            .default_size(330.0)
            .min_size(260.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    let a = self.controls.ui(ui, &mut self.settings, &self.data);
                    merge(&mut actions, a);
                });
            });

        // No fill: the clear colour is the panel colour, which saves
        // painting the largest area twice (software rendering is fill-bound).
        let frame = egui::Frame::central_panel(ui.style()).fill(egui::Color32::TRANSPARENT);
        egui::CentralPanel::default_margins()
            .frame(frame)
            .show(ui, |ui| self.views_ui(ui));

        self.handle_actions(actions, &ctx);
        self.sync_jobs(&ctx);
        self.toasts_ui(&ctx);
        if self.stats.enabled {
            self.stats_overlay(&ctx);
        }
    }

    fn views_ui(&mut self, ui: &mut Ui) {
        self.view_rects.clear();
        match self.settings.layout {
            Layout::Tabs => {
                let v = self.settings.tab;
                let r = ui.available_rect_before_wrap();
                self.view_ui(ui, v, r);
            }
            Layout::Tiles => {
                let views = self.settings.tiled.clone();
                let area = ui.available_rect_before_wrap();
                let n = views.len().max(1);
                let cols = if n == 1 { 1 } else { 2 };
                let rows = n.div_ceil(cols);
                let gap = 6.0;
                let w = (area.width() - gap * (cols as f32 - 1.0)) / cols as f32;
                let h = (area.height() - gap * (rows as f32 - 1.0)) / rows as f32;
                for (i, v) in views.into_iter().enumerate() {
                    let (r, c) = (i / cols, i % cols);
                    // The last row's single tile spans the width.
                    let span = if r == rows - 1 && n % cols == 1 && cols == 2 {
                        2.0
                    } else {
                        1.0
                    };
                    let min = area.min + egui::vec2(c as f32 * (w + gap), r as f32 * (h + gap));
                    let rect =
                        Rect::from_min_size(min, egui::vec2(w * span + gap * (span - 1.0), h));
                    self.view_ui(ui, v, rect);
                }
                ui.allocate_rect(area, egui::Sense::hover());
            }
        }
    }

    /// One view in `rect`, with its title and a screenshot button.
    fn view_ui(&mut self, ui: &mut Ui, v: View, rect: Rect) {
        self.view_rects.insert(v, rect);
        let mut shot = false;
        ui.scope_builder(
            egui::UiBuilder::new().max_rect(rect).id_salt(v.key()),
            |ui| {
                egui::Frame::group(ui.style())
                    .inner_margin(4.0)
                    .show(ui, |ui| {
                        ui.set_min_size(ui.available_size());
                        ui.horizontal(|ui| {
                            ui.label(RichText::new(v.title()).strong());
                            ui.with_layout(
                                egui::Layout::right_to_left(egui::Align::Center),
                                |ui| {
                                    if ui
                                        .small_button("PNG")
                                        .on_hover_text(format!(
                                            "Save a PNG of the {} view only",
                                            v.title()
                                        ))
                                        .clicked()
                                    {
                                        shot = true;
                                    }
                                },
                            );
                        });
                        match v {
                            View::Plane => self.plane.ui(ui, &mut self.settings, &self.data),
                            View::Block => self.block.ui(ui, &mut self.settings, &self.data),
                            View::Bifurcation => {
                                match self.bifurcation.ui(ui, &self.settings, &self.data.sweep) {
                                    Some(BifAction::SetThetaNu(x)) => {
                                        let (lo, hi) = self.settings.sweep_range();
                                        self.settings.params.theta_nu = x.clamp(lo, hi);
                                    }
                                    Some(BifAction::Zoomed) => {}
                                    None => {}
                                }
                            }
                            View::ReturnMap => self.return_map.ui(ui, &self.settings, &self.data),
                            View::Events => self.events.ui(ui, &mut self.settings, &self.data),
                            View::Numerics => match self.numerics.ui(ui, &self.settings) {
                                Some(NumericsAction::Run) => self.start_work_precision(),
                                Some(NumericsAction::Stop) => self.stop_work_precision(),
                                None => {}
                            },
                            View::Phase => {
                                let a = self.phase.ui(
                                    ui,
                                    &mut self.settings,
                                    &self.data.phase,
                                    self.data.phase_progress,
                                    &self.phase_job,
                                );
                                if let Some(a) = a {
                                    self.phase_action(a);
                                }
                            }
                        }
                    });
            },
        );
        if shot {
            let path = fresh_path(&self.settings.save_dir, v.key(), "png");
            self.shots.request(ui.ctx(), path, Some(rect));
        }
    }

    fn status_ui(&mut self, ui: &mut Ui) {
        let d = &self.data;
        ui.horizontal_wrapped(|ui| {
            let busy = [
                &d.trajectory.state,
                &d.iterate.state,
                &d.sweep.state,
                &d.phase.state,
            ]
            .iter()
            .any(|s| matches!(s, JobState::Running));
            if busy {
                ui.spinner();
            }
            let traj = match &d.trajectory.state {
                JobState::Running => format!("trajectory: {} cycles…", d.trajectory.events.len()),
                JobState::Done => format!("trajectory: {} cycles", d.trajectory.events.len()),
                s => format!("trajectory: {}", state_word(s)),
            };
            ui.label(traj);
            ui.separator();
            let orbit = match (&d.iterate.state, d.iterate.period) {
                (JobState::Running, _) => format!(
                    "orbit analysis {:.0}%",
                    100.0 * d.orbit_progress.fraction.clamp(0.0, 1.0)
                ),
                (_, Some(p)) => format!("period {p}"),
                (s, None) => format!("orbit: {}", state_word(s)),
            };
            ui.label(orbit);
            ui.separator();
            let frac = if d.sweep.columns.is_empty() {
                0.0
            } else {
                d.sweep.filled as f32 / d.sweep.columns.len() as f32
            };
            ui.label("diagram");
            ui.add(
                egui::ProgressBar::new(frac)
                    .desired_width(120.0)
                    .text(format!("{}/{}", d.sweep.filled, d.sweep.columns.len())),
            );
            let phase_cells = d.phase.rows * d.phase.columns;
            if phase_cells > 0 {
                ui.label("phase");
                ui.add(
                    egui::ProgressBar::new(d.phase.filled as f32 / phase_cells as f32)
                        .desired_width(100.0)
                        .text(format!("{}/{phase_cells}", d.phase.filled)),
                );
            }
            ui.label(format!(
                "{:.0} iterates/s",
                d.sweep_progress.iterates_per_second
                    + d.orbit_progress.iterates_per_second
                    + d.phase_progress.iterates_per_second
            ));
            if let Some(e) = &d.last_error {
                ui.separator();
                ui.label(RichText::new(format!("error: {e}")).color(style::ERROR));
            }
        });
    }

    fn toasts_ui(&self, ctx: &Context) {
        if self.shots.toasts.is_empty() {
            return;
        }
        egui::Area::new(egui::Id::unique("toasts"))
            .anchor(egui::Align2::RIGHT_BOTTOM, egui::vec2(-16.0, -40.0))
            .order(egui::Order::Foreground)
            .show(ctx, |ui| {
                for t in &self.shots.toasts {
                    egui::Frame::popup(ui.style()).show(ui, |ui| {
                        let c = if t.error {
                            style::ERROR
                        } else {
                            ui.visuals().text_color()
                        };
                        ui.label(RichText::new(&t.text).color(c));
                    });
                }
            });
    }

    fn stats_overlay(&self, ctx: &Context) {
        let last: Vec<f32> = self
            .stats
            .intervals
            .iter()
            .rev()
            .take(120)
            .copied()
            .collect();
        let text = match median(&last) {
            Some(m) => format!("frame {m:.1} ms (median of last {})", last.len()),
            None => "frame time: measuring…".into(),
        };
        egui::Area::new(egui::Id::unique("frame_stats"))
            .anchor(egui::Align2::RIGHT_TOP, egui::vec2(-10.0, 40.0))
            .order(egui::Order::Foreground)
            .show(ctx, |ui| {
                egui::Frame::popup(ui.style()).show(ui, |ui| {
                    ui.label(
                        RichText::new(text)
                            .monospace()
                            .color(Color32::from_rgb(0, 120, 60)),
                    );
                });
            });
    }
}

fn state_word(s: &JobState) -> String {
    match s {
        JobState::Idle => "idle".into(),
        JobState::Running => "running".into(),
        JobState::Done => "done".into(),
        JobState::Cancelled => "cancelled".into(),
        JobState::Failed(m) => format!("failed: {m}"),
    }
}

fn merge(a: &mut Actions, b: Actions) {
    a.screenshot |= b.screenshot;
    a.export_events |= b.export_events;
    a.export_trajectory |= b.export_trajectory;
    a.export_bifurcation |= b.export_bifurcation;
    a.export_phase |= b.export_phase;
    a.reset_defaults |= b.reset_defaults;
    a.restart |= b.restart;
}

impl eframe::App for Explorer {
    fn logic(&mut self, ctx: &Context, frame: &mut eframe::Frame) {
        self.record_frame(frame.info().cpu_usage);
        self.logic_step(ctx);
    }

    fn ui(&mut self, ui: &mut Ui, _frame: &mut eframe::Frame) {
        self.show(ui);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        if self.persist {
            eframe::set_value(storage, eframe::APP_KEY, &self.settings);
        }
    }

    fn persist_egui_memory(&self) -> bool {
        self.persist
    }

    fn raw_input_hook(&mut self, _ctx: &Context, raw_input: &mut egui::RawInput) {
        // A scripted run draws for a picture: wherever the X server left the
        // pointer, it must not hover a plot (crosshairs, tooltips).
        if self.script.is_some() {
            raw_input.events.retain(|e| {
                !matches!(
                    e,
                    egui::Event::PointerMoved(_)
                        | egui::Event::MouseMoved(_)
                        | egui::Event::PointerButton { .. }
                )
            });
            raw_input.events.push(egui::Event::PointerGone);
        }
    }

    fn clear_color(&self, visuals: &egui::Visuals) -> [f32; 4] {
        visuals.panel_fill.to_normalized_gamma_f32()
    }
}

impl Drop for Explorer {
    fn drop(&mut self) {
        if self.stats.enabled
            && let Some(sink) = &self.stats_sink
        {
            *sink.lock().unwrap_or_else(PoisonError::into_inner) = Some(self.stats.report());
        }
        // Stop both lanes promptly; the worker's own Drop joins its threads.
        self.backend.send(Command::Cancel {
            generation: self.next_generation,
            lane: None,
        });
    }
}
