//! `oneblock figure`'s flags checked before any work: the view, the
//! output's format and that it can be written, the ranges and counts,
//! the animation's flags (`--frames`, `--speed`, `--play`) and the look's;
//! each refusal one line naming the flag and its valid range (exit 2).
//! The flags themselves ([`FigureArgs`]) are declared here too.

use std::path::{Path, PathBuf};

use clap::Args;

use super::CliError;
use super::common::ModelArgs;
use super::gui::{VIEW_KEYS, parse_size_within};
use super::values::{MAX_ABS_THETA, echo, parse_count, parse_number, short};
use crate::sim::continuation::ContParam;

/// The smallest figure side, in points: a column's figure.
pub const MIN_SIDE: f32 = 100.0;

/// --size: WIDTHxHEIGHT, each in [[`MIN_SIDE`], 10000] points.
pub(super) fn parse_figure_size(s: &str) -> Result<[f32; 2], String> {
    parse_size_within(s, MIN_SIDE)
}

/// The PNG resolutions --dpi takes, pixels per inch (an inch is 72
/// points), and the most pixels along a PNG's longer side.
pub const DPI_RANGE: (f64, f64) = (72.0, 600.0);
pub const MAX_PNG_SIDE: f64 = 20_000.0;

/// --dpi: a .png's only, in [`DPI_RANGE`] and at most [`MAX_PNG_SIDE`]
/// pixels along the figure's longer side.
fn check_dpi(a: &FigureArgs, format: Format) -> Result<(), CliError> {
    let Some(d) = a.dpi else { return Ok(()) };
    if format != Format::Png {
        return Err(CliError::Usage(
            "--dpi: only a .png has a resolution (an SVG or PDF is vector): leave --dpi out".into(),
        ));
    }
    dpi_within(d, a.size.unwrap_or(super::figure::DEFAULT_SIZE))
}

/// --dpi = `d` for a figure of `[w, h]` points: in [`DPI_RANGE`] and at
/// most [`MAX_PNG_SIDE`] pixels along the longer side (`figure` and
/// `phase --png` alike).
pub(super) fn dpi_within(d: f64, [w, h]: [f32; 2]) -> Result<(), CliError> {
    let longer = f64::from(w.max(h));
    let most = DPI_RANGE.1.min((MAX_PNG_SIDE * 72.0 / longer).floor());
    if !(DPI_RANGE.0..=most).contains(&d) {
        return Err(CliError::Usage(format!(
            "--dpi = {} is out of range: must lie in [{}, {most}] pixels per inch \
             (at most {}, and {MAX_PNG_SIDE} pixels along the figure's {longer}-point side)",
            short(d),
            DPI_RANGE.0,
            DPI_RANGE.1
        )));
    }
    Ok(())
}

/// The smallest and largest --font-size, in points.
pub const FONT_SIZES: (f64, f64) = (4.0, 72.0);

/// The slowest and fastest GIF playback (as `app::animation`'s, which
/// the build without the window lacks).
const MIN_SPEED: f64 = 0.05;
const MAX_SPEED: f64 = 1.0;
#[cfg(feature = "gui")]
const _: () = assert!(
    MIN_SPEED == crate::app::animation::MIN_SPEED && MAX_SPEED == crate::app::animation::MAX_SPEED
);

/// The views `--play` plays θν in (as `app::animation::PLAY_VIEWS`,
/// which the build without the window lacks).
pub const PLAY_VIEW_KEYS: [&str; 6] = [
    "return-map",
    "plane",
    "block",
    "bifurcation",
    "events",
    "time-series",
];
#[cfg(feature = "gui")]
const _: () = assert!(PLAY_VIEW_KEYS.len() == crate::app::animation::PLAY_VIEWS.len());

/// The most frames a GIF may have (a minute at 10 a second).
pub const MAX_FRAMES: usize = 600;

/// The largest GIF, in points (= pixels) a side.
pub const MAX_GIF_SIDE: f32 = 1920.0;

/// The file formats `--out` may name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Svg,
    /// The SVG as a vector PDF.
    Pdf,
    Png,
    Gif,
    /// The data the view draws, as a table.
    Csv,
}

/// The format `path`'s extension names, or why it names none.
pub fn format_of(path: &Path) -> Result<Format, CliError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("svg") => Ok(Format::Svg),
        Some("pdf") => Ok(Format::Pdf),
        Some("png") => Ok(Format::Png),
        Some("gif") => Ok(Format::Gif),
        Some("csv") => Ok(Format::Csv),
        _ => Err(CliError::Usage(format!(
            "--out: {} has no known extension: name a .svg, .pdf, .png, .gif or .csv file",
            echo(&path.display().to_string())
        ))),
    }
}

