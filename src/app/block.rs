//! The teaching view: the paper's Fig. 1a, animated from the trajectory the
//! worker streamed. Seen from above: the block, its two springs to their
//! walls (k_x horizontal, k_y vertical), the rough surface sliding at V
//! under it, and the elastic and friction forces as arrows. Stick phases are
//! fast-forwarded and slips slowed down so that every slip can be watched.
//! Nothing is integrated here: positions are interpolated between samples,
//! and the friction is read off the equations of motion at that state.

use eframe::egui;
use egui::{Align2, Color32, FontId, Pos2, Rect, Sense, Stroke, Ui, pos2, vec2};

use super::jobs::Jobs;
use super::settings::{Settings, ViewKind};
use super::style;
use super::view::{Action, View};
use crate::sim::field::SlipField;
use crate::sim::{Phase, Sample};

/// Real seconds a stick phase takes on screen, whatever its length.
const STICK_SECONDS: f64 = 0.6;

/// The playback clock the block view (and an animation's frames) runs
/// on: model time advanced by real seconds, stick phases fast-forwarded
/// to [`STICK_SECONDS`] each, slips at a speed in time units per second.
#[derive(Clone, Copy, Debug, Default)]
pub struct Playback {
    /// The model time on screen.
    pub clock: f64,
}

impl Playback {
    /// Advances the clock by `dt` real seconds of playback at `speed`
    /// (slip time units per second), looping over the samples from
    /// `window_start`.
    pub fn advance(&mut self, samples: &[Sample], window_start: f64, dt: f64, speed: f64) {
        let Some(last) = samples.last() else { return };
        if self.clock < window_start || self.clock > last.t {
            self.clock = window_start;
        }
        let i = samples.partition_point(|s| s.t <= self.clock).max(1);
        let seg = (samples.get(i - 1), samples.get(i));
        let rate = match seg {
            (Some(a), Some(b)) if a.phase == Phase::Stick => (b.t - a.t) / STICK_SECONDS,
            _ => speed,
        };
        self.clock += dt * rate.max(1e-6);
        if self.clock >= last.t {
            // Loop over the cycles on screen (the trajectory may still grow).
            self.clock = window_start;
        }
    }
}

/// Playback state.
pub struct BlockView {
    pub playing: bool,
    clock: Playback,
    last_frame: Option<f64>,
    /// Draw x displacements ×κ so the stiff spring's motion is visible.
    pub magnify_x: bool,
    trajectory_revision_seen: u64,
}

impl Default for BlockView {
    fn default() -> Self {
        BlockView {
            playing: true,
            clock: Playback::default(),
            last_frame: None,
            magnify_x: true,
            trajectory_revision_seen: 0,
        }
    }
}

/// The block's state at model time t, interpolated between samples, with
/// the phase of the segment it lies on.
pub fn state_at(samples: &[Sample], t: f64) -> Option<(Sample, bool)> {
    if samples.is_empty() {
        return None;
    }
    let i = samples.partition_point(|s| s.t <= t);
    if i == 0 {
        return Some((samples[0], samples[0].phase == Phase::Stick));
    }
    if i >= samples.len() {
        let l = *samples.last()?;
        return Some((l, l.phase == Phase::Stick));
    }
    let (a, b) = (samples[i - 1], samples[i]);
    let f = if b.t > a.t {
        (t - a.t) / (b.t - a.t)
    } else {
        0.0
    };
    let lerp = |p: f64, q: f64| p + (q - p) * f;
    let stick = a.phase == Phase::Stick;
    Some((
        Sample {
            t,
            x: lerp(a.x, b.x),
            y: lerp(a.y, b.y),
            u: lerp(a.u, b.u),
            w: lerp(a.w, b.w),
            phase: if stick { Phase::Stick } else { b.phase },
        },
        stick,
    ))
}

