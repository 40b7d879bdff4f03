//! A phase grid larger than one machine: `oneblock phase ... --shard K/N`
//! computes part K of N (a run of whole blocks of the job's plan, whose
//! cells never seed across a block's edge, so each cell is the one the
//! whole grid computes), and `oneblock phase --merge PART...` joins the
//! parts into the CSV the whole grid writes, bit for bit apart from the
//! `#` lines (and its picture with `--png`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::CliError;
use super::common::{emit, with_provenance};
use super::phase::PhaseArgs;
use crate::jobs::{phase_blocks, shard_blocks};
use crate::sim::phase::{CellClass, PhaseCell};

/// The `#` line a part begins with: `# shard: K/N; grid: KEY`.
const SHARD_PREFIX: &str = "# shard: ";

/// `--shard K/N` for a `rows` × `columns` grid: 1 ≤ K ≤ N ≤ its blocks.
pub fn parse_shard(
    s: &str,
    rows: usize,
    columns: usize,
    png: bool,
) -> Result<(usize, usize), CliError> {
    let blocks = phase_blocks(rows, columns).len();
    let parsed = s
        .split_once('/')
        .and_then(|(k, n)| Some((k.trim().parse().ok()?, n.trim().parse().ok()?)));
    match parsed {
        Some((k, n)) if (1..=n).contains(&k) && n <= blocks => {
            if png {
                return Err(CliError::Usage(
                    "--shard: a part has no picture; draw the merged grid with --merge PART... --png FILE"
                        .into(),
                ));
            }
            Ok((k, n))
        }
        _ => Err(CliError::Usage(format!(
            "--shard = {} is out of range: must be K/N with 1 <= K <= N <= {blocks} (this grid's blocks of 32 x 32 cells)",
            super::values::escape_controls(s)
        ))),
    }
}

/// The flat indices (row·columns + column) of part `k` of `n`, in the
/// order its CSV lists them (rows of increasing κ, each along θν).
pub fn shard_cells(rows: usize, columns: usize, k: usize, n: usize) -> Vec<usize> {
    let blocks = phase_blocks(rows, columns);
    let mut cells: Vec<usize> = blocks[shard_blocks(blocks.len(), k, n)]
        .iter()
        .flat_map(|(r, c)| {
            r.clone()
                .flat_map(move |i| c.clone().map(move |j| i * columns + j))
        })
        .collect();
    cells.sort_unstable();
    cells
}

/// The `#` line of part `k` of `n` of the grid `key`.
pub fn shard_line(k: usize, n: usize, key: &str) -> String {
    format!("{SHARD_PREFIX}{k}/{n}; grid: {key}\n")
}

/// One part, read.
pub(super) struct Part {
    path: PathBuf,
    k: usize,
    n: usize,
    key: String,
    model: Option<String>,
    header: String,
    rows: Vec<String>,
}

/// The grid's rows and columns, from its key (`R x C cells, ...`).
fn grid_size(key: &str) -> Option<(usize, usize)> {
    let (rc, _) = key.split_once(" cells")?;
    let (r, c) = rc.split_once(" x ")?;
    Some((r.parse().ok()?, c.parse().ok()?))
}

fn read_part(path: &Path) -> Result<Part, CliError> {
    let name = path.display();
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::Usage(format!("--merge: cannot read {name}: {e}")))?;
    let mut shard = None;
    let mut model = None;
    let mut lines = text.lines();
    let mut header = None;
    for line in lines.by_ref() {
        if let Some(rest) = line.strip_prefix(SHARD_PREFIX) {
            shard = Some(rest.to_string());
        } else if let Some(m) = line.strip_prefix("# model: ") {
            model = Some(m.to_string());
        } else if !line.starts_with('#') {
            header = Some(line.to_string());
            break;
        }
    }
    let not_part = || {
        CliError::Usage(format!(
            "--merge: {name} is not a part of a sharded phase grid (no valid '{SHARD_PREFIX}K/N' line)"
        ))
    };
    let shard = shard.ok_or_else(not_part)?;
    let (kn, key) = shard.split_once("; grid: ").ok_or_else(not_part)?;
    let (k, n) = kn
        .split_once('/')
        .and_then(|(k, n)| Some((k.parse().ok()?, n.parse().ok()?)))
        .ok_or_else(not_part)?;
    Ok(Part {
        path: path.to_path_buf(),
        k,
        n,
        key: key.to_string(),
        model,
        header: header.ok_or_else(not_part)?,
        rows: lines.map(str::to_string).collect(),
    })
}

/// The parts given, checked: all of one grid, each of its N parts once,
/// each with its part's number of rows. The grid's rows and columns too.
fn read_parts(paths: &[PathBuf]) -> Result<(Vec<Part>, usize, usize), CliError> {
    let parts = paths
        .iter()
        .map(|p| read_part(p))
        .collect::<Result<Vec<_>, _>>()?;
    let first = &parts[0];
    let (rows, cols) = grid_size(&first.key).ok_or_else(|| {
        CliError::Usage(format!(
            "--merge: {} names no grid size in its shard line",
            first.path.display()
        ))
    })?;
    let mut seen: Vec<Option<&Part>> = vec![None; first.n];
    for p in &parts {
        if p.key != first.key || p.n != first.n || p.header != first.header {
            return Err(CliError::Usage(format!(
                "--merge: {} is a part of another grid (or another sharding) than {}",
                p.path.display(),
                first.path.display()
            )));
        }
        if !(1..=p.n).contains(&p.k) {
            return Err(CliError::Usage(format!(
                "--merge: {} says it is part {}/{}",
                p.path.display(),
                p.k,
                p.n
            )));
        }
        if let Some(q) = seen[p.k - 1].replace(p) {
            return Err(CliError::Usage(format!(
                "--merge: part {}/{} is given twice ({} and {})",
                p.k,
                p.n,
                q.path.display(),
                p.path.display()
            )));
        }
        let want = shard_cells(rows, cols, p.k, p.n).len();
        if p.rows.len() != want {
            return Err(CliError::Usage(format!(
                "--merge: {} has {} rows, part {}/{} of this grid has {want} cells",
                p.path.display(),
                p.rows.len(),
                p.k,
                p.n
            )));
        }
    }
    if let Some(k) = seen.iter().position(Option::is_none) {
        return Err(CliError::Usage(format!(
            "--merge: part {}/{} is missing (every part once)",
            k + 1,
            first.n
        )));
    }
    Ok((parts, rows, cols))
}