/// --dpi for a .png only ([`check_dpi`]); --frames and a .gif go
/// together, for the animated views only, within
/// the bounds.
fn check_frames(a: &FigureArgs, format: Format) -> Result<(), CliError> {
    check_dpi(a, format)?;
    let usage = |m: String| Err(CliError::Usage(m));
    if a.play && (format != Format::Gif || a.frames.is_none()) {
        return usage(format!(
            "--play records θν played as an animation: give --frames N (2 to {MAX_FRAMES}) \
             and a .gif --out"
        ));
    }
    if a.play && a.speed.is_some() {
        return usage(
            "--speed: a played GIF moves θν, one frame a tenth of a second: leave --speed out"
                .into(),
        );
    }
    match (format, a.frames) {
        (Format::Gif, None) => {
            usage("--out: a .gif is an animation: give --frames N (2 to 600)".into())
        }
        (Format::Svg | Format::Pdf | Format::Png | Format::Csv, Some(_)) => usage(
            "--frames makes an animation, which a .svg, .pdf or .png cannot hold: name a .gif file"
                .into(),
        ),
        (Format::Gif, Some(_)) if a.play && !PLAY_VIEW_KEYS.contains(&a.view.as_str()) => {
            usage(format!(
                "--play: θν plays in the {} views, not '{}'",
                PLAY_VIEW_KEYS.join(", "),
                echo(&a.view)
            ))
        }
        (Format::Gif, Some(n)) => {
            if !a.play && !matches!(a.view.as_str(), "block" | "plane") {
                return usage(format!(
                    "--frames: only the block and plane views are animated, not '{}'",
                    echo(&a.view)
                ));
            }
            if !(2..=MAX_FRAMES).contains(&n) {
                return usage(format!(
                    "--frames = {n} is out of range: must lie in [2, {MAX_FRAMES}]"
                ));
            }
            if let Some(v) = a.speed
                && !(MIN_SPEED..=MAX_SPEED).contains(&v)
            {
                return usage(format!(
                    "--speed = {} is out of range: must lie in [{MIN_SPEED}, {MAX_SPEED}] \
                     (1 real time, below slowed)",
                    short(v)
                ));
            }
            let [w, h] = a.size.unwrap_or(GIF_SIZE);
            if w > MAX_GIF_SIDE || h > MAX_GIF_SIDE {
                return usage(format!(
                    "--size {w}x{h}: a GIF may be at most {MAX_GIF_SIDE}x{MAX_GIF_SIDE}"
                ));
            }
            Ok(())
        }
        _ => Ok(()),
    }
}

/// --branches, --boundaries and --seeds: each for the views that draw it.
fn check_overlays(a: &FigureArgs) -> Result<(), CliError> {
    let only = |flag: &str, views: &[&str], what: &str| {
        if views.contains(&a.view.as_str()) {
            Ok(())
        } else {
            Err(CliError::Usage(format!(
                "--{flag}: only {what}, not '{}'",
                echo(&a.view)
            )))
        }
    };
    if a.branches {
        only(
            "branches",
            &["bifurcation"],
            "the bifurcation view draws branches",
        )?;
    }
    if a.boundaries {
        only("boundaries", &["phase"], "the phase view draws boundaries")?;
    }
    if let Some(n) = a.seeds {
        only(
            "seeds",
            &["bifurcation", "phase"],
            "the bifurcation and phase views seed",
        )?;
        if n > MAX_SEEDS {
            return Err(CliError::Usage(format!(
                "--seeds = {n} is out of range: must lie in [0, {MAX_SEEDS}]"
            )));
        }
    }
    Ok(())
}

/// --columns (the basins view's) and the phase grid's steps, in bounds.
fn check_counts(a: &FigureArgs) -> Result<(), CliError> {
    if let Some(n) = a.columns
        && (a.view != "basins" || !(2..=400).contains(&n))
    {
        return Err(CliError::Usage(format!(
            "--columns = {n}: the basins view's columns, in [2, 400]"
        )));
    }
    for (name, v) in [
        ("theta-nu-steps", a.theta_nu_steps),
        ("kappa-steps", a.kappa_steps),
    ] {
        if let Some(n) = v
            && !(2..=200).contains(&n)
        {
            return Err(CliError::Usage(format!(
                "--{name} = {n} is out of range: must lie in [2, 200]"
            )));
        }
    }
    Ok(())
}

