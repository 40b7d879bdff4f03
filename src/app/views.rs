//! The views the window holds, one of each kind, and how tiles share the
//! views' area: what the window and the SVG export both lay out.

use eframe::egui;
use egui::Rect;

use super::basins::BasinsView;
use super::bifurcation::BifurcationView;
use super::block::BlockView;
use super::events::EventsView;
use super::numerics_view::NumericsView;
use super::phase_view::PhaseView;
use super::plane::PlaneView;
use super::return_map::ReturnMapView;
use super::settings::ViewKind;
use super::time_series::TimeSeriesView;
use super::view::View;

/// The views' own state (textures, zoom stacks, switches).
#[derive(Default)]
pub struct Views {
    pub plane: PlaneView,
    pub block: BlockView,
    pub bifurcation: BifurcationView,
    pub return_map: ReturnMapView,
    pub events: EventsView,
    pub numerics: NumericsView,
    pub phase: PhaseView,
    pub time_series: TimeSeriesView,
    pub basins: BasinsView,
}

impl Views {
    /// The view of kind `v`.
    pub fn get_mut(&mut self, v: ViewKind) -> &mut dyn View {
        match v {
            ViewKind::Plane => &mut self.plane,
            ViewKind::Block => &mut self.block,
            ViewKind::Bifurcation => &mut self.bifurcation,
            ViewKind::ReturnMap => &mut self.return_map,
            ViewKind::Events => &mut self.events,
            ViewKind::Numerics => &mut self.numerics,
            ViewKind::Phase => &mut self.phase,
            ViewKind::TimeSeries => &mut self.time_series,
            ViewKind::Basins => &mut self.basins,
        }
    }
}

/// The least room a tile is laid out in, for text rows `row` points high:
/// a title, a row or two of controls and a plot whose axes keep four
/// labelled ticks or more (15 rows wide, 14 high). Past it fewer tiles are
/// shown ([`tiles_that_fit`]): eight tiles at text ×3 in a small window
/// once left the Block view no room at all, and its stripes then looped
/// until memory ran out.
pub fn min_tile(row: f32) -> egui::Vec2 {
    egui::vec2(15.0 * row, 14.0 * row)
}

/// How many of `n` tiles [`tile_rects`] lays out in `area` each at least
/// `min` in size: `n` when they all fit, else fewer, at least one.
pub fn tiles_that_fit(area: Rect, n: usize, min: egui::Vec2) -> usize {
    (2..=n)
        .rev()
        .find(|&k| {
            tile_rects(area, k)
                .iter()
                .all(|r| r.width() >= min.x && r.height() >= min.y)
        })
        .unwrap_or(1)
}

/// The tiles' rectangles in `area`: two columns (one for a single view),
/// the last row's single tile spanning the width.
pub(crate) fn tile_rects(area: Rect, n: usize) -> Vec<Rect> {
    let n = n.max(1);
    let cols = if n == 1 { 1 } else { 2 };
    let rows = n.div_ceil(cols);
    let gap = 6.0;
    let w = (area.width() - gap * (cols as f32 - 1.0)) / cols as f32;
    let h = (area.height() - gap * (rows as f32 - 1.0)) / rows as f32;
    (0..n)
        .map(|i| {
            let (r, c) = (i / cols, i % cols);
            let span = if r == rows - 1 && n % cols == 1 && cols == 2 {
                2.0
            } else {
                1.0
            };
            let min = area.min + egui::vec2(c as f32 * (w + gap), r as f32 * (h + gap));
            Rect::from_min_size(min, egui::vec2(w * span + gap * (span - 1.0), h))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_past_the_room_are_left_out_and_one_always_stays() {
        let area = Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(940.0, 700.0));
        // Text ×1 (rows about 17 points): a tile is at least 255 × 238
        // points; two rows of two fit in 940 × 700, three rows do not.
        let small = min_tile(17.0);
        assert_eq!(tiles_that_fit(area, 9, small), 4);
        // Text ×3 (rows about 50 points): a tile is at least 750 × 700
        // points, and two side by side do not fit in 940.
        let large = min_tile(50.0);
        let n = tiles_that_fit(area, 9, large);
        assert_eq!(n, 1, "{n}");
        for r in tile_rects(area, n) {
            assert!(r.width() >= large.x && r.height() >= large.y, "{r:?}");
        }
        // A wide, tall area holds more, each still at least the minimum.
        let wide = Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1600.0, 1600.0));
        let n = tiles_that_fit(wide, 9, large);
        assert!((2..9).contains(&n), "{n}");
        assert!(tile_rects(wide, n).iter().all(|r| r.height() >= large.y));
        assert!(tile_rects(wide, n + 1).iter().any(|r| r.height() < large.y));
        // No room at all: still the first tile.
        let none = Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(0.0, 0.0));
        assert_eq!(tiles_that_fit(none, 9, large), 1);
    }
}
