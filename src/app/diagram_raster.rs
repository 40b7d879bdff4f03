//! The bifurcation diagram's density texture: its columns' points binned
//! into texels (the followed attractor's and a seeded sweep's others in
//! their own colours), and the θ range that frames them.

use eframe::egui::{Color32, ColorImage};

use super::data::SweepData;
use super::{raster, style};

/// Texel rows of the density image.
pub const ROWS: usize = 420;

/// The colour of the attractors a seeded sweep finds besides the one it
/// follows (drawn over it).
pub const OTHER_ATTRACTOR: Color32 = style::ONSET;

/// Rasterises the columns into an RGBA image `columns × ROWS` over
/// θ ∈ [lo, hi] (row 0 at the top = hi), the followed attractor's points
/// in `ink` and the seeds' other attractors in [`OTHER_ATTRACTOR`]. Missing
/// columns take the nearest computed one to their left, so the coarse pass
/// already fills the picture. With `spread` > 0 (thick lines) each point
/// also fills the texels within `spread` of it, so that a branch stays a
/// line, not dashes, where the image is drawn narrower than its columns.
pub fn rasterise(sweep: &SweepData, lo: f64, hi: f64, ink: Color32, spread: usize) -> ColorImage {
    let w = sweep.columns.len().max(1);
    let mut counts = vec![0u32; w * ROWS];
    let mut others = vec![0u32; w * ROWS];
    let scale = (ROWS as f64) / (hi - lo).max(1e-12);
    let mut source: Option<usize> = sweep.columns.iter().position(Option::is_some);
    for j in 0..w {
        if sweep.columns.get(j).is_some_and(Option::is_some) {
            source = Some(j);
        }
        let Some(src) = source else { continue };
        let Some(col) = &sweep.columns[src] else {
            continue;
        };
        let labels = col.attractor.iter().chain(std::iter::repeat(&0));
        for (&t, &label) in col.thetas.iter().zip(labels) {
            if !(t >= lo && t <= hi) {
                continue;
            }
            let r = ((hi - t) * scale) as usize;
            let bin = if label == 0 { &mut counts } else { &mut others };
            bin[r.min(ROWS - 1) * w + j] += 1;
        }
    }
    let (counts, others) = (
        raster::dilate(&counts, w, spread),
        raster::dilate(&others, w, spread),
    );
    let pixels = counts
        .iter()
        .zip(&others)
        .map(|(&c, &o)| {
            let (n, colour) = if o > 0 {
                (o, OTHER_ATTRACTOR)
            } else {
                (c, ink)
            };
            if n == 0 {
                Color32::TRANSPARENT
            } else {
                let a = 1.0 - (-0.9 * n as f32).exp();
                let a = (0.25 + 0.75 * a).min(1.0);
                let [r, g, b, _] = colour.to_array();
                Color32::from_rgba_unmultiplied(r, g, b, (a * 255.0) as u8)
            }
        })
        .collect();
    ColorImage::new([w, ROWS], pixels)
}

/// The θ range holding every received iterate, padded.
pub fn auto_theta_range(sweep: &SweepData) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for c in sweep.columns.iter().flatten() {
        for &t in &c.thetas {
            if t.is_finite() {
                lo = lo.min(t);
                hi = hi.max(t);
            }
        }
    }
    if !lo.is_finite() {
        return (-0.5, 1.6);
    }
    let pad = ((hi - lo) * 0.06).max(0.05);
    (lo - pad, hi + pad)
}

#[cfg(test)]
mod seeded_tests {
    use super::*;
    use crate::app::data::Column;

    /// A seeded column's other attractor is drawn in its own colour, the
    /// followed one in ink.
    #[test]
    fn other_attractors_are_drawn_in_their_colour() {
        let mut sweep = SweepData::new(1.0, 1.1, 1);
        sweep.insert(
            0,
            Column {
                value: 1.0,
                thetas: vec![0.25, 0.75, 0.5],
                coarse: true,
                lyapunov: None,
                attractor: vec![0, 0, 1],
                uncounted: None,
            },
        );
        let ink = style::ink(false);
        let img = rasterise(&sweep, 0.0, 1.0, ink, 0);
        let at = |t: f64| img.pixels[((1.0 - t) * ROWS as f64) as usize];
        let rgb = |c: Color32| [c.r(), c.g(), c.b()];
        let unmul = |c: Color32| {
            let [r, g, b, _] = c.to_srgba_unmultiplied();
            [r, g, b]
        };
        // Premultiplied alpha rounds: within 2 of each channel.
        let near = |a: [u8; 3], b: [u8; 3]| a.iter().zip(b).all(|(x, y)| x.abs_diff(y) <= 2);
        assert!(near(unmul(at(0.25)), rgb(ink)), "{:?}", at(0.25));
        assert!(near(unmul(at(0.75)), rgb(ink)), "{:?}", at(0.75));
        assert!(near(unmul(at(0.5)), rgb(OTHER_ATTRACTOR)), "{:?}", at(0.5));
        assert!(!near(rgb(ink), rgb(OTHER_ATTRACTOR)));
        assert_eq!(at(0.1), Color32::TRANSPARENT);
    }
}
