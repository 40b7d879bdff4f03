//! `oneblock figure`'s flags checked before any work: the view, the
//! output's format and that it can be written, the ranges and counts,
//! the animation's flags (`--frames`, `--speed`, `--play`) and the look's;
//! each refusal one line naming the flag and its valid range (exit 2).

use std::path::Path;

use super::CliError;
use super::figure::FigureArgs;
use super::gui::VIEW_KEYS;
use super::values::{echo, short};

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
    /// The Basins view's columns as a table.
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

/// --frames and a .gif go together, for the animated views only, within
/// the bounds.
fn check_frames(a: &FigureArgs, format: Format) -> Result<(), CliError> {
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
        (Format::Csv, _) if a.view != "basins" => usage(format!(
            "--out: only the basins view writes a .csv (its columns), not '{}'",
            echo(&a.view)
        )),
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

/// --title and --font-size: a title with some text, a size in
/// [`FONT_SIZES`]; neither with the window's look, which has its own.
fn check_look(a: &FigureArgs) -> Result<(), CliError> {
    let usage = |m: String| Err(CliError::Usage(m));
    if let Some(t) = &a.title
        && t.trim().is_empty()
    {
        return usage("--title: give the title's text (or leave --title out)".into());
    }
    if let Some(v) = a.font_size
        && !(FONT_SIZES.0..=FONT_SIZES.1).contains(&v)
    {
        return usage(format!(
            "--font-size = {} is out of range: must lie in [{}, {}] (points)",
            short(v),
            FONT_SIZES.0,
            FONT_SIZES.1
        ));
    }
    if a.window_look && (a.title.is_some() || a.font_size.is_some()) {
        return usage(
            "--window-look draws the window's title and text sizes: leave out --title and --font-size"
                .into(),
        );
    }
    Ok(())
}

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
    check_look(a)?;
    check_overlays(a)?;
    let theta = range("theta", a.theta_from, a.theta_to)?;
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