/// The most seeds `--seeds` takes (the window's bound).
pub const MAX_SEEDS: usize = 64;
#[cfg(feature = "gui")]
const _: () = assert!(MAX_SEEDS == crate::app::settings::MAX_SWEEP_SEEDS);

/// A GIF's size when --size is not given: a slide's.
pub const GIF_SIZE: [f32; 2] = [640.0, 480.0];

/// A range flag pair: finite, increasing ends whose span and centre are
/// finite too (from -1e308 to 1e308 once wrote x="inf" into an SVG).
fn range(name: &str, from: Option<f64>, to: Option<f64>) -> Result<Option<(f64, f64)>, CliError> {
    match (from, to) {
        (Some(a), Some(b)) => {
            if !(a.is_finite() && b.is_finite() && a < b) {
                return Err(CliError::Usage(format!(
                    "--{name}-from = {}, --{name}-to = {}: must be finite with from < to",
                    short(a),
                    short(b)
                )));
            }
            if !((b - a).is_finite() && (a + b).is_finite()) {
                return Err(CliError::Usage(format!(
                    "--{name}-from = {}, --{name}-to = {}: its width or centre overflows: \
                     keep both ends within ±1e307",
                    short(a),
                    short(b)
                )));
            }
            Ok(Some((a, b)))
        }
        _ => Ok(None),
    }
}

