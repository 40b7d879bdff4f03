//! A GIF of θν played (`figure --play`, the window's Record → "θν played"):
//! frame k shows the view at θν = from + k·(to − from)/(frames − 1), as the
//! window shows it while Play moves θν. One job model over the
//! single-threaded worker runs the whole play: each frame's settings are
//! synced as the window syncs a slider's move, so only what θν changes is
//! computed again (the trajectory and the orbit analysis; the diagram
//! once). Each frame is drawn by the window's view code ([`FrameRenderer`]),
//! rasterised, indexed and encoded before the next is computed: memory
//! holds one frame, and the first chunk the palette is learnt from.
//!
//! The return map holds its axes over the whole play (the diagram's θ over
//! the played θν, which the diagram's sweep gives), so that its fixed point
//! is seen to move along the diagonal; the window's own map follows the
//! attractor.
//!
//! Every view holds its legends and plot bounds over the play
//! ([`super::super::hold`]): the frames are computed twice, the first time
//! only drawn off screen to gather each legend's entries and each plot's
//! bounds over all of them, the second time drawn with that union, so
//! that no axis moves and no legend entry comes and goes (a return map's
//! axes once jumped when the density's entry wrapped its legend onto a
//! second row). Computing twice costs time, not memory: a frame's data is
//! not kept (a plane's trajectory is megabytes a frame).

use std::sync::Arc;
use std::time::Duration;

use super::super::axes;
use super::super::figure::{ComputeRun, Figure, font_db, pixmap_with_fonts, view_settings};
use super::super::hold::{Held, Start};
use super::super::jobs::Jobs;
use super::super::settings::{Settings, ViewKind};
use super::super::svg_render::FrameRenderer;
use super::{CHUNK_BYTES, Encoder, FRAME_SECONDS};
use crate::sim::continuation::ContParam;

/// The views a played GIF can show: those that follow θν.
pub const PLAY_VIEWS: [ViewKind; 6] = [
    ViewKind::ReturnMap,
    ViewKind::Plane,
    ViewKind::Block,
    ViewKind::Bifurcation,
    ViewKind::Events,
    ViewKind::TimeSeries,
];

/// Where θν runs and over how many frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaySpan {
    pub from: f64,
    pub to: f64,
    pub frames: usize,
}

impl PlaySpan {
    /// `frames` frames over the θν range `fig` plays when none is given:
    /// its diagram's (the zoom's, else the whole range).
    pub fn of_diagram(fig: &Figure, frames: usize) -> PlaySpan {
        // θν plays: over the diagram's range when the diagram is in θν.
        let in_theta_nu = fig.settings.diagram.param == ContParam::ThetaNu;
        let (from, to) = fig
            .sweep_zoom()
            .filter(|_| in_theta_nu)
            .unwrap_or_else(|| fig.settings.theta_nu_range());
        PlaySpan { from, to, frames }
    }

    /// θν of frame `k`: `from` first, `to` last.
    pub fn theta_nu(&self, k: usize) -> f64 {
        if self.frames < 2 {
            return self.from;
        }
        self.from + (self.to - self.from) * k as f64 / (self.frames - 1) as f64
    }
}

/// A played GIF in the making, a piece at a time ([`PlayRun::advance`]):
/// a piece computes for a time budget, or draws and encodes one frame.
pub struct PlayRun {
    fig: Figure,
    span: PlaySpan,
    /// The frame being computed.
    frame: usize,
    computing: Option<ComputeRun>,
    /// The first run over the frames: the renderer gathering their
    /// legends and bounds.
    gathering: Option<FrameRenderer>,
    /// The union gathered, once the first run is over: the frames are
    /// then drawn.
    held: Option<Held>,
    drawing: Option<Drawer>,
}

/// The frames' part: renderer, fonts, the first chunk and the encoder.
struct Drawer {
    renderer: FrameRenderer,
    db: Arc<resvg::usvg::fontdb::Database>,
    size: (u16, u16),
    /// The first chunk's pixels (the palette is learnt from them).
    first: Vec<Vec<u8>>,
    first_n: usize,
    enc: Option<Encoder>,
}

