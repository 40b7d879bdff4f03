//! Flags every simulating subcommand shares, and the error type that maps
//! bad input to exit code 2 and failures to exit code 1.

use std::io::{IsTerminal, Write};
use std::path::Path;

use clap::Args;

use crate::integrate::{Method, SolverSettings};
use crate::model::Params;
use crate::model::{Regime, exit_arc};
use crate::output::{OutputError, check_writable, write_output};
use crate::sim::{SimError, Simulator};

/// A command-line failure: `Usage` (bad input: exit 2) or `Failed` (exit 1).
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    #[error("{0}")]
    Usage(String),
    #[error("{0}")]
    Failed(String),
}

impl CliError {
    pub fn exit_code(&self) -> i32 {
        match self {
            CliError::Usage(_) => 2,
            CliError::Failed(_) => 1,
        }
    }
}

impl From<SimError> for CliError {
    /// Errors about a parameter, a setting or an off-arc θ are the user's
    /// input; the rest are failures of the run.
    fn from(e: SimError) -> Self {
        match e {
            SimError::Param(_)
            | SimError::Settings(_)
            | SimError::OffExitArc { .. }
            | SimError::StepTooLarge { .. } => CliError::Usage(e.to_string()),
            _ => CliError::Failed(e.to_string()),
        }
    }
}

impl From<OutputError> for CliError {
    fn from(e: OutputError) -> Self {
        CliError::Usage(e.to_string())
    }
}

/// The model's parameters (docs/model.md), angles in radians.
#[derive(Debug, Clone, Args)]
pub struct ModelArgs {
    /// κ = k_x/k_y, the spring anisotropy (> 0).
    #[arg(long, allow_hyphen_values = true)]
    pub kappa: f64,
    /// γ, the friction weakening (≥ 0).
    #[arg(long, allow_hyphen_values = true)]
    pub gamma: f64,
    /// ν, the pulling speed (> 0).
    #[arg(long, allow_hyphen_values = true)]
    pub nu: f64,
    /// θν, the pulling direction in radians.
    #[arg(long = "theta-nu", allow_hyphen_values = true)]
    pub theta_nu: f64,
    /// Ω, the memory of the friction direction (> 0).
    #[arg(long, default_value_t = 50.0, allow_hyphen_values = true)]
    pub omega: f64,
}

impl ModelArgs {
    pub fn params(&self) -> Result<Params, CliError> {
        let p = Params {
            kappa: self.kappa,
            gamma: self.gamma,
            nu: self.nu,
            theta_nu: self.theta_nu,
            omega: self.omega,
        };
        p.validate()
            .map_err(|e| CliError::Usage(format!("--{e}")))?;
        Ok(p)
    }
}

/// The integration method and its accuracy.
#[derive(Debug, Clone, Args)]
pub struct SolverArgs {
    /// Integration method: dp54, dop853, rk4 or euler.
    #[arg(long, default_value = "dop853")]
    pub method: String,
    /// Tolerance of the adaptive methods (rtol = atol), in [1e-14, 1e-2]
    /// [default: 1e-10].
    #[arg(long, allow_hyphen_values = true, conflicts_with = "step")]
    pub tol: Option<f64>,
    /// Step of the fixed-step methods (rk4, euler), in (0, 1] [default: 1e-3].
    #[arg(long, allow_hyphen_values = true)]
    pub step: Option<f64>,
}

impl SolverArgs {
    pub fn settings(&self) -> Result<SolverSettings, CliError> {
        let method: Method = self
            .method
            .parse()
            .map_err(|e: String| CliError::Usage(format!("--method: {e}")))?;
        let s = if method.is_adaptive() {
            if self.step.is_some() {
                return Err(CliError::Usage(format!(
                    "--step applies to rk4 and euler, not {method}; use --tol"
                )));
            }
            SolverSettings::adaptive(method, self.tol.unwrap_or(1e-10))
        } else {
            if self.tol.is_some() {
                return Err(CliError::Usage(format!(
                    "--tol applies to dp54 and dop853, not {method}; use --step"
                )));
            }
            SolverSettings::fixed(method, self.step.unwrap_or(1e-3))
        };
        s.validate()
            .map_err(|e| CliError::Usage(format!("--{e}")))?;
        Ok(s)
    }
}

/// Checks a user-given finite number.
pub fn finite(name: &str, v: f64) -> Result<f64, CliError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(CliError::Usage(format!(
            "--{name} = {v} must be a finite number"
        )))
    }
}

/// Fails early (before any simulation) when the `--out` path cannot be
/// written; the message names the flag.
pub fn check_out(path: &Path, force: bool) -> Result<(), CliError> {
    check_writable(path, force).map_err(out_error)
}

/// Writes a finished output atomically to the `--out` path.
pub fn write_out(path: &Path, bytes: &[u8], force: bool) -> Result<(), CliError> {
    write_output(path, bytes, force).map_err(out_error)
}

