//! A scripted run (`oneblock gui --screenshot`): wait for the views to be
//! complete, optionally measure frame times and the slider-to-picture
//! latency (`--frame-stats`), or with `--play` let θν play for a while
//! (measuring its frames with `--frame-stats`), take one screenshot (a PNG, or an SVG when
//! the file name ends in `.svg`), close the window. A picture of the
//! bifurcation view alone shows its branches ("Find bifurcations"), one of
//! the phase view alone its boundary curves: both are run once the other
//! views are complete, and waited for.

use std::path::PathBuf;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;
use web_time::Instant;

use eframe::egui;
use egui::Context;

use super::bifurcation::Zoom;
use super::frame_stats::FrameStats;
use super::jobs::{JobState, Jobs, continuation_range};
use super::layout_report::LayoutReport;
use super::play::Play;
use super::screenshot::{Saved, Shots};
use super::settings::{Layout, Settings, ViewKind};
use super::svg_render;
use crate::worker::Generation;

/// How long a scripted run plays θν (`gui --play --screenshot`).
pub const PLAY_SECONDS: f64 = 5.0;

/// Whether a scripted run saves an SVG (by the file's extension) rather
/// than a PNG.
pub fn is_svg(p: &std::path::Path) -> bool {
    p.extension().is_some_and(|e| e.eq_ignore_ascii_case("svg"))
}

/// A scripted run: wait for the views, optionally measure frame times,
/// take one screenshot, close.
pub struct Script {
    pub path: PathBuf,
    /// Where the layout goes with the picture (`--layout`), if anywhere.
    pub layout: Option<PathBuf>,
    /// Saves asked for and not yet answered (the picture, the layout).
    pending: usize,
    pub timeout: Duration,
    /// Cycles the trajectory must have before the picture is taken.
    pub min_cycles: usize,
    /// Measure frame times for this long with a trajectory streaming.
    pub measure: Option<Duration>,
    /// Once the views are complete, play θν for [`PLAY_SECONDS`] (the
    /// frames measured instead of the streaming ones).
    pub play: bool,
    /// While θν plays: the trajectory's generation last seen, and how
    /// many times it restarted.
    play_seen: (Generation, usize),
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
    /// Or θν playing until then, from this θν.
    Playing(Instant, f64),
    /// Then slider-to-picture: θν moved (the n-th time) at this instant;
    /// waiting for the first slip of the new trajectory on screen.
    Latency(u32, Instant, Generation),
    Settling(u32),
    Shooting,
    Closing,
}

/// What a scripted step may touch.
pub struct Window<'a> {
    /// The size of the views' area on screen (for an SVG).
    pub area: egui::Vec2,
    /// The views, plots and tour box as last drawn (for `--layout`).
    pub layout: LayoutReport,
    /// The bifurcation diagram's zoom stack (for an SVG).
    pub zoom: &'a [Zoom],
    pub settings: &'a mut Settings,
    pub jobs: &'a mut Jobs,
    pub shots: &'a mut Shots,
    pub stats: &'a mut FrameStats,
    /// The play clock of θν.
    pub play: &'a mut Play,
    /// The ui time, seconds.
    pub now: f64,
}

impl Script {
    /// A run that saves to `path`, gives up after `timeout`, and measures
    /// frame times for `measure` if given.
    pub fn new(path: PathBuf, timeout: Duration, measure: Option<Duration>) -> Self {
        Script {
            path,
            layout: None,
            pending: 0,
            timeout,
            min_cycles: 12,
            measure,
            outcome: Arc::new(Mutex::new(None)),
            play: false,
            play_seen: (0, 0),
            started: None,
            stage: Stage::Waiting,
        }
    }

    fn finish(&mut self, ctx: &Context, r: Result<String, String>) {
        *self.outcome.lock().unwrap_or_else(PoisonError::into_inner) = Some(r);
        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        self.stage = Stage::Closing;
    }

