//! The keyboard: Ctrl+S, 1–9 for a view, T for tabs or tiles, Space for
//! the block's animation, R to restart the orbit, ← and → to step θν (or,
//! in the tour, to walk its steps), and presentation's H, F, Esc, P, N.

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
            Key::Num9,
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
        self.presentation_keys(ctx);
        let (left, right, shift) = ctx.input(|i| {
            (
                i.key_pressed(Key::ArrowLeft),
                i.key_pressed(Key::ArrowRight),
                i.modifiers.shift,
            )
        });
        if let Some(i) = self.tour.step {
            // In the tour the arrows (and a clicker's Page keys) walk the
            // steps; ↑ and ↓ nudge θν.
            let (back, next) = ctx.input(|i| {
                (
                    left || i.key_pressed(Key::PageUp),
                    right || i.key_pressed(Key::PageDown),
                )
            });
            if back && i > 0 {
                self.tour.go(i - 1, &mut self.settings);
            } else if next {
                self.tour.go(i + 1, &mut self.settings);
            }
            let (down, up) =
                ctx.input(|i| (i.key_pressed(Key::ArrowDown), i.key_pressed(Key::ArrowUp)));
            if down || up {
                out.push(Action::SetThetaNu(
                    self.settings.params.theta_nu + if up { 0.005 } else { -0.005 },
                ));
            }
        } else if left || right {
            let step = if shift { 0.05 } else { 0.005 };
            out.push(Action::SetThetaNu(
                self.settings.params.theta_nu + if right { step } else { -step },
            ));
        }
    }

    /// H: the side panel (a phone's drawer); F: the view under the pointer
    /// (or the tab) fills the window, Esc brings the layout back; P: play
    /// θν; N / Shift+N: the cobweb's next / previous iterate.
    fn presentation_keys(&mut self, ctx: &Context) {
        let pressed = |k: Key| ctx.input(|i| i.key_pressed(k));
        if pressed(Key::H) {
            if super::style::is_narrow(ctx) {
                self.drawer_open = !self.drawer_open;
            } else {
                self.settings.hide_panel = !self.settings.hide_panel;
            }
        }
        if pressed(Key::F) {
            let v = self
                .view_under_pointer(ctx)
                .unwrap_or(match self.settings.layout {
                    Layout::Tabs => self.settings.tab,
                    Layout::Tiles => self.settings.tiled[0],
                });
            self.toggle_fill(v);
        }
        if pressed(Key::Escape) && self.fill_restore.is_some() {
            self.toggle_fill(self.settings.tab);
        }
        if pressed(Key::P) {
            self.play.toggle();
        }
        if pressed(Key::N) {
            let back = ctx.input(|i| i.modifiers.shift);
            let available = self.jobs.trajectory.data.events.len();
            self.views
                .return_map
                .steps
                .step(if back { -1 } else { 1 }, available);
        }
    }
}
