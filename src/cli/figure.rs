//! `oneblock figure`: one view of the window as a file, drawn headless by
//! the window's own view code (no display, no GPU): an SVG, or a PNG
//! rasterised from that SVG, by the output's extension. Only the figure is
//! drawn (title, axes with units, legend), never the view's buttons. Needs
//! the `gui` feature (egui draws the view).

use super::CliError;
pub use super::figure_flags::{
    Checked, FONT_SIZES, FigureArgs, Format, GIF_SIZE, MAX_FRAMES, MAX_GIF_SIDE, MAX_SEEDS,
    PLAY_VIEW_KEYS, check, format_of,
};
#[cfg(feature = "gui")]
use super::run_control::{Limits, run_bounded};
#[cfg(feature = "gui")]
use super::values::echo;
#[cfg(feature = "gui")]
use crate::sim::continuation::ContParam;

/// The default figure size in points.
pub const DEFAULT_SIZE: [f32; 2] = [900.0, 600.0];
/// PNG pixels per point: sharp on a slide or a page.
pub const PNG_SCALE: f32 = 2.0;

/// The view's own flags into `settings`: the phase grid's ranges and
/// steps, the Basins view's columns and θν range.
#[cfg(feature = "gui")]
fn view_flags(
    view: crate::app::ViewKind,
    a: &FigureArgs,
    c: &Checked,
    settings: &mut crate::app::Settings,
) {
    use crate::app::ViewKind;
    if view == ViewKind::Phase {
        let ph = &mut settings.phase;
        let mut r = ph.current();
        r.theta_nu = c.theta_nu.unwrap_or(r.theta_nu);
        r.kappa = c.kappa.unwrap_or(r.kappa);
        ph.range = r;
        ph.zoom.clear();
        ph.theta_nu_steps = a.theta_nu_steps.unwrap_or(ph.theta_nu_steps);
        ph.kappa_steps = a.kappa_steps.unwrap_or(ph.kappa_steps);
    }
    if let Some(n) = a.seeds {
        settings.sweep_seeds = n;
        settings.phase.seeds = n;
    }
    if view == ViewKind::Basins {
        let b = &mut settings.basins;
        b.columns = a.columns.unwrap_or(b.columns);
        if let Some(tn) = c.theta_nu {
            b.zoom = vec![tn];
        }
    }
}

/// The diagram's varied parameter (--param, else the session's) and
/// range (--from and --to) into `settings`; the diagram's θν range, which
/// --theta-nu-from and --theta-nu-to give only when θν is varied. A
/// range of another parameter replaces the session's zoom (`zoom`).
#[cfg(feature = "gui")]
fn diagram_flags(
    view: crate::app::ViewKind,
    a: &FigureArgs,
    c: &Checked,
    settings: &mut crate::app::Settings,
    zoom: &mut Vec<crate::app::bifurcation::Zoom>,
) -> Result<Option<(f64, f64)>, CliError> {
    use crate::app::ViewKind;
    let bifurcation = view == ViewKind::Bifurcation;
    if !bifurcation && (a.param.is_some() || a.from.is_some()) {
        let flag = if a.param.is_some() {
            "--param"
        } else {
            "--from"
        };
        return Err(CliError::Usage(format!(
            "{flag}: only the bifurcation view varies a parameter, not '{}'",
            echo(&c.view)
        )));
    }
    if !bifurcation {
        return Ok(c
            .theta_nu
            .filter(|_| !matches!(view, ViewKind::Phase | ViewKind::Basins)));
    }
    let param = a.param.unwrap_or(settings.diagram.param);
    if param != settings.diagram.param {
        settings.diagram.param = param;
        zoom.clear();
    }
    let range = a.from.zip(a.to);
    let name = param.name();
    if let Some((from, to)) = range {
        param_range(param, from, to, &settings.params)?;
    }
    if param == ContParam::ThetaNu {
        return Ok(range.or(c.theta_nu));
    }
    if c.theta_nu.is_some() {
        return Err(CliError::Usage(format!(
            "--theta-nu-from: this diagram varies {name}, with θν held at {}: give {name}'s range \
             with --from and --to",
            super::values::short(settings.params.theta_nu)
        )));
    }
    if a.play {
        return Err(CliError::Usage(format!(
            "--play: θν plays over a diagram in θν; this one varies {name} (--param theta-nu)"
        )));
    }
    if let Some((from, to)) = range {
        settings
            .diagram
            .set_range(param, (from.min(to), from.max(to)));
        zoom.clear();
    }
    Ok(None)
}