impl PlayRun {
    /// The GIF of `fig`'s view with θν played over `span`; a view that
    /// does not follow θν, or fewer than two frames, is refused at once.
    pub fn new(fig: Figure, span: PlaySpan) -> Result<Self, String> {
        if !PLAY_VIEWS.contains(&fig.view) {
            return Err(format!(
                "the {} view does not follow θν: play {}",
                fig.view.key(),
                play_views()
            ));
        }
        if span.frames < 2 || !(span.from.is_finite() && span.to.is_finite()) {
            return Err("a played GIF needs two frames or more over a finite θν range".into());
        }
        let first = at_frame(&fig, &span, 0);
        Ok(PlayRun {
            computing: Some(ComputeRun::with_lanes(&first, holds_axes(&fig))),
            fig,
            span,
            frame: 0,
            gathering: None,
            held: None,
            drawing: None,
        })
    }

    /// Frames gathered, then encoded or waiting for the palette, so far,
    /// of how many (each frame counts twice).
    pub fn progress(&self) -> (usize, usize) {
        let gathered = if self.held.is_some() {
            self.span.frames
        } else {
            0
        };
        (gathered + self.frame, 2 * self.span.frames)
    }

    /// One piece: the current frame's data computed for about `budget`,
    /// or the frame drawn and encoded; then `None`, or the GIF's bytes
    /// (or why there are none) once the last frame is.
    pub fn advance(&mut self, budget: Duration) -> Option<Result<Vec<u8>, String>> {
        let fig_k = at_frame(&self.fig, &self.span, self.frame);
        let run = self.computing.as_mut()?;
        let jobs = match run.advance(&fig_k, budget)? {
            Ok(jobs) => jobs,
            Err(e) => return Some(Err(e)),
        };
        let clock = run.clock();
        self.computing = None;
        if self.held.is_some() {
            if let Err(e) = self.draw(&fig_k, &jobs) {
                return Some(Err(e));
            }
        } else {
            self.gather(&fig_k, &jobs);
        }
        self.frame += 1;
        if self.frame < self.span.frames {
            let next = at_frame(&self.fig, &self.span, self.frame);
            self.computing = Some(ComputeRun::resume(
                jobs,
                &next,
                clock,
                holds_axes(&self.fig),
            ));
            return None;
        }
        if self.held.is_none() {
            // Gathered: the frames again from the first, computed as the
            // first time (the same runs, so the same data), drawn.
            self.held = Some(
                self.gathering
                    .take()
                    .map_or_else(Held::default, |g| g.gathered()),
            );
            self.frame = 0;
            let first = at_frame(&self.fig, &self.span, 0);
            self.computing = Some(ComputeRun::with_lanes(&first, holds_axes(&self.fig)));
            return None;
        }
        Some(self.finish())
    }

    /// Frame `self.frame` of `fig_k`, from `jobs`, drawn off screen for
    /// its legends and bounds.
    fn gather(&mut self, fig_k: &Figure, jobs: &Jobs) {
        let s = view_settings(fig_k);
        let span = &self.span;
        let g = self
            .gathering
            .get_or_insert_with(|| renderer(fig_k, &s, jobs, span, Start::Collect));
        g.set_settings(&s, crosshair(fig_k));
        g.observe(jobs);
    }

    /// Frame `self.frame` of `fig_k`, from `jobs`, drawn and encoded (or
    /// kept for the palette).
    fn draw(&mut self, fig_k: &Figure, jobs: &Jobs) -> Result<(), String> {
        let s = view_settings(fig_k);
        let span = &self.span;
        let held = self.held.clone().unwrap_or_default();
        let d = self
            .drawing
            .get_or_insert_with(|| Drawer::new(fig_k, &s, jobs, span, held));
        d.renderer.set_settings(&s, crosshair(fig_k));
        let svg = d.renderer.next_frame(jobs);
        let px = pixmap_with_fonts(&svg, fig_k.size, 1.0, &d.db)?.take();
        match &mut d.enc {
            Some(e) => {
                let idx = e.palette.index(&px);
                e.frames(vec![idx])
            }
            None => {
                d.first.push(px);
                if d.first.len() == d.first_n {
                    d.start_encoding()
                } else {
                    Ok(())
                }
            }
        }
    }

    fn finish(&mut self) -> Result<Vec<u8>, String> {
        let mut d = self.drawing.take().ok_or("no frames")?;
        if d.enc.is_none() {
            d.start_encoding()?;
        }
        d.enc.take().ok_or("no frames")?.finish()
    }
}

