//! The phase diagram as a picture (`oneblock phase --png`): the attractor's
//! class over the (θν, κ) grid, θν across and κ upwards, with axes, tick
//! labels, the window's axis titles and the classes' legend, and any
//! bifurcation curves drawn over the cells.

use super::Svg;
use crate::formats::{PHASE_LEGEND, class_colour};
use crate::sim::phase::PhaseCell;

/// Tick labels' size and the axis titles' (SVG units = pixels).
const TICK_SIZE: f64 = 14.0;
const TITLE_SIZE: f64 = 16.0;

/// The margins around the grid: left, top, bottom, right (pixels).
pub const MARGINS: (f64, f64, f64, f64) = (100.0, 20.0, 70.0, 150.0);

/// The picture's size in pixels for a grid of `cols` × `rows` cells: by
/// default about 600 × 480 pixels of cells; at `size` exactly that size
/// (whole pixels per cell, as many as fit; what is left goes to the right
/// margin and the top). None if `size` leaves less than a pixel a cell.
pub fn picture_size(cols: usize, rows: usize, size: Option<[f64; 2]>) -> Option<[f64; 4]> {
    let (left, top, bottom, right) = MARGINS;
    let (cols, rows) = (cols.max(1), rows.max(1));
    let [cw, ch, w, h] = match size {
        None => {
            let cw = 600usize.div_ceil(cols).max(1) as f64;
            let ch = 480usize.div_ceil(rows).max(1) as f64;
            let (pw, ph) = (cw * cols as f64, ch * rows as f64);
            [cw, ch, left + pw + right, top + ph + bottom]
        }
        Some([w, h]) => {
            let cw = ((w - left - right) / cols as f64).floor();
            let ch = ((h - top - bottom) / rows as f64).floor();
            if cw < 1.0 || ch < 1.0 {
                return None;
            }
            [cw, ch, w.round(), h.round()]
        }
    };
    Some([cw, ch, w, h])
}

/// The picture of `grid` (rows of κ, `kappas[r]`; columns of θν,
/// `theta_nus[c]`) with `curves` in (θν, κ) over it, as an SVG document,
/// at `size` pixels ([`picture_size`]; a size too small for the grid is
/// taken as the default).
pub fn phase_svg(
    grid: &[Vec<PhaseCell>],
    (kappas, theta_nus): (&[f64], &[f64]),
    curves: &[Vec<[f64; 2]>],
    size: Option<[f64; 2]>,
) -> String {
    let (rows, cols) = (kappas.len().max(1), theta_nus.len().max(1));
    // Whole pixels per cell, so that cells meet on pixel edges.
    let [cw, ch, width, height] = picture_size(cols, rows, size)
        .or_else(|| picture_size(cols, rows, None))
        .unwrap_or([1.0, 1.0, 1.0, 1.0]);
    let (pw, ph) = (cw * cols as f64, ch * rows as f64);
    let (left, _, bottom, _) = MARGINS;
    let top = height - bottom - ph;
    let mut svg = Svg::new(width, height);
    for (r, row) in grid.iter().enumerate() {
        for (c, cell) in row.iter().enumerate() {
            // κ grows upwards: the first row is at the bottom.
            let y = top + (rows - 1 - r) as f64 * ch;
            svg.rect(left + c as f64 * cw, y, cw, ch, class_colour(cell.class));
            if cell.attractors > Some(1) {
                multistable_mark(&mut svg, left + c as f64 * cw, y, cw, ch);
            }
        }
    }
    svg.frame(left, top, pw, ph, 1.0);
    // Cell centres map linearly onto the grid's values.
    let (t0, t1) = (
        theta_nus.first().copied().unwrap_or(0.0),
        theta_nus.last().copied().unwrap_or(0.0),
    );
    let x_of = |v: f64| -> f64 {
        if cols == 1 || t1 == t0 {
            left + pw / 2.0
        } else {
            left + cw * (0.5 + (v - t0) / (t1 - t0) * (cols - 1) as f64)
        }
    };
    let (k0, k1) = (
        kappas.first().copied().unwrap_or(0.0),
        kappas.last().copied().unwrap_or(0.0),
    );
    let y_of = |v: f64| -> f64 {
        if rows == 1 || k1 == k0 {
            top + ph / 2.0
        } else {
            top + ph - ch * (0.5 + (v - k0) / (k1 - k0) * (rows - 1) as f64)
        }
    };
    for v in ticks(t0, t1) {
        let x = x_of(v);
        svg.line([x, top + ph], [x, top + ph + 6.0], 1.0);
        svg.text(x, top + ph + 22.0, TICK_SIZE, "middle", 0.0, &tick_label(v));
    }
    // The window's axis titles (app/phase_view.rs), with the unit.
    svg.text(
        left + pw / 2.0,
        top + ph + 52.0,
        TITLE_SIZE,
        "middle",
        0.0,
        "θν, pull direction [rad]",
    );
    for v in ticks(k0, k1) {
        let y = y_of(v);
        svg.line([left - 6.0, y], [left, y], 1.0);
        svg.text(
            left - 10.0,
            y + TICK_SIZE * 0.35,
            TICK_SIZE,
            "end",
            0.0,
            &tick_label(v),
        );
    }
    let (tx, ty) = (28.0, top + ph / 2.0);
    svg.text(
        tx,
        ty,
        TITLE_SIZE,
        "middle",
        -90.0,
        "κ = k_x/k_y, anisotropy",
    );
    for poly in curves {
        let pts: Vec<[f64; 2]> = poly.iter().map(|p| [x_of(p[0]), y_of(p[1])]).collect();
        svg.polyline(&pts, 2.0, [left, top, pw, ph]);
    }
    let lx = left + pw + 20.0;
    for (i, (name, c)) in PHASE_LEGEND.iter().enumerate() {
        let y = top + 10.0 + 26.0 * i as f64;
        svg.rect(lx, y, 18.0, 18.0, *c);
        svg.frame(lx, y, 18.0, 18.0, 1.0);
        svg.text(lx + 26.0, y + 14.0, TICK_SIZE, "start", 0.0, name);
    }
    if grid.iter().flatten().any(|c| c.attractors > Some(1)) {
        let y = top + 10.0 + 26.0 * PHASE_LEGEND.len() as f64;
        svg.rect(lx, y, 18.0, 18.0, [175, 175, 175]);
        multistable_mark(&mut svg, lx, y, 18.0, 18.0);
        svg.frame(lx, y, 18.0, 18.0, 1.0);
        svg.text(lx + 26.0, y + 14.0, TICK_SIZE, "start", 0.0, MULTISTABLE);
    }
    svg.finish()
}