/// --from and --to as a range of `param` over `base`: each end as
/// `bifurcation --param` checks it, two different ends, and within the
/// diagram's range of it (θν's [-π, π], as --theta-nu-from and
/// --theta-nu-to: --to 1e308 once drew an image at x="inf").
#[cfg(feature = "gui")]
fn param_range(param: ContParam, from: f64, to: f64, base: &crate::Params) -> Result<(), CliError> {
    use super::values::short;
    use crate::app::settings::DiagramAxis;
    let name = param.name();
    for (flag, v) in [("from", from), ("to", to)] {
        if param == ContParam::ThetaNu && v.abs() > std::f64::consts::PI {
            return Err(CliError::Usage(format!(
                "--{flag} = {} is out of range: theta-nu must lie in [-pi, pi], as --theta-nu-from and --theta-nu-to",
                short(v)
            )));
        }
        if v.is_finite() && v <= 0.0 && param.spans_decades() {
            return Err(CliError::Usage(format!(
                "--{flag} = {} is out of range: {name} must be positive (its axis is logarithmic)",
                short(v)
            )));
        }
        super::continue_cmd::range_end(flag, v, param, base)?;
    }
    if from == to {
        return Err(CliError::Usage(format!(
            "--to = {} equals --from: the range is empty",
            short(to)
        )));
    }
    if !DiagramAxis::is_valid_range(param, (from.min(to), from.max(to))) {
        let within = if param == ContParam::ThetaNu {
            "must lie in [-pi, pi], as --theta-nu-from and --theta-nu-to"
        } else {
            "its width or centre overflows"
        };
        return Err(CliError::Usage(format!(
            "--from = {}, --to = {}: {name}'s range {within}",
            short(from),
            short(to)
        )));
    }
    Ok(())
}

/// The look the flags ask for: a page's, or with --window-look the
/// window's.
#[cfg(feature = "gui")]
fn look(a: &FigureArgs) -> crate::app::svg_render::Look {
    crate::app::svg_render::Look {
        window: a.window_look,
        title: a.title.clone(),
        font_size: a.font_size.map(|v| v as f32),
        legend: legend_place(a.legend),
        font: a.font.clone(),
    }
}

/// `--legend`'s place.
#[cfg(feature = "gui")]
fn legend_place(l: super::figure_flags::LegendFlag) -> crate::app::style::LegendPlace {
    use super::figure_flags::LegendFlag as F;
    use crate::app::legend::Corner;
    use crate::app::style::LegendPlace as P;
    match l {
        F::Outside => P::Outside,
        F::Inside => P::Inside(Corner::Best),
        F::InsideTopRight => P::Inside(Corner::TopRight),
        F::InsideTopLeft => P::Inside(Corner::TopLeft),
        F::InsideBottomRight => P::Inside(Corner::BottomRight),
        F::InsideBottomLeft => P::Inside(Corner::BottomLeft),
        F::None => P::Hidden,
    }
}

/// The model's flags over `p` (the preset's or the session's), checked.
#[cfg(feature = "gui")]
fn model_flags(a: &FigureArgs, p: &mut crate::Params) -> Result<(), CliError> {
    p.kappa = a.model.kappa.unwrap_or(p.kappa);
    p.gamma = a.model.gamma.unwrap_or(p.gamma);
    p.nu = a.model.nu.unwrap_or(p.nu);
    p.theta_nu = a.model.theta_nu.unwrap_or(p.theta_nu);
    p.omega = a.model.omega.unwrap_or(p.omega);
    p.validate().map_err(super::values::param_error)
}

/// The session --session names, read (a warning said for what it set
/// aside).
#[cfg(feature = "gui")]
fn read_session(a: &FigureArgs) -> Result<Option<crate::app::session::Session>, CliError> {
    let Some(p) = &a.session else {
        return Ok(None);
    };
    let loaded = crate::app::session::Session::read(p)
        .map_err(|e| CliError::Usage(format!("--session: {e}")))?;
    if let Some(m) = &loaded.message {
        eprintln!("warning: {m}");
    }
    Ok(Some(loaded.session))
}

/// The integrator every job of the figure runs with: the flags' (as every
/// command's: dop853 at 1e-10 unless told), or a session's own accuracy
/// when it is given and no flag is.
#[cfg(feature = "gui")]
fn accuracy_flags(a: &FigureArgs, settings: &mut crate::app::Settings) -> Result<(), CliError> {
    use crate::app::settings::AccuracyMode;
    use crate::integrate::Method;
    let flagged = a.method.is_some() || a.tol.is_some() || a.step.is_some();
    if a.session.is_some() && !flagged {
        return Ok(());
    }
    let method = match (a.method, a.session.is_some()) {
        (Some(m), _) => m,
        (None, true) => settings.method,
        (None, false) => Method::Dop853,
    };
    let solver = super::common::SolverArgs {
        method,
        tol: a.tol,
        step: a.step,
    }
    .settings()?;
    settings.accuracy = AccuracyMode::Custom;
    settings.method = solver.method;
    if method.is_adaptive() {
        settings.tol = solver.rtol;
    } else {
        settings.step = solver.step;
    }
    Ok(())
}

