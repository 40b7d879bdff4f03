//! The guided tour for a lecture: the paper's story in six steps, from
//! creep to intermittency. Each step sets the parameters and the views
//! (tiles) and says in a few sentences what to look at; Previous and Next
//! (or ← and →, a clicker's Page keys) walk the steps, ↑ and ↓ nudge θν.
//! Each step shows only the views it talks about, side by side in columns
//! of the window's full height; the last column's view shares it with the
//! box, under it, so the box covers none of the step's plots (it can be
//! dragged elsewhere; the next step puts it back). The tiles fold their
//! controls away (the step sets what they would), which leaves the plots
//! room at a projector's 1024 × 768 with text ×1.5: the diagram keeps its
//! λ strip, the time series its four plots. End tour gives back the
//! parameters, views and layout from before it. On a phone's narrow
//! screen the step's views are shown one at a time, the whole width over
//! the box, which chooses among them. The tour is plain data
//! and settings changes: no thread, no file, so it runs as it is in a
//! browser.

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
    /// The views shown, as columns: the last one shares its column with
    /// the box (the first ones need the height: the diagram and its strip,
    /// the time series).
    pub views: &'static [ViewKind],
    /// Which of f², f³, f⁴ the return map draws.
    pub map_powers: [bool; 3],
    /// Whether the return map shows f(θ) − θ.
    pub map_difference: bool,
    /// Whether the text speaks of the λ strip under the diagram (which is
    /// then drawn: the tests check it).
    pub strip: bool,
    /// The Basins view's θν range, where the step shows it.
    pub basins_range: Option<(f64, f64)>,
}

use ViewKind::{Basins, Bifurcation, Events, Plane, ReturnMap, TimeSeries};

/// The paper's story.
pub const STEPS: [TourStep; 7] = [
    TourStep {
        title: "Creep",
        text: "With weak velocity weakening (γ = 0.5) the block never sticks for long: it \
               creeps. Each slip moves it by about 0.004, so the plane shows a dot; the time \
               series shows each slip as a spike of the slip speed. The return map lies on the \
               diagonal, so it is drawn as f(θ) − θ: it crosses 0 at the fixed point with a \
               slope just below 0, a multiplier just below 1.",
        preset: "creep",
        theta_nu: 0.7,
        views: &[TimeSeries, ReturnMap, Plane],
        map_powers: [false; 3],
        map_difference: true,
        strip: false,
        basins_range: None,
    },
    TourStep {
        title: "A stick-slip fixed point",
        text: "The paper's Fig. 3b parameters at θν = 1.0: every slip starts at the same point \
               of C. The return map's graph crosses the diagonal there with |f'| < 1, and the \
               cobweb spirals in. In the diagram this θν has one point, and λ < 0 under it.",
        preset: "fig3b",
        theta_nu: 1.0,
        views: &[Bifurcation, ReturnMap, Plane],
        map_powers: [false; 3],
        map_difference: false,
        strip: true,
        basins_range: None,
    },
    TourStep {
        title: "The first period doubling",
        text: "Past θν = 1.09 or so the fixed point's multiplier has passed −1: the slips alternate \
               between two onsets. The return map's orbit is a square on the cobweb, and f² \
               (purple) crosses the diagonal at both points. In the strip, λ touched 0 at the \
               doubling and is negative again.",
        preset: "fig3b",
        theta_nu: 1.15,
        views: &[Bifurcation, ReturnMap, Plane],
        map_powers: [true, false, false],
        map_difference: false,
        strip: true,
        basins_range: None,
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
        basins_range: None,
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
        basins_range: None,
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
        views: &[ReturnMap, Events, Plane],
        map_powers: [false; 3],
        map_difference: false,
        strip: false,
        basins_range: None,
    },
    TourStep {
        title: "Hysteresis: two attractors",
        text: "At κ = 10 two stable cycles coexist: which one the block settles on depends \
               on where its first slip starts. The Basins view colours each onset by the \
               attractor it reaches, against θν. The large P2 (blue) dies in a fold at \
               θν = 1.4202; a small P2 is born in a fold at 1.3640 and shrinks onto the fixed \
               point in a flip at 1.3708. The marks on top name each event; hover one, or a \
               basin, to read it. Sweep θν up past 1.4202 and back: the block does not come \
               back to the P2.",
        preset: "hysteresis",
        theta_nu: 1.40,
        views: &[Basins, ReturnMap],
        map_powers: [true, false, false],
        map_difference: false,
        strip: false,
        basins_range: Some((1.35, 1.43)),
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
        if let Some(r) = self.basins_range {
            s.basins.zoom = vec![r];
        }
    }
}