/// The legend's name for a cell with more than one attractor.
pub const MULTISTABLE: &str = "MULTISTABLE";

/// The mark of a multistable cell: a white square, a third of the cell,
/// at its centre.
fn multistable_mark(svg: &mut Svg, x: f64, y: f64, w: f64, h: f64) {
    let s = (w.min(h) / 3.0).max(1.0);
    svg.rect(x + (w - s) / 2.0, y + (h - s) / 2.0, s, s, [255, 255, 255]);
}

/// Ticks for an axis from `a` to `b`: about five round values.
fn ticks(a: f64, b: f64) -> Vec<f64> {
    let (lo, hi) = (a.min(b), a.max(b));
    if !(hi - lo > 0.0) || !(hi - lo).is_finite() {
        return vec![lo];
    }
    let raw = (hi - lo) / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let mut v = Vec::new();
    let mut t = (lo / step).ceil() * step;
    while t <= hi + 1e-9 * step {
        v.push(t);
        t += step;
    }
    v
}

fn tick_label(v: f64) -> String {
    let s = format!("{:.3}", v);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_inside() {
        let t = ticks(0.0, 1.0);
        assert_eq!(t.len(), 6, "{t:?}");
        assert!(
            t.iter()
                .enumerate()
                .all(|(k, v)| (v - 0.2 * k as f64).abs() < 1e-12)
        );
        let t = ticks(2.0, 16.0);
        assert!(
            t.iter().all(|v| (2.0..=16.0).contains(v)) && t == vec![5.0, 10.0, 15.0],
            "{t:?}"
        );
        assert_eq!(tick_label(-0.0), "0");
        assert_eq!(tick_label(1.25), "1.25");
    }

    /// A 4 × 3 grid of one class at (θν, κ) over [0, 1] × [1, 3].
    fn grid_of(class: crate::sim::phase::CellClass) -> (Vec<Vec<PhaseCell>>, Vec<f64>, Vec<f64>) {
        let (tns, ks) = (vec![0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0], vec![1.0, 2.0, 3.0]);
        let grid = ks
            .iter()
            .map(|&k| {
                tns.iter()
                    .map(|&t| PhaseCell {
                        class,
                        ..PhaseCell::failed(t, k, 0.0)
                    })
                    .collect()
            })
            .collect();
        (grid, ks, tns)
    }

    /// A boundary shows over every class: over black chaos cells its white
    /// halo, over pale ones its black line; and a picture asked for at a
    /// size has that size, with whole-pixel cells.
    #[test]
    fn a_boundary_shows_over_every_class_at_the_size_asked_for() {
        use crate::sim::phase::CellClass;
        let curve = vec![vec![[0.0, 1.0], [1.0, 3.0]]];
        for class in [CellClass::Chaos, CellClass::Periodic(1)] {
            let (grid, ks, tns) = grid_of(class);
            let svg = phase_svg(&grid, (&ks, &tns), &curve, Some([700.0, 400.0]));
            let png = crate::figure::svg_to_png(&svg).expect("a PNG");
            let img = image::load_from_memory(&png).expect("decodes").to_rgb8();
            assert_eq!(img.dimensions(), (700, 400));
            let cell = class_colour(class);
            // The plot's middle lies on the curve (it joins the corners).
            let [cw, ch, _, h] = picture_size(4, 3, Some([700.0, 400.0])).expect("fits");
            let (left, _, bottom, _) = MARGINS;
            let (x, y) = (left + 2.0 * cw, h - bottom - 1.5 * ch);
            let near: Vec<[u8; 3]> = (-6..=6)
                .flat_map(|dx| (-6..=6).map(move |dy| (dx, dy)))
                .map(|(dx, dy)| {
                    img.get_pixel((x + dx as f64) as u32, (y + dy as f64) as u32)
                        .0
                })
                .collect();
            let contrast = |p: &[u8; 3]| {
                p.iter()
                    .zip(cell)
                    .map(|(a, b)| (i32::from(*a) - i32::from(b)).abs())
                    .sum::<i32>()
            };
            let most = near.iter().map(contrast).max().unwrap_or(0);
            assert!(
                most > 400,
                "{class:?}: the curve does not stand out ({most})"
            );
        }
        // Too small for the cells: refused.
        assert!(picture_size(400, 3, Some([500.0, 400.0])).is_none());
    }
}
