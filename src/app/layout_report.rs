//! The window's layout as the user saw it, for `gui --layout FILE`: the
//! rectangle of every view drawn, of each of its plots (their frames, the
//! data area inside the axes) and of the tour's box, in points, as JSON.
//! Tests read it to check that a tour step shows what it talks about at a
//! projector's size, through the same binary a teacher runs.

use eframe::egui::Rect;
use serde::{Deserialize, Serialize};

use super::settings::ViewKind;

/// `[x, y, width, height]` in points, from the window's top left.
pub type Xywh = [f32; 4];

/// A rectangle as `[x, y, w, h]`, rounded to a hundredth of a point.
pub fn xywh(r: Rect) -> Xywh {
    let round = |v: f32| (v * 100.0).round() / 100.0;
    [
        round(r.min.x),
        round(r.min.y),
        round(r.width()),
        round(r.height()),
    ]
}

/// One plot of a view: its name (`"lyapunov"` for the diagram's λ strip,
/// `"time-series-y"` for y(t), …) and its frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlotLayout {
    pub name: String,
    pub rect: Xywh,
}

/// One view drawn: its key (`gui --view`'s), its tile, the union of its
/// plots wholly on screen (`null` if none is), and each of them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewLayout {
    pub view: String,
    pub rect: Xywh,
    pub plot: Option<Xywh>,
    pub plots: Vec<PlotLayout>,
}

/// The whole window's layout: the views in the order drawn, and the tour's
/// box (`null` when the tour is not running).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct LayoutReport {
    pub views: Vec<ViewLayout>,
    pub tour: Option<Xywh>,
}

/// The plots a view drew: each one's name and frame.
pub type Plots = Vec<(&'static str, Rect)>;

/// What the last frame drew: each view's tile and its plots' frames.
#[derive(Clone, Debug, Default)]
pub struct Drawn(pub Vec<(ViewKind, Rect, Plots)>);

impl Drawn {
    /// The report of this frame's views and the tour's box `tour`.
    pub fn report(&self, tour: Option<Rect>) -> LayoutReport {
        let views = self
            .0
            .iter()
            .map(|(v, rect, plots)| ViewLayout {
                view: v.key().to_string(),
                rect: xywh(*rect),
                plot: plots.iter().map(|p| p.1).reduce(Rect::union).map(xywh),
                plots: plots
                    .iter()
                    .map(|(name, r)| PlotLayout {
                        name: (*name).to_string(),
                        rect: xywh(*r),
                    })
                    .collect(),
            })
            .collect();
        LayoutReport {
            views,
            tour: tour.map(xywh),
        }
    }
}

impl LayoutReport {
    /// As the file holds it (pretty-printed, with a final newline).
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).unwrap_or_default();
        s.push('\n');
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use eframe::egui::{pos2, vec2};

    #[test]
    fn the_report_gives_each_view_its_tile_and_the_union_of_its_plots() {
        let tile = Rect::from_min_size(pos2(10.0, 20.0), vec2(300.0, 200.0));
        let a = Rect::from_min_size(pos2(20.0, 40.0), vec2(100.0, 50.0));
        let b = Rect::from_min_size(pos2(20.0, 100.0), vec2(120.0, 60.0));
        let drawn = Drawn(vec![
            (
                ViewKind::Bifurcation,
                tile,
                vec![("bifurcation", a), ("lyapunov", b)],
            ),
            (ViewKind::Block, tile, vec![]),
        ]);
        let r = drawn.report(Some(Rect::from_min_size(pos2(0.5, 1.0), vec2(2.0, 3.0))));
        assert_eq!(r.views[0].view, "bifurcation");
        assert_eq!(r.views[0].rect, [10.0, 20.0, 300.0, 200.0]);
        assert_eq!(r.views[0].plot, Some([20.0, 40.0, 120.0, 120.0]));
        assert_eq!(r.views[0].plots[1].name, "lyapunov");
        assert_eq!(r.views[1].plot, None);
        assert_eq!(r.tour, Some([0.5, 1.0, 2.0, 3.0]));
        let back: LayoutReport = serde_json::from_str(&r.to_json()).expect("reads back");
        assert_eq!(back, r);
        let v: serde_json::Value = serde_json::from_str(&r.to_json()).expect("JSON");
        assert!(v["views"][1]["plot"].is_null());
        assert!(
            Drawn::default()
                .report(None)
                .to_json()
                .contains("\"tour\": null")
        );
    }
}
