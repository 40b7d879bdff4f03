//! The side panel: sliders with typed value fields, method and tolerance,
//! the regime badge and the "what you are seeing" line, presets, and the
//! buttons that act on the window (screenshot, export, reset).
//!
//! Typed values reach [`Settings`] only once they parse and validate; an
//! invalid one stays in its field, in red, with the valid range under it.

use eframe::egui;
use std::f64::consts::{FRAC_PI_2, PI};
use std::ops::RangeInclusive;

use egui::{Color32, RichText, Slider, SliderClamping, TextEdit, Ui};

mod fine_step;
mod sweep;
mod view_options;

use view_options::view_options_ui;

use super::accuracy;
use super::describe;
use super::jobs::Jobs;
use super::play::{Play, play_ui};
use super::settings::{AccuracyMode, Settings};
use super::style;
use super::view::{Action, Export};
use crate::integrate::{Method, SolverSettings};
use crate::model::PRESETS;
use crate::model::{Regime, validity};

/// The numeric fields of the panel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    Kappa,
    Gamma,
    ThetaNu,
    Nu,
    Omega,
    Tol,
    Step,
}

impl Field {
    pub const PARAMS: [Field; 5] = [
        Field::Kappa,
        Field::Gamma,
        Field::ThetaNu,
        Field::Nu,
        Field::Omega,
    ];

    /// The symbol shown as the slider's label (and its accessible name).
    pub fn symbol(self) -> &'static str {
        match self {
            Field::Kappa => "κ",
            Field::Gamma => "γ",
            Field::ThetaNu => "θν",
            Field::Nu => "ν",
            Field::Omega => "Ω",
            Field::Tol => "tolerance",
            Field::Step => "step h",
        }
    }

    /// The hover text: what the parameter means physically.
    pub fn hover(self) -> &'static str {
        match self {
            Field::Kappa => {
                "κ = kx/ky (paper: κ): anisotropy of the two springs holding the block. \
                 κ = 1 is isotropic; a large κ makes the x spring stiff, so the curve C \
                 (κ²x² + y² = 1) becomes a thin ellipse. Slider 0.1–100; type any value in [1e-6, 1e3] (beyond, slips turn into steady sliding)."
            }
            Field::Gamma => {
                "γ = 1/(2ν_f) (paper: γ): how fast friction weakens as the block speeds up \
                 (velocity weakening). γ² < min(1, κ): only creep; γ² > max(1, κ): only \
                 stick-slip earthquakes; in between, both (mixed regime). The paper uses 6.5. \
                 Type any value in [0.1, 1e4] (outside, slips never stop)."
            }
            Field::ThetaNu => {
                "θν (paper: θ_ν): the direction, in radians from the x axis, in which the \
                 rough surface (the tectonic plate) is dragged. The horizontal axis of the \
                 bifurcation diagram."
            }
            Field::Nu => {
                "ν (paper: ν): the pulling speed of the surface, tiny next to slip speeds. \
                 It sets how long the block sticks between slips (about 1/ν time units). \
                 The paper uses 1e-3 and 1e-4. \
                 Type any value in [1e-12, 0.1] (beyond, slips turn into steady sliding)."
            }
            Field::Omega => {
                "Ω (paper: Ω): the memory of the friction's direction: how quickly, once \
                 slipping, friction turns to oppose the relative velocity. The paper uses 50."
            }
            Field::Tol => {
                "Relative and absolute tolerance of the adaptive Runge–Kutta methods \
                 (dop853, dp54): smaller is more accurate and slower. Valid: [1e-14, 1e-2]."
            }
            Field::Step => "Fixed step h of rk4 and euler, in time units. Valid: (0, 1].",
        }
    }

    fn slider_range(self, full_circle: bool) -> RangeInclusive<f64> {
        match self {
            Field::Kappa => 0.1..=100.0,
            Field::Gamma => 0.1..=10.0,
            Field::ThetaNu if full_circle => -PI..=PI,
            Field::ThetaNu => 0.0..=FRAC_PI_2,
            Field::Nu => 1e-6..=1e-1,
            Field::Omega => 1.0..=1000.0,
            Field::Tol => 1e-14..=1e-2,
            Field::Step => 1e-5..=1.0,
        }
    }

    /// The value a fine move of `fraction` of the rail makes from `v`: a
    /// tenth of what the slider would (shift-drag, shift+arrow), along
    /// its scale (a log rail multiplies).
    pub fn fine_value(self, v: f64, fraction: f64, full_circle: bool) -> f64 {
        let r = self.slider_range(full_circle);
        let (lo, hi) = (*r.start(), *r.end());
        let f = fraction / FINE;
        if self.logarithmic() && v > 0.0 {
            v * (hi / lo).powf(f)
        } else {
            v + (hi - lo) * f
        }
    }

    fn logarithmic(self) -> bool {
        matches!(
            self,
            Field::Kappa | Field::Nu | Field::Omega | Field::Tol | Field::Step
        )
    }

    pub fn get(self, s: &Settings) -> f64 {
        match self {
            Field::Kappa => s.params.kappa,
            Field::Gamma => s.params.gamma,
            Field::ThetaNu => s.params.theta_nu,
            Field::Nu => s.params.nu,
            Field::Omega => s.params.omega,
            Field::Tol => s.tol,
            Field::Step => s.step,
        }
    }

    fn set(self, s: &mut Settings, v: f64) {
        match self {
            Field::Kappa => s.params.kappa = v,
            Field::Gamma => s.params.gamma = v,
            Field::ThetaNu => s.params.theta_nu = v,
            Field::Nu => s.params.nu = v,
            Field::Omega => s.params.omega = v,
            Field::Tol => s.tol = v,
            Field::Step => s.step = v,
        }
    }

    /// Checks a typed value; the error names the symbol and the valid range.
    pub fn validate(self, s: &Settings, v: f64) -> Result<(), String> {
        let mut t = s.clone();
        self.set(&mut t, v);
        match self {
            Field::Tol | Field::Step => {
                let m = if self == Field::Tol {
                    Method::Dop853
                } else {
                    Method::Rk4
                };
                let solver = if self == Field::Tol {
                    SolverSettings::adaptive(m, v)
                } else {
                    SolverSettings::fixed(m, v)
                };
                solver
                    .validate()
                    .map_err(|e| format!("{} {}", self.symbol(), e.range))
            }
            _ => t
                .params
                .validate()
                .map_err(|e| format!("{} {}", self.symbol(), e.range)),
        }
    }

    fn format(self, v: f64) -> String {
        match self {
            Field::Nu | Field::Tol | Field::Step => format!("{v:e}"),
            _ => format!("{}", (v * 1e6).round() / 1e6),
        }
    }
}

