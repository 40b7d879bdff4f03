//! Where a figure's legends go: in a row above the plot they describe
//! (the window's, and `figure --legend outside`), or inside that plot in a
//! corner (`figure --legend inside[-CORNER]`), as a boxed key over the
//! data, placed where it covers the least of it when no corner is asked
//! for. An inside legend is laid out where its row would have started,
//! taking no room; after each pass of a figure its plot is found (the
//! frame below that spot) and the legends of one plot are stacked in the
//! chosen corner for the next pass ([`place`]), so they never overlap.

use std::collections::HashMap;

use eframe::egui;
use egui::epaint::{ClippedShape, Shape};
use egui::{Color32, Id, LayerId, Order, Pos2, Rect, Ui, Vec2};

use super::svg::Textures;

/// A corner of a plot for an inside legend; `Best` the one over the
/// least data.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Corner {
    #[default]
    Best,
    TopRight,
    TopLeft,
    BottomRight,
    BottomLeft,
}

/// The corners in the order `Best` tries them (a tie goes to the first).
const CORNERS: [Corner; 4] = [
    Corner::TopRight,
    Corner::TopLeft,
    Corner::BottomLeft,
    Corner::BottomRight,
];

/// A legend drawn this pass: where its row would have started (`anchor`),
/// the box it took, and whether it lies inside its plot.
#[derive(Clone, Copy, Debug)]
pub struct Drawn {
    pub id: Id,
    pub anchor: Pos2,
    pub rect: Rect,
    pub inside: bool,
}

#[derive(Clone, Default)]
struct DrawnList(Vec<Drawn>);

/// Where [`place`] put an inside legend for the next pass: its box's
/// corner, the width it may take (wider in a short plot), or back above
/// its plot when even so it does not fit inside (a λ strip at a column's
/// size), for good.
#[derive(Clone, Copy, Debug)]
struct Place {
    at: Pos2,
    width: Option<f32>,
    outside: bool,
}

#[derive(Clone, Default)]
struct Placed(HashMap<Id, Place>);

fn drawn_id() -> Id {
    Id::unique("oneblock-legends-drawn")
}

fn placed_id() -> Id {
    Id::unique("oneblock-legends-placed")
}

/// Forgets the legends drawn in the pass before (their places stay).
pub fn clear(ctx: &egui::Context) {
    super::hold::begin_pass(ctx);
    ctx.data_mut(|d| d.remove::<DrawnList>(drawn_id()));
}

/// The legends drawn since the last [`clear`].
pub fn drawn(ctx: &egui::Context) -> Vec<Drawn> {
    ctx.data(|d| {
        d.get_temp::<DrawnList>(drawn_id())
            .map(|l| l.0)
            .unwrap_or_default()
    })
}

fn push(ctx: &egui::Context, drawn: Drawn) {
    ctx.data_mut(|d| {
        d.get_temp_mut_or_default::<DrawnList>(drawn_id())
            .0
            .push(drawn);
    });
}

/// A legend row above its plot, wrapping, recorded for the SVG.
pub fn outside<R>(ui: &mut Ui, add: impl FnOnce(&mut Ui) -> R) -> R {
    let anchor = ui.cursor().min;
    let r = ui.horizontal_wrapped(|ui| super::hold::row(ui, add));
    push(
        ui.ctx(),
        Drawn {
            id: ui.scope_id(),
            anchor,
            rect: r.response.rect,
            inside: false,
        },
    );
    r.inner
}

/// The inner margin of an inside legend's box, points.
fn pad(ui: &Ui) -> f32 {
    0.35 * ui.text_style_height(&egui::TextStyle::Body)
}

/// A legend boxed inside its plot, drawn over the data where the last
/// [`place`] put it (laid out unseen until then). It takes no room.
pub fn inside<R>(ui: &mut Ui, add: impl FnOnce(&mut Ui) -> R) -> R {
    let id = ui.next_auto_id().with("inside-legend");
    ui.skip_ahead_auto_ids(1);
    let anchor = ui.cursor().min;
    let place = ui
        .ctx()
        .data(|d| d.get_temp::<Placed>(placed_id()))
        .and_then(|p| p.0.get(&id).copied());
    if place.is_some_and(|p| p.outside) {
        return outside(ui, add);
    }
    let at = place.map(|p| p.at);
    let pad = pad(ui);
    // At first half the plot's width: a key of a few rows, not a banner.
    let width = place
        .and_then(|p| p.width)
        .map_or(0.5 * ui.available_width(), |w| w - 2.0 * pad)
        .max(8.0 * pad);
    let origin = at.unwrap_or(anchor) + Vec2::splat(pad);
    let mut b = egui::UiBuilder::new()
        .layer_id(LayerId::new(Order::Foreground, id))
        .id_salt(id)
        .max_rect(Rect::from_min_size(origin, egui::vec2(width, 1.0e4)))
        .layout(egui::Layout::top_down(egui::Align::Min));
    if at.is_none() {
        b = b.invisible();
    }
    let mut child = ui.new_child(b);
    // The whole picture's clip: the box is no series of the plot.
    child.set_clip_rect(ui.ctx().content_rect());
    child.spacing_mut().item_spacing.y *= 0.5;
    let bg = child.painter().add(Shape::Noop);
    let inner = child
        .horizontal_wrapped(|ui| super::hold::row(ui, add))
        .inner;
    let rect = child.min_rect().expand(pad);
    child.painter().set(
        bg,
        egui::epaint::RectShape::new(
            rect,
            1.0,
            Color32::WHITE.gamma_multiply(0.92),
            egui::Stroke::new(0.6, Color32::from_gray(160)),
            egui::StrokeKind::Inside,
        ),
    );
    push(
        ui.ctx(),
        Drawn {
            id,
            anchor,
            rect,
            inside: true,
        },
    );
    inner
}

