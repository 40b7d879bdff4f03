//! Files the window makes for the user, below every view and exporter: a
//! fresh name that never meets an existing file, and a screenshot (or an
//! image in an SVG) encoded as PNG.

use eframe::egui;
use egui::{ColorImage, Rect};
use std::path::{Path, PathBuf};

/// A fresh file name in `dir`: `oneblock-<what>-<timestamp>.<ext>`, with a
/// counter if that exists already.
pub fn fresh_path(dir: &str, what: &str, ext: &str) -> PathBuf {
    // In a browser the name is the download's; the browser picks the folder
    // and never overwrites.
    if cfg!(target_arch = "wasm32") {
        let stamp = super::export::timestamp();
        return PathBuf::from(format!("oneblock-{what}-{stamp}.{ext}"));
    }
    let dir = if dir.trim().is_empty() {
        "."
    } else {
        dir.trim()
    };
    let stamp = super::export::timestamp();
    let base = Path::new(dir).join(format!("oneblock-{what}-{stamp}.{ext}"));
    if !base.exists() {
        return base;
    }
    (2..)
        .map(|i| Path::new(dir).join(format!("oneblock-{what}-{stamp}-{i}.{ext}")))
        .find(|p| !p.exists())
        .unwrap_or(base)
}

/// Crops (to `crop`, in points) and encodes a screenshot as PNG.
pub fn encode_png(
    img: &ColorImage,
    crop: Option<Rect>,
    pixels_per_point: f32,
) -> Result<Vec<u8>, String> {
    let img = match crop {
        Some(r) => img.region(&r, Some(pixels_per_point)),
        None => img.clone(),
    };
    let [w, h] = img.size;
    if w == 0 || h == 0 {
        return Err("the screenshot is empty".into());
    }
    let mut raw = Vec::with_capacity(w * h * 4);
    for c in &img.pixels {
        raw.extend_from_slice(&c.to_srgba_unmultiplied());
    }
    let rgba = image::RgbaImage::from_raw(w as u32, h as u32, raw)
        .ok_or_else(|| "screenshot size does not match its pixels".to_string())?;
    let mut bytes = std::io::Cursor::new(Vec::new());
    rgba.write_to(&mut bytes, image::ImageFormat::Png)
        .map_err(|e| format!("PNG encoding failed: {e}"))?;
    Ok(bytes.into_inner())
}
