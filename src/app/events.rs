//! The event catalogue: the size of every slip (distance or energy) as a
//! time series over the onsets, and the intermittency statistics of the
//! events after the transient (`sim::intermittency`): creep and stick-slip
//! slips by where each starts, the slip-size distribution on log–log axes,
//! the laminar lengths (runs of creep slips between stick-slip slips) with
//! the creep channel's passage time beside their mean, and on demand the
//! mean laminar length against the distance to a tangency located by
//! continuation.

use eframe::egui;
use egui::Ui;

use super::events_plots::Plots;
use super::jobs::{JobKind, JobState, Jobs};
use super::settings::{EventsPlot, Settings, SlipMeasure, ViewKind};
use super::style;
use super::view::{Action, View};
use crate::model::Params;
use crate::sim::SlipEvent;
use crate::sim::intermittency::{Intermittency, Passage, Scaling, creep_flags};

/// The size of a slip under `m`.
pub fn slip_size(e: &SlipEvent, m: SlipMeasure) -> f64 {
    match m {
        SlipMeasure::Distance => e.slip_distance,
        SlipMeasure::Energy => e.energy_released,
    }
}

/// Events of the trajectory's start left out of the statistics: the
/// trajectory starts at θ = θν, off the attractor. A quarter of the events,
/// at most this many.
pub const STATS_TRANSIENT: usize = 50;

/// How many of `n` events the statistics leave out as the transient.
pub fn stats_transient(n: usize) -> usize {
    (n / 4).min(STATS_TRANSIENT)
}

/// The intermittency statistics of the events on screen, kept until the
/// events, the measure or the parameters change.
#[derive(Default)]
struct StatsCache {
    key: Option<(u64, usize, bool, Params)>,
    stats: Option<Intermittency>,
    /// Whether each event (the transient included) is a creep slip.
    creep: Vec<bool>,
    /// The first creep onset after the transient (the channel's start).
    first_creep: Option<f64>,
    skipped: usize,
}

#[derive(Default)]
pub struct EventsView {
    cache: StatsCache,
}

impl EventsView {
    /// The scan's button and its outcome in words. The scan is a job of
    /// its own ([`Action::Start`]): in the browser it runs within the
    /// frames' slices like every job.
    fn scaling_row_ui(ui: &mut Ui, params: &Params, jobs: &Jobs, out: &mut Vec<Action>) {
        let scan = &jobs.scan;
        ui.horizontal_wrapped(|ui| {
            if scan.asked(params) && scan.state == JobState::Running {
                ui.spinner();
                ui.label("locating a tangency and measuring the laminar lengths near it ...");
            } else if ui
                .small_button("Laminar length vs distance to a tangency")
                .on_hover_text(
                    "Look for a periodic window within 0.05 of θν, follow its cycle by \
                     continuation to its fold (a tangency of f^p with the diagonal), then \
                     measure the mean laminar length and the channel passage at distances \
                     ε = |θν − θν_fold|/2^k, k = 0…7, on log–log axes beside type-I \
                     intermittency's slope −1/2. Where no fold is found, nothing is fitted. \
                     Seconds to a minute, beside the other jobs.",
                )
                .clicked()
            {
                out.push(Action::Start(JobKind::Scan));
            }
            match (scan.answer(params), &scan.state) {
                (Some(sc), _) => {
                    ui.label(sc.describe());
                }
                (None, JobState::Failed(e)) if scan.asked(params) => {
                    ui.colored_label(style::ERROR, format!("scan failed: {e}"));
                }
                _ => {}
            }
        });
    }

    /// Asks for the channel passage for the parameters on screen when it
    /// was not asked for yet (never in a picture, which is drawn once).
    fn want_passage(&self, params: &Params, jobs: &Jobs, figure: bool, out: &mut Vec<Action>) {
        let Some(near) = self.cache.first_creep else {
            return;
        };
        if figure || jobs.passage.asked(params) {
            return;
        }
        out.push(Action::Passage(near));
    }

