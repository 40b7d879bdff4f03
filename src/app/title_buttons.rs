//! A view's title bar: its title (cut short with "…" where the buttons
//! need the room) and its buttons: Fill, SVG, PNG, Record, the "?"
//! paragraph.

use eframe::egui;
use egui::{Popup, PopupCloseBehavior, Ui};

use super::settings::ViewKind;
use super::view::Action;

/// Frames of a recorded GIF (12 s of playback at 10 a second).
pub const RECORD_FRAMES: usize = 120;

/// Frames of a recorded GIF of θν played (6 s at 10 a second: each frame
/// computes an orbit).
pub const RECORD_PLAY_FRAMES: usize = 60;

/// The Record menu's playback speeds: real time and slowed.
pub const RECORD_SPEEDS: [(&str, f64); 3] = [
    ("Real time", 1.0),
    ("Half speed", 0.5),
    ("Quarter speed", 0.25),
];

/// The "?" of a view: what it shows, in one paragraph. Hovering shows it
/// (a mouse); a click or tap pins it in a popup that a click outside
/// closes (a touch screen, or a browser without hover).
pub fn help_button_ui(ui: &mut Ui, v: ViewKind) {
    let resp = ui.small_button("?");
    let paragraph = |ui: &mut Ui| {
        ui.set_max_width(420.0);
        ui.label(super::help::view_help(v));
    };
    let popup = Popup::from_toggle_button_response(&resp)
        .close_behavior(PopupCloseBehavior::CloseOnClickOutside);
    let open = Popup::is_id_open(ui.ctx(), Popup::default_response_id(&resp));
    if popup.show(paragraph).is_none() && !open {
        resp.on_hover_ui(paragraph);
    }
}

/// The Record menu: for the block and plane views a GIF of
/// [`RECORD_FRAMES`] frames at one of [`RECORD_SPEEDS`]; for every view
/// that follows θν, a GIF of θν played across the diagram's range.
pub fn record_menu_ui(ui: &mut Ui, v: ViewKind, out: &mut Vec<Action>) {
    ui.menu_button("Record", |ui| {
        let playback = matches!(v, ViewKind::Block | ViewKind::Plane);
        for (label, speed) in RECORD_SPEEDS.into_iter().filter(|_| playback) {
            let hover = format!(
                "Save a GIF of this view: {RECORD_FRAMES} frames at 10 a second, 640x480, \
                 playing at {speed}x the window's speed, made without holding the window \
                 (off its thread; in a browser, a frame or so per frame of the page)"
            );
            if ui.button(label).on_hover_text(hover).clicked() {
                out.push(Action::Record(v, speed));
                ui.close();
            }
        }
        let hover = format!(
            "Save a GIF of this view as Play θν shows it: θν across the diagram's range, \
             {RECORD_PLAY_FRAMES} frames at 10 a second, 640x480, made without holding the \
             window (each frame's orbit computed off its thread; in a browser, between the \
             page's frames)"
        );
        if ui.button("θν played").on_hover_text(hover).clicked() {
            out.push(Action::RecordPlay(v));
            ui.close();
        }
    });
}

/// A view's controls, drawn into a menu (see [`title_row_ui`]).
pub type ControlsMenu<'a> = &'a mut dyn FnMut(&mut Ui, &mut Vec<Action>);

/// The title bar of view `v` (`fills`: it fills the window now); whether
/// its Fill button was clicked. The buttons are laid out first, from the
/// right, and the title takes what is left, shortened rather than drawn
/// under them (a tile at 1024×768, text ×1.5). With `controls`, the view's
/// controls are folded into a "Controls" menu among the buttons.
pub fn title_row_ui(
    ui: &mut Ui,
    v: ViewKind,
    fills: bool,
    controls: Option<ControlsMenu>,
    out: &mut Vec<Action>,
) -> bool {
    let title = v.title();
    let mut fill = false;
    ui.horizontal(|ui| {
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            help_button_ui(ui, v);
            // Folded (the tour's tiles): the title and its paragraph only.
            if !super::style::controls_shown(ui.ctx()) {
                ui.with_layout(egui::Layout::left_to_right(egui::Align::Center), |ui| {
                    ui.add(egui::Label::new(egui::RichText::new(title).strong()).truncate());
                });
                return;
            }
            if let Some(draw) = controls {
                ui.menu_button("Controls", |ui| {
                    ui.set_max_width(28.0 * ui.text_style_height(&egui::TextStyle::Body));
                    draw(ui, out);
                })
                .response
                .on_hover_text("This view's controls, folded here: the tile is too small for them");
            }
            if super::animation::PLAY_VIEWS.contains(&v) {
                record_menu_ui(ui, v, out);
            }
            if ui
                .small_button("PNG")
                .on_hover_text(format!("Save a PNG of the {title} view only"))
                .clicked()
            {
                out.push(Action::ViewScreenshot(v));
            }
            if ui
                .small_button("SVG")
                .on_hover_text(format!(
                    "Save an SVG (vector) picture of the {title} view only"
                ))
                .clicked()
            {
                out.push(Action::SvgScreenshot(Some(v)));
            }
            let hover = if fills {
                "Back to the layout and panel before (F, Esc)"
            } else {
                "This view fills the window: one tab, the panel hidden (F)"
            };
            fill = ui
                .add(egui::Button::selectable(fills, "Fill").small())
                .on_hover_text(hover)
                .clicked();
            ui.with_layout(egui::Layout::left_to_right(egui::Align::Center), |ui| {
                ui.add(egui::Label::new(egui::RichText::new(title).strong()).truncate())
                    .on_hover_text(title);
            });
        });
    });
    fill
}
