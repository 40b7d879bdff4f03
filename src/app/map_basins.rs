//! The return map's basin band: the cell graph's basins at the current
//! parameters along the frame's foot, each in its attractor's colour (its
//! track's in the Basins view, so one attractor has one colour), and a
//! chaotic attractor's invariant density over it.

use eframe::egui::Color32;
use egui_plot::PlotPoints;

use super::jobs::Jobs;
use super::settings::Settings;
use super::style;

/// Stretches of θ (from, to, attractor; `None`: the boundary), and the
/// density curves.
type Band = (Vec<(f64, f64, Option<usize>)>, Vec<Vec<[f64; 2]>>);

/// What the band draws.
#[derive(Clone, Debug, Default)]
pub(super) struct BasinBand {
    basins: Vec<(f64, f64, Option<usize>)>,
    /// Each attractor's colour and legend name (basin: FP, P2, chaotic).
    colours: Vec<Color32>,
    names: Vec<String>,
    density: Vec<Vec<[f64; 2]>>,
}

/// The band's width and the density curve's, in lines (`style::width`).
pub(super) const BAND_WIDTH: f32 = 6.0;
pub(super) const DENSITY_WIDTH: f32 = 1.5;

/// The density curve's colour.
pub(super) fn density_colour() -> Color32 {
    style::POWERS[0].gamma_multiply(0.8)
}

impl BasinBand {
    /// Draws it over the plot's current bounds.
    pub(super) fn draw(&self, p: &mut egui_plot::PlotUi<'_>) {
        draw_basins(p, self);
    }

    /// The stretches drawn over θ in (`lo`, `hi`), one per attractor
    /// (`None`: the boundary) in the order first met, each with its
    /// colour and legend name: the legend's entries for the band.
    pub(super) fn drawn(&self, lo: f64, hi: f64) -> Vec<(Color32, String)> {
        let mut seen: Vec<Option<usize>> = Vec::new();
        for &(a, b, att) in &self.basins {
            if b.min(hi) > a.max(lo) && !seen.contains(&att) {
                seen.push(att);
            }
        }
        seen.into_iter()
            .map(|att| match att {
                Some(i) => (
                    self.colours
                        .get(i)
                        .copied()
                        .unwrap_or(super::basins::BOUNDARY),
                    self.names.get(i).cloned().unwrap_or_else(|| "basin".into()),
                ),
                None => (super::basins::BOUNDARY, "basin boundary".into()),
            })
            .collect()
    }

    /// Whether a density curve has a point over θ in [`lo`, `hi`].
    pub(super) fn density_drawn(&self, lo: f64, hi: f64) -> bool {
        self.density
            .iter()
            .any(|c| c.iter().filter(|q| (lo..=hi).contains(&q[0])).count() > 1)
    }
}

/// The colour of each attractor of `found` (at the current parameters):
/// its track's in the Basins view when that view holds it, else one no
/// track of the view has.
pub(super) fn attractor_colours(
    s: &Settings,
    jobs: &Jobs,
    found: &crate::sim::attractors::Found,
) -> Vec<Color32> {
    let d = &jobs.basins.data;
    let tracks = d.tracks_of(&s.params, found);
    let spare = if tracks.iter().any(Option::is_some) {
        d.ids.tracks.len()
    } else {
        0
    };
    tracks
        .iter()
        .enumerate()
        .map(|(i, t)| super::basins::track_color(t.unwrap_or(spare + i)))
        .collect()
}

/// The basins along θ and each chaotic attractor's density (bins' centres,
/// scaled to at most 1), from the cell graph's answer.
fn basins_of(found: Option<&crate::sim::attractors::Found>) -> Band {
    let Some(f) = found else {
        return (Vec::new(), Vec::new());
    };
    let basins = f
        .basins
        .iter()
        .map(|b| (b.from, b.to, b.attractor))
        .collect();
    let density = f
        .attractors
        .iter()
        .filter_map(|a| a.density.as_ref())
        .map(|d| {
            let n = d.values.len().max(1);
            let top = d.values.iter().copied().fold(0.0, f64::max).max(1e-300);
            let w = (d.to - d.from) / n as f64;
            let at = |i: usize| d.from + w * (i as f64 + 0.5);
            d.values
                .iter()
                .enumerate()
                .map(|(i, v)| [at(i), v / top])
                .collect()
        })
        .collect();
    (basins, density)
}

/// The basins as a band along the frame's foot (each stretch in its
/// attractor's colour, the boundary grey) and a chaotic attractor's
/// density as a curve over the band, a quarter of the frame high.
impl BasinBand {
    /// The band at the current parameters, once the cell graph found it.
    pub(super) fn of(s: &Settings, jobs: &Jobs) -> Self {
        let found = jobs.map_basins.at(&s.params);
        let (basins, density) = basins_of(found);
        let names = found.map_or(Vec::new(), |f| {
            f.attractors
                .iter()
                .map(|a| match a.period {
                    Some(1) => "basin: FP".to_owned(),
                    Some(p) => format!("basin: P{p}"),
                    None => "basin: chaotic".to_owned(),
                })
                .collect()
        });
        BasinBand {
            basins,
            colours: found.map_or(Vec::new(), |f| attractor_colours(s, jobs, f)),
            names,
            density,
        }
    }
}

fn draw_basins(p: &mut egui_plot::PlotUi<'_>, d: &BasinBand) {
    let b = p.plot_bounds();
    let (lo, hi) = (b.min()[0], b.max()[0]);
    let h = b.max()[1] - b.min()[1];
    let lw = style::width(p.ctx(), 1.0);
    let foot = b.min()[1] + 0.015 * h;
    for &(a, b, att) in &d.basins {
        let (a, b) = (a.max(lo), b.min(hi));
        if b <= a {
            continue;
        }
        let (name, colour) = match att {
            Some(i) => (
                "basins (cell graph)",
                d.colours.get(i).copied().unwrap_or(super::basins::BOUNDARY),
            ),
            None => ("basin boundary", super::basins::BOUNDARY),
        };
        p.line(
            style::line(name, PlotPoints::from(vec![[a, foot], [b, foot]]))
                .color(colour)
                .width(BAND_WIDTH * lw),
        );
    }
    for curve in &d.density {
        let pts: Vec<[f64; 2]> = curve
            .iter()
            .filter(|q| (lo..=hi).contains(&q[0]))
            .map(|q| [q[0], foot + 0.25 * h * q[1]])
            .collect();
        p.line(
            style::line("invariant density (scaled)", PlotPoints::from(pts))
                .color(density_colour())
                .width(DENSITY_WIDTH * lw),
        );
    }
}
