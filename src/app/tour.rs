//! The guided tour for a lecture: the paper's story in six steps, from
//! creep to intermittency. Each step sets the parameters and the views
//! (tiles) and says in a few sentences what to look at; Previous and Next
//! (or ← and →, a clicker's Page keys) walk the steps, ↑ and ↓ nudge θν.
//! The box sits in a band kept free under the views, so it covers none of
//! the step's plots (it can be dragged elsewhere; the next step puts it
//! back); a step that speaks of the λ strip gives the diagram a tall tile,
//! where the strip is drawn. The tour is plain data and settings changes:
//! no thread, no file, so it runs as it is in a browser.

use eframe::egui;
use egui::{Context, RichText};

use super::settings::{Layout, Settings, ViewKind};
use super::views::tile_rects;
use crate::model::presets::preset;

/// One step of the tour.
#[derive(Clone, Copy, Debug)]
pub struct TourStep {
    pub title: &'static str,
    /// What to look at, in a few sentences.
    pub text: &'static str,
    /// The preset whose κ, γ, ν, Ω the step takes…
    pub preset: &'static str,
    /// …at this θν.
    pub theta_nu: f64,
    /// The views shown, as tiles.
    pub views: &'static [ViewKind],
    /// Which of f², f³, f⁴ the return map draws.
    pub map_powers: [bool; 3],
    /// Whether the return map shows f(θ) − θ.
    pub map_difference: bool,
    /// Whether the text speaks of the λ strip under the diagram (the
    /// diagram then takes a tall tile, where the strip is drawn).
    pub strip: bool,
}

use ViewKind::{Bifurcation, Events, Plane, ReturnMap, TimeSeries};

/// The paper's story.
pub const STEPS: [TourStep; 6] = [
    TourStep {
        title: "Creep",
        text: "With weak velocity weakening (γ = 0.5) the block never sticks for long: it \
               creeps. Each slip moves it by about 0.004, so the plane shows a dot; the time \
               series shows each slip as a spike of the slip speed. The return map lies on the \
               diagonal, so it is drawn as f(θ) − θ: it crosses 0 at the fixed point with a \
               slope just below 0, a multiplier just below 1.",
        preset: "creep",
        theta_nu: 0.7,
        views: &[TimeSeries, Plane, ReturnMap],
        map_powers: [false; 3],
        map_difference: true,
        strip: false,
    },
    TourStep {
        title: "A stick-slip fixed point",
        text: "The paper's Fig. 3b parameters at θν = 1.0: every slip starts at the same point \
               of C. The return map's graph crosses the diagonal there with |f'| < 1, and the \
               cobweb spirals in. In the diagram this θν has one point, and λ < 0 under it.",
        preset: "fig3b",
        theta_nu: 1.0,
        views: &[Plane, ReturnMap, Bifurcation],
        map_powers: [false; 3],
        map_difference: false,
        strip: true,
    },
    TourStep {
        title: "The first period doubling",
        text: "Past θν = 1.09 or so the fixed point's multiplier has passed −1: the slips alternate \
               between two onsets. The return map's orbit is a square on the cobweb, and f² \
               (purple) crosses the diagonal at both points. In the strip, λ touched 0 at the \
               doubling and is negative again.",
        preset: "fig3b",
        theta_nu: 1.15,
        views: &[Plane, ReturnMap, Bifurcation],
        map_powers: [true, false, false],
        map_difference: false,
        strip: true,
    },
    TourStep {
        title: "The cascade and chaos",
        text: "Doublings follow faster and faster (P4, P8, …) and accumulate near θν = 1.22 or so, \
               where λ stays at 0; beyond, the onsets never repeat and λ > 0: chaos. The return \
               map's iterates fill a stretch of its graph, and the slip sizes spread.",
        preset: "fig3b",
        theta_nu: 1.25,
        views: &[Bifurcation, ReturnMap, Events],
        map_powers: [false; 3],
        map_difference: false,
        strip: true,
    },
    TourStep {
        title: "A period-3 window",
        text: "Inside the chaos, at θν = 1.30, a stable period-3 cycle: three onsets in the \
               diagram, λ < 0 again. f³ (green) touches the diagonal at the orbit's three \
               points, as just after the tangent bifurcation that opened the window.",
        preset: "fig3b",
        theta_nu: 1.30,
        views: &[Bifurcation, ReturnMap, Plane],
        map_powers: [false, true, false],
        map_difference: false,
        strip: true,
    },
    TourStep {
        title: "Intermittency in the mixed regime",
        text: "At κ = 50, γ = 6.5, ν = 1e-4 some slips start inside the critical ellipse and \
               creep, others stick and slip. Laminar phases, runs of creep slips drifting \
               slowly through the channel between f and the diagonal, are broken by \
               stick-slip bursts that re-inject the orbit. The events view counts the laminar \
               phases and sets their mean length beside the channel's passage time.",
        preset: "intermittent",
        theta_nu: 1.4,
        views: &[Plane, Events, TimeSeries],
        map_powers: [false; 3],
        map_difference: false,
        strip: false,
    },
];

