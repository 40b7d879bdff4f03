//! `oneblock gui`: opens the explorer window (also what `oneblock` with no
//! arguments does). With `--screenshot` it waits until the views for the
//! preset are complete, saves a PNG and exits: how the README's images are
//! made and how CI checks that the window really draws.

use std::path::PathBuf;

use clap::Args;

use super::CliError;
use super::values::{count_between, parse_count, parse_number, seconds, short};
use crate::model::Preset;

/// The views `--view` names.
pub const VIEW_KEYS: [&str; 9] = [
    "plane",
    "block",
    "bifurcation",
    "return-map",
    "events",
    "numerics",
    "phase",
    "time-series",
    "basins",
];

/// The guided tour's steps (`--tour-step` lies in [1, TOUR_STEPS]).
pub const TOUR_STEPS: usize = 7;
// Known without the window's code; the tour's table must agree.
#[cfg(feature = "gui")]
const _: () = assert!(crate::app::tour::STEPS.len() == TOUR_STEPS);

/// The longest `--timeout`, in seconds (a day).
pub const MAX_TIMEOUT: f64 = 86_400.0;

#[derive(Debug, Clone, Default, Args)]
pub struct GuiArgs {
    /// Start on a preset: fig3a, fig3b, fig4, creep, chaos, intermittent,
    /// hysteresis.
    #[arg(long)]
    pub preset: Option<Preset>,
    /// Save a picture of the window here once the views are complete, then
    /// exit: an SVG (vector: lines as paths, text as text) when FILE ends in
    /// .svg, else a PNG (never overwrites an existing file).
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// Window size in points, WIDTHxHEIGHT, each in [200, 10000] (default
    /// 1280x800).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_size)]
    pub size: Option<[f32; 2]>,
    /// Measure frame times (with --screenshot: for 5 s with the diagram full
    /// and a trajectory streaming, or with --play while θν plays) and print
    /// the median.
    #[arg(long)]
    pub frame_stats: bool,
    /// Show one view full size: plane, block, bifurcation, return-map, events,
    /// numerics, phase, time-series, basins.
    #[arg(long, value_parser = clap::builder::PossibleValuesParser::new(VIEW_KEYS))]
    pub view: Option<String>,
    /// Text size multiplier in [0.5, 3] (e.g. 1.5 on a projector).
    #[arg(long, allow_hyphen_values = true)]
    pub font_scale: Option<f32>,
    /// Start with the side panel hidden, the views taking its width (H or
    /// the top bar's Panel shows it again).
    #[arg(long)]
    pub hide_panel: bool,
    /// Start with Play θν on (P pauses). With --screenshot, θν plays for
    /// 5 s once the views are complete, then the picture is taken; with
    /// --frame-stats too, those frames are measured.
    #[arg(long)]
    pub play: bool,
    /// Give up a --screenshot run after this many seconds, in (0, 86400]
    /// (default 180).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub timeout: Option<f64>,
    /// Open on a session saved by the window's "Save session" (a JSON
    /// file); with --screenshot, render it headless. Invalid or unknown
    /// fields are named once and left at their defaults.
    #[arg(long)]
    pub session: Option<PathBuf>,
    /// With --screenshot: open on the saved state as a plain launch does
    /// (checked, set aside if unusable), never writing it. For tests.
    #[arg(long, hide = true)]
    pub saved_state: bool,
    /// Run every job on the window's own thread, a slice of each frame, as
    /// the browser build does (no simulation threads).
    #[arg(long)]
    pub single_thread: bool,
    /// Open on step N of the guided tour, in [1, 7]: its parameters and
    /// views (End tour goes back to what the other flags set).
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = parse_count)]
    pub tour_step: Option<usize>,
    /// With --screenshot: also write the rectangles, in points, of every
    /// view, its plots and the tour's box as JSON (never overwrites an
    /// existing file).
    #[arg(long, value_name = "FILE")]
    pub layout: Option<PathBuf>,
    /// Test-only: the first frame stalls for an hour (how the tests check
    /// that --timeout bounds a run whose frames stall).
    #[arg(long, hide = true)]
    pub stall_first_frame: bool,
}

pub(crate) fn parse_size(s: &str) -> Result<[f32; 2], String> {
    parse_size_within(s, 200.0)
}

/// WIDTHxHEIGHT, each in [`least`, 10000].
pub(crate) fn parse_size_within(s: &str, least: f32) -> Result<[f32; 2], String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| "must be WIDTHxHEIGHT, e.g. 1280x800".to_string())?;
    let w: f32 = w
        .trim()
        .parse()
        .map_err(|_| "the width is not a number (WIDTHxHEIGHT, e.g. 1280x800)".to_string())?;
    let h: f32 = h
        .trim()
        .parse()
        .map_err(|_| "the height is not a number (WIDTHxHEIGHT, e.g. 1280x800)".to_string())?;
    if !(least..=10_000.0).contains(&w) || !(least..=10_000.0).contains(&h) {
        return Err(format!("must lie between {least}x{least} and 10000x10000"));
    }
    Ok([w, h])
}

