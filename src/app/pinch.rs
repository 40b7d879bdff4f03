//! Two-finger pinch on a plot whose zoom is a recomputed range (the
//! bifurcation diagram, where a zoom asks the worker for new columns): the
//! fingers' spread scales a box about their centre, drawn while they move;
//! when they lift, a pinch in zooms into the box and a pinch out goes back
//! a level. Nothing is recomputed while the fingers move.

use eframe::egui;
use egui::{Rect, Ui};
use egui_plot::{PlotPoint, PlotTransform};

/// A pinch's scale within this of 1 is a tap or a slip of the fingers.
const DEAD_BAND: f64 = 0.05;

/// The most a pinch box may shrink the view in one gesture.
const MAX_SCALE: f64 = 1e3;

/// The pinch in progress over a plot.
#[derive(Clone, Copy, Debug, Default)]
pub struct Pinch {
    /// Where the fingers' centre is, in plot coordinates, and the spread
    /// so far (> 1: apart, zoom in).
    state: Option<(PlotPoint, f64)>,
}

/// What a finished pinch asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PinchEnd {
    /// Zoom into this box (θν range, θ range).
    In((f64, f64), (f64, f64)),
    /// Go back a zoom level.
    Out,
}

impl Pinch {
    /// Whether two fingers are on the plot (a drag's box is not drawn then).
    pub fn active(&self) -> bool {
        self.state.is_some()
    }

    /// Follows the touches this frame over the plot `rect` (transform `t`,
    /// whose bounds are the view's); the pinch's end once the fingers lift.
    pub fn follow(&mut self, ui: &Ui, rect: Rect, t: &PlotTransform) -> Option<PinchEnd> {
        match (ui.input(|i| i.multi_touch()), self.state) {
            (Some(m), state) if state.is_some() || rect.contains(m.center_pos) => {
                let centre = t.value_from_position(m.center_pos);
                let scale = state.map_or(1.0, |s| s.1) * f64::from(m.zoom_delta);
                self.state = Some((centre, scale.clamp(1.0 / MAX_SCALE, MAX_SCALE)));
                None
            }
            (None, Some((centre, scale))) => {
                self.state = None;
                end(t.bounds(), centre, scale)
            }
            _ => None,
        }
    }

    /// The box a pinch in would zoom to, to draw while the fingers move.
    pub fn preview(&self, t: &PlotTransform) -> Option<(PlotPoint, PlotPoint)> {
        let (centre, scale) = self.state?;
        match end(t.bounds(), centre, scale)? {
            PinchEnd::In((x0, x1), (y0, y1)) => {
                Some((PlotPoint::new(x0, y0), PlotPoint::new(x1, y1)))
            }
            PinchEnd::Out => None,
        }
    }
}

/// The end of a pinch of spread `scale` about `centre` over `bounds`: the
/// box of the bounds' size divided by the scale, centred where the fingers
/// were and kept inside the bounds.
fn end(bounds: &egui_plot::PlotBounds, centre: PlotPoint, scale: f64) -> Option<PinchEnd> {
    if scale < 1.0 - DEAD_BAND {
        return Some(PinchEnd::Out);
    }
    if scale <= 1.0 + DEAD_BAND {
        return None;
    }
    let inside = |c: f64, lo: f64, hi: f64| {
        let half = (hi - lo) / (2.0 * scale);
        let c = c.clamp(lo + half, hi - half);
        (c - half, c + half)
    };
    let [x0, y0] = bounds.min();
    let [x1, y1] = bounds.max();
    Some(PinchEnd::In(
        inside(centre.x, x0, x1),
        inside(centre.y, y0, y1),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui_plot::PlotBounds;

    #[test]
    fn a_pinch_in_boxes_the_centre_at_the_scale_and_stays_inside() {
        let b = PlotBounds::from_min_max([0.0, -1.0], [2.0, 1.0]);
        let Some(PinchEnd::In(x, y)) = end(&b, PlotPoint::new(1.0, 0.0), 4.0) else {
            panic!("no zoom")
        };
        assert!(
            (x.0 - 0.75).abs() < 1e-12 && (x.1 - 1.25).abs() < 1e-12,
            "{x:?}"
        );
        assert!(
            (y.0 + 0.25).abs() < 1e-12 && (y.1 - 0.25).abs() < 1e-12,
            "{y:?}"
        );
        // Near an edge the box slides inside.
        let Some(PinchEnd::In(x, _)) = end(&b, PlotPoint::new(1.95, 0.0), 2.0) else {
            panic!("no zoom")
        };
        assert!(
            (x.1 - 2.0).abs() < 1e-12 && (x.0 - 1.0).abs() < 1e-12,
            "{x:?}"
        );
    }

    #[test]
    fn a_pinch_out_goes_back_and_a_tiny_one_does_nothing() {
        let b = PlotBounds::from_min_max([0.0, 0.0], [1.0, 1.0]);
        assert_eq!(end(&b, PlotPoint::new(0.5, 0.5), 0.5), Some(PinchEnd::Out));
        assert_eq!(end(&b, PlotPoint::new(0.5, 0.5), 1.02), None);
    }
}
