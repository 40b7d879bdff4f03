//! A settled period's exponent when its cycle could not be solved.

use super::{PhaseCell, SimError, Simulator, map_derivative};

/// A period-p cycle's exponent from the orbit alone, when the cycle could
/// not be solved: the mean of ln|f'| over the last p iterates (`thetas`,
/// then the next onset `theta`), from the kept iterates' `logs` when there
/// are p of them, else by p derivatives charged to the cell.
pub(super) fn cycle_exponent(
    cell: &mut PhaseCell,
    sim: &Simulator,
    thetas: &[f64],
    theta: f64,
    logs: &[f64],
    p: usize,
) -> Result<f64, SimError> {
    if logs.len() >= p {
        return Ok(logs[logs.len() - p..].iter().sum::<f64>() / p as f64);
    }
    let mut sum = 0.0;
    for j in 0..p {
        let th = thetas[thetas.len() - p + j];
        let next = if j + 1 < p {
            thetas[thetas.len() - p + j + 1]
        } else {
            theta
        };
        let (d, n) = map_derivative(sim, th, next)?;
        cell.iterates += 1;
        cell.rhs_evals += n;
        sum += d.abs().ln();
    }
    Ok(sum / p as f64)
}
