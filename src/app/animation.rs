//! Animated GIFs of the block and plane views (`figure --frames N`, the
//! window's Record). Each frame is the view drawn by the window's code
//! ([`FrameRenderer`], one off-screen egui context) and written as SVG,
//! then rasterised by resvg as a figure's PNG is: one drawing path.
//!
//! What makes 120 frames cheap (measured with perf; docs/performance.md):
//! - the frames are rasterised in parallel, a chunk at a time, so memory
//!   stays bounded whatever the frame count;
//! - one palette for the whole animation, learnt once (NeuQuant) from the
//!   first chunk's pixels, with a lookup table from colour to index,
//!   instead of a NeuQuant palette learnt per frame (a third of the time);
//! - each frame after the first stores only the rectangle that changed.

use std::sync::atomic::{AtomicU16, Ordering};

use rayon::prelude::*;

use super::block::{Playback, state_at};
use super::data::TrajectoryData;
use super::figure::{Figure, compute, font_db, pixmap_with_fonts, view_settings};
use super::jobs::Jobs;
use super::settings::{Settings, ViewKind};
use super::svg_render::FrameRenderer;

mod play;
mod sliced;

pub use play::{PLAY_VIEWS, PlayRun, PlaySpan, play_gif, play_views};
pub use sliced::GifRun;

/// A GIF made a piece at a time, for a host that wants its thread back
/// between pieces (the browser's Record): the block or plane's playback,
/// or θν played.
pub enum Recording {
    Playback(Box<GifRun>),
    Played(Box<PlayRun>),
}

impl Recording {
    /// One piece, then `None`, or the GIF's bytes (or why there are none).
    pub fn advance(&mut self, budget: std::time::Duration) -> Option<Result<Vec<u8>, String>> {
        match self {
            Recording::Playback(r) => r.advance(budget),
            Recording::Played(r) => r.advance(budget),
        }
    }
}

/// Seconds of playback between an animation's frames (10 frames a second).
pub const FRAME_SECONDS: f64 = 0.1;

/// The slowest playback: a twentieth of real time.
pub const MIN_SPEED: f64 = 0.05;
/// Real time: the view plays as the window plays it.
pub const MAX_SPEED: f64 = 1.0;

/// Bytes of RGBA pixels a chunk of frames may hold at once.
const CHUNK_BYTES: usize = 40 << 20;

/// Bits kept per colour channel in the colour → palette index table.
const LUT_BITS: u32 = 6;

/// The plane's path grown with the playback clock, frame by frame (the
/// block's own clock is the renderer's ui time).
pub(super) struct Growth {
    full: TrajectoryData,
    plane: bool,
    window_start: f64,
    clock: Playback,
    dt: f64,
    block_speed: f64,
}

impl Growth {
    /// From `jobs`' whole trajectory, for `view`, frames `dt` of playback
    /// apart, from the start of the window the settings `s` show.
    pub(super) fn new(view: ViewKind, s: &Settings, jobs: &Jobs, dt: f64) -> Self {
        let full = jobs.trajectory.data.clone();
        let start = full.recent_start(s.keep_cycles);
        let window_start = full.samples.get(start).map_or(0.0, |p| p.t);
        Growth {
            full,
            plane: view == ViewKind::Plane,
            window_start,
            clock: Playback {
                clock: window_start,
            },
            dt,
            block_speed: s.block_speed as f64,
        }
    }

    /// The plane's path up to the playback clock, ending at the point the
    /// block is at then; the clock moves on a frame.
    pub(super) fn grow(&mut self, jobs: &mut Jobs) {
        let full = &self.full;
        if !self.plane || full.samples.is_empty() {
            return;
        }
        let t = self.clock.clock;
        let cut = full.samples.partition_point(|p| p.t <= t).max(1);
        let data = &mut jobs.trajectory.data;
        data.samples = full.samples[..cut].to_vec();
        if let Some((now, _)) = state_at(&full.samples, t)
            && now.t > data.samples[cut - 1].t
        {
            data.samples.push(now);
        }
        data.events = full
            .events
            .iter()
            .filter(|e| e.onset_time <= t)
            .cloned()
            .collect();
        self.clock
            .advance(&full.samples, self.window_start, self.dt, self.block_speed);
    }
}