    fn stats(&mut self, jobs: &Jobs, m: SlipMeasure, params: &Params) {
        let evs = &jobs.trajectory.data.events;
        let key = (
            jobs.trajectory.generation,
            evs.len(),
            m == SlipMeasure::Distance,
            *params,
        );
        if self.cache.key == Some(key) {
            return;
        }
        let skip = stats_transient(evs.len());
        let creep = creep_flags(params.kappa, params.gamma, evs.iter().map(|e| e.theta));
        let sizes: Vec<f64> = evs[skip..].iter().map(|e| slip_size(e, m)).collect();
        let first_creep = evs[skip..]
            .iter()
            .zip(&creep[skip..])
            .find(|(_, c)| **c)
            .map(|(e, _)| e.theta);
        self.cache = StatsCache {
            key: Some(key),
            stats: (!evs.is_empty()).then(|| Intermittency::of(&creep[skip..], &sizes)),
            creep,
            first_creep,
            skipped: skip,
        };
    }

    /// The channel passage in a few words, for the summary.
    fn passage_words(params: &Params, jobs: &Jobs) -> String {
        let slot = &jobs.passage;
        match (slot.answer(params), &slot.state) {
            (Some(Passage::Open(c)), _) => format!("channel passage {:.1}", c.mean),
            (Some(p), _) => p.describe(),
            (None, JobState::Failed(e)) if slot.asked(params) => {
                format!("channel passage failed: {e}")
            }
            (None, JobState::Running) if slot.asked(params) => "channel passage ...".into(),
            _ => String::new(),
        }
    }

    fn show(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, out: &mut Vec<Action>) {
        let evs = &jobs.trajectory.data.events;
        let params = s.params;
        self.stats(jobs, s.slip_measure, &params);
        self.want_passage(&params, jobs, style::figure_only(ui.ctx()), out);
        // Controls folded (a figure, the tour's tiles): no menus.
        let figure = !style::controls_shown(ui.ctx());
        let stats = self.cache.stats.clone();
        let scaled = jobs
            .scan
            .answer(&params)
            .filter(|sc| matches!(sc, Scaling::Fitted { .. }))
            .cloned();
        // All plots side by side need room for five ticks on each axis of
        // each: about 36 lines of text across, and 8 down per stacked plot.
        let em = ui.text_style_height(&egui::TextStyle::Body);
        let stacked = if scaled.is_some() { 3.0 } else { 2.0 };
        let wide = ui.available_width() >= 36.0 * em
            && ui.available_height() >= (stacked * 8.0 + 4.0) * em;
        header_ui(ui, s, evs.len(), figure, wide);
        let m = s.slip_measure;
        // The axis title: the quantity in full where there is room.
        let unit = match (m, wide) {
            (SlipMeasure::Distance, true) => "slip distance |Δr| (F₀/k_y)",
            (SlipMeasure::Energy, true) => "energy released ΔE (F₀²/k_y)",
            (SlipMeasure::Distance, false) => "|Δr| (F₀/k_y)",
            (SlipMeasure::Energy, false) => "ΔE (F₀²/k_y)",
        };
        let plots = Plots {
            sizes: evs.iter().map(|e| slip_size(e, m)).collect(),
            creep: self.cache.creep.clone(),
            stats: stats.as_ref(),
            unit,
            scaled: scaled.as_ref(),
        };
        if let Some(st) = &stats {
            let pass = Self::passage_words(&params, jobs);
            let skipped = self.cache.skipped;
            // The full text is formatted only while the summary is hovered.
            ui.label(summary(st, &pass, skipped, wide))
                .on_hover_ui(|ui| {
                    ui.label(summary(st, &pass, skipped, true) + "\n\n" + STATS_HELP);
                });
        }
        if wide {
            if !figure {
                Self::scaling_row_ui(ui, &params, jobs, out);
            }
            let h = ui.available_height();
            let width = ui.available_width();
            ui.horizontal(|ui| {
                ui.vertical(|ui| {
                    ui.set_width(width * 0.5);
                    plots.series_ui(ui, h - 8.0);
                });
                ui.vertical(|ui| {
                    let part = (h - 8.0 * stacked) / stacked;
                    plots.sizes_ui(ui, part);
                    plots.laminar_ui(ui, part);
                    plots.scaling_ui(ui, part);
                });
            });
            return;
        }
        if s.events_plot == EventsPlot::Scaling && !figure {
            Self::scaling_row_ui(ui, &params, jobs, out);
        }
        let h = ui.available_height() - 4.0;
        match s.events_plot {
            EventsPlot::Series => plots.series_ui(ui, h),
            EventsPlot::Sizes => plots.sizes_ui(ui, h),
            EventsPlot::Laminar => plots.laminar_ui(ui, h),
            EventsPlot::Scaling => plots.scaling_ui(ui, h),
        }
    }
}