/// `oneblock figure`'s flags.
#[derive(Debug, Clone, Args)]
pub struct FigureArgs {
    /// The view: plane, block, bifurcation, return-map, events, numerics, phase,
    /// time-series, basins.
    #[arg(long)]
    pub view: String,
    /// Where the figure goes; its extension picks the format: .svg (vector:
    /// lines as paths, text as text), .pdf (that SVG as a vector PDF, its
    /// text text in an embedded font) or .png (that SVG rasterised at
    /// --dpi, 2 pixels per point by default); or .csv, the data the view
    /// draws with '#' lines naming how it was made (every view: the
    /// diagram's onsets and λ per column, the basins' attractors, the phase
    /// grid's cells, the trajectory, the slips, the return map's curve and
    /// orbit, the numerics' work-precision rows). Never overwrites an
    /// existing file.
    #[arg(long)]
    pub out: PathBuf,
    /// The model's parameters [default: the session's, else fig3b's].
    #[command(flatten)]
    pub model: ModelArgs,
    /// Start from a session saved by the window's "Save session" (its
    /// parameters, views' settings and diagram zoom, and the branches and
    /// boundaries it kept, drawn as they are unless a flag changes what they
    /// depend on); the flags override it. Without one, and without
    /// --preset, the parameters are fig3b's.
    #[arg(long)]
    pub session: Option<PathBuf>,
    /// Integration method for every job the figure runs: dp54, dop853, rk4
    /// or euler [default: the session's accuracy, else dop853 at tol 1e-10,
    /// as the other commands, so a figure's numbers are theirs].
    #[arg(long, value_enum, ignore_case = true)]
    pub method: Option<crate::integrate::Method>,
    /// Tolerance of the adaptive methods (rtol = atol), in [1e-14, 1e-2]
    /// [default: 1e-10].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, conflicts_with = "step")]
    pub tol: Option<f64>,
    /// Step of the fixed-step methods (rk4, euler), in (0, 1] [default: 1e-3].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub step: Option<f64>,
    /// Figure size in points, WIDTHxHEIGHT, each in [100, 10000] (default 900x600).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_figure_size)]
    pub size: Option<[f32; 2]>,
    /// A .png's resolution in pixels per inch (a point is 1/72 inch), in
    /// [72, 600], at most 20000 pixels along the longer side [default:
    /// 144, 2 pixels per point].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub dpi: Option<f64>,
    /// Stop after this many seconds (0 < S ≤ 1e7), writing nothing, exit 1.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub max_seconds: Option<f64>,
    /// Lower end of θν: the bifurcation diagram's, the basins' or the phase grid's range, or where --play starts (radians).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, requires = "theta_nu_to")]
    pub theta_nu_from: Option<f64>,
    /// Upper end of θν (with --theta-nu-from).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, requires = "theta_nu_from")]
    pub theta_nu_to: Option<f64>,
    /// The parameter the bifurcation diagram varies: theta-nu, kappa,
    /// gamma, nu or omega, the others held fixed (as `bifurcation
    /// --param`) [default: the session's, else theta-nu].
    #[arg(long)]
    pub param: Option<ContParam>,
    /// Lower end of the diagram's range of --param (with --to; for
    /// theta-nu the same as --theta-nu-from) [default: the session's,
    /// else the window's].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, requires = "to", conflicts_with_all = ["theta_nu_from", "theta_nu_to"])]
    pub from: Option<f64>,
    /// Upper end of the diagram's range of --param (with --from).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, requires = "from")]
    pub to: Option<f64>,
    /// Lower end of the bifurcation diagram's θ axis, both ends in
    /// [-1000, 1000] radians [default: the columns' range].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, requires = "theta_to")]
    pub theta_from: Option<f64>,
    /// Upper end of the diagram's θ axis (with --theta-from).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, requires = "theta_from")]
    pub theta_to: Option<f64>,
    /// Lower end of the phase grid's κ range, in [1e-6, 1e3] (κ's range).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, requires = "kappa_to")]
    pub kappa_from: Option<f64>,
    /// Upper end of the phase grid's κ range (with --kappa-from).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, requires = "kappa_from")]
    pub kappa_to: Option<f64>,
    /// The Basins view's θν columns, in [2, 400] [default: the session's, else 48].
    #[arg(long, value_parser = parse_count, allow_hyphen_values = true)]
    pub columns: Option<usize>,
    /// The phase grid's θν columns, in [2, 200].
    #[arg(long, value_parser = parse_count, allow_hyphen_values = true)]
    pub theta_nu_steps: Option<usize>,
    /// The phase grid's κ rows, in [2, 200].
    #[arg(long, value_parser = parse_count, allow_hyphen_values = true)]
    pub kappa_steps: Option<usize>,
    /// Frames of an animated GIF (--view block or plane, or with --play,
    /// --out x.gif), in [2, 600], 10 a second.
    #[arg(long, value_parser = parse_count, allow_hyphen_values = true)]
    pub frames: Option<usize>,
    /// Play θν over the GIF's frames, from the diagram's range's lower end
    /// to its upper (or from --theta-nu-from to --theta-nu-to), the view
    /// following it as the window's Play θν does: --view return-map (its
    /// axes held, the fixed point moving along the diagonal), plane, block,
    /// bifurcation (its θν cursor), events or time-series; with --frames N
    /// and --out x.gif.
    #[arg(long)]
    pub play: bool,
    /// The GIF's playback speed, in [0.05, 1]: 1 plays as the window does
    /// (slips at the slip speed, stick phases 0.6 s each), 0.25 four times
    /// slower [default: 1].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, requires = "frames")]
    pub speed: Option<f64>,
    /// The slip speed the block and plane play at, in time units per second
    /// of playback, in [0.1, 10] (the window's "slip speed") [default: the
    /// session's, else 1].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub slip_speed: Option<f64>,
    /// The return map as f(θ) − θ against θ: its distance from the
    /// diagonal, where f hugs it (creep, Fig. 3a's inset). --view return-map only.
    #[arg(long)]
    pub map_difference: bool,
    /// Mark the current parameters: the θν line on the diagram, its λ
    /// strip and the phase diagram (with κ's there). A figure leaves them
    /// out unless asked for.
    #[arg(long)]
    pub crosshair: bool,
    /// A title over the figure (by default a figure has none: a journal
    /// sets its caption itself).
    #[arg(long)]
    pub title: Option<String>,
    /// Every text's size in points (tick labels, axis titles, legend,
    /// title), in [4, 72] [default: the window's, 13 for the tick labels].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub font_size: Option<f64>,
    /// The text's font family in a .svg, .pdf or .png: a family name
    /// (letters, digits, spaces, '-', '_', '.'; such as "DejaVu Serif")
    /// or a generic family (serif, sans-serif, monospace). The SVG names
    /// it (with sans-serif faces after it); the PDF and PNG set the text
    /// in it where this system has it, else in the built-in sans-serif,
    /// with a note on stderr [default: sans-serif].
    #[arg(long)]
    pub font: Option<String>,
    /// Draw the figure with the window's look instead of a page's: its
    /// background, a frame and the view's name.
    #[arg(long)]
    pub window_look: bool,
    /// Draw the continued branches with their special points (PD, fold,
    /// border, ...) over the diagram, as the window's "Find bifurcations"
    /// does (a session's kept branches are used, not computed again).
    /// --view bifurcation only.
    #[arg(long)]
    pub branches: bool,
    /// Draw the doubling curves with their generalised flips, and the fold
    /// curves, over the phase diagram, as the window's "Boundaries" does
    /// (a session's kept curves are used). --view phase only.
    #[arg(long)]
    pub boundaries: bool,
    /// Seeds per column of the diagram, or per cell of the phase diagram,
    /// in [0, 64]: any seed draws every attractor found there (the
    /// window's "every attractor"); 0 only the followed one [default: the
    /// session's, else 0].
    #[arg(long, value_parser = parse_count, allow_hyphen_values = true)]
    pub seeds: Option<usize>,
    /// Where the legend goes: outside (in a row above the plot it
    /// describes); inside the plot, boxed, in the corner over the least
    /// data (inside) or in the one named (inside-top-right,
    /// inside-top-left, inside-bottom-right, inside-bottom-left); or none
    /// (no legend: a caption says what is drawn). Its entries are only
    /// what the plot shows; its keys shrink with --font-size and --size.
    #[arg(long, value_enum, default_value_t = LegendFlag::Outside)]
    pub legend: LegendFlag,
}

