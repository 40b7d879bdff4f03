//! Play: a clock that moves θν across the diagram's range at a chosen
//! speed, turning at each end (the cursor, the return map, the path and the
//! block follow, as when the slider is dragged), or, with the return map's
//! cobweb stepped, adds one iterate per tick. Only settings change: the
//! jobs restart as for a drag, so it runs the same in a browser.

use eframe::egui;
use egui::Ui;

use super::settings::{PLAY_SPEEDS, Settings};

/// The longest time step one frame may play (a stalled frame does not
/// jump θν across the range).
const MAX_STEP: f64 = 0.1;

/// The play clock's state (not persisted).
#[derive(Clone, Debug)]
pub struct Play {
    pub on: bool,
    /// θν grows (true) or falls.
    pub forward: bool,
    /// The time of the last tick, seconds.
    last: Option<f64>,
    /// Cobweb iterates owed by the ticks so far (fractional).
    owed: f64,
}

impl Default for Play {
    fn default() -> Self {
        Play {
            on: false,
            forward: true,
            last: None,
            owed: 0.0,
        }
    }
}

/// What one tick of the clock asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tick {
    Nothing,
    /// θν to this value.
    ThetaNu(f64),
    /// This many more cobweb iterates.
    Iterates(usize),
}

impl Play {
    /// Starts or stops the clock.
    pub fn toggle(&mut self) {
        self.on = !self.on;
        self.last = None;
        self.owed = 0.0;
    }

    /// The tick at time `now` (seconds): θν moved by the speed times the
    /// time since the last tick, turning at the ends of `range`; or, when
    /// `cobweb` is stepped, whole iterates at speed × 100 a second (the
    /// slowest speed one a second).
    pub fn tick(&mut self, s: &Settings, range: (f64, f64), cobweb: bool, now: f64) -> Tick {
        if !self.on {
            return Tick::Nothing;
        }
        let dt = self.last.map_or(0.0, |t| (now - t).clamp(0.0, MAX_STEP));
        self.last = Some(now);
        if cobweb {
            self.owed += dt * s.play_speed * 100.0;
            // A whole iterate owed is taken even when the clock's sums
            // fall a rounding error short of it (ten ticks of 0.1 s).
            let n = (self.owed + 1e-9).floor();
            self.owed -= n;
            return if n >= 1.0 {
                Tick::Iterates(n as usize)
            } else {
                Tick::Nothing
            };
        }
        let (lo, hi) = range;
        let step = s.play_speed * dt;
        let mut x = s.params.theta_nu + if self.forward { step } else { -step };
        if x >= hi {
            x = hi - (x - hi).min(hi - lo);
            self.forward = false;
        } else if x <= lo {
            x = lo + (lo - x).min(hi - lo);
            self.forward = true;
        }
        if dt > 0.0 {
            Tick::ThetaNu(x.clamp(lo, hi))
        } else {
            Tick::Nothing
        }
    }
}

/// The play row: Play/Pause, the direction and the speed.
pub fn play_ui(ui: &mut Ui, play: &mut Play, s: &mut Settings) {
    ui.horizontal_wrapped(|ui| {
        play_button_ui(ui, play);
        ui.selectable_value(&mut play.forward, false, "θν−")
            .on_hover_text("Play towards smaller θν");
        ui.selectable_value(&mut play.forward, true, "θν+")
            .on_hover_text("Play towards larger θν");
        for (v, label) in PLAY_SPEEDS.iter().zip(["slow", "medium", "fast"]) {
            ui.selectable_value(&mut s.play_speed, *v, label)
                .on_hover_text(format!(
                    "θν moves {v} rad a second; a stepped cobweb adds {} iterates a second",
                    v * 100.0
                ));
        }
    });
}

/// The Play / Pause button (P).
pub fn play_button_ui(ui: &mut Ui, play: &mut Play) {
    let label = if play.on { "Pause" } else { "Play θν" };
    if ui
        .selectable_label(play.on, label)
        .on_hover_text(
            "Let θν run across the diagram's range and back (P): the cursor, the return map, \
             the path and the block follow. With the cobweb stepped, Play adds its iterates.",
        )
        .clicked()
    {
        play.toggle();
    }
}