/// How much finer a shift-drag or shift+arrow moves a slider.
pub const FINE: f64 = 10.0;

/// What every slider's hover says about moving it finely.
pub const FINE_HELP: &str = "Shift-drag, or Shift+←/→ once clicked, moves the slider ten times finer; \
     ←/→ alone move it one step. κ, ν, Ω and the tolerance slide on a log scale: they span decades.";

/// A typed value field: its text, and the error when it does not validate.
#[derive(Clone, Debug, Default)]
pub struct FieldInput {
    pub text: String,
    pub error: Option<String>,
    /// The value the text was last synchronised from.
    shown: Option<f64>,
}

/// The panel's own state: the typed fields.
#[derive(Clone, Debug, Default)]
pub struct Controls {
    pub inputs: Vec<(Field, FieldInput)>,
    /// OpenGL is a software rasteriser: "smooth lines" Auto means off.
    pub software_gl: bool,
}

impl Controls {
    pub fn new() -> Self {
        let mut inputs: Vec<(Field, FieldInput)> = Field::PARAMS
            .iter()
            .map(|&f| (f, FieldInput::default()))
            .collect();
        inputs.push((Field::Tol, FieldInput::default()));
        inputs.push((Field::Step, FieldInput::default()));
        Controls {
            inputs,
            software_gl: false,
        }
    }

    /// The error shown under `field`, if any.
    pub fn error(&self, field: Field) -> Option<&str> {
        self.inputs
            .iter()
            .find(|(f, _)| *f == field)
            .and_then(|(_, i)| i.error.as_deref())
    }

