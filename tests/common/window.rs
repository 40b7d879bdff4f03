//! The harness the window tests share: an [`Explorer`] over a recording
//! backend driven headless through AccessKit (egui_kittest), so each test
//! sees exactly what was sent; and readers of the commands it recorded, a
//! slip-event fixture, and a phase-grid answer.
//!
//! Included by each `tests/gui_*.rs` with `#[path]` (each uses a subset).
#![allow(dead_code)]

use eframe::egui;
use egui_kittest::Harness;
use egui_plot::PlotPoint;
use oneblock::worker::Spec;

use oneblock::app::backend::Backend;
use oneblock::app::{Explorer, Layout, Recorder, Settings, ViewKind};
use oneblock::integrate::SolverSettings;
use oneblock::model::Params;
use oneblock::sim::phase::{CellClass, PhaseCell};
use oneblock::sim::{SlipEvent, theta_nu_grid};
use oneblock::worker::{Command, Generation, GridCell, Lane, Outcome, Update};

/// A 1280 × 1000 window showing `settings`, its commands going to `rec`.
pub fn harness(rec: &Recorder, settings: Settings) -> Harness<'static, Explorer> {
    window_of(Box::new(rec.clone()), settings)
}

/// A 1280 × 1000 window showing `settings` whose jobs on `lanes` run on
/// the real worker; every command is recorded in `rec`, and those of the
/// other lanes go no further (the orbit and the rest are not what such a
/// test is about, and would keep both cores busy).
pub fn harness_on_lanes(
    rec: &Recorder,
    settings: Settings,
    lanes: &'static [Lane],
) -> Harness<'static, Explorer> {
    let worker = oneblock::worker::Worker::spawn(
        oneblock::worker::WorkerConfig::default(),
        std::sync::Arc::new(|| {}),
    );
    let backend = SomeLanes {
        worker,
        rec: rec.clone(),
        lanes,
    };
    window_of(Box::new(backend), settings)
}

/// The real worker for some lanes, behind a recorder ([`harness_on_lanes`]).
struct SomeLanes {
    worker: oneblock::worker::Worker,
    rec: Recorder,
    lanes: &'static [Lane],
}

impl Backend for SomeLanes {
    fn send(&mut self, cmd: Command) -> bool {
        self.rec.send(cmd.clone());
        let lane = match &cmd {
            Command::Run { spec, .. } => Some(spec.lane()),
            Command::Cancel { lane, .. } => *lane,
            _ => None,
        };
        if lane.is_some_and(|l| self.lanes.contains(&l)) {
            self.worker.send(cmd)
        } else {
            true
        }
    }
    fn try_recv(&mut self) -> Option<Update> {
        self.worker.try_recv()
    }
}

/// A 1280 × 1000 window showing `settings` over `backend`.
fn window_of(backend: Box<dyn Backend>, settings: Settings) -> Harness<'static, Explorer> {
    let app = Explorer::new(backend, settings);
    Harness::builder()
        .with_size([1280.0, 1000.0])
        .build_ui_state(
            |ui, app: &mut Explorer| {
                app.logic_step(ui.ctx());
                app.show(ui);
            },
            app,
        )
}