/// The return map's cobweb, stepped: only the first `shown` iterates of the
/// trajectory (its transient included) are drawn, one more per N or per
/// tick of the play clock.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CobwebSteps {
    pub on: bool,
    pub shown: usize,
}

impl CobwebSteps {
    /// One iterate more (`by` > 0) or fewer, at most `available`.
    pub fn step(&mut self, by: isize, available: usize) {
        if !self.on {
            self.on = true;
            self.shown = 0;
        }
        self.shown = self.shown.saturating_add_signed(by).min(available);
    }

    /// The onsets the stepped cobweb follows: θ of the first slip, then
    /// each next onset, `shown` iterates in all.
    pub fn onsets(&self, events: &[crate::sim::SlipEvent]) -> Vec<f64> {
        let Some(first) = events.first() else {
            return Vec::new();
        };
        std::iter::once(first.theta)
            .chain(events.iter().take(self.shown).map(|e| e.theta_next))
            .collect()
    }
}

/// The cobweb's step row in the return map.
pub fn cobweb_steps_ui(ui: &mut Ui, steps: &mut CobwebSteps, available: usize) {
    {
        ui.checkbox(&mut steps.on, "cobweb step by step")
            .on_hover_text(
                "Draw the cobweb from the first slip on, one iterate at a time: N adds one, \
             Shift+N takes one back, Play adds them at its speed.",
            );
        if steps.on {
            if ui
                .small_button("−")
                .on_hover_text("One iterate back (Shift+N)")
                .clicked()
            {
                steps.step(-1, available);
            }
            ui.label(format!("{} of {available}", steps.shown));
            if ui
                .small_button("+")
                .on_hover_text("One iterate more (N)")
                .clicked()
            {
                steps.step(1, available);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn theta_nu_plays_at_its_speed_and_turns_at_the_ends() {
        let mut s = Settings::default();
        s.params.theta_nu = 1.0;
        s.play_speed = 0.05;
        let mut p = Play::default();
        assert_eq!(p.tick(&s, (0.0, 1.2), false, 0.0), Tick::Nothing);
        p.toggle();
        assert_eq!(p.tick(&s, (0.0, 1.2), false, 10.0), Tick::Nothing);
        // 0.1 s at 0.05 rad/s.
        let Tick::ThetaNu(x) = p.tick(&s, (0.0, 1.2), false, 10.1) else {
            panic!("no θν")
        };
        assert!((x - 1.005).abs() < 1e-12, "{x}");
        // Past the end it turns: 1.19 + 0.005 × … reflected off 1.2.
        s.params.theta_nu = 1.198;
        let Tick::ThetaNu(x) = p.tick(&s, (0.0, 1.2), false, 10.2) else {
            panic!("no θν")
        };
        assert!((x - 1.197).abs() < 1e-12 && !p.forward, "{x}");
        // A stalled frame moves at most MAX_STEP's worth.
        s.params.theta_nu = 0.5;
        let Tick::ThetaNu(x) = p.tick(&s, (0.0, 1.2), false, 99.0) else {
            panic!("no θν")
        };
        assert!((x - (0.5 - 0.05 * MAX_STEP)).abs() < 1e-12, "{x}");
    }

    #[test]
    fn a_stepped_cobweb_takes_whole_iterates_from_the_clock() {
        let s = Settings {
            play_speed: 0.025,
            ..Settings::default()
        };
        let mut p = Play::default();
        p.toggle();
        p.tick(&s, (0.0, 1.0), true, 0.0);
        // 2.5 iterates a second: none in 0.1 s, then ticks add up.
        let mut n = 0;
        for i in 1..=40 {
            if let Tick::Iterates(k) = p.tick(&s, (0.0, 1.0), true, 0.1 * f64::from(i)) {
                n += k;
            }
        }
        assert_eq!(n, 10);
        let mut c = CobwebSteps::default();
        c.step(1, 3);
        c.step(5, 3);
        assert_eq!((c.on, c.shown), (true, 3));
        c.step(-1, 3);
        assert_eq!(c.shown, 2);
    }
}