/// Checks `--merge`'s flags, outputs and parts before writing anything.
pub(super) fn check(args: &PhaseArgs) -> Result<(Vec<Part>, usize, usize, PathBuf), CliError> {
    let grid_flags = args.kappa_from.is_some()
        || args.kappa_to.is_some()
        || args.kappa_steps.is_some()
        || args.theta_nu_steps.is_some()
        || args.shard.is_some();
    if grid_flags {
        return Err(CliError::Usage(
            "--merge: the grid comes from its parts; give no --kappa-*, --theta-nu-steps or --shard"
                .into(),
        ));
    }
    // The CSV's place and the picture's, checked as the one-shot grid's.
    let out = super::phase::check_outputs(args)?;
    let (parts, rows, cols) = read_parts(&args.merge)?;
    Ok((parts, rows, cols, out.unwrap_or_default()))
}

/// Writes the merged CSV (and picture).
pub(super) fn run(args: &PhaseArgs) -> Result<(), CliError> {
    let (parts, rows, cols, out) = check(args)?;
    let mut placed: Vec<Option<&str>> = vec![None; rows * cols];
    for p in &parts {
        for (i, row) in shard_cells(rows, cols, p.k, p.n).into_iter().zip(&p.rows) {
            placed[i] = Some(row);
        }
    }
    let first = &parts[0];
    let mut csv = String::with_capacity(80 * (rows * cols + 1));
    csv.push_str(&first.header);
    csv.push('\n');
    for row in placed.iter().flatten() {
        writeln!(csv, "{row}").ok();
    }
    if args.png.is_some() {
        let model = first.model.as_deref().unwrap_or_default();
        picture(args, model, &first.header, &placed, (rows, cols))?;
    }
    if args.out.is_some() || args.png.is_none() {
        let model = first.model.clone().unwrap_or_default();
        emit(&out, with_provenance(&model, &csv).as_bytes(), args.force)?;
    }
    eprintln!(
        "phase --merge: {} part(s) joined into {rows} x {cols} cells",
        parts.len()
    );
    Ok(())
}

/// A cell's class from its CSV label.
fn class_of(label: &str) -> CellClass {
    match label {
        "FP" => CellClass::Periodic(1),
        "chaos" => CellClass::Chaos,
        "undecided" => CellClass::Undecided,
        l => match l.strip_prefix('P').and_then(|p| p.parse().ok()) {
            Some(p) => CellClass::Periodic(p),
            None => CellClass::Failed,
        },
    }
}

/// The merged grid drawn by `phase --png`'s own picture code, from the
/// rows' θν, κ, class (and attractors, when counted).
fn picture(
    args: &PhaseArgs,
    model: &str,
    header: &str,
    rows: &[Option<&str>],
    (nr, nc): (usize, usize),
) -> Result<(), CliError> {
    let attractors = header.split(',').position(|h| h == "attractors");
    let bad = || CliError::Usage(format!("--merge: a row is not a phase CSV row: {header}"));
    let mut grid: Vec<Vec<PhaseCell>> = Vec::with_capacity(nr);
    for r in 0..nr {
        let mut row = Vec::with_capacity(nc);
        for row_text in rows[r * nc..(r + 1) * nc].iter().flatten() {
            let f: Vec<&str> = row_text.split(',').collect();
            let num = |i: usize| f.get(i).and_then(|v| v.parse::<f64>().ok());
            let (tn, k) = (num(0).ok_or_else(bad)?, num(1).ok_or_else(bad)?);
            let mut cell = PhaseCell::failed(tn, k, tn);
            cell.class = class_of(f.get(6).ok_or_else(bad)?);
            cell.attractors = attractors.and_then(|i| f.get(i)?.parse().ok());
            row.push(cell);
        }
        grid.push(row);
    }
    let kappas: Vec<f64> = grid.iter().map(|row| row[0].kappa).collect();
    let theta_nus: Vec<f64> = grid[0].iter().map(|c| c.theta_nu).collect();
    let Some(p) = super::phase_picture::check(args)? else {
        return Ok(());
    };
    // γ, ν and Ω as the parts' `# model:` line names them (the title's).
    let named = |key: &str| {
        model.split(", ").find_map(|kv| {
            kv.strip_prefix(key)?
                .strip_prefix(" = ")?
                .split(' ')
                .next()?
                .parse()
                .ok()
        })
    };
    let d = crate::model::Params::default();
    let params = crate::model::Params {
        gamma: named("gamma").unwrap_or(d.gamma),
        nu: named("nu").unwrap_or(d.nu),
        omega: named("omega").unwrap_or(d.omega),
        kappa: kappas[0],
        theta_nu: theta_nus[0],
    };
    let grid = super::phase_picture::Grid {
        cells: &grid,
        theta_nu: (theta_nus[0], theta_nus[nc - 1]),
        kappa: (kappas[0], kappas[nr - 1]),
        params,
        transient: args.transient,
        keep: args.keep,
        seeds: args.seeds,
    };
    super::phase_picture::write(&p, &grid, args.force)
}