/// The friction force on the block: during stick it balances the spring;
/// during a slip it is the equations' acceleration minus the elastic force.
pub fn friction(field: &SlipField, s: &Sample) -> [f64; 2] {
    let fel = [-field.kappa * s.x, -s.y];
    match s.phase {
        Phase::Stick => [-fel[0], -fel[1]],
        _ => {
            let vr = [s.u - field.v[0], s.w - field.v[1]];
            if vr[0].hypot(vr[1]) < 1e-14 {
                return [-fel[0], -fel[1]];
            }
            let st = [s.x, s.y, vr[0], vr[1]];
            let d = if s.phase == Phase::Accel {
                field.accel(&st)
            } else {
                field.decel(&st)
            };
            [d[2] - fel[0], d[3] - fel[1]]
        }
    }
}

impl BlockView {
    /// Advances the clock by one frame's worth of playback.
    fn advance(&mut self, samples: &[Sample], window_start: f64, now: f64, speed: f64) {
        let dt = self.last_frame.map_or(0.0, |l| (now - l).clamp(0.0, 0.1));
        self.last_frame = Some(now);
        let dt = if self.playing { dt } else { 0.0 };
        self.clock.advance(samples, window_start, dt, speed);
    }

    fn show(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs) {
        let samples = &jobs.trajectory.data.samples;
        if jobs.trajectory_revision < self.trajectory_revision_seen {
            self.clock = Playback::default();
        }
        self.trajectory_revision_seen = jobs.trajectory_revision;
        let start = jobs.trajectory.data.recent_start(s.keep_cycles.min(4));
        let window_start = samples.get(start).map_or(0.0, |p| p.t);
        let now = ui.input(|i| i.time);
        self.advance(samples, window_start, now, s.block_speed as f64);
        if self.playing && !samples.is_empty() {
            ui.ctx().request_repaint();
        }
        self.scene_ui(ui, s, samples);
    }

    /// Play / pause, the playback speed, the x magnification.
    fn buttons_ui(&mut self, ui: &mut Ui, s: &mut Settings) {
        ui.horizontal_wrapped(|ui| {
            let label = if self.playing { "Pause" } else { "Play" };
            if ui.button(label).on_hover_text("Space").clicked() {
                self.playing = !self.playing;
            }
            ui.add(
                egui::Slider::new(&mut s.block_speed, 0.1..=10.0)
                    .logarithmic(true)
                    .text("slip speed"),
            )
            .on_hover_text(
                "Time units per second during slips. Stick phases, which last about 1/ν, \
                 are fast-forwarded to 0.6 s each.",
            );
            ui.checkbox(&mut self.magnify_x, "x stretched ×κ")
                .on_hover_text("The x spring is κ times stiffer, so its stretch is κ times smaller: magnify it to see it.");
        });
    }

    /// The block on the moving surface at the clock's time.
    fn scene_ui(&self, ui: &mut Ui, s: &Settings, samples: &[Sample]) {
        let (rect, _) = ui.allocate_exact_size(ui.available_size(), Sense::hover());
        let painter = ui.painter_at(rect);
        let dark = s.dark;
        let ink = style::ink(dark);
        let bg = if dark {
            Color32::from_gray(35)
        } else {
            Color32::from_gray(245)
        };
        painter.rect_filled(rect, 4.0, bg);

        let Some((st, stick)) = state_at(samples, self.clock.clock) else {
            centred_note(
                &painter,
                rect,
                "waiting for the trajectory…",
                18.0 * s.font_scale,
                ink,
            );
            return;
        };
        let p = s.params;
        // Geometry: rest position at the centre; y up on screen.
        let unit = rect.height().min(rect.width()) * 0.28;
        if unit < MIN_UNIT {
            // A tile with no room left under its controls (large text, many
            // tiles): a word instead of a scene drawn at no size.
            centred_note(
                &painter,
                rect,
                "no room: enlarge the tile",
                12.0 * s.font_scale,
                ink,
            );
            return;
        }
        let sx = if self.magnify_x {
            unit * p.kappa as f32
        } else {
            unit
        };
        let centre = rect.center() + vec2(unit * 0.3, -unit * 0.1);
        let scene = Scene {
            painter,
            rect,
            unit,
            block_at: centre + vec2(st.x as f32 * sx, -(st.y as f32) * unit),
            half: unit * 0.22,
            ink,
            dark,
            text_scale: style::text_scale(ui),
        };
        scene.surface(&p, st.t);
        scene.walls_and_springs();
        let fill = style::phase_color(st.phase);
        scene.block_and_forces(&p, &st, fill);
        let phase = if stick {
            "STICK: the block rides with the surface"
        } else if st.phase == Phase::Accel {
            "SLIP: accelerating (friction weakens)"
        } else {
            "SLIP: decelerating to a stop"
        };
        scene.legend(phase, fill, st.t);
        if self.magnify_x {
            put_text(
                &scene.painter,
                rect,
                pos2(rect.left() + unit * 0.5, rect.bottom() - 8.0),
                Align2::LEFT_BOTTOM,
                format!("x displacements magnified ×κ = {:.3}", p.kappa),
                scene.font(13.0),
                ink,
            );
        }
    }
}