/// An animated GIF of `fig`'s view (the block or the plane), `frames`
/// frames 0.1 s apart, looping, one pixel a point, played at `speed`
/// (1 real time, as in the window: stick phases fast-forwarded, slips at
/// the settings' slip speed; 0.25 four times slower). The block moves on
/// that clock; the plane's path grows up to its time.
pub fn gif(fig: &Figure, frames: usize, speed: f64) -> Result<Vec<u8>, String> {
    if !(MIN_SPEED..=MAX_SPEED).contains(&speed) {
        return Err(format!(
            "speed {speed} is out of range: must lie in [{MIN_SPEED}, {MAX_SPEED}]"
        ));
    }
    let mut jobs = compute(fig)?;
    let s = view_settings(fig);
    let dt = FRAME_SECONDS * speed;
    let mut growth = Growth::new(fig.view, &s, &jobs, dt);
    growth.grow(&mut jobs);
    let mut renderer = FrameRenderer::new(fig.view, &s, &jobs, (fig.size, &fig.look), dt);
    let (w, h) = (fig.size.x.round() as u16, fig.size.y.round() as u16);
    let chunk = (CHUNK_BYTES / (usize::from(w) * usize::from(h) * 4).max(1)).clamp(2, 32);
    let db = font_db();
    let raster = |svg: &String| pixmap_with_fonts(svg, fig.size, 1.0, &db).map(|p| p.take());
    let mut enc: Option<Encoder> = None;
    let mut done = 0;
    while done < frames {
        let n = chunk.min(frames - done);
        let svgs: Vec<String> = (0..n)
            .map(|k| {
                if done + k > 0 {
                    growth.grow(&mut jobs);
                }
                renderer.next_frame(&jobs)
            })
            .collect();
        let indexed: Vec<Vec<u8>> = match &enc {
            Some(e) => svgs
                .par_iter()
                .map(|svg| raster(svg).map(|px| e.palette.index(&px)))
                .collect::<Result<_, _>>()?,
            None => {
                // The palette is learnt from the first chunk's pixels.
                let rgba: Vec<Vec<u8>> = svgs.par_iter().map(raster).collect::<Result<_, _>>()?;
                let e = enc.insert(Encoder::new(w, h, &rgba)?);
                rgba.par_iter().map(|px| e.palette.index(px)).collect()
            }
        };
        if let Some(e) = &mut enc {
            e.frames(indexed)?;
        }
        done += n;
    }
    enc.ok_or_else(|| "no frames".to_string())?.finish()
}

/// The animation's one palette and a table from colour to its index.
struct Palette {
    quant: color_quant::NeuQuant,
    /// Palette index by colour at [`LUT_BITS`] a channel (the entry of
    /// the bucket's centre), filled on first use (`u16::MAX`: not yet);
    /// racing fills write the same value.
    lut: Vec<AtomicU16>,
}

impl Palette {
    /// A palette of 256 colours learnt from `frames` (RGBA), every pixel
    /// of the first and a sample of the others.
    fn learn(frames: &[Vec<u8>]) -> Palette {
        let mut sample = Vec::new();
        for (i, f) in frames.iter().enumerate() {
            // Every other pixel of the first, every 16th of the others
            // (what moves is small): about two frames' worth to learn from.
            let step = if i == 0 { 2 } else { 16 };
            for px in f.chunks_exact(4).step_by(step) {
                sample.extend_from_slice(px);
            }
        }
        Palette {
            quant: color_quant::NeuQuant::new(10, 256, &sample),
            lut: (0..1usize << (3 * LUT_BITS))
                .map(|_| AtomicU16::new(u16::MAX))
                .collect(),
        }
    }

    /// `rgba`'s pixels as palette indices (the frames are opaque).
    fn index(&self, rgba: &[u8]) -> Vec<u8> {
        let shift = 8 - LUT_BITS;
        rgba.chunks_exact(4)
            .map(|p| {
                let key = (usize::from(p[0] >> shift) << (2 * LUT_BITS))
                    | (usize::from(p[1] >> shift) << LUT_BITS)
                    | usize::from(p[2] >> shift);
                let slot = &self.lut[key];
                match slot.load(Ordering::Relaxed) {
                    u16::MAX => {
                        // The bucket's centre, not this pixel: the entry is
                        // then the same whichever pixel of the bucket comes
                        // first (frames are indexed in parallel).
                        let centre = |c: u8| (c >> shift << shift) | (1 << (shift - 1));
                        let rgb = [centre(p[0]), centre(p[1]), centre(p[2]), 255];
                        let i = self.quant.index_of(&rgb) as u16;
                        slot.store(i, Ordering::Relaxed);
                        i as u8
                    }
                    i => i as u8,
                }
            })
            .collect()
    }
}

