//! The top bar (the Panel switch, the name, Tour, Play, Share, the layout
//! and the tabs) and presentation mode: the side panel hidden (H), one view
//! filling the window (F), and on a phone's narrow screen one view at a
//! time with the panel as a drawer over it.

use eframe::egui;
use egui::{RichText, Ui};

use super::explorer::Explorer;
use super::play::play_button_ui;
use super::settings::{Layout, ViewKind};
use super::style::is_narrow;
use super::view::Action;

impl Explorer {
    /// The top bar: everything a lecture needs on one line at 1280 points.
    pub(super) fn top_bar_ui(&mut self, ui: &mut Ui, out: &mut Vec<Action>) {
        let narrow = is_narrow(ui.ctx());
        ui.horizontal_wrapped(|ui| {
            self.panel_button_ui(ui, narrow);
            if !narrow {
                ui.label(
                    RichText::new("oneblock")
                        .strong()
                        .size(ui.text_style_height(&egui::TextStyle::Heading)),
                );
            }
            validity_badge_ui(ui, &self.settings, narrow);
            ui.separator();
            if ui
                .button("Tour")
                .on_hover_text("The paper's story in six steps, from creep to intermittency")
                .clicked()
            {
                self.tour.go(0, &mut self.settings);
            }
            play_button_ui(ui, &mut self.play);
            share_button_ui(ui, out);
            ui.separator();
            // On a phone in the tour, its box chooses the view.
            match (narrow, self.tour.step) {
                (true, None) => view_chooser_ui(ui, &mut self.settings.tab),
                (true, Some(_)) => {}
                (false, _) => self.layout_ui(ui),
            }
        });
    }

    /// Shows or hides the side panel (on a phone, opens the drawer).
    fn panel_button_ui(&mut self, ui: &mut Ui, narrow: bool) {
        if narrow {
            if ui
                .selectable_label(self.drawer_open, "Controls")
                .on_hover_text("The parameters, presets and files, over the view")
                .clicked()
            {
                self.drawer_open = !self.drawer_open;
            }
        } else if ui
            .selectable_label(!self.settings.hide_panel, "Panel")
            .on_hover_text("Show or hide the side panel (H): hidden, the views take its width")
            .clicked()
        {
            self.settings.hide_panel = !self.settings.hide_panel;
        }
    }

    /// The layout switch, and the tabs or the tiles' menu.
    fn layout_ui(&mut self, ui: &mut Ui) {
        let s = &mut self.settings;
        ui.selectable_value(&mut s.layout, Layout::Tiles, "Tiles")
            .on_hover_text("Several views at once (T toggles)");
        ui.selectable_value(&mut s.layout, Layout::Tabs, "Tabs")
            .on_hover_text("One view, full size (keys 1–9)");
        ui.separator();
        match s.layout {
            Layout::Tabs => {
                for v in ViewKind::ALL {
                    ui.selectable_value(&mut s.tab, v, v.tab_title())
                        .on_hover_text(v.title());
                }
            }
            // The tiles' choice in a menu: eight checkboxes in a row
            // wrapped the bar onto a second line at text ×1.5, taking
            // height from every tile.
            Layout::Tiles => {
                let all = ViewKind::ALL.len();
                ui.menu_button(format!("tiles: {} of {all}", s.tiled.len()), |ui| {
                    for v in ViewKind::ALL {
                        let mut on = s.tiled.contains(&v);
                        if ui.checkbox(&mut on, v.title()).changed() {
                            if on {
                                s.tiled.push(v);
                                s.tiled
                                    .sort_by_key(|x| ViewKind::ALL.iter().position(|y| y == x));
                            } else if s.tiled.len() > 1 {
                                s.tiled.retain(|x| *x != v);
                            }
                        }
                    }
                });
            }
        }
    }

    /// Whether `v` fills the window now (its Fill button was pressed).
    pub fn fills(&self, v: ViewKind) -> bool {
        self.fill_restore.is_some()
            && self.settings.layout == Layout::Tabs
            && self.settings.tab == v
    }

    /// Makes `v` fill the window (one tab, the panel hidden), or, if it
    /// does, brings back the layout and panel it replaced.
    pub fn toggle_fill(&mut self, v: ViewKind) {
        let fills = self.fills(v);
        let s = &mut self.settings;
        if fills {
            if let Some((layout, hidden)) = self.fill_restore.take() {
                (s.layout, s.hide_panel) = (layout, hidden);
            }
        } else {
            if self.fill_restore.is_none() {
                self.fill_restore = Some((s.layout, s.hide_panel));
            }
            (s.layout, s.tab, s.hide_panel) = (Layout::Tabs, v, true);
        }
    }
}

/// The warning that the parameters leave the model's physical assumptions
/// (a "!" on a phone), its reasons on hover.
fn validity_badge_ui(ui: &mut Ui, s: &super::Settings, narrow: bool) {
    let warnings = crate::model::validity(&s.params);
    if warnings.is_empty() {
        return;
    }
    let text: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
    egui::Frame::new()
        .fill(egui::Color32::from_rgb(190, 40, 40))
        .corner_radius(6.0)
        .inner_margin(egui::Margin::symmetric(6, 2))
        .show(ui, |ui| {
            ui.label(
                RichText::new(if narrow {
                    "!"
                } else {
                    "Outside the model's validity"
                })
                .color(egui::Color32::WHITE)
                .strong(),
            )
        })
        .response
        .on_hover_text(text.join("\n"));
}

/// Share: the state as a link (in the browser; the native window has no
/// address to share).
#[cfg_attr(not(target_arch = "wasm32"), allow(unused_variables, clippy::ptr_arg))]
fn share_button_ui(ui: &mut Ui, out: &mut Vec<Action>) {
    #[cfg(target_arch = "wasm32")]
    if ui
        .button("Share")
        .on_hover_text(
            "Copy a link to this state (preset, view and parameters): it opens the explorer \
             here, for students or a slide.",
        )
        .clicked()
    {
        out.push(Action::CopyLink);
    }
}

/// A phone's view chooser: one view at a time, by name.
fn view_chooser_ui(ui: &mut Ui, tab: &mut ViewKind) {
    egui::ComboBox::from_id_salt("view-chooser")
        .selected_text(tab.tab_title())
        .show_ui(ui, |ui| {
            for v in ViewKind::ALL {
                ui.selectable_value(tab, v, v.title());
            }
        })
        .response
        .on_hover_text("The view shown: one at a time on a narrow screen.");
}