/// A word in the middle of `rect`, in place of the scene.
fn centred_note(painter: &egui::Painter, rect: Rect, text: &str, size: f32, ink: Color32) {
    put_text(
        painter,
        rect,
        rect.center(),
        Align2::CENTER_CENTER,
        text,
        FontId::proportional(size),
        ink,
    );
}

/// The least length unit (screen points per unit of displacement) the
/// scene is drawn at; below it the tile says it has no room.
const MIN_UNIT: f32 = 8.0;

/// The least distance between the surface's stripes, in points.
const MIN_STRIPE_SPACING: f32 = 2.0;

/// Where the block view draws: its rect, its length unit (screen points per
/// unit of displacement), the block's centre and half size.
struct Scene {
    painter: egui::Painter,
    rect: Rect,
    unit: f32,
    block_at: Pos2,
    half: f32,
    ink: Color32,
    dark: bool,
    /// The window's text size multiplier.
    text_scale: f32,
}

impl Scene {
    /// A font of `size` points at the window's text size.
    fn font(&self, size: f32) -> FontId {
        FontId::proportional(size * self.text_scale)
    }

    /// The rough surface at time `t`: stripes across V moving with it, and
    /// its velocity arrow.
    fn surface(&self, p: &crate::model::Params, t: f64) {
        let (painter, rect, unit, dark) = (&self.painter, self.rect, self.unit, self.dark);
        // The rough surface: stripes across V moving with it.
        let surf = Rect::from_min_max(
            pos2(rect.left() + unit * 0.45, rect.top() + 8.0),
            pos2(rect.right() - 8.0, rect.bottom() - unit * 0.45),
        );
        painter.rect_filled(
            surf,
            6.0,
            if dark {
                Color32::from_gray(55)
            } else {
                Color32::from_rgb(232, 226, 210)
            },
        );
        let (sn, cs) = (p.theta_nu.sin() as f32, p.theta_nu.cos() as f32);
        let dir = vec2(cs, -sn);
        let normal = vec2(sn, cs);
        // At least MIN_STRIPE_SPACING apart, so the stripes are at most the
        // surface's diagonal over that: at a spacing of 0 (a tile with no
        // room) this loop once never ended, filling memory.
        let spacing = (unit * 0.25).max(MIN_STRIPE_SPACING);
        let travel = (p.nu * t) as f32 * unit;
        let offset = travel.rem_euclid(spacing);
        let offset = if offset.is_finite() { offset } else { 0.0 };
        let diag = surf.size().length();
        let stripe = if dark {
            Color32::from_gray(75)
        } else {
            Color32::from_rgb(205, 195, 170)
        };
        let mut k = -(diag / spacing) as i32 - 1;
        while (k as f32) * spacing < diag {
            let c = surf.center() + dir * (k as f32 * spacing + offset);
            let a = c + normal * diag;
            let b = c - normal * diag;
            clip_line(painter, surf, a, b, Stroke::new(3.0, stripe));
            k += 1;
        }
        // Surface velocity arrow.
        let v_from = pos2(surf.right() - unit * 0.9, surf.bottom() - unit * 0.55);
        arrow(
            painter,
            v_from,
            dir * unit * 0.6,
            Stroke::new(3.0, style::PULL),
        );
        put_text(
            painter,
            rect,
            v_from + dir * unit * 0.6 + vec2(4.0, -4.0),
            Align2::LEFT_BOTTOM,
            "V (surface)",
            self.font(15.0),
            style::PULL,
        );
    }

