//! The keyboard: Ctrl+S, 1–8 for a view, T for tabs or tiles, Space for
//! the block's animation, R to restart the orbit, ← and → to step θν.

use eframe::egui;
use egui::{Context, Key, KeyboardShortcut, Modifiers};

use super::explorer::Explorer;
use super::settings::{Layout, ViewKind};
use super::view::Action;

impl Explorer {
    /// Keyboard shortcuts: those that act on the window go to `out`.
    pub(super) fn shortcuts(&mut self, ctx: &Context, out: &mut Vec<Action>) {
        let save = KeyboardShortcut::new(Modifiers::COMMAND, Key::S);
        if ctx.input_mut(|i| i.consume_shortcut(&save)) {
            out.push(Action::Screenshot);
        }
        if ctx.egui_wants_keyboard_input() {
            return;
        }
        let tabs = [
            Key::Num1,
            Key::Num2,
            Key::Num3,
            Key::Num4,
            Key::Num5,
            Key::Num6,
            Key::Num7,
            Key::Num8,
        ];
        for (k, v) in tabs.into_iter().zip(ViewKind::ALL) {
            if ctx.input(|i| i.key_pressed(k)) {
                self.settings.layout = Layout::Tabs;
                self.settings.tab = v;
            }
        }
        if ctx.input(|i| i.key_pressed(Key::T)) {
            self.settings.layout = match self.settings.layout {
                Layout::Tabs => Layout::Tiles,
                Layout::Tiles => Layout::Tabs,
            };
        }
        if ctx.input(|i| i.key_pressed(Key::Space)) {
            self.views.block.playing = !self.views.block.playing;
        }
        if ctx.input(|i| i.key_pressed(Key::R)) {
            out.push(Action::RestartOrbit);
        }
        let (left, right, shift) = ctx.input(|i| {
            (
                i.key_pressed(Key::ArrowLeft),
                i.key_pressed(Key::ArrowRight),
                i.modifiers.shift,
            )
        });
        if left || right {
            let step = if shift { 0.05 } else { 0.005 };
            out.push(Action::SetThetaNu(
                self.settings.params.theta_nu + if right { step } else { -step },
            ));
        }
    }
}