    /// The whole panel: sections that collapse (egui remembers which, by
    /// their titles), inside the window's scroll area.
    pub fn ui(
        &mut self,
        ui: &mut Ui,
        s: &mut Settings,
        jobs: &Jobs,
        play: &mut Play,
        out: &mut Vec<Action>,
    ) {
        // The slider shrinks with the panel, leaving room for the typed
        // field (about 7 characters) and the symbol.
        let field_w = 7.5 * ui.text_style_height(&egui::TextStyle::Body);
        ui.spacing_mut().slider_width = (ui.available_width() - field_w - 40.0).clamp(60.0, 150.0);
        validity_ui(ui, s);
        section(ui, "Parameters", |ui| self.parameters_ui(ui, s, play));
        section(ui, "Accuracy", |ui| {
            accuracy::mode_ui(ui, s);
            if s.accuracy == AccuracyMode::Custom {
                self.custom_solver_ui(ui, s);
            }
            accuracy::estimates_ui(ui, s);
        });
        section(ui, "Regime", |ui| regime_ui(ui, s, jobs));
        section(ui, "Presets", |ui| self.presets_ui(ui, s));
        section(ui, "View", |ui| view_options_ui(ui, s, self.software_gl));
        section(ui, "Files", |ui| files_ui(ui, s, out));
    }

    /// The model's parameters, each a slider with a typed field.
    fn parameters_ui(&mut self, ui: &mut Ui, s: &mut Settings, play: &mut Play) {
        for field in Field::PARAMS {
            self.field_row(ui, s, field);
            if field == Field::ThetaNu {
                fine_step::fine_step_ui(ui, s);
                let was = s.full_circle;
                ui.checkbox(&mut s.full_circle, "full circle for θν")
                    .on_hover_text(
                        "Let θν take any direction (−π … π) instead of the paper's 0 … π/2; \
                         the bifurcation diagram follows.",
                    );
                if was != s.full_circle && !s.full_circle {
                    s.params.theta_nu = s.params.theta_nu.clamp(0.0, FRAC_PI_2);
                }
                play_ui(ui, play, s);
            }
        }
    }

    /// One button per preset.
    fn presets_ui(&mut self, ui: &mut Ui, s: &mut Settings) {
        for p in &PRESETS {
            let r = ui
                .add(egui::Button::new(p.label).wrap())
                .on_hover_text(format!(
                    "κ = {}, γ = {}, ν = {:e}, θν = {}, Ω = {}   (--preset {})",
                    p.params.kappa,
                    p.params.gamma,
                    p.params.nu,
                    p.params.theta_nu,
                    p.params.omega,
                    p.key
                ));
            if r.clicked() {
                s.apply_preset(&p.params, p.key);
                self.clear_errors();
            }
        }
    }
}

/// A section of the panel under a heading that collapses; open at first.
fn section(ui: &mut Ui, title: &str, body: impl FnOnce(&mut Ui)) {
    egui::CollapsingHeader::new(RichText::new(title).heading())
        .id_salt(("panel", title))
        .default_open(true)
        .show(ui, body);
}

/// A warning above everything when the parameters leave the model's
/// physical assumptions (`model::validity`): the results are still
/// computed, but are not those of a slowly pulled block.
pub fn validity_ui(ui: &mut Ui, s: &Settings) {
    let warnings = validity(&s.params);
    if warnings.is_empty() {
        return;
    }
    egui::Frame::new()
        .fill(Color32::from_rgb(190, 40, 40))
        .corner_radius(6.0)
        .inner_margin(egui::Margin::symmetric(8, 4))
        .show(ui, |ui| {
            ui.label(
                RichText::new("Outside the model's validity")
                    .color(Color32::WHITE)
                    .strong(),
            );
            for w in &warnings {
                ui.label(RichText::new(w.to_string()).color(Color32::WHITE));
            }
        });
}

/// The projector preset: large text, thick lines, high contrast.
pub const PROJECTOR_FONT_SCALE: f32 = 1.5;