/// Checks the flags before the window opens.
pub fn check(args: &GuiArgs) -> Result<(), CliError> {
    if let Some(t) = args.timeout {
        seconds("timeout", t)?;
        if t > MAX_TIMEOUT {
            return Err(CliError::Usage(format!(
                "--timeout = {} is out of range: must lie in (0, {MAX_TIMEOUT}] seconds",
                short(t)
            )));
        }
    }
    if let Some(f) = args.font_scale
        && !(0.5..=3.0).contains(&f)
    {
        return Err(CliError::Usage(format!(
            "--font-scale = {} is out of range: must lie in [0.5, 3]",
            short(f as f64)
        )));
    }
    if let Some(p) = &args.session {
        // Read (and its version checked) before the window opens: a FIFO,
        // a directory, a file not UTF-8 or of an unknown version is the
        // user's to fix, in one line.
        #[cfg(feature = "gui")]
        crate::app::session::Session::read(p)
            .map_err(|e| CliError::Usage(format!("--session: {e}")))?;
        #[cfg(not(feature = "gui"))]
        std::fs::metadata(p).map_err(|e| {
            CliError::Usage(format!(
                "--session: cannot read {}: {e}",
                super::values::echo(&p.display().to_string())
            ))
        })?;
    }
    if args.saved_state && args.screenshot.is_none() {
        return Err(CliError::Usage(
            "--saved-state: only with --screenshot (a plain launch always reads it)".into(),
        ));
    }
    if let Some(n) = args.tour_step {
        count_between("tour-step", n, 1, TOUR_STEPS)?;
        if args.view.is_some() {
            return Err(CliError::Usage(
                "--tour-step: not with --view (a tour step shows its own views)".into(),
            ));
        }
    }
    if args.layout.is_some() && args.screenshot.is_none() {
        return Err(CliError::Usage(
            "--layout: only with --screenshot (it is written with the picture)".into(),
        ));
    }
    for (flag, path) in [("screenshot", &args.screenshot), ("layout", &args.layout)] {
        if let Some(p) = path {
            writable(flag, p)?;
        }
    }
    if let (Some(a), Some(b)) = (&args.screenshot, &args.layout)
        && a == b
    {
        return Err(CliError::Usage(
            "--layout: the same file as --screenshot: give each its own name".into(),
        ));
    }
    Ok(())
}

/// Checks that `--flag`'s file `p` can be written and does not exist.
fn writable(flag: &str, p: &std::path::Path) -> Result<(), CliError> {
    crate::output::check_writable(p, false).map_err(|e| match e {
        crate::output::OutputError::Exists { path } => CliError::Usage(format!(
            "--{flag}: {} already exists: the window never overwrites a file, choose another name",
            path.display()
        )),
        e => CliError::Usage(format!("--{flag}: {e}")),
    })
}

#[cfg(feature = "gui")]
pub fn run(args: GuiArgs) -> Result<(), CliError> {
    use crate::app::{RunOptions, ViewKind};
    check(&args)?;
    let view = match &args.view {
        Some(v) => Some(ViewKind::from_key(v).ok_or_else(|| {
            CliError::Usage(format!(
                "--view: unknown view '{v}': expected one of {}",
                VIEW_KEYS.join(", ")
            ))
        })?),
        None => None,
    };
    crate::app::run(RunOptions {
        // The first launch is the Fig. 3b demo (the default settings); later
        // launches restore the saved parameters unless a preset is named. A
        // scripted run is reproducible: Fig. 3b unless told otherwise.
        preset: args.preset.map(|p| p.key.to_string()).or_else(|| {
            (args.screenshot.is_some() && args.session.is_none() && !args.saved_state)
                .then(|| "fig3b".to_string())
        }),
        session: args.session,
        saved_state: args.saved_state,
        single_thread: args.single_thread,
        stall_first_frame: args.stall_first_frame,
        screenshot: args.screenshot,
        layout: args.layout,
        tour_step: args.tour_step.map(|n| n - 1),
        size: args.size,
        frame_stats: args.frame_stats,
        view,
        font_scale: args.font_scale,
        hide_panel: args.hide_panel,
        play: args.play,
        timeout: args.timeout.map(std::time::Duration::from_secs_f64),
    })
    .map_err(CliError::Failed)
}

#[cfg(not(feature = "gui"))]
pub fn run(args: GuiArgs) -> Result<(), CliError> {
    check(&args)?;
    Err(CliError::Failed(
        "this oneblock was built without the window (cargo feature 'gui'); \
         rebuild with default features, or use the headless subcommands (see --help)"
            .into(),
    ))
}
