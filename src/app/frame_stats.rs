//! Frame-time bookkeeping for `--frame-stats`: the intervals between
//! frames while a trajectory streams and while nothing does, eframe's CPU
//! time per frame, and the slider-to-picture latency; the one-line report
//! and the small overlay that shows the running median.

use web_time::Instant;

use eframe::egui;
use egui::{Color32, Context, RichText};

/// Frame-time bookkeeping (`--frame-stats`).
#[derive(Default)]
pub struct FrameStats {
    pub enabled: bool,
    last: Option<Instant>,
    /// Whether intervals are being recorded now.
    pub recording: bool,
    /// Intervals between frames, in milliseconds, with a trajectory streaming.
    pub intervals: Vec<f32>,
    /// The same with nothing streaming (diagram full, trajectory done).
    pub idle: Vec<f32>,
    /// From a θν change to the frame showing the new trajectory's first slip, ms.
    pub latency: Vec<f32>,
    /// Whether a trajectory streams now (which list an interval goes to).
    pub streaming: bool,
    /// CPU time eframe reports per frame, in milliseconds.
    pub cpu: Vec<f32>,
    /// Whether θν plays now (`gui --play`): intervals go to `play_frames`.
    pub playing: bool,
    /// Intervals between frames while θν plays, ms, and eframe's CPU time.
    pub play_frames: Vec<f32>,
    pub play_cpu: Vec<f32>,
    /// θν where the play started and stopped, and how many times the
    /// trajectory restarted meanwhile.
    pub played: Option<(f64, f64)>,
    pub play_restarts: usize,
    /// Points in the diagram and samples received while recording.
    pub points: usize,
    pub samples_at_start: usize,
    pub samples_at_end: usize,
    /// Per view shown while θν played: (frames it showed a result in,
    /// frames), by the view's key.
    pub filled: std::collections::BTreeMap<&'static str, (usize, usize)>,
    /// The last [`LIVE_FRAMES`] intervals, recorded whenever stats are on:
    /// what the overlay shows in a live window, where nothing scripts a
    /// measurement (it used to wait for one and say "measuring…" for ever).
    live: std::collections::VecDeque<f32>,
}

/// Frames the overlay's running median is taken over.
const LIVE_FRAMES: usize = 120;

/// The middle value of `v` (the upper of two).
fn median(v: &[f32]) -> Option<f32> {
    if v.is_empty() {
        return None;
    }
    let mut s = v.to_vec();
    s.sort_by(f32::total_cmp);
    Some(s[s.len() / 2])
}

/// The `q`-quantile of `v` (the lower of two middle values).
fn percentile(v: &[f32], q: f32) -> Option<f32> {
    if v.is_empty() {
        return None;
    }
    let mut s = v.to_vec();
    s.sort_by(f32::total_cmp);
    Some(s[((s.len() - 1) as f32 * q) as usize])
}

/// Whether view `v` shows a result of some θν now (the latest finished or
/// streaming one), not an empty plot or "computing…".
pub fn shows_result(jobs: &crate::app::jobs::Jobs, v: crate::app::ViewKind) -> bool {
    use crate::app::ViewKind;
    match v {
        ViewKind::Plane | ViewKind::Block | ViewKind::TimeSeries => {
            !jobs.trajectory.data.samples.is_empty()
        }
        ViewKind::Events => !jobs.trajectory.data.events.is_empty(),
        ViewKind::ReturnMap => {
            let it = &jobs.iterate.data;
            it.period.is_some() && !it.thetas.is_empty()
        }
        ViewKind::Bifurcation => jobs.sweep.data.filled > 0,
        ViewKind::Phase => jobs.phase.data.filled > 0,
        ViewKind::Basins => jobs.basins.data.arrived() > 0,
        ViewKind::Numerics => !jobs.numerics.data.rows.is_empty(),
    }
}

impl FrameStats {
    /// Counts one played frame for each of the `views` shown: whether it
    /// showed a result ([`shows_result`]).
    pub fn count_filled(&mut self, jobs: &crate::app::jobs::Jobs, views: &[crate::app::ViewKind]) {
        if !(self.enabled && self.recording && self.playing) {
            return;
        }
        for &v in views {
            let e = self.filled.entry(v.key()).or_default();
            e.0 += usize::from(shows_result(jobs, v));
            e.1 += 1;
        }
    }

