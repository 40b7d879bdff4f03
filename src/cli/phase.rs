//! `oneblock phase`: the phase diagram in (θν, κ) (the paper's Fig. 4), CSV
//! `theta_nu,kappa,period,lyapunov,regime,iterates,class,lyapunov_stderr`
//! and optionally a PNG. Rows (one per κ) run in parallel; each row is a
//! continued sweep along θν, so the file depends only on the flags, not on
//! the number of threads. Ctrl+C stops the run and writes nothing.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;

use super::CliError;
use super::bifurcation::theta_nu_end;
use super::common::{
    SolverArgs, check_out, check_second_out, count_in, describe_sweep, emit, emit_as, finite,
    max_seconds, warn_validity,
};
use super::run_control::{Limits, Progress};
use super::values::{given_or_preset, param_error, parse_count, parse_number, preset_params};
use crate::formats::{PHASE_COLUMNS, PHASE_LEGEND, class_colour, legend_class, phase_row};
use crate::jobs::{Axis, JobError, PhaseSpec, PhaseTuning, Spec, Update, run_collect};
use crate::model::Params;
use crate::sim::interpolant::MapTally;
use crate::sim::phase::{PhaseCell, PhaseOptions};
use crate::sim::theta_nu_grid;

/// A phase diagram: the attractor's class over a (θν, κ) grid.
#[derive(Debug, Clone, Args)]
pub struct PhaseArgs {
    /// Take γ, ν and Ω from a named parameter set (fig3a, fig3b, fig4,
    /// creep, chaos, intermittent); the flags below override them.
    #[arg(long)]
    pub preset: Option<String>,
    /// γ, the friction weakening, in [0.1, 1e4] (outside, slips turn into
    /// steady sliding or never stop, which the map cannot represent).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, required_unless_present = "preset")]
    pub gamma: Option<f64>,
    /// ν, the pulling speed, in [1e-12, 0.1] (beyond, slips turn into steady
    /// sliding, which the map cannot represent; the model assumes ν ≤ 1e-2).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, required_unless_present = "preset")]
    pub nu: Option<f64>,
    /// Ω, the memory of the friction direction, in (0, 1e8] (the model
    /// assumes [1, 1e4]) [default: 50,
    /// or the preset's].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub omega: Option<f64>,
    /// First κ (the bottom row), in [1e-6, 1e3].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub kappa_from: f64,
    /// Last κ (the top row), in [1e-6, 1e3].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub kappa_to: f64,
    /// Number of κ rows, evenly spaced, ends included (1 to 10000).
    #[arg(long, value_parser = parse_count, allow_hyphen_values = true)]
    pub kappa_steps: usize,
    /// First θν, in radians, in [-1000, 1000].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = parse_number)]
    pub theta_nu_from: f64,
    /// Last θν, in radians, in [-1000, 1000].
    #[arg(long, default_value_t = std::f64::consts::FRAC_PI_2, allow_hyphen_values = true, value_parser = parse_number)]
    pub theta_nu_to: f64,
    /// Number of θν columns, evenly spaced, ends included (1 to 10000;
    /// rows × columns ≤ 4e6).
    #[arg(long, value_parser = parse_count, allow_hyphen_values = true)]
    pub theta_nu_steps: usize,
    /// The most iterates a cell spends looking for a period (0 to 1e6).
    #[arg(long, default_value_t = 400, value_parser = parse_count, allow_hyphen_values = true)]
    pub transient: usize,
    /// The most iterates with f'(θ) for the Lyapunov exponent when no period
    /// was found (16 to 1e6).
    #[arg(long, default_value_t = 128, value_parser = parse_count, allow_hyphen_values = true)]
    pub keep: usize,
    #[command(flatten)]
    pub solver: SolverArgs,
    /// Tolerance of the period test, in radians, in (0, 1] [default: 1e4·tol
    /// within [1e-9, 1e-3]; 1e-6 for the fixed-step methods].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub period_tol: Option<f64>,
    /// No early exit: every cell runs the whole transient and keeps every
    /// iterate with f'(θ) (the reference the fast path is compared with).
    #[arg(long)]
    pub brute_force: bool,
    /// How a cell evaluates the map after its first 400 iterates: direct,
    /// interpolant (docs/interpolant.md) or auto (the interpolant when at
    /// least 20000 iterates are left). Where refused, the cell integrates.
    #[arg(long, default_value = "auto")]
    pub map: String,
    /// Worker threads, 1 to 1024 [default: the number of cores]. The output
    /// does not depend on it.
    #[arg(long, value_parser = parse_count, allow_hyphen_values = true)]
    pub threads: Option<usize>,
    /// CSV file ("-" = stdout) [default: stdout, or none with --png].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Also (or only) render the diagram as a PNG.
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Draw these curves over the PNG: a CSV with theta_nu and kappa
    /// columns, as `oneblock continue --curve` writes (needs --png).
    #[arg(long, requires = "png")]
    pub boundaries: Option<PathBuf>,
    /// Overwrite existing --out / --png files.
    #[arg(long)]
    pub force: bool,
    /// Stop after this many seconds, in (0, 1e7], writing nothing, exit 1.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub max_seconds: Option<f64>,
}