impl TourStep {
    /// Sets the step's parameters and views.
    pub fn apply(&self, s: &mut Settings) {
        if let Some(p) = preset(self.preset) {
            s.apply_preset(&p.params.with_theta_nu(self.theta_nu), self.preset);
        }
        s.layout = Layout::Tiles;
        s.tiled = self.views.to_vec();
        s.map_powers = self.map_powers;
        s.map_difference = self.map_difference;
    }
}

/// Where the tour stands: `None` when it is not running.
#[derive(Default)]
pub struct Tour {
    pub step: Option<usize>,
    /// The box's rectangle in the last frame.
    pub box_rect: Option<egui::Rect>,
    /// The user dragged the box away since the step began: it is left
    /// where they put it (until the next step).
    moved: bool,
}

/// `n` rectangles stacked in `area`, a small gap apart.
fn tile_rects_stacked(area: egui::Rect, n: usize) -> Vec<egui::Rect> {
    let gap = 6.0;
    let n = n.max(1);
    let h = (area.height() - gap * (n as f32 - 1.0)) / n as f32;
    (0..n)
        .map(|k| {
            let min = area.min + egui::vec2(0.0, k as f32 * (h + gap));
            egui::Rect::from_min_size(min, egui::vec2(area.width(), h))
        })
        .collect()
}

/// The band's height before the box was first measured.
const FIRST_BAND: f32 = 170.0;

impl Tour {
    /// Goes to step `i` (clamped to the last), applying it.
    pub fn go(&mut self, i: usize, s: &mut Settings) {
        let i = i.min(STEPS.len() - 1);
        STEPS[i].apply(s);
        self.step = Some(i);
        self.moved = false;
    }

    /// The height kept free under the views for the box, while it runs.
    pub fn band(&self) -> f32 {
        match (self.step, self.box_rect) {
            (None, _) => 0.0,
            (Some(_), Some(r)) => r.height() + 8.0,
            (Some(_), None) => FIRST_BAND,
        }
    }

    /// The views' rectangles in `whole` (the views' area) and the band
    /// kept free for the box while the tour runs (`Rect::NOTHING` when it
    /// does not). The band spans the bottom; a step that speaks of the λ
    /// strip, showing its own views, gives the diagram the left half at
    /// full height (room for the strip) and the band the right half.
    pub fn arrange(&self, whole: egui::Rect, views: &[ViewKind]) -> (Vec<egui::Rect>, egui::Rect) {
        let Some(i) = self.step else {
            return (tile_rects(whole, views.len()), egui::Rect::NOTHING);
        };
        let step = &STEPS[i];
        let band = self.band().min(whole.height() * 0.6);
        let strip = step.strip && views == step.views && views.contains(&Bifurcation);
        if !strip {
            let area = egui::Rect::from_min_max(whole.min, whole.max - egui::vec2(0.0, band));
            let free = egui::Rect::from_min_max(egui::pos2(whole.left(), area.bottom()), whole.max);
            return (tile_rects(area, views.len()), free);
        }
        let gap = 6.0;
        let half = (whole.width() - gap) / 2.0;
        let left = egui::Rect::from_min_size(whole.min, egui::vec2(half, whole.height()));
        let right = egui::Rect::from_min_max(
            egui::pos2(left.right() + gap, whole.top()),
            whole.max - egui::vec2(0.0, band),
        );
        let free = egui::Rect::from_min_max(egui::pos2(right.left(), right.bottom()), whole.max);
        let mut others = tile_rects_stacked(right, views.len() - 1).into_iter();
        let rects = views
            .iter()
            .map(|v| {
                if *v == Bifurcation {
                    left
                } else {
                    others.next().unwrap_or(right)
                }
            })
            .collect();
        (rects, free)
    }