/// Where the tour stands: `None` when it is not running.
#[derive(Default)]
pub struct Tour {
    pub step: Option<usize>,
    /// The settings from before the tour, which End tour gives back.
    before: Option<Box<Settings>>,
    /// The box's rectangle in the last frame.
    pub box_rect: Option<egui::Rect>,
    /// The user dragged the box away since the step began: it is left
    /// where they put it (until the next step).
    moved: bool,
    /// On a phone, which of the step's views is shown (one at a time).
    pub phone_view: usize,
}

/// The least width of a view beside another on the right, points.
const LEAST_WIDTH: f32 = 260.0;

/// `n` rectangles in `area`, a small gap apart: side by side `in_a_row`,
/// else stacked.
fn side_by_side(area: egui::Rect, n: usize, in_a_row: bool) -> Vec<egui::Rect> {
    let gap = 6.0;
    let (cols, rows) = if in_a_row { (n, 1) } else { (1, n) };
    let w = (area.width() - gap * (cols as f32 - 1.0)) / cols as f32;
    let h = (area.height() - gap * (rows as f32 - 1.0)) / rows as f32;
    (0..n)
        .map(|k| {
            let (c, r) = if in_a_row { (k, 0) } else { (0, k) };
            let min = area.min + egui::vec2(c as f32 * (w + gap), r as f32 * (h + gap));
            egui::Rect::from_min_size(min, egui::vec2(w, h))
        })
        .collect()
}

/// The band's height before the box was first measured.
const FIRST_BAND: f32 = 220.0;

impl Tour {
    /// Goes to step `i` (clamped to the last), applying it.
    pub fn go(&mut self, i: usize, s: &mut Settings) {
        let i = i.min(STEPS.len() - 1);
        if self.step.is_none() {
            self.before = Some(Box::new(s.clone()));
        }
        STEPS[i].apply(s);
        self.step = Some(i);
        self.moved = false;
        self.phone_view = 0;
    }

    /// The view a phone shows at this step (one at a time), if the tour
    /// runs.
    pub fn phone_view(&self) -> Option<ViewKind> {
        let views = STEPS[self.step?].views;
        views.get(self.phone_view).or(views.first()).copied()
    }

    /// Ends the tour: the parameters, views and layout from before it come
    /// back (what the user changed meanwhile that no step sets, the text
    /// size or the panel, say, stays as they left it).
    pub fn end(&mut self, s: &mut Settings) {
        self.step = None;
        self.moved = false;
        if let Some(b) = self.before.take() {
            s.params = b.params;
            s.preset = b.preset;
            s.full_circle = b.full_circle;
            s.layout = b.layout;
            s.tab = b.tab;
            s.tiled = b.tiled;
            s.map_powers = b.map_powers;
            s.map_difference = b.map_difference;
            s.basins.zoom = b.basins.zoom;
        }
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
    /// does not). The first view takes the left two fifths at full height
    /// (the diagram and its strip, the time series' four plots); the
    /// others share a row on the right, over the band, or where the row
    /// would leave each less than [`LEAST_WIDTH`] (the side panel shown at
    /// 1024 points) half the width, stacked. On a phone (`narrow`) the
    /// one view shown takes the whole width over a band as wide.
    pub fn arrange(
        &self,
        whole: egui::Rect,
        views: &[ViewKind],
        narrow: bool,
    ) -> (Vec<egui::Rect>, egui::Rect) {
        if self.step.is_none() {
            return (tile_rects(whole, views.len()), egui::Rect::NOTHING);
        }
        let gap = 6.0;
        if narrow {
            let band = self.band().min(whole.height() * 0.6);
            let free = egui::Rect::from_min_max(
                egui::pos2(whole.left(), whole.bottom() - band),
                whole.max,
            );
            let view =
                egui::Rect::from_min_max(whole.min, egui::pos2(whole.right(), free.top() - gap));
            return (vec![view; views.len().min(1)], free);
        }
        let others = views.len().saturating_sub(1);
        let in_a_row = (whole.width() - gap) * 0.6 >= others as f32 * (LEAST_WIDTH + gap);
        let share = if in_a_row { 0.4 } else { 0.5 };
        let split = whole.left() + (whole.width() - gap) * share;
        let left = egui::Rect::from_min_max(whole.min, egui::pos2(split, whole.bottom()));
        let band = self.band().min(whole.height() * 0.6);
        let free =
            egui::Rect::from_min_max(egui::pos2(split + gap, whole.bottom() - band), whole.max);
        let right = egui::Rect::from_min_max(
            egui::pos2(free.left(), whole.top()),
            egui::pos2(whole.right(), free.top() - gap),
        );
        let mut rects = vec![left];
        if others > 0 {
            rects.extend(side_by_side(right, others, in_a_row));
        }
        rects.truncate(views.len());
        (rects, free)
    }

    /// The step's box, in the band under the views (`band`: that band),
    /// with Previous, Next and End tour ("Previous", not "Back": the
    /// diagram's zoom has a Back button). On a phone (`narrow`) the box
    /// also chooses which of the step's views is shown.
    pub fn ui(&mut self, ctx: &Context, s: &mut Settings, band: egui::Rect, narrow: bool) {
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
            if narrow {
                ui.horizontal_wrapped(|ui| {
                    ui.label("show:");
                    for (k, v) in step.views.iter().enumerate() {
                        ui.selectable_value(&mut self.phone_view, k, v.tab_title());
                    }
                });
            }
            go = buttons_ui(ui, i, narrow);
        });
        self.box_rect = shown.map(|r| r.response.rect);
        // Dragged by its title: not where it was put.
        if let (false, Some(r)) = (self.moved, self.box_rect) {
            self.moved = (r.min - (band.min + egui::vec2(4.0, 4.0))).length() > 1.0;
        }
        match go {
            Some(Some(j)) => self.go(j, s),
            Some(None) => self.end(s),
            None => {}
        }
    }
}