/// Screenshot, exports, the save folder, restart and reset.
#[cfg_attr(target_arch = "wasm32", allow(unused_variables))]
fn files_ui(ui: &mut Ui, s: &mut Settings, out: &mut Vec<Action>) {
    ui.horizontal_wrapped(|ui| {
        if ui
            .button("Save screenshot")
            .on_hover_text("A PNG of the window (Ctrl+S), or of one view (its PNG button).")
            .clicked()
        {
            out.push(Action::Screenshot);
        }
        if ui
            .button("SVG")
            .on_hover_text(
                "A vector picture (SVG) of the views shown: lines as paths, text as text.",
            )
            .clicked()
        {
            out.push(Action::SvgScreenshot(None));
        }
        if ui
            .button("Save session")
            .on_hover_text(
                "Parameters, accuracy, views and zoom as a JSON file, with the branches of \
                 Find bifurcations and the curves of Boundaries when they are shown: reopen \
                 it with Open session… or `oneblock gui --session FILE`.",
            )
            .clicked()
        {
            out.push(Action::SaveSession);
        }
        #[cfg(not(target_arch = "wasm32"))]
        if ui
            .button("Open session…")
            .on_hover_text(
                "A session saved before: its parameters, views, zoom and kept results \
                 replace the window's (the save folder stays).",
            )
            .clicked()
        {
            out.push(Action::OpenSession);
        }
        #[cfg(target_arch = "wasm32")]
        super::web::files_ui(ui, out);
        ui.menu_button("Export data", |ui| {
            if ui.button("Events CSV").clicked() {
                out.push(Action::Export(Export::Events));
            }
            if ui.button("Trajectory CSV (t,x,y,u,w,phase)").clicked() {
                out.push(Action::Export(Export::Trajectory));
            }
            if ui
                .button("Bifurcation CSV (theta_nu,theta,lyapunov,…)")
                .clicked()
            {
                out.push(Action::Export(Export::Bifurcation));
            }
            if ui.button("Phase diagram CSV (oneblock phase)").clicked() {
                out.push(Action::Export(Export::Phase));
            }
        });
    });
    // The browser chooses where downloads go.
    #[cfg(not(target_arch = "wasm32"))]
    ui.horizontal_wrapped(|ui| {
        ui.label("folder");
        ui.add(TextEdit::singleline(&mut s.save_dir).desired_width(f32::INFINITY))
            .on_hover_text(
                "Screenshots and exports go here, named with the time; \
                     an existing file is never overwritten.",
            );
    });
    ui.horizontal_wrapped(|ui| {
        if ui
            .button("Restart orbit")
            .on_hover_text("Start the trajectory again from θ = θν (R).")
            .clicked()
        {
            out.push(Action::RestartOrbit);
        }
        if ui
            .button("Reset to defaults")
            .on_hover_text("Every parameter and view choice back to the first-launch demo.")
            .clicked()
        {
            out.push(Action::ResetDefaults);
        }
    });
}

impl Controls {
    /// Custom's method and tolerance (or step), used by every job.
    fn custom_solver_ui(&mut self, ui: &mut Ui, s: &mut Settings) {
        ui.horizontal(|ui| {
            ui.label("method");
            egui::ComboBox::from_id_salt("method")
                .selected_text(s.method.name())
                .show_ui(ui, |ui| {
                    for m in Method::ALL {
                        ui.selectable_value(&mut s.method, m, m.name());
                    }
                })
                .response
                .on_hover_text(
                    "How each slip is integrated: dop853 (Dormand–Prince 8, default), dp54, \
                     or the fixed-step rk4 and euler (euler is kept as the method that fails).",
                );
        });
        if s.method.is_adaptive() {
            self.field_row(ui, s, Field::Tol);
        } else {
            self.field_row(ui, s, Field::Step);
        }
    }

    fn clear_errors(&mut self) {
        for (_, i) in &mut self.inputs {
            i.error = None;
            i.shown = None;
        }
    }

    /// Called when settings changed behind the panel's back (reset).
    pub fn resync(&mut self) {
        self.clear_errors();
    }