    /// One frame of the run.
    pub fn step(&mut self, ctx: &Context, w: Window<'_>) {
        let start = *self.started.get_or_insert_with(Instant::now);
        ctx.request_repaint();
        match self.stage {
            Stage::Waiting => self.wait_for_views(ctx, w, start),
            Stage::MeasuringIdle(until) if self.play => {
                if Instant::now() >= until {
                    self.start_playing(w);
                }
            }
            Stage::Playing(until, from) => {
                // A restart at most every 40 ms, a frame apart at least:
                // each new generation seen is one.
                let g = w.jobs.trajectory.generation;
                if g != self.play_seen.0 {
                    self.play_seen = (g, self.play_seen.1 + 1);
                }
                if Instant::now() >= until {
                    self.stop_playing(w, from);
                }
            }
            Stage::MeasuringIdle(until) => {
                if Instant::now() >= until {
                    // A trajectory streaming without end over a full diagram.
                    w.jobs.stream_forever = true;
                    w.jobs.restart_orbit(w.settings, w.now);
                    w.stats.streaming = true;
                    w.stats.samples_at_start = 0;
                    let d = self.measure.unwrap_or(Duration::from_secs(5));
                    self.stage = Stage::Measuring(Instant::now() + d);
                }
            }
            Stage::Measuring(until) => {
                if Instant::now() >= until {
                    w.stats.recording = false;
                    w.stats.points = w.jobs.sweep.data.points();
                    w.stats.samples_at_end = w.jobs.trajectory.data.samples.len();
                    w.jobs.stream_forever = false;
                    w.settings.params.theta_nu += 0.01;
                    self.stage = Stage::Latency(0, Instant::now(), w.jobs.trajectory.generation);
                }
            }
            Stage::Latency(n, since, before) => {
                let tr = &w.jobs.trajectory;
                // Logic runs before drawing: a slip here is on this frame.
                if tr.generation > before && !tr.data.events.is_empty() {
                    w.stats.latency.push(since.elapsed().as_secs_f32() * 1e3);
                    if n + 1 >= 10 {
                        self.stage = Stage::Settling(0);
                    } else {
                        w.settings.params.theta_nu += if n % 2 == 0 { -0.01 } else { 0.01 };
                        self.stage = Stage::Latency(n + 1, Instant::now(), tr.generation);
                    }
                } else if since.elapsed() > Duration::from_secs(10) {
                    self.stage = Stage::Settling(0);
                }
            }
            Stage::Settling(n) => {
                // A few frames so plots settle their bounds and textures upload.
                if n >= 4 {
                    self.pending = 1;
                    if let Some(p) = &self.layout {
                        w.shots.write(p.clone(), w.layout.to_json().into_bytes());
                        self.pending += 1;
                    }
                    if is_svg(&self.path) {
                        let views = svg_render::shown_views(w.settings);
                        let svg = svg_render::render_svg(
                            &views, w.settings, w.jobs, w.zoom, w.area, false,
                        );
                        w.shots.write(self.path.clone(), svg.into_bytes());
                    } else {
                        w.shots.request(ctx, self.path.clone(), None);
                    }
                    self.stage = Stage::Shooting;
                } else {
                    self.stage = Stage::Settling(n + 1);
                }
            }
            Stage::Shooting => {
                // The picture's outcome, or the layout's: a failure of
                // either ends the run, the last success names both.
                if let Some(r) = w.shots.finished.pop() {
                    self.pending = self.pending.saturating_sub(1);
                    match r {
                        Saved::Failed(e) => {
                            self.finish(ctx, Err(format!("screenshot failed: {e}")));
                        }
                        Saved::Ok(_) if self.pending > 0 => {}
                        Saved::Ok(_) => {
                            let said = match &self.layout {
                                Some(l) => {
                                    format!("{} (layout in {})", self.path.display(), l.display())
                                }
                                None => self.path.display().to_string(),
                            };
                            self.finish(ctx, Ok(said));
                        }
                    }
                } else if start.elapsed() > self.timeout + super::SCREENSHOT_GRACE / 2 {
                    self.finish(ctx, Err("the window never delivered the screenshot".into()));
                }
            }
            Stage::Closing => {}
        }
    }