    /// One line per view shown while θν played: `filled VIEW: 0.97`, the
    /// share of played frames in which it showed a result.
    fn filled_report(&self) -> String {
        self.filled
            .iter()
            .map(|(k, (f, n))| format!("\nfilled {k}: {:.2}", *f as f64 / (*n).max(1) as f64))
            .collect()
    }

    /// Records one frame (with eframe's CPU time for it, if known).
    pub fn record(&mut self, cpu_seconds: Option<f32>) {
        if !self.enabled {
            return;
        }
        let now = Instant::now();
        if let Some(l) = self.last {
            let ms = (now - l).as_secs_f32() * 1e3;
            if self.live.len() == LIVE_FRAMES {
                self.live.pop_front();
            }
            self.live.push_back(ms);
        }
        if let Some(l) = self.last
            && self.recording
        {
            let ms = (now - l).as_secs_f32() * 1e3;
            if self.playing {
                self.play_frames.push(ms);
            } else if self.streaming {
                self.intervals.push(ms);
            } else {
                self.idle.push(ms);
            }
        }
        self.last = Some(now);
        if let Some(c) = cpu_seconds
            && self.recording
        {
            if self.playing {
                self.play_cpu.push(c * 1e3);
            } else {
                self.cpu.push(c * 1e3);
            }
        }
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
        if let Some(m) = median(&self.play_frames) {
            return format!("{idle}{}{}", self.play_report(m), self.filled_report());
        }
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

    /// The line of a run that played θν, whose frames' median is `m`.
    fn play_report(&self, m: f32) -> String {
        let (from, to) = self.played.unwrap_or((f64::NAN, f64::NAN));
        format!(
            "frame-stats: playing θν: median frame time {m:.1} ms (p90 {:.1} ms) over {} frames; \
             median CPU per frame {}; θν {from:.4} → {to:.4}, the trajectory restarted {} times",
            percentile(&self.play_frames, 0.9).unwrap_or(m),
            self.play_frames.len(),
            median(&self.play_cpu).map_or("n/a".into(), |c| format!("{c:.1} ms")),
            self.play_restarts,
        )
    }

    /// The text of the overlay: the running median of the last frames.
    pub fn overlay_text(&self) -> String {
        let last: Vec<f32> = self.live.iter().copied().collect();
        match median(&last) {
            Some(m) => format!("frame {m:.1} ms (median of last {})", last.len()),
            None => "frame time: measuring…".into(),
        }
    }

    /// The running median of the last frames, in the bottom-left corner
    /// above the status bar, where it covers no view's buttons (the views'
    /// SVG and PNG buttons are at their top right), and lets clicks through.
    pub fn overlay(&self, ctx: &Context) {
        let text = self.overlay_text();
        egui::Area::new(egui::Id::unique("frame_stats"))
            .anchor(egui::Align2::LEFT_BOTTOM, egui::vec2(10.0, -34.0))
            .interactable(false)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_pick_from_the_sorted_values() {
        let v = [5.0, 1.0, 4.0, 2.0, 3.0];
        assert_eq!(median(&v), Some(3.0));
        assert_eq!(median(&[2.0, 1.0]), Some(2.0));
        assert_eq!(percentile(&v, 0.9), Some(4.0));
        assert_eq!(percentile(&v, 1.0), Some(5.0));
        assert_eq!(median(&[]), None);
    }

    #[test]
    fn the_overlay_measures_a_live_window_with_nothing_recording() {
        let mut s = FrameStats {
            enabled: true,
            ..FrameStats::default()
        };
        assert!(s.overlay_text().contains("measuring"));
        for _ in 0..3 {
            s.record(None);
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        assert!(!s.recording && s.intervals.is_empty());
        let t = s.overlay_text();
        assert!(
            t.starts_with("frame ") && t.contains("median of last 2"),
            "{t}"
        );
        for _ in 0..200 {
            s.record(None);
        }
        assert!(s.overlay_text().contains("median of last 120"));
    }
}