    /// One parameter: slider, typed field, error line.
    fn field_row(&mut self, ui: &mut Ui, s: &mut Settings, field: Field) {
        let Some(idx) = self.inputs.iter().position(|(f, _)| *f == field) else {
            return;
        };
        let current = field.get(s);
        ui.horizontal(|ui| {
            let mut v = current;
            let slider = Slider::new(&mut v, field.slider_range(s.full_circle))
                .logarithmic(field.logarithmic())
                .clamping(SliderClamping::Never)
                .show_value(false)
                .text(field.symbol());
            let r = ui
                .add(slider)
                .on_hover_text(format!("{}\n\n{FINE_HELP}", field.hover()));
            if let Some(fine) = fine_move(ui, &r) {
                v = field.fine_value(current, fine, s.full_circle);
            }
            if v != current && field.validate(s, v).is_ok() {
                field.set(s, v);
                let input = &mut self.inputs[idx].1;
                input.error = None;
                input.shown = None;
            }

            let value_now = field.get(s);
            let input = &mut self.inputs[idx].1;
            let te_id = ui.make_persistent_id(("typed", field.symbol()));
            let editing = ui.memory(|m| m.has_focus(te_id));
            if !editing && input.error.is_none() && input.shown != Some(value_now) {
                input.text = field.format(value_now);
                input.shown = Some(value_now);
            }
            let color = input.error.as_ref().map(|_| Color32::from_rgb(220, 30, 30));
            let mut te = TextEdit::singleline(&mut input.text)
                .id(te_id)
                .desired_width(84.0);
            if let Some(c) = color {
                te = te.text_color(c);
            }
            let label = format!("{} value", field.symbol());
            let r = ui
                .add(te)
                .accessible_name(label)
                .on_hover_text(field.hover());
            if r.changed() {
                match input.text.trim().parse::<f64>() {
                    Ok(x) => match field.validate(s, x) {
                        Ok(()) => {
                            input.error = None;
                            input.shown = Some(x);
                            field.set(s, x);
                        }
                        Err(e) => input.error = Some(e),
                    },
                    Err(_) => {
                        input.error = Some(format!("{}: not a number", field.symbol()));
                    }
                }
            }
        });
        if let Some(e) = &self.inputs[idx].1.error {
            ui.label(RichText::new(e).color(Color32::from_rgb(220, 30, 30)));
        }
    }
}

/// With Shift held, the part of the rail the pointer's drag (or an arrow
/// key, one point) moved this frame; `None` without Shift or a move.
fn fine_move(ui: &Ui, r: &egui::Response) -> Option<f64> {
    let (shift, left, right) = ui.input(|i| {
        (
            i.modifiers.shift,
            i.num_presses(egui::Key::ArrowLeft),
            i.num_presses(egui::Key::ArrowRight),
        )
    });
    let width = f64::from(ui.spacing().slider_width.max(1.0));
    if !shift {
        None
    } else if r.is_pointer_button_down_on() {
        Some(f64::from(r.drag_delta().x) / width)
    } else if r.has_focus() && left + right > 0 {
        Some((right as f64 - left as f64) / width)
    } else {
        None
    }
}

/// The regime badge, θc, and the plain-words line.
fn regime_ui(ui: &mut Ui, s: &Settings, jobs: &Jobs) {
    let (k, g) = (s.params.kappa, s.params.gamma);
    let (fill, text) = match Regime::of(k, g) {
        Regime::PureCreep => (Color32::from_rgb(40, 130, 60), Color32::WHITE),
        Regime::Mixed { .. } => (Color32::from_rgb(200, 130, 20), Color32::BLACK),
        // Blue, not red: red is kept for warnings (the validity line).
        Regime::PureStickSlip => (style::STICK, Color32::WHITE),
    };
    let badge = describe::regime_badge(k, g);
    ui.horizontal(|ui| {
        ui.label("regime");
        egui::Frame::new()
            .fill(fill)
            .corner_radius(6.0)
            .inner_margin(egui::Margin::symmetric(8, 3))
            .show(ui, |ui| {
                ui.label(RichText::new(&badge).color(text).strong());
            })
            .response
            .on_hover_text(describe::regime_explanation(k, g));
    });
    let line = describe::attractor_line(
        k,
        g,
        &jobs.iterate.data.thetas,
        jobs.iterate.data.period,
        (
            jobs.iterate.data.lyapunov,
            jobs.iterate.data.lyapunov_stderr,
        ),
    );
    ui.label(RichText::new(line).italics());
}