fn out_error(e: OutputError) -> CliError {
    CliError::Usage(format!("--out: {e}"))
}

/// Checks a count flag against [1, max]: 0 would produce nothing, and the
/// upper bound keeps the results (held in memory until they are written
/// atomically) far from exhausting it.
pub fn count_in(name: &str, v: usize, max: usize) -> Result<usize, CliError> {
    if (1..=max).contains(&v) {
        Ok(v)
    } else {
        Err(CliError::Usage(format!(
            "--{name} = {v} is out of range: must lie in [1, {max}]"
        )))
    }
}

/// The most rows a CSV may have (a few GB of text).
pub const MAX_ROWS: usize = 100_000_000;

/// The iterates a run of `transient` + `keep` (× `columns`) asks for, refused
/// when it would not fit in a count (a typo such as an extra dozen digits).
pub fn total_iterates(
    transient: usize,
    (kept_flag, keep): (&str, usize),
    columns: usize,
) -> Result<u64, CliError> {
    (transient as u64)
        .checked_add(keep as u64)
        .and_then(|n| n.checked_mul(columns as u64))
        .filter(|&n| n <= MAX_ITERATES)
        .ok_or_else(|| {
            CliError::Usage(format!(
                "--transient = {transient} with --{kept_flag} = {keep} is out of range: the run would ask for more than {MAX_ITERATES:e} iterates"
            ))
        })
}

/// More iterates than any run could finish (years at 1e5 iterates/s).
pub const MAX_ITERATES: u64 = 1_000_000_000_000_000;

/// Checks that an onset angle given as `--{flag}` is a reachable slip onset
/// (docs/model.md, "The exit arc"), naming the flag and the exit arc in the message.
pub fn check_theta(sim: &Simulator, flag: &str, theta: f64) -> Result<f64, CliError> {
    match sim.check_onset(theta) {
        Ok(()) => Ok(theta),
        Err(_) => {
            let p = sim.params();
            let (psi, half) = exit_arc(p.kappa, p.theta_nu);
            let what = if theta.is_finite() {
                "is not on the exit arc"
            } else {
                "is not a finite angle"
            };
            Err(CliError::Usage(format!(
                "--{flag} = {theta} {what}: for kappa = {}, theta-nu = {} it must lie in ({:.6}, {:.6}) radians (mod 2π), where a stick phase can end",
                p.kappa,
                p.theta_nu,
                psi - half,
                psi + half
            )))
        }
    }
}

/// Writes `bytes` to `--out` (or stdout for "-"). A closed pipe on stdout
/// (`| head`) is not an error: the reader has what it wanted.
pub fn emit(path: &Path, bytes: &[u8], force: bool) -> Result<(), CliError> {
    if path.as_os_str() == "-" {
        let mut out = std::io::stdout().lock();
        return match out.write_all(bytes).and_then(|_| out.flush()) {
            Ok(()) => Ok(()),
            Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
            Err(e) => Err(CliError::Failed(format!("cannot write to stdout: {e}"))),
        };
    }
    match write_output(path, bytes, force) {
        // A pipe given by name (/dev/stdout) whose reader has gone.
        Err(OutputError::Io { source, .. }) if source.kind() == std::io::ErrorKind::BrokenPipe => {
            Ok(())
        }
        r => r.map_err(out_error),
    }
}

/// Whether progress bars should be drawn: only on a terminal.
pub fn stderr_is_terminal() -> bool {
    std::io::stderr().is_terminal()
}

/// A one-line description of the parameters and the solver, for summaries.
pub fn describe(params: &Params, settings: &SolverSettings) -> String {
    describe_with(params, settings, true)
}

/// The same without θν, for sweeps over it.
pub fn describe_sweep(params: &Params, settings: &SolverSettings) -> String {
    describe_with(params, settings, false)
}

fn describe_with(params: &Params, settings: &SolverSettings, theta_nu: bool) -> String {
    let accuracy = if settings.method.is_adaptive() {
        format!("tol {:e}", settings.rtol)
    } else {
        format!("step {}", settings.step)
    };
    let theta_nu = if theta_nu {
        format!("theta-nu = {}, ", params.theta_nu)
    } else {
        String::new()
    };
    format!(
        "kappa = {}, gamma = {}, nu = {}, {theta_nu}omega = {} ({}); {} {}",
        params.kappa,
        params.gamma,
        params.nu,
        params.omega,
        Regime::of(params.kappa, params.gamma).name(),
        settings.method,
        accuracy
    )
}

/// The solver settings as JSON, for summaries.
pub fn settings_json(settings: &SolverSettings) -> serde_json::Value {
    if settings.method.is_adaptive() {
        serde_json::json!({ "method": settings.method.name(), "tol": settings.rtol })
    } else {
        serde_json::json!({ "method": settings.method.name(), "step": settings.step })
    }
}
