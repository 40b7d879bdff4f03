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
