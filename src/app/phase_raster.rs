//! The phase diagram as pixels: one texel per cell (missing cells take the
//! nearest received class, paler), the classes' colours, and which cell a
//! plot point falls in.

use std::collections::VecDeque;

use eframe::egui;
use egui::{Color32, ColorImage};
use egui_plot::PlotPoint;

use super::phase_data::PhaseData;
use crate::formats::class_colour as png_colour;
use crate::sim::phase::CellClass;

/// Opacity of a texel that shows a neighbour's class, not its own yet.
pub const PROVISIONAL_ALPHA: u8 = 110;

/// A class's colour in the view: the same as `oneblock phase --png`.
pub fn class_colour(c: CellClass, alpha: u8) -> Color32 {
    let [r, g, b] = png_colour(c);
    Color32::from_rgba_unmultiplied(r, g, b, alpha)
}

/// Rasterises the grid: `columns × rows` texels, κ upwards (texel row 0 is
/// the last κ row). A missing cell takes the class of the nearest received
/// one (breadth-first over the 8 neighbours, so coarse cells become blocks
/// centred on themselves), paler; with none received, transparent.
pub fn rasterise(data: &PhaseData) -> ColorImage {
    let (w, h) = (data.columns, data.rows);
    if w == 0 || h == 0 {
        return ColorImage::new([1, 1], vec![Color32::TRANSPARENT]);
    }
    let mut source: Vec<Option<usize>> = (0..w * h)
        .map(|i| data.cells[i].as_ref().map(|_| i))
        .collect();
    let mut queue: VecDeque<usize> = (0..w * h).filter(|&i| source[i].is_some()).collect();
    while let Some(i) = queue.pop_front() {
        let (r, c) = ((i / w) as isize, (i % w) as isize);
        for dr in -1..=1 {
            for dc in -1..=1 {
                let (rr, cc) = (r + dr, c + dc);
                if rr < 0 || cc < 0 || rr >= h as isize || cc >= w as isize {
                    continue;
                }
                let j = rr as usize * w + cc as usize;
                if source[j].is_none() {
                    source[j] = source[i];
                    queue.push_back(j);
                }
            }
        }
    }
    let mut pixels = Vec::with_capacity(w * h);
    for y in 0..h {
        let r = h - 1 - y;
        for c in 0..w {
            let i = r * w + c;
            let px = match source[i].and_then(|k| data.cells[k].as_ref().map(|cell| (k, cell))) {
                Some((k, cell)) if k == i => class_colour(cell.class, 255),
                Some((_, cell)) => class_colour(cell.class, PROVISIONAL_ALPHA),
                None => Color32::TRANSPARENT,
            };
            pixels.push(px);
        }
    }
    ColorImage::new([w, h], pixels)
}

/// The cell (row, column) of `data` under the plot point `p`, if inside.
pub fn cell_at(data: &PhaseData, p: PlotPoint) -> Option<(usize, usize)> {
    let index = |v: f64, (a, b): (f64, f64), n: usize| -> Option<usize> {
        if n == 0 {
            return None;
        }
        let step = if n > 1 { (b - a) / (n - 1) as f64 } else { 1.0 };
        let k = ((v - a) / step).round();
        (k >= 0.0 && k <= (n - 1) as f64 && (v - (a + k * step)).abs() <= step.abs() / 2.0 + 1e-12)
            .then_some(k as usize)
    };
    Some((
        index(p.y, data.kappa, data.rows)?,
        index(p.x, data.theta_nu, data.columns)?,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::phase::PhaseCell;
    use crate::worker::GridCell;

    fn cell(class: CellClass) -> PhaseCell {
        PhaseCell {
            theta_nu: 0.0,
            kappa: 1.0,
            class,
            lyapunov: Some(-0.5),
            lyapunov_stderr: None,
            regime: None,
            iterates: 30,
            rhs_evals: 0,
            theta_last: 0.0,
            error: None,
            map: Default::default(),
            attractors: None,
            uncounted: None,
        }
    }

    #[test]
    fn missing_cells_take_the_nearest_received_class_paler() {
        let mut d = PhaseData::new((0.0, 1.0), (1.0, 2.0), 5, 3);
        let img = rasterise(&d);
        assert!(img.pixels.iter().all(|p| *p == Color32::TRANSPARENT));
        // Two received cells: (row 0, col 0) FP and (row 2, col 4) chaos.
        d.insert(
            vec![
                GridCell {
                    row: 0,
                    column: 0,
                    cell: cell(CellClass::Periodic(1)),
                    listed: Vec::new(),
                },
                GridCell {
                    row: 2,
                    column: 4,
                    cell: cell(CellClass::Chaos),
                    listed: Vec::new(),
                },
            ],
            true,
        );
        let img = rasterise(&d);
        assert_eq!(img.size, [5, 3]);
        let at = |row: usize, col: usize| img.pixels[(2 - row) * 5 + col];
        assert_eq!(at(0, 0), class_colour(CellClass::Periodic(1), 255));
        assert_eq!(at(2, 4), class_colour(CellClass::Chaos, 255));
        assert_eq!(
            at(0, 1),
            class_colour(CellClass::Periodic(1), PROVISIONAL_ALPHA)
        );
        assert_eq!(at(2, 3), class_colour(CellClass::Chaos, PROVISIONAL_ALPHA));
        assert!(img.pixels.iter().all(|p| *p != Color32::TRANSPARENT));
    }

    #[test]
    fn a_point_maps_to_the_cell_it_falls_in() {
        let d = PhaseData::new((0.0, 1.0), (1.0, 3.0), 5, 3);
        assert_eq!(cell_at(&d, PlotPoint::new(0.0, 1.0)), Some((0, 0)));
        assert_eq!(cell_at(&d, PlotPoint::new(0.26, 2.9)), Some((2, 1)));
        assert_eq!(cell_at(&d, PlotPoint::new(1.2, 2.0)), None);
        assert_eq!(cell_at(&d, PlotPoint::new(0.5, 0.4)), None);
    }
}
