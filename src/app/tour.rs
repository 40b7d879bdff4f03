//! The guided tour for a lecture: the paper's story in six steps, from
//! creep to intermittency. Each step sets the parameters and the views
//! (tiles) and says in a few sentences what to look at; Previous and Next walk
//! the steps, and the arrow keys still nudge θν. The tour is plain data and
//! settings changes: no thread, no file, so it runs as it is in a browser.

use eframe::egui;
use egui::{Context, RichText};

use super::controls::apply_preset;
use super::settings::{Layout, Settings, ViewKind};
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
    },
];

impl TourStep {
    /// Sets the step's parameters and views.
    pub fn apply(&self, s: &mut Settings) {
        if let Some(p) = preset(self.preset) {
            apply_preset(s, &p.params.with_theta_nu(self.theta_nu), self.preset);
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
}

impl Tour {
    /// Goes to step `i` (clamped to the last), applying it.
    pub fn go(&mut self, i: usize, s: &mut Settings) {
        let i = i.min(STEPS.len() - 1);
        STEPS[i].apply(s);
        self.step = Some(i);
    }

    /// The step's box, bottom right, with Previous, Next and End tour
    /// ("Previous", not "Back": the diagram's zoom has a Back button).
    pub fn ui(&mut self, ctx: &Context, s: &mut Settings) {
        let Some(i) = self.step else { return };
        let step = &STEPS[i];
        let mut go: Option<Option<usize>> = None;
        egui::Window::new(format!("Tour {}/{}: {}", i + 1, STEPS.len(), step.title))
            .id(egui::Id::unique("oneblock-tour"))
            .anchor(egui::Align2::RIGHT_BOTTOM, egui::vec2(-12.0, -36.0))
            .collapsible(false)
            .resizable(false)
            .default_width(380.0)
            .show(ctx, |ui| {
                ui.label(step.text);
                ui.label(RichText::new("the arrow keys still nudge θν").weak());
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