    /// Stops θν playing (started at θν `from`)
    /// and says what was played; the picture is taken once the views are
    /// complete at the θν it stopped at (nothing measured again).
    fn stop_playing(&mut self, w: Window<'_>, from: f64) {
        w.play.toggle();
        let st = &mut *w.stats;
        st.playing = false;
        st.recording = false;
        st.played = Some((from, w.settings.params.theta_nu));
        st.play_restarts = self.play_seen.1;
        self.play = false;
        self.measure = None;
        self.stage = Stage::Waiting;
    }

    /// Starts θν playing for [`PLAY_SECONDS`], its frames recorded.
    fn start_playing(&mut self, w: Window<'_>) {
        if !w.play.on {
            w.play.toggle();
        }
        w.stats.playing = true;
        self.stage = Stage::Playing(
            Instant::now() + Duration::from_secs_f64(PLAY_SECONDS),
            w.settings.params.theta_nu,
        );
        self.play_seen = (w.jobs.trajectory.generation, 0);
    }

    /// Waits until every view shown has its results (or one failed, or the
    /// time is up). The Numerics view's measurement is started here, once
    /// the orbit analysis is done, so that it starts on the attractor.
    fn wait_for_views(&mut self, ctx: &Context, w: Window<'_>, start: Instant) {
        let jobs = &*w.jobs;
        let shows_phase = w.settings.shows(ViewKind::Phase);
        let shows_numerics = w.settings.shows(ViewKind::Numerics);
        let failed = [
            &jobs.sweep.state,
            &jobs.trajectory.state,
            &jobs.iterate.state,
        ]
        .into_iter()
        .chain(shows_phase.then_some(&jobs.phase.state))
        .find_map(|s| match s {
            JobState::Failed(m) => Some(m.clone()),
            _ => None,
        });
        if let Some(failed) = failed {
            self.finish(ctx, Err(format!("the simulation failed: {failed}")));
            return;
        }
        let orbit_views = jobs.complete(self.min_cycles);
        if orbit_views && shows_numerics && !jobs.numerics.issued() {
            w.jobs.start_work_precision(w.settings);
            return;
        }
        let alone = |v: ViewKind| w.settings.layout == Layout::Tabs && w.settings.tab == v;
        let (branches, curves) = (alone(ViewKind::Bifurcation), alone(ViewKind::Phase));
        // Not started, or a session's kept result cleared (its slot idle):
        // computed, as the window's button does.
        if orbit_views && branches && jobs.branches.state == JobState::Idle {
            let zoom = w.zoom.last().map(|z| z.theta_nu);
            let range = continuation_range(w.settings, zoom);
            w.jobs.find_bifurcations(w.settings, range);
            return;
        }
        if orbit_views
            && curves
            && jobs.phase.state == JobState::Done
            && jobs.curves.state == JobState::Idle
        {
            w.jobs.compute_boundaries(w.settings);
            return;
        }
        let jobs = &*w.jobs;
        let settled = |state: &JobState| state != &JobState::Running;
        if orbit_views
            && (!shows_numerics || jobs.numerics_settled())
            && (!shows_phase || jobs.phase.state == JobState::Done)
            && (!w.settings.shows(ViewKind::Basins)
                || jobs.basins.issued() && settled(&jobs.basins.state))
            && (!branches || settled(&jobs.branches.state))
            && (!curves || (jobs.curves.issued() && settled(&jobs.curves.state)))
        {
            if self.measure.is_some() {
                w.stats.enabled = true;
                w.stats.recording = true;
                w.stats.streaming = false;
                self.stage = Stage::MeasuringIdle(Instant::now() + Duration::from_secs(3));
            } else if self.play {
                self.start_playing(w);
            } else {
                self.stage = Stage::Settling(0);
            }
        } else if start.elapsed() > self.timeout {
            let msg = format!(
                "timed out after {:.0} s waiting for the views: trajectory {} cycles ({:?}), \
                 orbit analysis {:?}, diagram {}/{} columns ({:?})",
                self.timeout.as_secs_f64(),
                jobs.trajectory.data.events.len(),
                jobs.trajectory.state,
                jobs.iterate.state,
                jobs.sweep.data.filled,
                jobs.sweep.data.columns.len(),
                jobs.sweep.state,
            );
            self.finish(ctx, Err(msg));
        }
    }
}