/// Previous, Next and End tour at step `i` and, beside them on a wide
/// screen, the keys; where a click goes: a step, or `None` to end.
fn buttons_ui(ui: &mut egui::Ui, i: usize, narrow: bool) -> Option<Option<usize>> {
    let mut go = None;
    ui.horizontal_wrapped(|ui| {
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
        if ui
            .button("End tour")
            .on_hover_text("Back to the parameters, views and layout from before the tour")
            .clicked()
        {
            go = Some(None);
        }
        if !narrow {
            ui.label(
                RichText::new("keys: left, right: steps · up, down: θν · drag the title to move")
                    .weak(),
            );
        }
    });
    go
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

    #[test]
    fn end_tour_gives_back_the_parameters_views_and_layout_from_before() {
        let before = Settings {
            params: Settings::default().params.with_theta_nu(0.42),
            preset: None,
            layout: Layout::Tabs,
            tab: ViewKind::Basins,
            tiled: vec![ViewKind::Block, ViewKind::Phase],
            map_powers: [false, false, true],
            map_difference: true,
            ..Settings::default()
        };
        let mut s = before.clone();
        let mut tour = Tour::default();
        tour.go(1, &mut s);
        tour.go(4, &mut s);
        // What no step sets, changed during the tour, stays changed.
        s.font_scale = 1.5;
        s.hide_panel = true;
        assert_ne!(s.params, before.params);
        tour.end(&mut s);
        assert_eq!(tour.step, None);
        assert_eq!(
            s,
            Settings {
                font_scale: 1.5,
                hide_panel: true,
                ..before.clone()
            }
        );
        // A second tour starts from the settings it finds.
        s.params.theta_nu = 0.5;
        tour.go(0, &mut s);
        tour.end(&mut s);
        assert_eq!(s.params.theta_nu, 0.5);
    }

    #[test]
    fn each_step_shows_three_views_or_fewer_with_the_tall_one_first() {
        for step in &STEPS {
            assert!((1..=3).contains(&step.views.len()), "{}", step.title);
            // The diagram (its λ strip) and the time series (four plots)
            // need the full height: the first column's.
            for v in &step.views[1..] {
                assert!(!matches!(v, Bifurcation | TimeSeries), "{}", step.title);
            }
            assert_eq!(
                step.strip,
                step.views.contains(&Bifurcation),
                "{}",
                step.title
            );
        }
        let whole = egui::Rect::from_min_size(egui::pos2(8.0, 49.0), egui::vec2(1008.0, 684.0));
        let mut tour = Tour::default();
        tour.go(1, &mut Settings::default());
        tour.box_rect = Some(egui::Rect::from_min_size(
            egui::Pos2::ZERO,
            egui::vec2(580.0, 200.0),
        ));
        let (rects, band) = tour.arrange(whole, STEPS[1].views, false);
        assert_eq!(rects.len(), 3);
        for (i, r) in rects.iter().enumerate() {
            assert!(whole.contains_rect(*r), "{r:?}");
            assert!(!r.intersects(band), "{r:?} {band:?}");
            for q in &rects[i + 1..] {
                assert!(!r.intersects(*q), "{r:?} {q:?}");
            }
        }
        assert_eq!(rects[0].height(), whole.height());
        assert!(band.height() >= 208.0 && band.max == whole.max, "{band:?}");
    }
}