/// The GIF being written: the palette, the last frame (to store only what
/// changed) and the bytes.
struct Encoder {
    palette: Palette,
    last: Option<Vec<u8>>,
    size: (u16, u16),
    gif: gif::Encoder<Vec<u8>>,
}

fn gif_err(e: gif::EncodingError) -> String {
    format!("GIF encoding failed: {e}")
}

impl Encoder {
    /// A looping GIF of `w`×`h` whose palette is learnt from `first` frames.
    fn new(w: u16, h: u16, first: &[Vec<u8>]) -> Result<Encoder, String> {
        let palette = Palette::learn(first);
        let mut gif =
            gif::Encoder::new(Vec::new(), w, h, &palette.quant.color_map_rgb()).map_err(gif_err)?;
        gif.set_repeat(gif::Repeat::Infinite).map_err(gif_err)?;
        Ok(Encoder {
            palette,
            last: None,
            size: (w, h),
            gif,
        })
    }

    /// Adds frames of palette indices, each as the rectangle where it
    /// differs from the one before, drawn over it (a 1×1 patch if nothing
    /// changed), compressed in parallel and written in order.
    fn frames(&mut self, idx: Vec<Vec<u8>>) -> Result<(), String> {
        let (w, h) = (usize::from(self.size.0), usize::from(self.size.1));
        let last = self.last.take();
        let encoded: Vec<gif::Frame<'static>> = (0..idx.len())
            .into_par_iter()
            .map(|k| {
                let before = if k == 0 {
                    last.as_ref()
                } else {
                    idx.get(k - 1)
                };
                let now = &idx[k];
                let [x0, y0, x1, y1] = match before {
                    None => [0, 0, w, h],
                    Some(b) => changed(b, now, w).unwrap_or([0, 0, 1, 1]),
                };
                let mut buffer = Vec::with_capacity((x1 - x0) * (y1 - y0));
                for y in y0..y1 {
                    buffer.extend_from_slice(&now[y * w + x0..y * w + x1]);
                }
                let mut frame = gif::Frame {
                    delay: (FRAME_SECONDS * 100.0).round() as u16,
                    dispose: gif::DisposalMethod::Keep,
                    left: x0 as u16,
                    top: y0 as u16,
                    width: (x1 - x0) as u16,
                    height: (y1 - y0) as u16,
                    buffer: std::borrow::Cow::Owned(buffer),
                    ..gif::Frame::default()
                };
                frame.make_lzw_pre_encoded();
                frame
            })
            .collect();
        for f in &encoded {
            self.gif.write_lzw_pre_encoded_frame(f).map_err(gif_err)?;
        }
        self.last = idx.into_iter().last();
        Ok(())
    }

    fn finish(self) -> Result<Vec<u8>, String> {
        self.gif
            .into_inner()
            .map_err(|e| format!("GIF encoding failed: {e}"))
    }
}

/// The bounding box `[x0, y0, x1, y1)` of the pixels where `b` differs
/// from `a` (both `w` wide), or `None` if none does.
fn changed(a: &[u8], b: &[u8], w: usize) -> Option<[usize; 4]> {
    let rows: Vec<usize> = (0..a.len() / w)
        .filter(|&y| a[y * w..(y + 1) * w] != b[y * w..(y + 1) * w])
        .collect();
    let (&y0, &y1) = (rows.first()?, rows.last()?);
    let (mut x0, mut x1) = (w, 0);
    for y in y0..=y1 {
        let (ra, rb) = (&a[y * w..(y + 1) * w], &b[y * w..(y + 1) * w]);
        if let Some(l) = (0..w).find(|&x| ra[x] != rb[x]) {
            x0 = x0.min(l);
            x1 = x1.max((l..w).rev().find(|&x| ra[x] != rb[x]).unwrap_or(l) + 1);
        }
    }
    Some([x0, y0, x1, y1 + 1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn changed_box_bounds_exactly_the_differing_pixels() {
        let w = 7;
        let a = vec![0u8; w * 5];
        let mut b = a.clone();
        assert_eq!(changed(&a, &b, w), None);
        b[w + 2] = 1; // (2, 1)
        b[3 * w + 5] = 1; // (5, 3)
        assert_eq!(changed(&a, &b, w), Some([2, 1, 6, 4]));
    }
}
