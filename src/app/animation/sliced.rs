//! [`super::gif`] in pieces, for a host that wants its thread back between
//! them (the browser's Record): the view's data computed a time budget at
//! a time, then one frame per piece (drawn, rasterised, indexed and
//! encoded; the first chunk's frames rasterised first, the palette learnt
//! from them in a piece of its own). The frames are drawn one after the
//! other on this thread, where `gif` rasterises a chunk in parallel; the
//! bytes are the same.

use std::sync::Arc;
use std::time::Duration;

use super::super::figure::{ComputeRun, Figure, font_db, pixmap_with_fonts, view_settings};
use super::super::jobs::Jobs;
use super::super::svg_render::FrameRenderer;
use super::{CHUNK_BYTES, Encoder, FRAME_SECONDS, Growth, MAX_SPEED, MIN_SPEED};

/// An animated GIF in the making ([`GifRun::advance`]).
pub struct GifRun {
    fig: Figure,
    frames: usize,
    speed: f64,
    computing: Option<ComputeRun>,
    drawing: Option<Frames>,
}

/// The frames' part: the view's data, the renderer and the encoder.
struct Frames {
    jobs: Jobs,
    growth: Growth,
    renderer: FrameRenderer,
    size: (u16, u16),
    db: Arc<resvg::usvg::fontdb::Database>,
    /// The first chunk's pixels (the palette is learnt from them), and
    /// how many frames it holds.
    first: Vec<Vec<u8>>,
    first_n: usize,
    enc: Option<Encoder>,
    rendered: usize,
    encoded: usize,
}

impl GifRun {
    /// The GIF `gif(fig, frames, speed)` makes, nothing computed yet; an
    /// out-of-range speed or no frames is refused at once.
    pub fn new(fig: Figure, frames: usize, speed: f64) -> Result<Self, String> {
        if !(MIN_SPEED..=MAX_SPEED).contains(&speed) {
            return Err(format!(
                "speed {speed} is out of range: must lie in [{MIN_SPEED}, {MAX_SPEED}]"
            ));
        }
        if frames == 0 {
            return Err("no frames".into());
        }
        Ok(GifRun {
            computing: Some(ComputeRun::new(&fig)),
            fig,
            frames,
            speed,
            drawing: None,
        })
    }

    /// Frames encoded so far, of how many.
    pub fn progress(&self) -> (usize, usize) {
        (self.drawing.as_ref().map_or(0, |d| d.encoded), self.frames)
    }

    /// One piece (the data computed for about `budget`, or one frame),
    /// then `None`, or the GIF's bytes (or why there are none).
    pub fn advance(&mut self, budget: Duration) -> Option<Result<Vec<u8>, String>> {
        if let Some(run) = &mut self.computing {
            return match run.advance(&self.fig, budget)? {
                Ok(jobs) => {
                    self.computing = None;
                    self.drawing = Some(Frames::new(&self.fig, jobs, self.frames, self.speed));
                    None
                }
                Err(e) => Some(Err(e)),
            };
        }
        self.drawing.as_mut()?.advance(&self.fig, self.frames)
    }
}

impl Frames {
    fn new(fig: &Figure, mut jobs: Jobs, frames: usize, speed: f64) -> Self {
        let s = view_settings(fig);
        let dt = FRAME_SECONDS * speed;
        let mut growth = Growth::new(fig.view, &s, &jobs, dt);
        growth.grow(&mut jobs);
        let renderer = FrameRenderer::new(fig.view, &s, &jobs, (fig.size, &fig.look), dt);
        let (w, h) = (fig.size.x.round() as u16, fig.size.y.round() as u16);
        let chunk = (CHUNK_BYTES / (usize::from(w) * usize::from(h) * 4).max(1)).clamp(2, 32);
        Frames {
            jobs,
            growth,
            renderer,
            size: (w, h),
            db: font_db(),
            first: Vec::new(),
            first_n: chunk.min(frames),
            enc: None,
            rendered: 0,
            encoded: 0,
        }
    }

    /// The next frame drawn and rasterised (RGBA).
    fn render(&mut self, fig: &Figure) -> Result<Vec<u8>, String> {
        if self.rendered > 0 {
            self.growth.grow(&mut self.jobs);
        }
        self.rendered += 1;
        let svg = self.renderer.next_frame(&self.jobs);
        pixmap_with_fonts(&svg, fig.size, 1.0, &self.db).map(|p| p.take())
    }

    /// One piece: a frame of the first chunk rasterised, the palette
    /// learnt, or a frame indexed and encoded; the bytes once all are.
    fn advance(&mut self, fig: &Figure, frames: usize) -> Option<Result<Vec<u8>, String>> {
        if self.enc.is_none() {
            let r = if self.first.len() < self.first_n {
                self.render(fig).map(|px| self.first.push(px))
            } else {
                let (w, h) = self.size;
                Encoder::new(w, h, &self.first).map(|e| self.enc = Some(e))
            };
            return r.err().map(Err);
        }
        if self.encoded == frames {
            return Some(self.enc.take()?.finish());
        }
        let px = if self.encoded < self.first_n {
            std::mem::take(&mut self.first[self.encoded])
        } else {
            match self.render(fig) {
                Ok(px) => px,
                Err(e) => return Some(Err(e)),
            }
        };
        let enc = self.enc.as_mut()?;
        let idx = enc.palette.index(&px);
        self.encoded += 1;
        enc.frames(vec![idx]).err().map(Err)
    }
}
