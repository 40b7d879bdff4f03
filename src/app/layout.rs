//! The window's layout: the top bar and status bar, the side panel (or a
//! phone's drawer), and the views as one tab or as tiles within the
//! layout's budget, beside the tour's band while it runs.

use eframe::egui;
use egui::{Rect, Ui};

use super::axes::plot_frames;
use super::explorer::{Explorer, PANEL_WIDTH};
use super::settings::{Layout, ViewKind};
use super::status;
use super::style::is_narrow;
use super::title_buttons::title_row_ui;
use super::view::Action;
use super::views::{min_tile, tiles_that_fit};

impl Explorer {
    /// The bars, the side panel (or a phone's drawer) and the views.
    pub(super) fn panels_ui(&mut self, ui: &mut Ui, actions: &mut Vec<Action>) {
        let narrow = is_narrow(ui.ctx());
        // No fills on the panels either (see the central panel below).
        let bare = egui::Frame::side_top_panel(ui.style()).fill(egui::Color32::TRANSPARENT);
        egui::Panel::top("top")
            .frame(bare)
            .show(ui, |ui| self.top_bar_ui(ui, actions));
        self.status_rect = egui::Panel::bottom("status")
            .frame(bare)
            .show(ui, |ui| {
                status::status_ui(ui, &self.jobs, &self.shots.toasts)
            })
            .response
            .rect;
        self.panel_rect = Rect::NOTHING;
        if !narrow && !self.settings.hide_panel {
            let width = ui.ctx().content_rect().width();
            // Never more than a third of the window (a projector's 1024);
            // back to the normal width for a few frames once projector
            // mode is switched off (its large text had widened it, and a
            // panel remembers its width).
            let mut panel = egui::Panel::left("controls")
                .frame(bare)
                .resizable(true)
                .default_size(PANEL_WIDTH)
                .min_size(260.0)
                .max_size((width / 3.0).max(260.0));
            if self.panel_reset > 0 {
                self.panel_reset -= 1;
                panel = panel.exact_size(PANEL_WIDTH);
            }
            self.panel_rect = panel
                .show(ui, |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| {
                        self.controls.ui(
                            ui,
                            &mut self.settings,
                            &self.jobs,
                            &mut self.play,
                            actions,
                        );
                    });
                })
                .response
                .rect;
        }
        // No fill: the clear colour is the panel colour, which saves
        // painting the largest area twice (software rendering is fill-bound).
        let frame = egui::Frame::central_panel(ui.style()).fill(egui::Color32::TRANSPARENT);
        egui::CentralPanel::default_margins()
            .frame(frame)
            .show(ui, |ui| {
                if narrow && self.drawer_open {
                    self.drawer_ui(ui, actions);
                } else {
                    self.views_ui(ui, actions);
                }
            });
    }

    /// A phone's drawer: the side panel's controls over the whole view.
    fn drawer_ui(&mut self, ui: &mut Ui, actions: &mut Vec<Action>) {
        if ui.button("Close").clicked() {
            self.drawer_open = false;
        }
        egui::ScrollArea::vertical().show(ui, |ui| {
            self.controls
                .ui(ui, &mut self.settings, &self.jobs, &mut self.play, actions);
        });
    }

    /// The views as a tab or tiles, beside the tour's band while it runs.
    fn views_ui(&mut self, ui: &mut Ui, out: &mut Vec<Action>) {
        self.view_rects.clear();
        self.drawn.0.clear();
        let whole = ui.available_rect_before_wrap();
        // A phone shows one view (its chooser is the top bar's); the saved
        // layout is kept for a wider window.
        let narrow = is_narrow(ui.ctx());
        let layout = match narrow {
            true => Layout::Tabs,
            false => self.settings.layout,
        };
        let (views, area) = match layout {
            // The tour on a phone: the step's view its box chose.
            Layout::Tabs if narrow && let Some(v) = self.tour.phone_view() => (vec![v], whole),
            Layout::Tabs => (vec![self.settings.tab], whole),
            // The tour lays out its step's few views itself, every one
            // shown: a step never hides its subject.
            Layout::Tiles if self.tour.step.is_some() => (self.settings.tiled.clone(), whole),
            Layout::Tiles => self.tiles_shown_ui(ui),
        };
        let (rects, band) = self.tour.arrange(area, &views, narrow);
        self.tour_band = band;
        // The tour's tiles fold their controls away: the step sets them,
        // and the plots need the room.
        super::style::set_controls_folded(ui.ctx(), self.tour.step.is_some());
        for (v, rect) in views.iter().zip(rects) {
            self.view_ui(ui, *v, rect, out);
        }
        super::style::set_controls_folded(ui.ctx(), false);
        ui.allocate_rect(whole, egui::Sense::hover());
    }

    /// The tiles that have room at this text size (the first of those
    /// ticked, each at least [`min_tile`]) and the area they share; when
    /// some are left out, a line above them says so. The settings keep
    /// every tile: a larger window shows them again.
    fn tiles_shown_ui(&self, ui: &mut Ui) -> (Vec<ViewKind>, Rect) {
        let mut views = self.settings.tiled.clone();
        let mut area = ui.available_rect_before_wrap();
        let row = ui.text_style_height(&egui::TextStyle::Body);
        let min = min_tile(row);
        if tiles_that_fit(area, views.len(), min) < views.len() {
            let line = Rect::from_min_max(area.min, egui::pos2(area.max.x, area.min.y + row));
            area.min.y = (line.max.y + 4.0).min(area.max.y);
            let fit = tiles_that_fit(area, views.len(), min);
            let text = format!(
                "{fit} of {} tiles shown: no room for more at this text size \
                 (enlarge the window, lower the text size or use Tabs)",
                views.len()
            );
            ui.put(
                line,
                egui::Label::new(egui::RichText::new(text).strong()).truncate(),
            );
            views.truncate(fit);
        }
        (views, area)
    }

    /// One view in `rect`, with its title and a screenshot button.
    fn view_ui(&mut self, ui: &mut Ui, v: ViewKind, rect: Rect, out: &mut Vec<Action>) {
        self.view_rects.insert(v, rect);
        // The plots drawn from here on are this view's (for `--layout`).
        let before = plot_frames(ui.ctx()).len();
        let fills = self.fills(v);
        let mut fill = false;
        let placement = self.controls_placement(v, rect, ui.ctx());
        let view = self.views.get_mut(v);
        let (settings, jobs) = (&mut self.settings, &self.jobs);
        let mut measured = None;
        ui.scope_builder(
            egui::UiBuilder::new().max_rect(rect).id_salt(v.key()),
            |ui| {
                // A view too short for its plots is cut at its tile's
                // edge, not drawn over the next tile (or the tour's box).
                ui.set_clip_rect(ui.clip_rect().intersect(rect));
                egui::Frame::group(ui.style())
                    .inner_margin(4.0)
                    .show(ui, |ui| {
                        ui.set_min_size(ui.available_size());
                        let mut menu = |ui: &mut Ui, out: &mut Vec<Action>| {
                            view.controls_ui(ui, settings, jobs, out);
                        };
                        let folded = (placement == Controls::Menu).then_some(&mut menu as _);
                        if title_row_ui(ui, v, fills, folded, out) {
                            fill = true;
                        }
                        if placement == Controls::Above {
                            let top = ui.cursor().top();
                            view.controls_ui(ui, settings, jobs, out);
                            measured = Some(ui.cursor().top() - top);
                        }
                        view.ui(ui, settings, jobs, out);
                    });
            },
        );
        let plots = plot_frames(ui.ctx())
            .get(before..)
            .map(<[_]>::to_vec)
            .unwrap_or_default();
        self.drawn.0.push((v, rect, plots));
        if let Some(h) = measured {
            self.controls_heights.insert(v, h);
        }
        if fill {
            self.toggle_fill(v);
        }
    }

    /// Where view `v`'s controls go in `rect`: none in the tour's tiles
    /// (the step sets them) nor on a phone's narrow tab; in the title
    /// row's menu where, as last drawn, they took over a quarter of a
    /// tile's height (a tile at a projector's text size); else above it.
    fn controls_placement(&self, v: ViewKind, rect: Rect, ctx: &egui::Context) -> Controls {
        if self.tour.step.is_some() || super::style::figure_only(ctx) {
            return Controls::None;
        }
        let tiled = !is_narrow(ctx) && self.settings.layout == Layout::Tiles;
        match self.controls_heights.get(&v) {
            Some(&h) if tiled && !self.fills(v) && h > 0.25 * rect.height() => Controls::Menu,
            _ => Controls::Above,
        }
    }
}

/// Where a view's controls are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Controls {
    /// Not at all (the tour's tiles).
    None,
    /// Above the view.
    Above,
    /// In its title row's menu.
    Menu,
}