/// The most rows or columns of a grid.
pub const MAX_STEPS: usize = 10_000;
/// The most cells of a grid.
pub const MAX_CELLS: usize = 4_000_000;

/// The checked inputs of `phase`.
pub struct Plan {
    params: Params,
    settings: crate::SolverSettings,
    kappas: Vec<f64>,
    theta_nus: Vec<f64>,
    opts: PhaseOptions,
    threads: usize,
    out: Option<PathBuf>,
    max_seconds: Option<f64>,
    boundaries: Vec<super::phase_boundaries::Polyline>,
}

/// Checks the flags and the outputs before any work.
pub fn check(args: &PhaseArgs) -> Result<Plan, CliError> {
    let t_from = theta_nu_end("theta-nu-from", args.theta_nu_from)?;
    let t_to = theta_nu_end("theta-nu-to", args.theta_nu_to)?;
    let base = preset_params(args.preset.as_deref())?;
    let params = Params {
        kappa: 1.0,
        gamma: given_or_preset("gamma", args.gamma, base.map(|b| b.gamma))?,
        nu: given_or_preset("nu", args.nu, base.map(|b| b.nu))?,
        theta_nu: t_from,
        omega: args.omega.or(base.map(|b| b.omega)).unwrap_or(50.0),
    };
    params.validate().map_err(param_error)?;
    // Each end of the κ range is a κ of the grid, checked as one, under
    // its own flag's name.
    let (k_from, k_to) = (
        finite("kappa-from", args.kappa_from)?,
        finite("kappa-to", args.kappa_to)?,
    );
    for (name, k) in [("kappa-from", k_from), ("kappa-to", k_to)] {
        Params { kappa: k, ..params }.validate().map_err(|mut e| {
            e.name = name;
            param_error(e)
        })?;
    }
    let settings = args.solver.settings()?;
    let rows = count_in("kappa-steps", args.kappa_steps, MAX_STEPS)?;
    let cols = count_in("theta-nu-steps", args.theta_nu_steps, MAX_STEPS)?;
    if rows * cols > MAX_CELLS {
        return Err(CliError::Usage(format!(
            "--kappa-steps = {rows} with --theta-nu-steps = {cols} is out of range: at most {MAX_CELLS} cells"
        )));
    }
    if args.transient > 1_000_000 {
        return Err(CliError::Usage(format!(
            "--transient = {} is out of range: must lie in [0, 1e6]",
            args.transient
        )));
    }
    let keep = if (16..=1_000_000).contains(&args.keep) {
        args.keep
    } else {
        return Err(CliError::Usage(format!(
            "--keep = {} is out of range: must lie in [16, 1e6] (the Lyapunov exponent's error needs 8 batches of 2)",
            args.keep
        )));
    };
    let mut opts = PhaseOptions::for_settings(&settings);
    opts.transient = args.transient;
    opts.keep = keep;
    opts.early_exit = !args.brute_force;
    opts.map = super::orbit::map_choice(&args.map)?;
    if let Some(t) = args.period_tol {
        if !(t.is_finite() && t > 0.0 && t <= 1.0) {
            return Err(CliError::Usage(format!(
                "--period-tol = {} is out of range: must lie in (0, 1] radians",
                super::values::short(t)
            )));
        }
        opts.period_tol = t;
    }
    let threads = match args.threads {
        Some(n) => count_in("threads", n, 1024)?,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    // Without --png the CSV goes to stdout unless --out names a file; with
    // --png alone only the picture is written.
    let out = match (&args.out, &args.png) {
        (Some(o), _) => Some(o.clone()),
        (None, None) => Some(PathBuf::from("-")),
        (None, Some(_)) => None,
    };
    if let Some(o) = &out {
        check_out(o, args.force)?;
    }
    if let Some(png) = &args.png {
        if png.as_os_str() == "-" {
            return Err(CliError::Usage(
                "--png: give a file name (the image is not written to stdout)".into(),
            ));
        }
        check_second_out(
            "png",
            png,
            out.as_deref().unwrap_or(Path::new("-")),
            args.force,
        )?;
    }
    let max_seconds = max_seconds(args.max_seconds)?;
    let boundaries = match &args.boundaries {
        Some(b) => super::phase_boundaries::read_boundaries(b)
            .map_err(|e| CliError::Usage(format!("--boundaries: {}: {e}", b.display())))?,
        None => Vec::new(),
    };
    Ok(Plan {
        params: Params {
            kappa: k_from,
            ..params
        },
        settings,
        kappas: theta_nu_grid(k_from, k_to, rows),
        theta_nus: theta_nu_grid(t_from, t_to, cols),
        opts,
        threads,
        out,
        max_seconds,
        boundaries,
    })
}

pub fn run(args: PhaseArgs) -> Result<(), CliError> {
    let Plan {
        params,
        settings,
        kappas,
        theta_nus,
        opts,
        threads,
        out,
        max_seconds,
        boundaries,
    } = check(&args)?;
    let (rows, cols) = (kappas.len(), theta_nus.len());
    let (k_from, k_to) = (kappas[0], kappas[rows - 1]);
    let (t_from, t_to) = (theta_nus[0], theta_nus[cols - 1]);
    let keep = opts.keep;
    warn_validity(&params);
    let progress = Progress::with_extra("phase", "cells", (rows * cols) as u64, "iterates");
    let limits = Limits::start(max_seconds);
    let stop = || limits.stop();
    let spec = PhaseSpec {
        params,
        settings,
        theta_nu: Axis::new(t_from, t_to, cols),
        kappa: Axis::new(k_from, k_to, rows),
        transient: opts.transient,
        keep: opts.keep,
        tuning: PhaseTuning {
            early_exit: opts.early_exit,
            map: opts.map,
            period_tol: Some(opts.period_tol),
        },
    };
    let on_update = |u: &Update| {
        if let Update::PhaseCells { cells, .. } = u {
            for c in cells {
                // The shown count only grows: both counts are read under
                // one lock.
                progress.add_extra(c.cell.iterates);
                progress.inc(1);
            }
        }
    };
    let start = Instant::now();
    let run = run_collect(Spec::Phase(spec), threads, on_update, stop);
    progress.finish();
    let seconds = start.elapsed().as_secs_f64();
    let updates = match run {
        Ok(u) => u,
        Err(JobError::Stop) => return Err(limits.stopped("phase")),
        Err(JobError::Sim(e)) => return Err(e.into()),
        Err(JobError::Failed(m)) => return Err(CliError::Failed(m)),
    };
    let mut grid: Vec<Vec<Option<PhaseCell>>> = vec![vec![None; cols]; rows];
    for u in updates {
        if let Update::PhaseCells { cells, .. } = u {
            for c in cells {
                grid[c.row][c.column] = Some(c.cell);
            }
        }
    }
    let grid: Vec<Vec<PhaseCell>> = grid
        .into_iter()
        .map(|row| row.into_iter().flatten().collect())
        .collect();

    let cells: Vec<&PhaseCell> = grid.iter().flatten().collect();
    let mut csv = String::with_capacity(80 * (cells.len() + 1));
    csv.push_str(PHASE_COLUMNS);
    csv.push('\n');
    for c in &cells {
        writeln!(csv, "{}", phase_row(c)).ok();
    }
    // The picture first: if it cannot be written, neither is the CSV.
    if let Some(png) = &args.png {
        let bytes = render_png_with(&grid, &kappas, &theta_nus, &boundaries);
        emit_as("png", png, &bytes, args.force)?;
    }
    if let Some(o) = &out {
        emit(o, csv.as_bytes(), args.force)?;
    }

    let iterates: u64 = cells.iter().map(|c| c.iterates).sum();
    let evals: u64 = cells.iter().map(|c| c.rhs_evals).sum();
    let mut counts: Vec<(String, usize)> = Vec::new();
    for c in &cells {
        let label = legend_class(c.class).to_string();
        match counts.iter_mut().find(|(l, _)| *l == label) {
            Some((_, n)) => *n += 1,
            None => counts.push((label, 1)),
        }
    }
    counts.sort_by_key(|(l, _)| PHASE_LEGEND.iter().position(|(n, _)| n == l));
    let failed: Vec<&&PhaseCell> = cells.iter().filter(|c| c.error.is_some()).collect();
    for c in failed.iter().take(5) {
        if let Some(e) = &c.error {
            eprintln!(
                "warning: cell kappa = {}, theta-nu = {} failed: {e}",
                c.kappa, c.theta_nu
            );
        }
    }
    eprintln!(
        "phase: {}\n  {rows} x {cols} cells (kappa [{k_from}, {k_to}], theta-nu [{t_from}, {t_to}]), at most {} transient + {keep} kept iterates{}, period tol {:e}\n  {}\n  {iterates} iterates ({:.1} per cell), {:.0} rhs evaluations per iterate; {seconds:.2} s on {threads} thread(s)",
        describe_sweep(&params, &settings),
        opts.transient,
        if opts.early_exit {
            ", early exit"
        } else {
            ", brute force"
        },
        opts.period_tol,
        counts
            .iter()
            .map(|(l, n)| format!("{l} {n}"))
            .collect::<Vec<_>>()
            .join(", "),
        iterates as f64 / cells.len().max(1) as f64,
        evals as f64 / iterates.max(1) as f64,
    );
    if let Some(line) = map_line(&cells) {
        eprintln!("{line}");
    }
    if !failed.is_empty() && failed.len() == cells.len() {
        return Err(CliError::Failed(format!(
            "every one of the {} cells failed",
            cells.len()
        )));
    }
    Ok(())
}

/// A 5×7 bitmap font for the few characters the picture needs: each glyph is
/// 7 rows of 5 bits, most significant bit on the left.
fn glyph(ch: char) -> [u8; 7] {
    match ch {
        '0' => [14, 17, 19, 21, 25, 17, 14],
        '1' => [4, 12, 4, 4, 4, 4, 14],
        '2' => [14, 17, 1, 2, 4, 8, 31],
        '3' => [31, 2, 4, 2, 1, 17, 14],
        '4' => [2, 6, 10, 18, 31, 2, 2],
        '5' => [31, 16, 30, 1, 1, 17, 14],
        '6' => [6, 8, 16, 30, 17, 17, 14],
        '7' => [31, 1, 2, 4, 8, 8, 8],
        '8' => [14, 17, 17, 14, 17, 17, 14],
        '9' => [14, 17, 17, 15, 1, 2, 12],
        '.' => [0, 0, 0, 0, 0, 12, 12],
        '-' => [0, 0, 0, 31, 0, 0, 0],
        '+' => [0, 4, 4, 31, 4, 4, 0],
        '/' => [1, 1, 2, 4, 8, 16, 16],
        'A' => [14, 17, 17, 31, 17, 17, 17],
        'C' => [14, 17, 16, 16, 16, 17, 14],
        'D' => [28, 18, 17, 17, 17, 18, 28],
        'E' => [31, 16, 16, 30, 16, 16, 31],
        'F' => [31, 16, 16, 30, 16, 16, 16],
        'H' => [17, 17, 17, 31, 17, 17, 17],
        'I' => [14, 4, 4, 4, 4, 4, 14],
        'K' => [17, 18, 20, 24, 20, 18, 17],
        'L' => [16, 16, 16, 16, 16, 16, 31],
        'N' => [17, 17, 25, 21, 19, 17, 17],
        'O' => [14, 17, 17, 17, 17, 17, 14],
        'P' => [30, 17, 17, 30, 16, 16, 16],
        'S' => [15, 16, 16, 14, 1, 1, 30],
        'T' => [31, 4, 4, 4, 4, 4, 4],
        'U' => [17, 17, 17, 17, 17, 17, 14],
        _ => [0; 7],
    }
}

/// An RGB canvas with the few drawing operations the picture needs.
struct Canvas {
    w: usize,
    h: usize,
    px: Vec<u8>,
}

impl Canvas {
    fn new(w: usize, h: usize) -> Self {
        Canvas {
            w,
            h,
            px: vec![255; w * h * 3],
        }
    }

    fn rect(&mut self, x0: usize, y0: usize, w: usize, h: usize, c: [u8; 3]) {
        for y in y0..(y0 + h).min(self.h) {
            for x in x0..(x0 + w).min(self.w) {
                let i = 3 * (y * self.w + x);
                self.px[i..i + 3].copy_from_slice(&c);
            }
        }
    }

    /// Text at (x, y) (top left), each font pixel `s`×`s`; returns its width.
    fn text(&mut self, x: usize, y: usize, s: usize, t: &str, c: [u8; 3]) -> usize {
        for (k, ch) in t.chars().enumerate() {
            let g = glyph(ch);
            for (r, bits) in g.iter().enumerate() {
                for b in 0..5 {
                    if bits & (16 >> b) != 0 {
                        self.rect(x + (6 * k + b) * s, y + r * s, s, s, c);
                    }
                }
            }
        }
        text_width(t, s)
    }
}

fn text_width(t: &str, s: usize) -> usize {
    (6 * t.chars().count()).saturating_sub(1) * s
}

/// Ticks for an axis from `a` to `b`: about five round values.
fn ticks(a: f64, b: f64) -> Vec<f64> {
    let (lo, hi) = (a.min(b), a.max(b));
    if hi - lo <= 0.0 {
        return vec![lo];
    }
    let raw = (hi - lo) / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let mut v = Vec::new();
    let mut t = (lo / step).ceil() * step;
    while t <= hi + 1e-9 * step {
        v.push(t);
        t += step;
    }
    v
}

fn tick_label(v: f64) -> String {
    let s = format!("{:.3}", v);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

/// Renders the grid: θν across, κ upwards, one colour per class, with axes,
/// tick labels and a legend. Returns the PNG's bytes.
pub fn render_png(grid: &[Vec<PhaseCell>], kappas: &[f64], theta_nus: &[f64]) -> Vec<u8> {
    render_png_with(grid, kappas, theta_nus, &[])
}

/// [`render_png`] with bifurcation curves in (θν, κ) drawn over the cells.
pub fn render_png_with(
    grid: &[Vec<PhaseCell>],
    kappas: &[f64],
    theta_nus: &[f64],
    curves: &[super::phase_boundaries::Polyline],
) -> Vec<u8> {
    let (rows, cols) = (kappas.len().max(1), theta_nus.len().max(1));
    let cw = 600usize.div_ceil(cols).max(1);
    let ch = 480usize.div_ceil(rows).max(1);
    let (pw, ph) = (cw * cols, ch * rows);
    let s = 2;
    let (left, top, bottom, right) = (110, 20, 70, 180);
    let mut cv = Canvas::new(left + pw + right, top + ph + bottom);
    let black = [0, 0, 0];
    for (r, row) in grid.iter().enumerate() {
        for (c, cell) in row.iter().enumerate() {
            // κ grows upwards: the first row is at the bottom.
            let y = top + (rows - 1 - r) * ch;
            cv.rect(left + c * cw, y, cw, ch, class_colour(cell.class));
        }
    }
    // Frame.
    cv.rect(left - 1, top - 1, pw + 2, 1, black);
    cv.rect(left - 1, top + ph, pw + 2, 1, black);
    cv.rect(left - 1, top - 1, 1, ph + 2, black);
    cv.rect(left + pw, top - 1, 1, ph + 2, black);
    // θν axis: cell centres map linearly onto the grid's values.
    let (t0, t1) = (theta_nus[0], theta_nus[cols - 1]);
    let x_of = |v: f64| -> f64 {
        if cols == 1 || t1 == t0 {
            (left + pw / 2) as f64
        } else {
            left as f64 + cw as f64 * (0.5 + (v - t0) / (t1 - t0) * (cols - 1) as f64)
        }
    };
    for v in ticks(t0, t1) {
        let x = x_of(v).round() as usize;
        cv.rect(x, top + ph, 1, 6, black);
        let l = tick_label(v);
        let w = text_width(&l, s);
        cv.text(x.saturating_sub(w / 2), top + ph + 10, s, &l, black);
    }
    let title = "THETA NU";
    let w = text_width(title, s);
    cv.text(left + pw / 2 - w / 2, top + ph + 40, s, title, black);
    let (k0, k1) = (kappas[0], kappas[rows - 1]);
    let y_of = |v: f64| -> f64 {
        if rows == 1 || k1 == k0 {
            (top + ph / 2) as f64
        } else {
            (top + ph) as f64 - ch as f64 * (0.5 + (v - k0) / (k1 - k0) * (rows - 1) as f64)
        }
    };
    for v in ticks(k0, k1) {
        let y = y_of(v).round() as usize;
        cv.rect(left - 6, y, 6, 1, black);
        let l = tick_label(v);
        let w = text_width(&l, s);
        cv.text(left - 10 - w, y.saturating_sub(7), s, &l, black);
    }
    cv.text(4, top + ph / 2 - 7, s, "KAPPA", black);
    for poly in curves {
        for w in poly.windows(2) {
            let [a, b] = [w[0], w[1]].map(|p| [x_of(p[0]), y_of(p[1])]);
            for [x, y] in super::phase_boundaries::segment_pixels(a, b) {
                let inside = (left as i64..(left + pw) as i64 - 1).contains(&x)
                    && (top as i64..(top + ph) as i64 - 1).contains(&y);
                if inside {
                    cv.rect(x as usize, y as usize, 2, 2, black);
                }
            }
        }
    }
    // Legend.
    let lx = left + pw + 20;
    for (i, (name, c)) in PHASE_LEGEND.iter().enumerate() {
        let y = top + 10 + 26 * i;
        cv.rect(lx, y, 18, 18, *c);
        cv.rect(lx, y, 18, 1, black);
        cv.rect(lx, y + 17, 18, 1, black);
        cv.rect(lx, y, 1, 18, black);
        cv.rect(lx + 17, y, 1, 18, black);
        cv.text(lx + 26, y + 2, s, name, black);
    }
    let img = image::RgbImage::from_raw(cv.w as u32, cv.h as u32, cv.px)
        .unwrap_or_else(|| image::RgbImage::new(1, 1));
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .ok();
    bytes
}

/// Reads back a phase CSV's class column per cell (for tests and tools).
pub fn read_classes(path: &Path) -> std::io::Result<Vec<(f64, f64, String)>> {
    let text = std::fs::read_to_string(path)?;
    Ok(text
        .lines()
        .skip(1)
        .filter_map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            Some((
                f.first()?.parse().ok()?,
                f.get(1)?.parse().ok()?,
                f.get(6)?.to_string(),
            ))
        })
        .collect())
}

/// The summary's line on the interpolant, when any cell asked for it: how
/// many cells iterated it (with the largest error measured and the map
/// evaluations their constructions took) and how many it was refused.
fn map_line(cells: &[&PhaseCell]) -> Option<String> {
    MapTally::of(cells.iter().map(|c| &c.map)).map(|t| {
        format!(
            "  map: {} cell(s) continued on the interpolant (built from {} map evaluations, measured max error {:.1e} rad), {} refused it and integrated",
            t.used, t.evaluations, t.max_error, t.refused
        )
    })
}
