//! The bifurcation diagram's points as vector marks in a figure's SVG
//! and PDF (issue 57): each distinct point of each column a dot, one
//! `<path>` of short round-capped subpaths per colour, in place of the
//! window's density image, up to [`MAX_VECTOR_POINTS`]; beyond, the image
//! stays and `figure` says so on stderr. Points that fall on one spot at
//! a quarter of the image's row height are one dot.

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;
use std::sync::Arc;

use eframe::egui;
use egui::{Color32, Id, Rect, TextureId};

use super::data::SweepData;

/// The most dots drawn as vectors; a larger diagram is drawn as an image.
pub const MAX_VECTOR_POINTS: usize = 200_000;

/// Rows of the grid on which coinciding points are merged.
const GRID_ROWS: f64 = 1680.0;

/// The dots of one diagram: per colour, each dot's place as fractions of
/// the image's width (from the left) and height (from the top); the dot's
/// diameter in points.
#[derive(Clone, Debug, Default)]
pub struct Marks {
    pub groups: Vec<(Color32, Vec<[f32; 2]>)>,
    pub width: f32,
}

impl Marks {
    /// How many dots.
    pub fn len(&self) -> usize {
        self.groups.iter().map(|g| g.1.len()).sum()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The marks registered this pass, by the texture they replace.
pub type MarksOf = HashMap<TextureId, Arc<Marks>>;

fn marks_id() -> Id {
    Id::unique("oneblock-diagram-marks")
}

/// The dots of `sweep` over θ in [lo, hi]: the followed attractor's in
/// `ink`, the others' in `other`, merged where they coincide.
pub fn of(sweep: &SweepData, (lo, hi): (f64, f64), (ink, other): (Color32, Color32)) -> Marks {
    let w = sweep.columns.len().max(1) as f64;
    let mut seen: HashSet<(usize, i64, bool)> = HashSet::new();
    let (mut own, mut others) = (Vec::new(), Vec::new());
    for (j, col) in sweep.columns.iter().enumerate() {
        let Some(col) = col else { continue };
        let u = ((j as f64 + 0.5) / w) as f32;
        let labels = col.attractor.iter().chain(std::iter::repeat(&0));
        for (&t, &label) in col.thetas.iter().zip(labels) {
            if !(t >= lo && t <= hi) {
                continue;
            }
            let v = (hi - t) / (hi - lo).max(1e-300);
            let key = (j, (v * GRID_ROWS) as i64, label != 0);
            if seen.insert(key) {
                let list = if label == 0 { &mut own } else { &mut others };
                list.push([u, v as f32]);
            }
        }
    }
    Marks {
        groups: vec![(ink, own), (other, others)],
        width: 1.0,
    }
}

/// A figure's dots of `sweep` ([`of`]), a little wider than a line
/// (thinner with a figure's line scale); none in the window.
pub fn for_figure(
    ctx: &egui::Context,
    sweep: &SweepData,
    range: (f64, f64),
    inks: (Color32, Color32),
) -> Option<Marks> {
    super::style::figure_only(ctx).then(|| Marks {
        width: (1.2 * super::style::width(ctx, 1.0)).max(0.5),
        ..of(sweep, range, inks)
    })
}

/// Registers `marks` for the figure drawn in `ctx` as the texture `tex`'s
/// replacement; more than [`MAX_VECTOR_POINTS`] are not (the image
/// stays), and a note says so.
pub fn register(ctx: &egui::Context, tex: TextureId, marks: Marks) {
    let n = marks.len();
    if n > MAX_VECTOR_POINTS {
        super::style::figure_note(
            ctx,
            &format!(
                "the diagram's {n} points are drawn as an image: more than {MAX_VECTOR_POINTS} as vector marks"
            ),
        );
        ctx.data_mut(|d| {
            d.get_temp_mut_or_default::<MarksOf>(marks_id())
                .remove(&tex)
        });
        return;
    }
    ctx.data_mut(|d| {
        d.get_temp_mut_or_default::<MarksOf>(marks_id())
            .insert(tex, Arc::new(marks));
    });
}

/// The marks registered in `ctx`.
pub fn registered(ctx: &egui::Context) -> MarksOf {
    ctx.data(|d| d.get_temp::<MarksOf>(marks_id()).unwrap_or_default())
}

/// `m` drawn over the image's place `bounds` as SVG paths, a series of
/// `plot` (`data-series="PLOT:points"`).
pub fn svg(m: &Marks, bounds: Rect, plot: Option<&str>) -> String {
    let mut out = String::new();
    let tag = plot.map_or(String::new(), |p| {
        format!(
            " class=\"series\" data-series=\"{}:points\"",
            super::svg::escape(p)
        )
    });
    for (c, dots) in m.groups.iter().filter(|g| !g.1.is_empty()) {
        let [r, g, b, _] = c.to_srgba_unmultiplied();
        let mut d = String::with_capacity(dots.len() * 16);
        for [u, v] in dots {
            let x = bounds.left() + u * bounds.width();
            let y = bounds.top() + v * bounds.height();
            write!(d, "M{x:.1} {y:.1}h.1").ok();
        }
        write!(
            out,
            "<path d=\"{d}\" fill=\"none\" stroke=\"#{r:02x}{g:02x}{b:02x}\" stroke-width=\"{:.2}\" stroke-linecap=\"round\" data-points=\"{}\"{tag}/>",
            m.width,
            dots.len()
        )
        .ok();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Up to the bound the marks replace the image; beyond, the image
    /// stays and a note says so.
    #[test]
    fn too_many_dots_leave_the_image_and_say_so() {
        let ctx = egui::Context::default();
        super::super::style::set_figure_only(&ctx, true);
        let tex = TextureId::User(7);
        let dots = |n: usize| Marks {
            groups: vec![(Color32::BLACK, vec![[0.5, 0.5]; n])],
            width: 1.0,
        };
        register(&ctx, tex, dots(10));
        assert_eq!(registered(&ctx)[&tex].len(), 10);
        register(&ctx, tex, dots(MAX_VECTOR_POINTS + 1));
        assert!(!registered(&ctx).contains_key(&tex));
        let notes = super::super::style::take_figure_notes();
        assert!(notes.iter().any(|n| n.contains("as an image")), "{notes:?}");
    }
}