/// The plot an inside legend anchored at `anchor` describes: the frame
/// nearest below it (its row would have been above the plot), else the
/// nearest above (a legend under its plot).
fn frame_of(frames: &[(&'static str, Rect)], anchor: Pos2) -> Option<Rect> {
    let cost = |f: &Rect| {
        let dy = if f.top() >= anchor.y - 1.0 {
            f.top() - anchor.y
        } else if f.bottom() <= anchor.y + 1.0 {
            2.0 * (anchor.y - f.bottom()) + 1.0
        } else {
            0.0
        };
        let dx = if f.right() < anchor.x {
            1.0e6
        } else {
            (f.left() - anchor.x).abs()
        };
        dy + dx
    };
    frames
        .iter()
        .map(|(_, f)| *f)
        .min_by(|a, b| cost(a).total_cmp(&cost(b)))
}

/// The rectangle of `size` in `corner` of `frame`, `margin` in from its
/// sides.
fn corner_rect(frame: Rect, corner: Corner, size: Vec2, margin: f32) -> Rect {
    let x = match corner {
        Corner::TopLeft | Corner::BottomLeft => frame.left() + margin,
        _ => frame.right() - margin - size.x,
    };
    let y = match corner {
        Corner::BottomLeft | Corner::BottomRight => frame.bottom() - margin - size.y,
        _ => frame.top() + margin,
    };
    Rect::from_min_size(egui::pos2(x, y), size)
}

/// Places the inside legends of the pass just drawn for the next: those
/// of one plot stacked in `corner` (for `Best` the corner whose box
/// covers the fewest of the plot's marks in `shapes`).
pub fn place(
    ctx: &egui::Context,
    corner: Corner,
    frames: &[(&'static str, Rect)],
    shapes: &[ClippedShape],
    textures: &Textures,
) {
    let mut groups: Vec<(Rect, Vec<Drawn>)> = Vec::new();
    for d in drawn(ctx).into_iter().filter(|d| d.inside) {
        let Some(f) = frame_of(frames, d.anchor) else {
            continue;
        };
        match groups.iter_mut().find(|(g, _)| *g == f) {
            Some(g) => g.1.push(d),
            None => groups.push((f, vec![d])),
        }
    }
    let old = ctx
        .data(|d| d.get_temp::<Placed>(placed_id()))
        .unwrap_or_default()
        .0;
    // A legend gone back above its plot stays there.
    let mut placed: HashMap<Id, Place> = old
        .iter()
        .filter(|(_, p)| p.outside)
        .map(|(id, p)| (*id, *p))
        .collect();
    for (f, ds) in groups {
        let gap = 2.0;
        let margin = (0.015 * f.width().min(f.height())).clamp(2.0, 8.0);
        let room = f.size() - Vec2::splat(2.0 * margin);
        let size = egui::vec2(
            ds.iter().map(|d| d.rect.width()).fold(0.0, f32::max),
            ds.iter().map(|d| d.rect.height() + gap).sum::<f32>() - gap,
        );
        // Too tall for a short plot: laid out wider next pass; still too
        // large once as wide as it may be: above the plot.
        let mut widened = false;
        let mut width = |d: &Drawn| {
            let before = old.get(&d.id).and_then(|p| p.width);
            if size.y > 0.45 * room.y && d.rect.width() < 0.8 * room.x && before.is_none() {
                widened = true;
                return Some(0.95 * room.x);
            }
            before
        };
        let widths: Vec<Option<f32>> = ds.iter().map(&mut width).collect();
        let outside = !widened && (size.y > room.y || size.x > room.x);
        let c = match corner {
            Corner::Best => best(f, size, margin, shapes, textures),
            c => c,
        };
        let at = corner_rect(f, c, size, margin);
        let right = matches!(c, Corner::TopRight | Corner::BottomRight);
        let mut y = at.top();
        for (d, width) in ds.iter().zip(widths) {
            let x = if right {
                at.right() - d.rect.width()
            } else {
                at.left()
            };
            let at = egui::pos2(x, y);
            placed.insert(d.id, Place { at, width, outside });
            y += d.rect.height() + gap;
        }
    }
    ctx.data_mut(|d| d.insert_temp(placed_id(), Placed(placed)));
}

/// The corner whose box of `size` covers the least of the marks drawn in
/// `frame`.
fn best(frame: Rect, size: Vec2, margin: f32, shapes: &[ClippedShape], tex: &Textures) -> Corner {
    let of_plot: Vec<&Shape> = shapes
        .iter()
        .filter(|cs| frame.expand(1.0).contains_rect(cs.clip_rect) && cs.clip_rect.area() > 0.0)
        .map(|cs| &cs.shape)
        .collect();
    let mut best = (Corner::TopRight, f32::INFINITY);
    for c in CORNERS {
        let r = corner_rect(frame, c, size, margin);
        let score: f32 = of_plot.iter().map(|s| covered(s, r, tex)).sum();
        if score < best.1 {
            best = (c, score);
        }
    }
    best.0
}

/// How much of `shape` lies under `r`: samples every 2 points along its
/// lines, its markers, its filled area in 2 × 2 point cells, an image's
/// inked pixels at those cells.
fn covered(shape: &Shape, r: Rect, tex: &Textures) -> f32 {
    match shape {
        Shape::Vec(v) => v.iter().map(|s| covered(s, r, tex)).sum(),
        Shape::Path(p) => along(&p.points, p.closed, r),
        Shape::LineSegment { points, .. } => along(points, false, r),
        Shape::Circle(c) => f32::from(u8::from(r.expand(c.radius).contains(c.center))),
        Shape::Rect(x) if x.fill.a() > 0 => x.rect.intersect(r).area().max(0.0) / 4.0,
        Shape::Text(t) if t.visual_bounding_rect().intersects(r) => 50.0,
        Shape::Mesh(m) => match tex.get(&m.texture_id) {
            Some(img) => inked(img, m.calc_bounds(), r),
            None => m.vertices.iter().filter(|v| r.contains(v.pos)).count() as f32,
        },
        _ => 0.0,
    }
}

/// Samples every 2 points along the polyline `points` inside `r`.
fn along(points: &[Pos2], closed: bool, r: Rect) -> f32 {
    let mut n = 0.0;
    let count = points.len();
    let segs = if closed {
        count
    } else {
        count.saturating_sub(1)
    };
    for i in 0..segs {
        let (a, b) = (points[i], points[(i + 1) % count]);
        let len = (b - a).length();
        let k = ((len / 2.0).ceil() as usize).clamp(1, 400);
        for j in 0..k {
            if r.contains(a + (b - a) * (j as f32 / k as f32)) {
                n += 1.0;
            }
        }
    }
    n
}

/// The image `img` shown over `bounds`: its inked (not white, not
/// transparent) pixels under `r`, sampled every 2 points.
fn inked(img: &egui::ColorImage, bounds: Rect, r: Rect) -> f32 {
    let [w, h] = img.size;
    let over = bounds.intersect(r);
    if w == 0 || h == 0 || over.width() <= 0.0 || over.height() <= 0.0 {
        return 0.0;
    }
    let mut n = 0.0;
    let mut y = over.top();
    while y < over.bottom() {
        let mut x = over.left();
        let ty = (((y - bounds.top()) / bounds.height()) * h as f32) as usize;
        while x < over.right() {
            let tx = (((x - bounds.left()) / bounds.width()) * w as f32) as usize;
            let c = img.pixels[ty.min(h - 1) * w + tx.min(w - 1)];
            if c.a() > 20 && u16::from(c.r()) + u16::from(c.g()) + u16::from(c.b()) < 720 {
                n += 1.0;
            }
            x += 2.0;
        }
        y += 2.0;
    }
    n
}

/// The legends' boxes as invisible SVG rectangles (`class="legend"`,
/// `data-place` inside or outside), for a reader and the tests to find.
pub fn svg_boxes(drawn: &[Drawn]) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    for d in drawn {
        writeln!(
            s,
            "<rect class=\"legend\" data-place=\"{}\" x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"none\" stroke=\"none\"/>",
            if d.inside { "inside" } else { "outside" },
            d.rect.min.x,
            d.rect.min.y,
            d.rect.width(),
            d.rect.height()
        )
        .ok();
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_corner_box_lies_inside_its_frame() {
        let f = Rect::from_min_max(egui::pos2(10.0, 20.0), egui::pos2(110.0, 90.0));
        for c in CORNERS {
            let r = corner_rect(f, c, egui::vec2(30.0, 20.0), 3.0);
            assert!(f.contains_rect(r), "{c:?}: {r:?}");
        }
        // A line along the top: the best corner is a bottom one.
        let line = Shape::line_segment(
            [egui::pos2(10.0, 25.0), egui::pos2(110.0, 25.0)],
            egui::Stroke::new(1.0, Color32::BLACK),
        );
        let shapes = [ClippedShape {
            clip_rect: f,
            shape: line,
            transform_after_tessellation: Default::default(),
        }];
        let c = best(f, egui::vec2(30.0, 20.0), 3.0, &shapes, &Textures::new());
        assert!(
            matches!(c, Corner::BottomLeft | Corner::BottomRight),
            "{c:?}"
        );
    }
}