    /// The step's box, in the band under the views (`band`: that band),
    /// with Previous, Next and End tour ("Previous", not "Back": the
    /// diagram's zoom has a Back button).
    pub fn ui(&mut self, ctx: &Context, s: &mut Settings, band: egui::Rect) {
        let Some(i) = self.step else {
            self.box_rect = None;
            return;
        };
        let step = &STEPS[i];
        let mut go: Option<Option<usize>> = None;
        // The window's frame and margins come on top of its contents' width.
        let width = (band.width() - 24.0).clamp(200.0, 1100.0);
        let id = egui::Id::unique("oneblock-tour");
        let mut window =
            egui::Window::new(format!("Tour {}/{}: {}", i + 1, STEPS.len(), step.title))
                .id(id)
                .collapsible(false)
                .resizable(false)
                .min_width(width)
                .max_width(width)
                // Not pushed back into the screen by egui by a stale size
                // (it put the box over the views); the band is on screen.
                .constrain(false);
        if !self.moved {
            let at = band.min + egui::vec2(4.0, 4.0);
            window = window.current_pos(at);
            // A window dragged by its title puts back the position it had
            // before this frame (egui 0.37), undoing `current_pos` after
            // the first frame: so the stored position is set too.
            if let Some(mut state) = egui::AreaState::load(ctx, id) {
                state.pivot_pos = Some(at);
                let layer = egui::LayerId::new(egui::Order::Middle, id);
                ctx.memory_mut(|m| m.areas_mut().set_state(layer, state));
            }
        }
        let shown = window.show(ctx, |ui| {
            ui.label(step.text);
            ui.label(
                RichText::new(
                    "the arrow keys: left and right walk the steps, up and down nudge θν; \
                         drag the title to move this box",
                )
                .weak(),
            );
            ui.horizontal(|ui| {
                if ui
                    .add_enabled(i > 0, egui::Button::new("Previous"))
                    .clicked()
                {
                    go = Some(Some(i - 1));
                }
                let last = i + 1 == STEPS.len();
                if ui.add_enabled(!last, egui::Button::new("Next")).clicked() {
                    go = Some(Some(i + 1));
                }
                if ui.button("End tour").clicked() {
                    go = Some(None);
                }
            });
        });
        self.box_rect = shown.map(|r| r.response.rect);
        // Dragged by its title: not where it was put.
        if let (false, Some(r)) = (self.moved, self.box_rect) {
            self.moved = (r.min - (band.min + egui::vec2(4.0, 4.0))).length() > 1.0;
        }
        match go {
            Some(Some(j)) => self.go(j, s),
            Some(None) => self.step = None,
            None => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Regime;

    #[test]
    fn each_step_sets_the_parameters_and_views_it_names() {
        let mut s = Settings::default();
        let mut tour = Tour::default();
        for (i, step) in STEPS.iter().enumerate() {
            tour.go(i, &mut s);
            assert_eq!(tour.step, Some(i));
            let p = preset(step.preset).expect("a preset").params;
            assert_eq!(s.params, p.with_theta_nu(step.theta_nu), "{}", step.title);
            assert_eq!(s.preset.as_deref(), Some(step.preset));
            assert_eq!((s.layout, s.tiled.as_slice()), (Layout::Tiles, step.views));
            assert_eq!(
                (s.map_powers, s.map_difference),
                (step.map_powers, step.map_difference)
            );
        }
        // The story's regimes: creep first, the mixed regime last.
        let regime = |i: usize| {
            let p = preset(STEPS[i].preset).expect("a preset").params;
            Regime::of(p.kappa, p.gamma)
        };
        assert!(matches!(regime(0), Regime::PureCreep));
        assert!(matches!(regime(1), Regime::PureStickSlip));
        assert!(matches!(regime(5), Regime::Mixed { .. }));
        // Past the end stays on the last step.
        tour.go(99, &mut s);
        assert_eq!(tour.step, Some(STEPS.len() - 1));
    }
}