    /// The two walls and the springs from them to the block.
    fn walls_and_springs(&self) {
        let (painter, rect, unit, ink) = (&self.painter, self.rect, self.unit, self.ink);
        let (block_at, half) = (self.block_at, self.half);
        // Walls and springs.
        let wall_x = rect.left() + unit * 0.25;
        let wall_y = rect.bottom() - unit * 0.25;
        let wall = Stroke::new(4.0, ink);
        painter.line_segment(
            [
                pos2(wall_x, rect.top() + 10.0),
                pos2(wall_x, rect.bottom() - 10.0),
            ],
            wall,
        );
        painter.line_segment(
            [
                pos2(rect.left() + 10.0, wall_y),
                pos2(rect.right() - 10.0, wall_y),
            ],
            wall,
        );
        spring(
            painter,
            pos2(wall_x, block_at.y),
            pos2(block_at.x - half, block_at.y),
            10,
            unit * 0.08,
            Stroke::new(2.5, ink),
        );
        spring(
            painter,
            pos2(block_at.x, wall_y),
            pos2(block_at.x, block_at.y + half),
            10,
            unit * 0.08,
            Stroke::new(2.5, ink),
        );
        put_text(
            painter,
            rect,
            pos2(wall_x + 6.0, block_at.y - unit * 0.12),
            Align2::LEFT_BOTTOM,
            "kx = κ",
            self.font(15.0),
            ink,
        );
        put_text(
            painter,
            rect,
            pos2(block_at.x + unit * 0.1, wall_y - 6.0),
            Align2::LEFT_BOTTOM,
            "ky = 1",
            self.font(15.0),
            ink,
        );
    }

    /// The block, coloured by phase, with the elastic and friction forces
    /// (|F| ≤ about 1 on C) drawn at it.
    fn block_and_forces(&self, p: &crate::model::Params, st: &Sample, fill: Color32) {
        let (painter, unit, ink) = (&self.painter, self.unit, self.ink);
        let (block_at, half) = (self.block_at, self.half);
        let field = SlipField::new(p);
        // The block, coloured by phase.
        painter.rect_filled(
            Rect::from_center_size(block_at, vec2(2.0 * half, 2.0 * half)),
            4.0,
            fill,
        );
        painter.rect_stroke(
            Rect::from_center_size(block_at, vec2(2.0 * half, 2.0 * half)),
            4.0,
            Stroke::new(2.0, ink),
            egui::StrokeKind::Inside,
        );

        // Forces (|F| ≤ about 1 on C), drawn at the block.
        let fel = [-p.kappa * st.x, -st.y];
        let ffr = friction(&field, st);
        let fscale = unit * 0.9;
        let to_screen = |f: [f64; 2]| vec2(f[0] as f32, -(f[1] as f32)) * fscale;
        arrow(
            painter,
            block_at,
            to_screen(fel),
            Stroke::new(3.5, style::STICK),
        );
        arrow(
            painter,
            block_at,
            to_screen(ffr),
            Stroke::new(3.5, style::ACCEL),
        );
    }

