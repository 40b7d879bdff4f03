//! Screenshots the egui way: ask the viewport for one
//! (`ctx.request_screenshot`), crop it to a view's rect, encode the PNG on a
//! thread of its own and write it atomically, never over an existing file.
//! The outcome comes back through a channel and shows as a toast.

use eframe::egui;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, Sender, channel};

use egui::{ColorImage, Context, Rect};

use super::files::encode_png;
#[cfg(not(target_arch = "wasm32"))]
use crate::output::write_output;

/// How a save ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Saved {
    Ok(PathBuf),
    Failed(String),
}

/// A short message, shown at the start of the status bar while it lasts
/// (never over a plot: the bar keeps its one line).
#[derive(Clone, Debug)]
pub struct Toast {
    pub text: String,
    pub error: bool,
    /// `ui` time after which it disappears.
    pub until: f64,
}

/// Screenshot and export bookkeeping.
pub struct Shots {
    tx: Sender<Saved>,
    rx: Receiver<Saved>,
    /// Saves under way (screenshot callbacks or writes not yet answered).
    pub in_flight: usize,
    pub toasts: Vec<Toast>,
    /// Results for the scripted run, which waits for its own.
    pub finished: Vec<Saved>,
}

impl Default for Shots {
    fn default() -> Self {
        let (tx, rx) = channel();
        Shots {
            tx,
            rx,
            in_flight: 0,
            toasts: Vec::new(),
            finished: Vec::new(),
        }
    }
}

/// A save whose thread could not start: a failure the user sees as a
/// toast (and a scripted run as its error), not a file silently missing.
#[cfg(not(target_arch = "wasm32"))]
fn not_started(path: &str, e: &std::io::Error) -> Saved {
    Saved::Failed(format!("cannot save {path}: cannot start a thread: {e}"))
}

impl Shots {
    #[cfg(not(target_arch = "wasm32"))]
    /// Asks for a screenshot of the window, cropped to `crop`, saved to `path`.
    pub fn request(&mut self, ctx: &Context, path: PathBuf, crop: Option<Rect>) {
        let tx = self.tx.clone();
        let ppp = ctx.pixels_per_point();
        ctx.request_screenshot(move |img: Arc<ColorImage>| {
            let (failed_tx, shown) = (tx.clone(), path.display().to_string());
            let spawned = std::thread::Builder::new()
                .name("oneblock-png".into())
                .spawn(move || {
                    let r = encode_png(&img, crop, ppp).and_then(|bytes| {
                        write_output(&path, &bytes, false).map_err(|e| e.to_string())
                    });
                    tx.send(match r {
                        Ok(()) => Saved::Ok(path),
                        Err(e) => Saved::Failed(e),
                    })
                    .ok();
                });
            if let Err(e) = spawned {
                failed_tx.send(not_started(&shown, &e)).ok();
            }
        });
        self.in_flight += 1;
        ctx.request_repaint();
    }

    /// Records an animated GIF into `path` on a thread of its own:
    /// `make` computes it (the view's data recomputed on the job model's
    /// single-threaded host, each frame drawn as `oneblock figure --frames`
    /// does), `frames` of them. A toast says it started; another says
    /// where it was saved, or why not.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn record(
        &mut self,
        make: impl FnOnce() -> Result<Vec<u8>, String> + Send + 'static,
        frames: usize,
        path: PathBuf,
        now: f64,
    ) {
        let tx = self.tx.clone();
        self.in_flight += 1;
        self.toast(
            format!("Recording {} frames to {}…", frames, path.display()),
            false,
            now,
        );
        let (failed_tx, shown) = (tx.clone(), path.display().to_string());
        let spawned = std::thread::Builder::new()
            .name("oneblock-gif".into())
            .spawn(move || {
                let r = make().and_then(|bytes| {
                    write_output(&path, &bytes, false).map_err(|e| e.to_string())
                });
                tx.send(match r {
                    Ok(()) => Saved::Ok(path),
                    Err(e) => Saved::Failed(e),
                })
                .ok();
            });
        if let Err(e) = spawned {
            failed_tx.send(not_started(&shown, &e)).ok();
        }
    }

    #[cfg(not(target_arch = "wasm32"))]
    /// Writes `bytes` to `path` on a thread (for CSV exports).
    pub fn write(&mut self, path: PathBuf, bytes: Vec<u8>) {
        let tx = self.tx.clone();
        self.in_flight += 1;
        let (failed_tx, shown) = (tx.clone(), path.display().to_string());
        let spawned = std::thread::Builder::new()
            .name("oneblock-export".into())
            .spawn(move || {
                let r = write_output(&path, &bytes, false);
                tx.send(match r {
                    Ok(()) => Saved::Ok(path),
                    Err(e) => Saved::Failed(e.to_string()),
                })
                .ok();
            });
        if let Err(e) = spawned {
            failed_tx.send(not_started(&shown, &e)).ok();
        }
    }

    /// Asks for a screenshot of the page, cropped to `crop`, downloaded as
    /// `path`'s file name (the browser build: encoded in the callback, as a
    /// page has no threads).
    #[cfg(target_arch = "wasm32")]
    pub fn request(&mut self, ctx: &Context, path: PathBuf, crop: Option<Rect>) {
        let tx = self.tx.clone();
        let ppp = ctx.pixels_per_point();
        ctx.request_screenshot(move |img: Arc<ColorImage>| {
            let r =
                encode_png(&img, crop, ppp).and_then(|bytes| super::web::download(&path, &bytes));
            tx.send(match r {
                Ok(()) => Saved::Ok(path),
                Err(e) => Saved::Failed(e),
            })
            .ok();
        });
        self.in_flight += 1;
        ctx.request_repaint();
    }

    /// Downloads `bytes` as `path`'s file name (the browser build).
    #[cfg(target_arch = "wasm32")]
    pub fn write(&mut self, path: PathBuf, bytes: Vec<u8>) {
        self.in_flight += 1;
        let r = super::web::download(&path, &bytes);
        self.tx
            .send(match r {
                Ok(()) => Saved::Ok(path),
                Err(e) => Saved::Failed(e),
            })
            .ok();
    }

    /// Collects finished saves into toasts; `now` is the ui time.
    pub fn poll(&mut self, now: f64) {
        while let Ok(s) = self.rx.try_recv() {
            self.in_flight = self.in_flight.saturating_sub(1);
            let t = match &s {
                Saved::Ok(p) => Toast {
                    text: format!("Saved {}", p.display()),
                    error: false,
                    until: now + 6.0,
                },
                Saved::Failed(e) => Toast {
                    text: format!("Not saved: {e}"),
                    error: true,
                    until: now + 10.0,
                },
            };
            self.toasts.push(t);
            self.finished.push(s);
        }
        self.toasts.retain(|t| t.until > now);
    }

    /// Adds a toast directly (e.g. nothing to export). An error stays
    /// long enough to be read: 6 s and a second for every 15 characters
    /// (a link's or a session's message may name several values).
    pub fn toast(&mut self, text: String, error: bool, now: f64) {
        let reading = if error {
            text.chars().count() as f64 / 15.0
        } else {
            0.0
        };
        self.toasts.push(Toast {
            text,
            error,
            until: now + 6.0 + reading,
        });
    }
}
