//! The one place where what the user asked for ([`Action`]) is applied
//! to the window's state: screenshots and exports, sessions, parameters
//! set from a plot, the jobs started and stopped.

use eframe::egui;
use egui::Context;

use super::explorer::Explorer;
use super::files::fresh_path;
use super::save;
use super::session::Session;
use super::settings::{Settings, ViewKind};
use super::svg_render;
#[cfg(not(target_arch = "wasm32"))]
use super::title_buttons::RECORD_FRAMES;
use super::view::Action;
use crate::sim::continuation::ContParam;

impl Explorer {
    /// Applies what the user asked for.
    pub(super) fn apply(&mut self, a: Action, ctx: &Context) {
        let now = self.now;
        match a {
            Action::Screenshot => {
                let path = fresh_path(&self.settings.save_dir, "window", "png");
                self.shots.request(ctx, path, None);
            }
            Action::ViewScreenshot(v) => {
                let path = fresh_path(&self.settings.save_dir, v.key(), "png");
                let crop = self.view_rects.get(&v).copied();
                self.shots.request(ctx, path, crop);
            }
            #[cfg(not(target_arch = "wasm32"))]
            Action::Record(v, speed) => {
                let fig = super::figure::Figure::record(v, self.settings.clone());
                let path = fresh_path(&self.settings.save_dir, v.key(), "gif");
                let make = move || super::animation::gif(&fig, RECORD_FRAMES, speed);
                self.shots.record(make, RECORD_FRAMES, path, self.now);
            }
            #[cfg(not(target_arch = "wasm32"))]
            Action::RecordPlay(v) => {
                let (fig, span) = self.played(v);
                let name = format!("{}-played", v.key());
                let path = fresh_path(&self.settings.save_dir, &name, "gif");
                let make = move || super::animation::play_gif(fig, span);
                self.shots.record(make, span.frames, path, self.now);
            }
            // In the browser a frame or so of the GIF per frame of the page.
            #[cfg(target_arch = "wasm32")]
            Action::Record(v, speed) => self.record_web(v, Some(speed)),
            #[cfg(target_arch = "wasm32")]
            Action::RecordPlay(v) => self.record_web(v, None),
            Action::SvgScreenshot(v) => self.svg_screenshot(v),
            Action::SaveSession => self.save_session(),
            Action::Export(what) => {
                save::export_csv(what, &self.settings, &self.jobs, &mut self.shots, now);
            }
            #[cfg(not(target_arch = "wasm32"))]
            Action::OpenSession => {
                self.open_dialog = Some(super::open_session::OpenDialog::new(
                    &self.settings.save_dir,
                ));
            }
            #[cfg(target_arch = "wasm32")]
            Action::OpenSession | Action::CopyLink => self.apply_web(a, ctx),
            Action::ResetDefaults => self.reset_defaults(),
            Action::RestartOrbit => self.jobs.restart_orbit(&self.settings, now),
            Action::SetThetaNu(x) => {
                let (lo, hi) = self.settings.theta_nu_range();
                self.settings.params.theta_nu = x.clamp(lo, hi);
            }
            Action::SetParam(ContParam::ThetaNu, x) => {
                self.apply(Action::SetThetaNu(x), ctx);
            }
            Action::SetParam(p, x) => self.set_param(p, x),
            Action::SetPoint { theta_nu, kappa } => self.set_point(theta_nu, kappa),
            Action::Start(kind) => {
                let shown = self.shown();
                self.jobs.start(kind, &self.settings, &shown);
            }
            Action::Stop(kind) => self.jobs.stop(kind),
            Action::Passage(near) => self.jobs.start_passage(self.settings.params, near),
        }
    }

    /// An SVG of view `v`, or of the tiles that had room on screen.
    fn svg_screenshot(&mut self, v: Option<ViewKind>) {
        let (views, what) = match v {
            Some(v) => (vec![v], v.key()),
            None => {
                // The tiles that had room on screen (tiles_shown_ui).
                let mut shown = svg_render::shown_views(&self.settings);
                if !self.view_rects.is_empty() {
                    shown.retain(|k| self.view_rects.contains_key(k));
                }
                (shown, "window")
            }
        };
        let area = self.views_area(&views);
        let svg = svg_render::render_svg(
            &views,
            &self.settings,
            &self.jobs,
            &self.views.bifurcation.zoom,
            area,
            false,
        );
        let path = fresh_path(&self.settings.save_dir, what, "svg");
        self.shots.write(path, svg.into_bytes());
    }

    /// Every setting back to its default but the save folder; the zoom
    /// cleared.
    fn reset_defaults(&mut self) {
        let dir = std::mem::take(&mut self.settings.save_dir);
        self.settings = Settings {
            save_dir: dir,
            ..Settings::default()
        };
        self.controls.resync();
        self.views.bifurcation.zoom.clear();
        self.views.bifurcation.invalidate();
    }

    /// The diagram's parameter `p` set to `x`: within the diagram's range,
    /// and only where the model is.
    fn set_param(&mut self, p: ContParam, x: f64) {
        let (lo, hi) = self.settings.sweep_range();
        let params = p.set(&self.settings.params, x.clamp(lo, hi));
        if params.validate().is_ok() {
            self.settings.params = params;
        }
    }

    /// θν and κ from a click on the phase diagram (the full circle shown
    /// if θν is outside [0, π/2]).
    fn set_point(&mut self, theta_nu: f64, kappa: f64) {
        let p = &mut self.settings.params;
        (p.theta_nu, p.kappa) = (theta_nu, kappa);
        if !(0.0..=std::f64::consts::FRAC_PI_2).contains(&theta_nu) {
            self.settings.full_circle = true;
        }
    }

    /// Save session: the settings, the diagram's zoom and the results a
    /// session keeps, written into the save folder under a fresh name.
    fn save_session(&mut self) {
        let s = Session {
            settings: self.settings.clone(),
            bifurcation_zoom: self.views.bifurcation.zoom.clone(),
            results: self.jobs.results_to_keep(&self.settings),
        };
        let path = fresh_path(&self.settings.save_dir, "session", "json");
        let (text, left_out) = s.to_file_text();
        if let Some(m) = left_out {
            self.shots.toast(m, true, self.now);
        }
        self.shots.write(path, text.into_bytes());
    }
}
