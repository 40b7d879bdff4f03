//! The Events view's work off the UI thread: the creep channel's passage
//! time (a few hundred map evaluations, started on its own when the
//! parameters change) and the tangency scan (tens of orbits and a
//! continuation, on demand). Each runs on a thread of its own, answers
//! through a channel of one, and is cancelled when the parameters move on
//! or the view goes.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use crossbeam_channel::Receiver;
use eframe::egui;

use crate::integrate::{Method, SolverSettings};
use crate::model::Params;
use crate::sim::SimError;

/// The accuracy of the view's own map evaluations: slip onsets to ~1e-8.
pub fn settings() -> SolverSettings {
    SolverSettings::adaptive(Method::Dop853, 1e-8)
}

/// One running computation for `params`.
struct Running<T> {
    params: Params,
    cancel: Arc<AtomicBool>,
    rx: Receiver<Result<T, String>>,
}

impl<T> Drop for Running<T> {
    fn drop(&mut self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
}

/// A computation's slot: the one running, and the last result with the
/// parameters it is for.
pub struct Slot<T> {
    running: Option<Running<T>>,
    done: Option<(Params, Result<T, String>)>,
}

impl<T> Default for Slot<T> {
    fn default() -> Self {
        Slot {
            running: None,
            done: None,
        }
    }
}

impl<T: Send + 'static> Slot<T> {
    /// Starts `work` for `params` on a thread named `name`; the view is
    /// repainted when it answers. A thread that cannot start is shown
    /// where the result would be.
    pub fn start<F>(&mut self, ctx: &egui::Context, params: Params, name: &str, work: F)
    where
        F: FnOnce(&dyn Fn() -> bool) -> Result<T, SimError> + Send + 'static,
    {
        let cancel = Arc::new(AtomicBool::new(false));
        let (tx, rx) = crossbeam_channel::bounded(1);
        let (c, ctx) = (cancel.clone(), ctx.clone());
        let spawned = std::thread::Builder::new()
            .name(name.into())
            .spawn(move || {
                crate::worker::priority::lower_current_thread();
                let r = work(&|| c.load(Ordering::Relaxed)).map_err(|e| e.to_string());
                tx.send(r).ok();
                ctx.request_repaint();
            });
        match spawned {
            Ok(_) => {
                self.running = Some(Running { params, cancel, rx });
            }
            Err(e) => {
                self.running = None;
                self.done = Some((params, Err(format!("cannot start its thread: {e}"))));
            }
        }
    }

    /// Collects the answer, or drops the work when the parameters moved on.
    pub fn poll(&mut self, params: &Params) {
        let Some(r) = &self.running else { return };
        if r.params != *params {
            self.running = None;
            return;
        }
        if let Ok(out) = r.rx.try_recv() {
            self.done = Some((r.params, out));
            self.running = None;
        }
    }

    /// Whether work is under way.
    pub fn busy(&self) -> bool {
        self.running.is_some()
    }

    /// The last result, when it is for `params`.
    pub fn result(&self, params: &Params) -> Option<&Result<T, String>> {
        self.done
            .as_ref()
            .filter(|(p, _)| p == params)
            .map(|d| &d.1)
    }

    /// Whether nothing for `params` is running or done.
    pub fn missing(&self, params: &Params) -> bool {
        self.running.as_ref().is_none_or(|r| r.params != *params) && self.result(params).is_none()
    }
}