    /// What phase the block is in, the arrows' colours, and the time.
    fn legend(&self, phase: &str, fill: Color32, t: f64) {
        let (rect, ink) = (self.rect, self.ink);
        // Legend and state.
        let font = self.font(17.0);
        let mut y = rect.top() + 12.0;
        let x = rect.right() - 12.0;
        for (text, color) in [
            (phase.to_string(), fill),
            (
                "blue arrow: elastic force (springs)".to_string(),
                style::STICK,
            ),
            ("orange arrow: friction force".to_string(), style::ACCEL),
            (format!("t = {t:.1}"), ink),
        ] {
            let r = put_text(
                &self.painter,
                rect,
                pos2(x, y),
                Align2::RIGHT_TOP,
                text,
                font.clone(),
                color,
            );
            y = r.bottom() + 4.0;
        }
    }
}

/// Writes `text` anchored at `pos`, wrapped to the width of `bounds` and
/// moved inside it if it would stick out: a label is never clipped,
/// whatever the tile's size or the text size. Returns where it went.
#[allow(clippy::too_many_arguments)]
fn put_text(
    painter: &egui::Painter,
    bounds: Rect,
    pos: Pos2,
    align: Align2,
    text: impl ToString,
    font: FontId,
    color: Color32,
) -> Rect {
    let margin = 4.0;
    let galley = painter.layout(
        text.to_string(),
        font,
        color,
        (bounds.width() - 2.0 * margin).max(20.0),
    );
    let r = align.anchor_size(pos, galley.size());
    let inner = bounds.shrink(margin);
    let shift = |lo: f32, hi: f32, a: f32, b: f32| {
        if a < lo {
            lo - a
        } else if b > hi {
            (hi - b).max(lo - a)
        } else {
            0.0
        }
    };
    let r = r.translate(vec2(
        shift(inner.left(), inner.right(), r.left(), r.right()),
        shift(inner.top(), inner.bottom(), r.top(), r.bottom()),
    ));
    painter.galley(r.min, galley, color);
    r
}

/// An arrow from `from` along `v`.
fn arrow(painter: &egui::Painter, from: Pos2, v: egui::Vec2, stroke: Stroke) {
    if v.length() < 1.0 {
        return;
    }
    painter.arrow(from, v, stroke);
}

/// A zigzag spring from `a` to `b`.
fn spring(painter: &egui::Painter, a: Pos2, b: Pos2, coils: usize, width: f32, stroke: Stroke) {
    let d = b - a;
    let len = d.length().max(1.0);
    let t = d / len;
    let n = vec2(-t.y, t.x);
    let lead = (len * 0.1).min(12.0);
    let mut pts = vec![a, a + t * lead];
    let body = len - 2.0 * lead;
    for i in 0..(2 * coils) {
        let f = (i as f32 + 0.5) / (2 * coils) as f32;
        let side = if i % 2 == 0 { 1.0 } else { -1.0 };
        pts.push(a + t * (lead + body * f) + n * width * side);
    }
    pts.push(b - t * lead);
    pts.push(b);
    painter.add(egui::Shape::line(pts, stroke));
}

/// A segment clipped to `r` (Liang–Barsky), for the surface stripes.
fn clip_line(painter: &egui::Painter, r: Rect, a: Pos2, b: Pos2, stroke: Stroke) {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    for (p, q) in [
        (-d.x, a.x - r.left()),
        (d.x, r.right() - a.x),
        (-d.y, a.y - r.top()),
        (d.y, r.bottom() - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    if t0 < t1 {
        painter.line_segment([a + d * t0, a + d * t1], stroke);
    }
}

impl View for BlockView {
    fn title(&self) -> &'static str {
        ViewKind::Block.title()
    }

    fn controls_ui(&mut self, ui: &mut Ui, s: &mut Settings, _jobs: &Jobs, _out: &mut Vec<Action>) {
        self.buttons_ui(ui, s);
    }

    fn ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, _out: &mut Vec<Action>) {
        self.show(ui, s, jobs);
    }
}