/// The CSV an export writes into `dir` (on a thread of its own), stepping
/// the window while waiting for it; `None` after about 2 s.
pub fn wait_for_csv(
    h: &mut Harness<'static, Explorer>,
    dir: &std::path::Path,
) -> Option<std::path::PathBuf> {
    for _ in 0..100 {
        h.step();
        let found = std::fs::read_dir(dir)
            .expect("read dir")
            .flatten()
            .map(|e| e.path())
            .find(|p| p.extension().is_some_and(|e| e == "csv"));
        if found.is_some() {
            return found;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    None
}

/// A GIF's size and number of frames (decoding every frame: a broken
/// GIF fails).
pub fn gif_size_and_frames(path: &std::path::Path) -> ((u16, u16), usize) {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut d = opts
        .read_info(std::fs::File::open(path).expect("open"))
        .expect("a GIF");
    let size = (d.width(), d.height());
    let mut frames = 0;
    while d.read_next_frame().expect("a frame").is_some() {
        frames += 1;
    }
    (size, frames)
}

/// The parameters of the latest trajectory command, if any.
pub fn last_trajectory(rec: &Recorder) -> Option<Params> {
    rec.commands().into_iter().rev().find_map(|c| match c {
        Command::Run {
            spec: Spec::Trajectory(spec),
            ..
        } => Some(spec.params),
        _ => None,
    })
}

/// The parameters of the latest sweep command, if any.
pub fn last_sweep(rec: &Recorder) -> Option<Params> {
    rec.commands().into_iter().rev().find_map(|c| match c {
        Command::Run {
            spec: Spec::Sweep(spec),
            ..
        } => Some(spec.params),
        _ => None,
    })
}

/// The solver settings of the latest command of each job kind.
pub fn last_settings(rec: &Recorder) -> (Option<SolverSettings>, Option<SolverSettings>) {
    let cmds = rec.commands();
    let traj = cmds.iter().rev().find_map(|c| match c {
        Command::Run {
            spec: Spec::Trajectory(spec),
            ..
        } => Some(spec.settings),
        _ => None,
    });
    let sweep = cmds.iter().rev().find_map(|c| match c {
        Command::Run {
            spec: Spec::Sweep(spec),
            ..
        } => Some(spec.settings),
        _ => None,
    });
    (traj, sweep)
}

/// A slip event from θ to θ_next at time t (the other fields plausible).
pub fn event(theta: f64, next: f64, t: f64) -> SlipEvent {
    SlipEvent {
        theta,
        onset_x: theta.cos() / 18.95,
        onset_y: theta.sin(),
        onset_time: t,
        accel_duration: 1.0,
        slip_duration: 3.0,
        stop_x: 0.0,
        stop_y: 0.1,
        slip_distance: 0.9,
        peak_vr: 0.4,
        energy_released: 0.4,
        stick_duration: 100.0,
        theta_next: next,
        restarted: false,
        rhs_evals: 500,
        steps: 50,
    }
}

/// A phase command's generation, θν range and steps, κ range and steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseJob {
    pub generation: Generation,
    pub theta_nu: (f64, f64, usize),
    pub kappa: (f64, f64, usize),
    pub params: Params,
}

/// Every phase command sent, in order.
pub fn phase_jobs(rec: &Recorder) -> Vec<PhaseJob> {
    rec.commands()
        .into_iter()
        .filter_map(|c| match c {
            Command::Run {
                generation,
                spec: Spec::Phase(spec),
            } => Some(PhaseJob {
                generation,
                theta_nu: (spec.theta_nu.from, spec.theta_nu.to, spec.theta_nu.steps),
                kappa: (spec.kappa.from, spec.kappa.to, spec.kappa.steps),
                params: spec.params,
            }),
            _ => None,
        })
        .collect()
}

/// How many cancels of the phase lane were sent.
pub fn phase_cancels(rec: &Recorder) -> usize {
    rec.commands()
        .iter()
        .filter(|c| {
            matches!(
                c,
                Command::Cancel {
                    lane: Some(Lane::Phase),
                    ..
                }
            )
        })
        .count()
}

/// The phase diagram as the one tab.
pub fn phase_tab() -> Settings {
    Settings {
        layout: Layout::Tabs,
        tab: ViewKind::Phase,
        ..Settings::default()
    }
}

/// Answers a phase job with every cell, coarse half first: FP below
/// θν = 0.8, P2 above, chaos in the top right corner.
pub fn feed_phase(rec: &Recorder, job: &PhaseJob) {
    feed_phase_with(rec, job, |_| {});
}

/// [`feed_phase`] with each cell changed by `change` before it is sent.
pub fn feed_phase_with(rec: &Recorder, job: &PhaseJob, change: impl Fn(&mut GridCell)) {
    let tns = theta_nu_grid(job.theta_nu.0, job.theta_nu.1, job.theta_nu.2);
    let ks = theta_nu_grid(job.kappa.0, job.kappa.1, job.kappa.2);
    let mut cells = Vec::new();
    for (row, &kappa) in ks.iter().enumerate() {
        for (column, &theta_nu) in tns.iter().enumerate() {
            let class = if kappa > 30.0 && theta_nu > 1.2 {
                CellClass::Chaos
            } else if theta_nu > 0.8 {
                CellClass::Periodic(2)
            } else {
                CellClass::Periodic(1)
            };
            cells.push(GridCell {
                row,
                column,
                cell: PhaseCell {
                    theta_nu,
                    kappa,
                    class,
                    lyapunov: Some(if class == CellClass::Chaos { 0.3 } else { -0.2 }),
                    lyapunov_stderr: (class == CellClass::Chaos).then_some(0.05),
                    regime: None,
                    iterates: 40,
                    rhs_evals: 20_000,
                    theta_last: theta_nu,
                    error: None,
                    map: Default::default(),
                    attractors: None,
                    uncounted: None,
                },
                listed: Vec::new(),
            });
        }
    }
    cells.iter_mut().for_each(change);
    let half = cells.len() / 2;
    let rest = cells.split_off(half);
    rec.push(Update::PhaseCells {
        generation: job.generation,
        cells,
        coarse: true,
    });
    rec.push(Update::PhaseCells {
        generation: job.generation,
        cells: rest,
        coarse: false,
    });
    rec.push(Update::Finished {
        generation: job.generation,
        lane: Lane::Phase,
        outcome: Outcome::Completed,
    });
}

/// Where the centre of the phase cell (row, column) of `job` is on screen.
pub fn phase_cell_pos(
    h: &Harness<'static, Explorer>,
    job: &PhaseJob,
    row: usize,
    column: usize,
) -> egui::Pos2 {
    let tns = theta_nu_grid(job.theta_nu.0, job.theta_nu.1, job.theta_nu.2);
    let ks = theta_nu_grid(job.kappa.0, job.kappa.1, job.kappa.2);
    let t = h
        .state()
        .views
        .phase
        .transform
        .expect("the phase plot was drawn");
    t.position_from_point(&PlotPoint::new(tns[column], ks[row]))
}

/// The generation of the first trajectory job the window asked for.
pub fn trajectory_generation(rec: &Recorder) -> Generation {
    rec.commands()
        .into_iter()
        .find_map(|c| match c {
            Command::Run {
                generation,
                spec: Spec::Trajectory(..),
            } => Some(generation),
            _ => None,
        })
        .expect("the window starts a trajectory")
}

/// Every text the last frame painted, with where: a row at a time (a
/// wrapped label is its rows, not their bounding box; a turned text is
/// its turned box), each cut to the clip rectangle it was painted in, and
/// left out where nothing of it shows.
pub fn painted_texts(h: &Harness<'static, Explorer>) -> Vec<(String, egui::Rect)> {
    fn walk(s: &egui::Shape, clip: egui::Rect, out: &mut Vec<(String, egui::Rect)>) {
        match s {
            egui::Shape::Text(t) if t.angle != 0.0 => out.push((
                t.galley.text().to_string(),
                t.visual_bounding_rect().intersect(clip),
            )),
            egui::Shape::Text(t) => {
                for row in &t.galley.rows {
                    let r = row
                        .rect_without_leading_space()
                        .translate(t.pos.to_vec2())
                        .intersect(clip);
                    out.push((row.text(), r));
                }
            }
            egui::Shape::Vec(v) => v.iter().for_each(|s| walk(s, clip, out)),
            _ => {}
        }
    }
    let mut out = Vec::new();
    for cs in &h.output().shapes {
        walk(&cs.shape, cs.clip_rect, &mut out);
    }
    out.retain(|(_, r)| r.is_positive());
    out
}

/// Whether `t` reads as a tick label: a number, possibly in degrees or a
/// multiple or fraction of π.
pub fn is_tick(t: &str) -> bool {
    let t = t.trim_end_matches('°');
    if t.parse::<f64>().is_ok() {
        return true;
    }
    // "π", "-π/2", "3π/8", "0.38π"
    let t = t.trim_start_matches('-');
    match t.split_once('π') {
        Some((num, rest)) => {
            (num.is_empty() || num.parse::<f64>().is_ok())
                && (rest.is_empty()
                    || rest
                        .strip_prefix('/')
                        .is_some_and(|d| d.parse::<u32>().is_ok()))
        }
        None => false,
    }
}

/// The tick labels under the x axis and left of the y axis of each plot
/// drawn in the last frame: (plot, x labels, y labels).
pub fn tick_labels(
    h: &Harness<'static, Explorer>,
) -> Vec<(&'static str, Vec<String>, Vec<String>)> {
    let texts = painted_texts(h);
    let line = h.ctx.global_style().text_styles[&egui::TextStyle::Body].size;
    oneblock::app::axes::plot_frames(&h.ctx)
        .into_iter()
        .map(|(name, f)| {
            let xs = texts
                .iter()
                .filter(|(t, r)| {
                    is_tick(t)
                        && r.center().x >= f.left() - 1.0
                        && r.center().x <= f.right() + 1.0
                        && r.top() >= f.bottom() - 1.0
                        && r.top() <= f.bottom() + 2.0 * line
                })
                .map(|(t, _)| t.clone())
                .collect();
            let ys = texts
                .iter()
                .filter(|(t, r)| {
                    is_tick(t)
                        && r.center().y >= f.top() - 1.0
                        && r.center().y <= f.bottom() + 1.0
                        && r.right() <= f.left() + 1.0
                        && r.right() >= f.left() - 12.0 * line
                })
                .map(|(t, _)| t.clone())
                .collect();
            (name, xs, ys)
        })
        .collect()
}

/// The window at `size` with `settings`, after a catalogue of 300 slips of
/// varied sizes has arrived (as a running window has one).
pub fn window_with_slips(
    settings: Settings,
    rec: &Recorder,
    size: (f32, f32),
) -> Harness<'static, Explorer> {
    let mut h = harness(rec, settings);
    h.set_size(egui::vec2(size.0, size.1));
    h.run_steps(2);
    if let Some(generation) = rec.commands().into_iter().find_map(|c| match c {
        Command::Run {
            generation,
            spec: Spec::Trajectory(..),
        } => Some(generation),
        _ => None,
    }) {
        for i in 0..300 {
            let mut e = event(0.5, 0.2, 103.0 * i as f64);
            e.slip_distance = 0.2 + 0.7 * ((i * 37) % 100) as f64 / 100.0;
            rec.push(Update::Slip {
                generation,
                event: e,
            });
        }
    }
    h.run_steps(4);
    h
}
