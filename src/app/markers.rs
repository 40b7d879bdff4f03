//! A plot's point markers, described once: the plot's `Points` and the
//! legend's key are both made from one [`Marker`], so that a legend shows
//! the shape, fill and colour that are plotted (a ring in the plot is a
//! ring in the legend, never a diamond). The shapes are drawn as egui_plot
//! draws a marker.

use eframe::egui;
use egui::{Color32, Pos2, Shape, Stroke, Ui, vec2};
use egui_plot::{MarkerShape, PlotPoints, Points};

/// One kind of marker: shape, colour, radius (points), filled or outlined.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Marker {
    pub shape: MarkerShape,
    pub color: Color32,
    pub radius: f32,
    pub filled: bool,
}

/// The largest radius a legend key is drawn at (a larger marker's key is
/// scaled down, the layers of a stacked one together).
const KEY_RADIUS: f32 = 5.5;

impl Marker {
    pub const fn new(shape: MarkerShape, color: Color32, radius: f32, filled: bool) -> Self {
        Marker {
            shape,
            color,
            radius,
            filled,
        }
    }

    /// This marker at another radius.
    pub const fn radius(self, radius: f32) -> Self {
        Marker { radius, ..self }
    }

    /// The plot item: `points` named `name`, marked with this marker.
    pub fn points<'a>(
        self,
        name: impl Into<String>,
        points: impl Into<PlotPoints<'a>>,
    ) -> Points<'a> {
        Points::new(name, points)
            .shape(self.shape)
            .color(self.color)
            .radius(self.radius)
            .filled(self.filled)
    }

    /// The shapes of this marker at `center`, `radius` points wide, as
    /// egui_plot draws them: an outline is `radius / 5` wide, a cross, a
    /// plus and an asterisk are always strokes.
    pub fn shapes_at(self, center: Pos2, radius: f32) -> Vec<Shape> {
        let stroke = Stroke::new(self.radius / 5.0, self.color);
        let (fill, outline) = if self.filled {
            (self.color, Stroke::NONE)
        } else {
            (Color32::TRANSPARENT, stroke)
        };
        let tf = |dx: f32, dy: f32| center + radius * vec2(dx, dy);
        let (h, s3) = (std::f32::consts::FRAC_1_SQRT_2, 0.5 * 3f32.sqrt());
        let polygon = |pts: Vec<Pos2>| vec![Shape::convex_polygon(pts, fill, outline)];
        let segments = |segs: &[[(f32, f32); 2]]| {
            segs.iter()
                .map(|[a, b]| Shape::line_segment([tf(a.0, a.1), tf(b.0, b.1)], stroke))
                .collect()
        };
        match self.shape {
            MarkerShape::Circle => vec![Shape::Circle(egui::epaint::CircleShape {
                center,
                radius,
                fill,
                stroke: outline,
            })],
            MarkerShape::Diamond => polygon(vec![
                tf(0.0, 1.0),
                tf(-1.0, 0.0),
                tf(0.0, -1.0),
                tf(1.0, 0.0),
            ]),
            MarkerShape::Square => polygon(vec![tf(-h, h), tf(-h, -h), tf(h, -h), tf(h, h)]),
            MarkerShape::Up => polygon(vec![tf(0.0, -1.0), tf(s3, 0.5), tf(-s3, 0.5)]),
            MarkerShape::Down => polygon(vec![tf(0.0, 1.0), tf(-s3, -0.5), tf(s3, -0.5)]),
            MarkerShape::Left => polygon(vec![tf(-1.0, 0.0), tf(0.5, -s3), tf(0.5, s3)]),
            MarkerShape::Right => polygon(vec![tf(1.0, 0.0), tf(-0.5, s3), tf(-0.5, -s3)]),
            MarkerShape::Cross => segments(&[[(-h, -h), (h, h)], [(h, -h), (-h, h)]]),
            MarkerShape::Plus => segments(&[[(-1.0, 0.0), (1.0, 0.0)], [(0.0, -1.0), (0.0, 1.0)]]),
            MarkerShape::Asterisk => segments(&[
                [(0.0, -1.0), (0.0, 1.0)],
                [(-s3, 0.5), (s3, -0.5)],
                [(-s3, -0.5), (s3, 0.5)],
            ]),
        }
    }

    /// This marker at `center`, at its own radius, in `painter`.
    pub fn paint(self, painter: &egui::Painter, center: Pos2) {
        painter.extend(self.shapes_at(center, self.radius));
    }
}

/// The layers of a marker (one, or several drawn over each other, the
/// largest first) as a legend key centred in `rect`, scaled together so
/// that the largest is at most [`KEY_RADIUS`].
pub fn paint_key(ui: &Ui, rect: egui::Rect, layers: &[Marker]) {
    ui.painter()
        .extend(key_shapes(super::style::key_scale(ui.ctx()), rect, layers));
}

/// [`paint_key`]'s shapes at key scale `scale`.
fn key_shapes(scale: f32, rect: egui::Rect, layers: &[Marker]) -> Vec<Shape> {
    let largest = layers.iter().map(|m| m.radius).fold(0.0f32, f32::max);
    let most = KEY_RADIUS * scale;
    let k = if largest > most { most / largest } else { 1.0 };
    layers
        .iter()
        .flat_map(|m| m.shapes_at(rect.center(), m.radius * k))
        .collect()
}

/// A legend entry: the marker (its layers, see [`paint_key`]) and its label.
pub fn legend(ui: &mut Ui, layers: &[Marker], label: &str) {
    if !super::style::legend_shown(ui.ctx()) {
        return;
    }
    let scale = super::style::key_scale(ui.ctx());
    let side = (2.0 * KEY_RADIUS + 3.0) * scale;
    super::hold::entry(ui, vec2(side, side), label, |rect| {
        key_shapes(scale, rect, layers)
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An outlined marker's key is outlined, a filled one's filled.
    #[test]
    fn a_key_keeps_the_markers_fill() {
        let ring = Marker::new(MarkerShape::Circle, Color32::RED, 3.0, false);
        let shapes = ring.shapes_at(Pos2::ZERO, 3.0);
        let Shape::Circle(c) = &shapes[0] else {
            panic!("a circle")
        };
        assert_eq!(c.fill, Color32::TRANSPARENT);
        assert_eq!(c.stroke.color, Color32::RED);
        let down = Marker::new(MarkerShape::Down, Color32::BLUE, 5.0, true);
        let Shape::Path(p) = &down.shapes_at(Pos2::ZERO, 5.0)[0] else {
            panic!("a polygon")
        };
        assert_eq!((p.points.len(), p.fill), (3, Color32::BLUE));
        // Pointing down: the tip below the centre (y grows downwards).
        assert!(p.points[0].y > 0.0 && p.points[1].y < 0.0);
    }
}