/// The count of events and, in the window, the choices: as buttons where
/// all plots fit, else in two menus on one row (one plot at a time).
fn header_ui(ui: &mut Ui, s: &mut Settings, events: usize, figure: bool, wide: bool) {
    if figure {
        // A picture has no menus: the count only.
        ui.label(format!("{events} slip events"));
    } else if wide {
        measure_ui(ui, s, events);
    } else {
        ui.horizontal_wrapped(|ui| {
            ui.label(format!("{events} slips"));
            egui::ComboBox::from_id_salt("events_measure")
                .selected_text(measure_name(s.slip_measure))
                .show_ui(ui, |ui| {
                    for m in [SlipMeasure::Distance, SlipMeasure::Energy] {
                        ui.selectable_value(&mut s.slip_measure, m, measure_name(m));
                    }
                })
                .response
                .on_hover_text("How a slip's size is measured");
            egui::ComboBox::from_id_salt("events_plot")
                .selected_text(plot_name(s.events_plot))
                .show_ui(ui, |ui| {
                    for v in EventsPlot::ALL {
                        ui.selectable_value(&mut s.events_plot, v, plot_name(v));
                    }
                })
                .response
                .on_hover_text("What the events plot shows");
        });
    }
}

/// The count of events and the choice of size measure, as buttons.
fn measure_ui(ui: &mut Ui, s: &mut Settings, events: usize) {
    ui.horizontal_wrapped(|ui| {
        ui.label(format!("{events} slip events · size as"));
        ui.selectable_value(&mut s.slip_measure, SlipMeasure::Distance, "slip distance")
            .on_hover_text("|stop − onset|: how far the block jumped");
        ui.selectable_value(&mut s.slip_measure, SlipMeasure::Energy, "energy released")
            .on_hover_text("½(κx² + y²) at onset minus at the stop");
    });
}

fn measure_name(m: SlipMeasure) -> &'static str {
    match m {
        SlipMeasure::Distance => "slip distance",
        SlipMeasure::Energy => "energy released",
    }
}

fn plot_name(p: EventsPlot) -> &'static str {
    match p {
        EventsPlot::Series => "series",
        EventsPlot::Sizes => "size distribution",
        EventsPlot::Laminar => "laminar lengths",
        EventsPlot::Scaling => "laminar vs ε to a tangency",
    }
}

/// What the summary's hover adds: the definitions.
const STATS_HELP: &str = "A slip is creep or stick-slip by where it starts, the model's \
     criterion: creep where γ² < A(θ) = κ cos²θ + sin²θ (κ³x0² + y0² > γ² at the onset). A \
     laminar phase is a run of creep slips between two stick-slip slips. The channel \
     passage is the number of creep slips a crossing of the creep arc holds, ⌈T⌉ with \
     T = ∫dθ/(f(θ) − θ) from where the stick-slip slips re-inject the orbit to the arc's \
     end, computed from f itself. The trajectory's \
     first events (its transient) are left out; `oneblock orbit --stats` writes the same \
     statistics as CSV.";

/// One line: the counts by onset, and the mean laminar length with the
/// channel passage `pass` beside it when the orbit is intermittent, or why
/// it is not; `full` adds the verdict in full and the events left out.
fn summary(st: &Intermittency, pass: &str, skipped: usize, full: bool) -> String {
    let regime = st.regime();
    let counts = st.onsets.describe();
    let verdict = if regime.is_intermittent() {
        let mean = match (st.mean_laminar, st.mean_laminar_stderr) {
            (Some(m), Some(e)) => format!("mean laminar length {m:.1} ± {e:.1}"),
            (Some(m), None) => format!("mean laminar length {m:.1}"),
            _ => "no complete laminar phase".into(),
        };
        format!("{} laminar phases, {mean}", st.laminar.len())
    } else if full {
        regime.describe()
    } else {
        regime.short_reason().into()
    };
    let pass = if pass.is_empty() || st.onsets.creep == 0 {
        String::new()
    } else {
        format!(" · {pass}")
    };
    if full {
        format!("{counts} · {verdict}{pass} · first {skipped} events left out")
    } else {
        format!("{counts} · {verdict}{pass}")
    }
}

impl View for EventsView {
    fn title(&self) -> &'static str {
        ViewKind::Events.title()
    }

    fn ui(&mut self, ui: &mut Ui, s: &mut Settings, jobs: &Jobs, out: &mut Vec<Action>) {
        self.show(ui, s, jobs, out);
    }
}