/// Whether a frame draws the current parameters' lines: a played
/// diagram its θν cursor always.
fn crosshair(fig: &Figure) -> bool {
    fig.crosshair || fig.view == ViewKind::Bifurcation
}

/// A renderer of `fig`'s frames from the first's `jobs`, gathering or
/// holding the play's legends and bounds (`start`); a return map in the
/// window held over the play.
fn renderer(
    fig: &Figure,
    s: &Settings,
    jobs: &Jobs,
    span: &PlaySpan,
    start: Start,
) -> FrameRenderer {
    let window = (fig.view == ViewKind::ReturnMap)
        .then(|| held_window(jobs, span))
        .flatten();
    FrameRenderer::new_with(
        fig.view,
        s,
        jobs,
        (fig.size, &fig.look),
        FRAME_SECONDS,
        (
            |views: &mut super::super::views::Views| views.return_map.held = window,
            Some(start),
        ),
    )
}

impl Drawer {
    fn new(fig: &Figure, s: &Settings, jobs: &Jobs, span: &PlaySpan, held: Held) -> Drawer {
        let renderer = renderer(fig, s, jobs, span, Start::Hold(held));
        let (w, h) = (fig.size.x.round() as u16, fig.size.y.round() as u16);
        let chunk = (CHUNK_BYTES / (usize::from(w) * usize::from(h) * 4).max(1)).clamp(2, 32);
        Drawer {
            renderer,
            db: font_db(),
            size: (w, h),
            first: Vec::new(),
            first_n: chunk.min(span.frames),
            enc: None,
        }
    }

    /// The palette learnt from the first chunk, which is then encoded.
    fn start_encoding(&mut self) -> Result<(), String> {
        let (w, h) = self.size;
        let mut e = Encoder::new(w, h, &self.first)?;
        let idx = std::mem::take(&mut self.first)
            .iter()
            .map(|px| e.palette.index(px))
            .collect();
        e.frames(idx)?;
        self.enc = Some(e);
        Ok(())
    }
}

/// `fig` at frame `k`'s θν.
fn at_frame(fig: &Figure, span: &PlaySpan, k: usize) -> Figure {
    let mut f = fig.clone();
    f.settings.params.theta_nu = span.theta_nu(k);
    f
}

/// Whether the view holds axes taken from the diagram (the return map).
fn holds_axes(fig: &Figure) -> bool {
    fig.view == ViewKind::ReturnMap
}

/// The return map's window over the whole play: the diagram's θ over the
/// played θν (its columns there, and the nearest on each side), padded
/// as the map's own window and out to round values; `None` without
/// columns.
fn held_window(jobs: &Jobs, span: &PlaySpan) -> Option<(f64, f64)> {
    // A diagram in another parameter has its columns at the current θν:
    // its θ is no window over a θν play.
    if jobs.sweep.data.param != crate::sim::continuation::ContParam::ThetaNu {
        return None;
    }
    let (lo, hi) = (span.from.min(span.to), span.from.max(span.to));
    let cols: Vec<&crate::app::data::Column> = jobs.sweep.data.columns.iter().flatten().collect();
    let step = cols
        .windows(2)
        .map(|w| (w[1].value - w[0].value).abs())
        .fold(0.0, f64::max);
    let thetas: Vec<f64> = cols
        .iter()
        .filter(|c| c.value >= lo - step && c.value <= hi + step)
        .flat_map(|c| c.thetas.iter().copied())
        .collect();
    let (a, b) = crate::sim::return_map_window(&thetas)?;
    Some(axes::nice_bounds(a, b, axes::MIN_TICKS))
}

/// The views a GIF can play θν in, for messages.
pub fn play_views() -> String {
    PLAY_VIEWS.map(ViewKind::key).join(", ")
}

/// The played GIF made at once, on this thread (the command line and the
/// desktop's recording thread).
pub fn play_gif(fig: Figure, span: PlaySpan) -> Result<Vec<u8>, String> {
    let mut run = PlayRun::new(fig, span)?;
    loop {
        if let Some(r) = run.advance(Duration::from_secs(3600)) {
            return r;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_run_from_the_first_theta_nu_to_the_last() {
        let span = PlaySpan {
            from: 1.0,
            to: 1.5,
            frames: 11,
        };
        assert_eq!(span.theta_nu(0), 1.0);
        assert!((span.theta_nu(5) - 1.25).abs() < 1e-15);
        assert_eq!(span.theta_nu(10), 1.5);
    }
}