/// `figure --legend`'s places.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum LegendFlag {
    Outside,
    Inside,
    InsideTopRight,
    InsideTopLeft,
    InsideBottomRight,
    InsideBottomLeft,
    None,
}

/// The checked flags: the view, format and ranges.
#[derive(Clone, Debug)]
pub struct Checked {
    pub view: String,
    pub format: Format,
    pub theta_nu: Option<(f64, f64)>,
    pub theta: Option<(f64, f64)>,
    pub kappa: Option<(f64, f64)>,
}

/// Checks the flags before any work: the view, the output's extension and
/// that it can be written, the ranges and counts.
pub fn check(a: &FigureArgs) -> Result<Checked, CliError> {
    if !VIEW_KEYS.contains(&a.view.as_str()) {
        return Err(CliError::Usage(format!(
            "--view: unknown view '{}': expected one of {}",
            echo(&a.view),
            VIEW_KEYS.join(", ")
        )));
    }
    let format = format_of(&a.out)?;
    check_frames(a, format)?;
    let theta_nu = range("theta-nu", a.theta_nu_from, a.theta_nu_to)?;
    if let Some((lo, hi)) = theta_nu
        && (lo < -std::f64::consts::PI || hi > std::f64::consts::PI)
    {
        return Err(CliError::Usage(format!(
            "--theta-nu-from = {}, --theta-nu-to = {}: must lie in [-pi, pi]",
            short(lo),
            short(hi)
        )));
    }
    if a.map_difference && a.view != "return-map" {
        return Err(CliError::Usage(format!(
            "--map-difference: only the return-map view draws f(θ) − θ, not '{}'",
            echo(&a.view)
        )));
    }
    if let Some(v) = a.slip_speed
        && !(0.1..=10.0).contains(&v)
    {
        return Err(CliError::Usage(format!(
            "--slip-speed = {} is out of range: must lie in [0.1, 10] (time units per second)",
            short(v)
        )));
    }
    super::figure_look::check_look(a, format)?;
    check_overlays(a)?;
    let theta = range("theta", a.theta_from, a.theta_to)?;
    // θ is an angle: an axis beyond ±1000 radians (θν's bound in
    // `bifurcation` and `continue`) shows nothing, and one of ±1e50 once
    // overflowed the diagram's single-precision image into x="inf".
    if let Some((lo, hi)) = theta
        && (lo < -MAX_ABS_THETA || hi > MAX_ABS_THETA)
    {
        return Err(CliError::Usage(format!(
            "--theta-from = {}, --theta-to = {}: must lie in [-1000, 1000] radians",
            short(lo),
            short(hi)
        )));
    }
    let kappa = range("kappa", a.kappa_from, a.kappa_to)?;
    // κ's own range: a grid past it failed only after starting.
    let (k_lo, k_hi) = (
        *crate::model::KAPPA_RANGE.start(),
        *crate::model::KAPPA_RANGE.end(),
    );
    if let Some((lo, hi)) = kappa
        && (lo < k_lo || hi > k_hi)
    {
        return Err(CliError::Usage(format!(
            "--kappa-from = {}, --kappa-to = {}: must lie in [{k_lo:e}, {k_hi:e}], κ's range",
            short(lo),
            short(hi),
        )));
    }
    check_counts(a)?;
    crate::output::check_writable(&a.out, false).map_err(|e| match e {
        crate::output::OutputError::Exists { path } => CliError::Usage(format!(
            "--out: {} already exists: a figure never overwrites a file, choose another name",
            path.display()
        )),
        e => CliError::Usage(format!("--out: {e}")),
    })?;
    Ok(Checked {
        view: a.view.clone(),
        format,
        theta_nu,
        theta,
        kappa,
    })
}