/// The θν a played GIF runs over: `range` (its flags'), else its
/// diagram's.
#[cfg(feature = "gui")]
fn play_span(
    range: Option<(f64, f64)>,
    fig: &crate::app::figure::Figure,
    frames: usize,
) -> crate::app::animation::PlaySpan {
    use crate::app::animation::PlaySpan;
    match range {
        Some((from, to)) => PlaySpan { from, to, frames },
        None => PlaySpan::of_diagram(fig, frames),
    }
}

/// The PDF's and PNG's fonts: the family --font names where this system
/// has it (said once on stderr where it has not).
#[cfg(feature = "gui")]
fn pdf_png_fonts(font: Option<&str>) -> std::sync::Arc<resvg::usvg::fontdb::Database> {
    let (db, note) = crate::app::figure::fonts_for(font);
    if let Some(n) = note {
        eprintln!("note: {n}");
    }
    db
}

/// Draws the figure and writes it.
#[cfg(feature = "gui")]
pub fn run(a: FigureArgs) -> Result<(), CliError> {
    use crate::app::animation::{gif, play_gif};
    use crate::app::figure::{Figure, pdf_of_svg_with, png_of_svg_with, svg};
    use crate::app::{Settings, ViewKind};
    let c = check(&a)?;
    let view = ViewKind::from_key(&c.view)
        .ok_or_else(|| CliError::Usage(format!("--view: unknown view '{}'", echo(&c.view))))?;
    let session = read_session(&a)?;
    let (mut settings, mut zoom) = session.as_ref().map_or_else(
        || (Settings::default(), Vec::new()),
        |s| (s.settings.clone(), s.bifurcation_zoom.clone()),
    );
    let preset = a
        .model
        .preset
        .map(|p| p.key)
        .or_else(|| a.session.is_none().then_some("fig3b"));
    if let Some(k) = preset
        && let Some(p) = crate::model::preset(k)
    {
        settings.apply_preset(&p.params, p.key);
    }
    model_flags(&a, &mut settings.params)?;
    accuracy_flags(&a, &mut settings)?;
    settings.map_difference |= a.map_difference;
    if let Some(v) = a.slip_speed {
        settings.block_speed = v as f32;
    }
    view_flags(view, &a, &c, &mut settings);
    let theta_nu = diagram_flags(view, &a, &c, &mut settings, &mut zoom)?;
    let size = a.size.unwrap_or(match c.format {
        Format::Gif => GIF_SIZE,
        _ => DEFAULT_SIZE,
    });
    let fig = Figure {
        view,
        settings,
        zoom,
        theta_nu,
        theta: c.theta,
        size: eframe::egui::vec2(size[0], size[1]),
        crosshair: a.crosshair,
        look: look(&a),
        overlays: crate::app::figure::Overlays {
            branches: a.branches,
            boundaries: a.boundaries,
        },
        session,
    };
    // Bounded like every long command (a large phase grid takes a while):
    // a line of life on a terminal; --max-seconds or Ctrl+C end it with one
    // line, writing nothing.
    let limits = Limits::start(super::common::max_seconds(a.max_seconds)?);
    let size = fig.size;
    let scale = a.dpi.map_or(PNG_SCALE, |d| (d / 72.0) as f32);
    let (format, frames, speed) = (c.format, a.frames.unwrap_or(0), a.speed.unwrap_or(1.0));
    let play = a
        .play
        .then(|| play_span(c.theta_nu.or(a.from.zip(a.to)), &fig, frames));
    let font = a.font.clone();
    let bytes = run_bounded("figure", &limits, move || match format {
        Format::Svg => svg(&fig).map(String::into_bytes),
        Format::Pdf => svg(&fig).and_then(|t| pdf_of_svg_with(&t, &pdf_png_fonts(font.as_deref()))),
        Format::Png => svg(&fig)
            .and_then(|t| png_of_svg_with(&t, size, scale, &pdf_png_fonts(font.as_deref()))),
        Format::Gif => match play {
            Some(span) => play_gif(fig, span),
            None => gif(&fig, frames, speed),
        },
        Format::Csv => super::figure_csv::data_csv(&fig).map(String::into_bytes),
    })?
    .map_err(CliError::Failed)?;
    for n in crate::app::style::take_figure_notes() {
        eprintln!("note: {n}");
    }
    crate::output::write_output(&a.out, &bytes, false)
        .map_err(|e| CliError::Failed(format!("--out: {e}")))?;
    eprintln!("saved {}", a.out.display());
    Ok(())
}

/// Without the window's code there is nothing to draw with.
#[cfg(not(feature = "gui"))]
pub fn run(a: FigureArgs) -> Result<(), CliError> {
    check(&a)?;
    Err(CliError::Failed(
        "figure draws with the window's code: this oneblock was built without it \
         (cargo feature 'gui'); rebuild with default features"
            .into(),
    ))
}
