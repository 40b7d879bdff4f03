//! `oneblock phase --png FILE`: the grid just computed, drawn by
//! `oneblock figure`'s code (the window's Phase view, figure only: its
//! title-less page, axis titles with units, ticks, legend of what is drawn
//! and class colours), so that `phase --png` and `figure --view phase`
//! over the same grid are the same picture. The cells are not computed
//! again: the figure's job model is handed the grid. `--boundaries` curves
//! are drawn as the view's Boundaries are, each kind and doubling level in
//! its own style. `--size` is the figure's, in points; `--dpi` the PNG's
//! pixels per inch. Needs the `gui` feature (the view draws the figure).

use std::path::{Path, PathBuf};

use super::CliError;
use super::figure_flags::dpi_within;
use super::phase::PhaseArgs;
use crate::model::Params;
use crate::sim::continuation::Curve;
use crate::sim::phase::PhaseCell;

/// What the picture's file holds, by its name's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Svg,
    Pdf,
    Png,
}

impl Kind {
    /// .svg and .pdf (any case) are vector files, any other name a PNG.
    fn of(path: &Path) -> Kind {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if ext.eq_ignore_ascii_case("svg") {
            Kind::Svg
        } else if ext.eq_ignore_ascii_case("pdf") {
            Kind::Pdf
        } else {
            Kind::Png
        }
    }
}

/// The picture `phase --png` writes, its flags checked.
// Without the window's code a picture is refused before it is made.
#[cfg_attr(not(feature = "gui"), allow(dead_code))]
pub struct Picture {
    path: PathBuf,
    kind: Kind,
    /// The figure's size in points (--size, else `figure`'s default).
    size: [f32; 2],
    /// PNG pixels per point (--dpi / 72, else `figure`'s).
    scale: f32,
    /// The curves of --boundaries in (θν, κ).
    boundaries: Vec<Curve>,
}

/// The grid the picture shows: its cells (rows of κ, each of columns of
/// θν), their ranges (ends included), and what the view's settings say
/// of them (the model, the budgets, the seeds).
#[cfg_attr(not(feature = "gui"), allow(dead_code))]
pub struct Grid<'a> {
    pub cells: &'a [Vec<PhaseCell>],
    pub theta_nu: (f64, f64),
    pub kappa: (f64, f64),
    pub params: Params,
    pub transient: usize,
    pub keep: usize,
    pub seeds: usize,
}

/// Checks --png, --size, --dpi and --boundaries before any work; `None`
/// without --png. Without the `gui` feature --png is refused in one line.
pub fn check(args: &PhaseArgs) -> Result<Option<Picture>, CliError> {
    let Some(path) = &args.png else {
        return Ok(None);
    };
    if !cfg!(feature = "gui") {
        return Err(CliError::Usage(
            "--png: the picture is drawn by the window's figure code, which this oneblock was \
             built without (cargo feature 'gui'): rebuild with default features, or leave --png out"
                .into(),
        ));
    }
    let kind = Kind::of(path);
    let size = args.size.unwrap_or(super::figure::DEFAULT_SIZE);
    let scale = match args.dpi {
        None => super::figure::PNG_SCALE,
        Some(_) if kind != Kind::Png => {
            return Err(CliError::Usage(
                "--dpi: only a PNG has a resolution (an SVG or PDF is vector): leave --dpi out"
                    .into(),
            ));
        }
        Some(d) => {
            dpi_within(d, size)?;
            (d / 72.0) as f32
        }
    };
    let boundaries = match &args.boundaries {
        Some(b) => super::phase_boundaries::read_boundaries(b)
            .map_err(|e| CliError::Usage(format!("--boundaries: {}: {e}", b.display())))?,
        None => Vec::new(),
    };
    Ok(Some(Picture {
        path: path.clone(),
        kind,
        size,
        scale,
        boundaries,
    }))
}

/// Draws `grid` (with the curves of --boundaries) as `figure --view
/// phase` draws its grid, and writes it (atomically; an existing file
/// only with --force). A picture that cannot be encoded is an error,
/// never an empty file.
#[cfg(feature = "gui")]
pub fn write(p: &Picture, grid: &Grid<'_>, force: bool) -> Result<(), CliError> {
    use crate::app::figure::{Figure, given, pdf_of_svg, png_of_svg, svg_of};
    use crate::app::{Settings, ViewKind};
    let mut settings = Settings {
        params: grid.params,
        ..Settings::default()
    };
    let ph = &mut settings.phase;
    ph.range = crate::app::settings::PhaseRange {
        theta_nu: grid.theta_nu,
        kappa: grid.kappa,
    };
    ph.zoom.clear();
    ph.kappa_steps = grid.cells.len();
    ph.theta_nu_steps = grid.cells.first().map_or(0, Vec::len);
    (ph.transient, ph.keep, ph.seeds) = (grid.transient, grid.keep, grid.seeds);
    let size = eframe::egui::vec2(p.size[0], p.size[1]);
    // `figure --view phase`'s figure with its default flags: a page's
    // look, no cross-hair, the curves given rather than computed.
    let fig = Figure {
        view: ViewKind::Phase,
        settings,
        zoom: Vec::new(),
        theta_nu: None,
        theta: None,
        size,
        crosshair: false,
        look: crate::app::svg_render::Look::default(),
        overlays: crate::app::figure::Overlays::default(),
        session: None,
    };
    let jobs = given::phase_jobs(grid.cells, grid.theta_nu, grid.kappa, p.boundaries.clone());
    let svg = svg_of(&fig, &jobs);
    for n in crate::app::style::take_figure_notes() {
        eprintln!("note: {n}");
    }
    let bytes = match p.kind {
        Kind::Svg => Ok(svg.into_bytes()),
        Kind::Pdf => pdf_of_svg(&svg),
        Kind::Png => png_of_svg(&svg, size, p.scale),
    }
    .map_err(|e| CliError::Failed(format!("--png: {e}")))?;
    super::common::emit_as("png", &p.path, &bytes, force)
}

/// Without the window's code there is no picture ([`check`] refuses it).
#[cfg(not(feature = "gui"))]
pub fn write(_: &Picture, _: &Grid<'_>, _: bool) -> Result<(), CliError> {
    Err(CliError::Usage(
        "--png: this oneblock was built without the window's figure code (cargo feature 'gui')"
            .into(),
    ))
}
