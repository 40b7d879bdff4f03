//! `bench-worker --phase N`: an N × N phase grid over the paper's Fig. 4
//! range from its command to the full coarse lattice and to the full grid.

use std::time::Instant;

use super::machine::{cpu_seconds, load_average};
use super::{BenchWorkerArgs, recv, say, worker};
use crate::bench::diagram::fig3b;
use crate::cli::CliError;
use crate::integrate::SolverSettings;
use crate::jobs::{block_plan, phase_blocks};
use crate::sim::stats::median;
use crate::worker::{Axis, COARSE_STRIDE, Command, Outcome, PhaseSpec, PhaseTuning, Update};

/// One N × N phase grid from command to `Finished`.
struct PhaseTiming {
    /// Seconds to the whole coarse lattice and to the whole grid.
    coarse: f64,
    full: f64,
    /// CPU seconds of the process meanwhile.
    cpu_coarse: Option<f64>,
    cpu: Option<f64>,
    iterates: u64,
    /// Cells per class label, in the order first seen.
    classes: Vec<(String, usize)>,
}

fn time_phase(
    args: &BenchWorkerArgs,
    settings: SolverSettings,
    n: usize,
) -> Result<PhaseTiming, CliError> {
    let w = worker(args);
    let n_coarse = block_plan(n, n, COARSE_STRIDE, 0..phase_blocks(n, n).len())
        .iter()
        .filter(|p| p.coarse)
        .count();
    let t0 = Instant::now();
    let cpu0 = cpu_seconds();
    let sent = w.send(Command::run(
        1,
        PhaseSpec {
            params: fig3b(),
            settings,
            theta_nu: Axis::new(0.0, std::f64::consts::FRAC_PI_2, n),
            kappa: Axis::new(1.0, 42.0, n),
            transient: 400,
            keep: 128,
            tuning: PhaseTuning::default(),
        },
    ));
    if !sent {
        return Err(CliError::Failed("the worker refused the phase grid".into()));
    }
    let (mut seen, mut coarse, mut cpu_coarse, mut iterates) = (0, None, None, 0);
    let mut classes: Vec<(String, usize)> = Vec::new();
    let full = loop {
        match recv(&w)? {
            Update::PhaseCells {
                cells, coarse: c, ..
            } => {
                iterates += cells.iter().map(|c| c.cell.iterates).sum::<u64>();
                for c in &cells {
                    let l = c.cell.class.label();
                    match classes.iter_mut().find(|(k, _)| *k == l) {
                        Some((_, k)) => *k += 1,
                        None => classes.push((l, 1)),
                    }
                }
                if c {
                    seen += cells.len();
                    if seen == n_coarse {
                        coarse = Some(t0.elapsed().as_secs_f64());
                        cpu_coarse = cpu_seconds().zip(cpu0).map(|(b, a)| b - a);
                    }
                }
            }
            Update::Finished { outcome, .. } => {
                if let Outcome::Failed(m) = outcome {
                    return Err(CliError::Failed(format!("the phase grid failed: {m}")));
                }
                break t0.elapsed().as_secs_f64();
            }
            _ => {}
        }
    };
    let cpu = cpu_seconds().zip(cpu0).map(|(b, a)| b - a);
    w.shutdown();
    // FP, then P2, P3, … P10 in numeric order, then chaos and the rest.
    classes.sort_by_key(|(l, _)| class_order(l));
    Ok(PhaseTiming {
        coarse: coarse.unwrap_or(full),
        full,
        cpu_coarse,
        cpu,
        iterates,
        classes,
    })
}

/// Where a class label sorts: the fixed point, the periods by number,
/// then the other labels by name.
fn class_order(label: &str) -> (u8, usize, String) {
    match label {
        "FP" => (0, 1, String::new()),
        l => match l.strip_prefix('P').and_then(|n| n.parse().ok()) {
            Some(p) => (0, p, String::new()),
            None => (1, 0, l.to_string()),
        },
    }
}

pub(super) fn run_phase(
    args: &BenchWorkerArgs,
    settings: SolverSettings,
    n: usize,
) -> Result<(), CliError> {
    say(&format!(
        "phase: {n} x {n} cells over theta-nu in [0, pi/2], kappa in [1, 42]; gamma = 6.5, nu = 1e-3, omega = 50; dop853 tol = {:e}; 400 transient + 128 kept; {} threads",
        args.tol, args.threads
    ))?;
    if let Some(l) = load_average() {
        say(&format!("load average before the run: {l:.2}"))?;
    }
    let mut runs = Vec::new();
    for r in 0..args.repeats {
        let t = time_phase(args, settings, n)?;
        let fmt = |c: Option<f64>| c.map_or("?".into(), |c| format!("{c:.2} s"));
        say(&format!(
            "  grid {}: coarse lattice {:.3} s (CPU {}), full {:.3} s (CPU {}), {} iterates; {}",
            r + 1,
            t.coarse,
            fmt(t.cpu_coarse),
            t.full,
            fmt(t.cpu),
            t.iterates,
            t.classes
                .iter()
                .map(|(l, k)| format!("{l} {k}"))
                .collect::<Vec<_>>()
                .join(", "),
        ))?;
        runs.push((t.coarse, t.full));
    }
    say(&format!(
        "phase grid: coarse lattice median {:.3} s, full grid median {:.3} s",
        median(&runs.iter().map(|r| r.0).collect::<Vec<_>>()),
        median(&runs.iter().map(|r| r.1).collect::<Vec<_>>()),
    ))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::class_order;

    #[test]
    fn classes_sort_by_period_number_not_by_name() {
        let mut l = vec!["chaos", "P12", "P2", "FP", "P3", "creep?", "P10"];
        l.sort_by_key(|x| class_order(x));
        assert_eq!(l, ["FP", "P2", "P3", "P10", "P12", "chaos", "creep?"]);
    }
}
