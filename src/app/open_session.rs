//! The desktop window's "Open session…": a small modal with the session
//! file's path, the save folder's latest sessions to pick from, and Open.
//! The file is read by the same loader as `oneblock gui --session`
//! ([`Session::read`]); a file it refuses keeps the modal open with the
//! reason in red and changes nothing.
//!
//! A path field rather than the system's file dialog: the `rfd` crate
//! would build here without system packages (its portal backend loads
//! libdbus at run time), but its dialog then needs a running
//! xdg-desktop-portal or zenity, which a plain X session (or Xvfb) lacks
//! and where it returns nothing without a word; it blocks the frame it is
//! called in; and it cannot be driven by the headless tests. The browser
//! has its own picker (src/app/web.rs).

use std::path::{Path, PathBuf};

use eframe::egui;
use egui::{Context, Id, RichText, TextEdit};

use super::session::{Loaded, Session};
use super::style;

/// How many of the save folder's sessions the modal lists.
const LISTED: usize = 6;

/// The modal's accessible name of the path field.
pub const PATH_LABEL: &str = "session file";

/// The modal while it is open: the path typed or picked, why the last
/// try failed, and the save folder's latest sessions.
#[derive(Clone, Debug, Default)]
pub struct OpenDialog {
    pub path: String,
    pub error: Option<String>,
    recent: Vec<PathBuf>,
}

/// What the user did in the modal this frame.
pub enum Outcome {
    /// A session was read: open it.
    Open(Box<Loaded>),
    /// Closed without opening anything.
    Close,
}

impl OpenDialog {
    /// The modal over the save folder `dir` (where Save session writes).
    pub fn new(dir: &str) -> Self {
        let dir = if dir.trim().is_empty() {
            "."
        } else {
            dir.trim()
        };
        let recent = latest_sessions(Path::new(dir));
        let path = recent.first().map_or_else(
            || format!("{}/", dir.trim_end_matches('/')),
            |p| p.display().to_string(),
        );
        OpenDialog {
            path,
            error: None,
            recent,
        }
    }

    /// Draws the modal; what the user did, if anything.
    pub fn ui(&mut self, ctx: &Context) -> Option<Outcome> {
        let mut out = None;
        let modal = egui::Modal::new(Id::unique("open session")).show(ctx, |ui| {
            ui.set_max_width(520.0);
            ui.heading("Open session");
            ui.label(
                "A file saved by Save session: its parameters, views, zoom and the \
                 branches and boundaries it kept.",
            );
            let r = ui.add(
                TextEdit::singleline(&mut self.path)
                    .desired_width(f32::INFINITY)
                    .hint_text("path/to/oneblock-session.json"),
            );
            let r = r.accessible_name(PATH_LABEL);
            let entered = r.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
            self.recent_ui(ui);
            if let Some(e) = &self.error {
                ui.label(RichText::new(e).color(style::ERROR));
            }
            ui.horizontal(|ui| {
                if ui.button("Open").clicked() || entered {
                    out = self.try_open();
                }
                if ui.button("Cancel").clicked() {
                    out = Some(Outcome::Close);
                }
            });
        });
        if out.is_none() && modal.should_close() {
            out = Some(Outcome::Close);
        }
        out
    }

    /// The save folder's latest sessions, a click putting one in the field.
    fn recent_ui(&mut self, ui: &mut egui::Ui) {
        if self.recent.is_empty() {
            return;
        }
        ui.label("Latest in the save folder:");
        for p in &self.recent {
            let name = p
                .file_name()
                .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into());
            if ui.selectable_label(false, name).clicked() {
                self.path = p.display().to_string();
                self.error = None;
            }
        }
    }

    /// Reads the file at the path as `gui --session` does.
    fn try_open(&mut self) -> Option<Outcome> {
        let path = self.path.trim();
        if path.is_empty() {
            self.error = Some("no file given".into());
            return None;
        }
        match Session::read(Path::new(path)) {
            Ok(loaded) => Some(Outcome::Open(Box::new(loaded))),
            Err(e) => {
                self.error = Some(e);
                None
            }
        }
    }
}

/// The session files Save session wrote into `dir`, newest first.
fn latest_sessions(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut found: Vec<(std::time::SystemTime, PathBuf)> = entries
        .flatten()
        .filter(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            name.starts_with("oneblock-session") && name.ends_with(".json")
        })
        .filter_map(|e| Some((e.metadata().ok()?.modified().ok()?, e.path())))
        .collect();
    found.sort_by(|a, b| b.0.cmp(&a.0).then_with(|| b.1.cmp(&a.1)));
    found.into_iter().take(LISTED).map(|(_, p)| p).collect()
}
