//! Flags every simulating subcommand shares, and the checks and summaries
//! built on them.

use std::path::Path;

use clap::Args;

use super::CliError;
use super::run_control::write_stdout;
use super::values::{
    given_or_preset, param_error, parse_number, preset_params, short, short_count,
};
use crate::integrate::{Method, SolverSettings};
use crate::model::{Params, Preset};
use crate::model::{event_anomalies, exit_arc, validity};
use crate::output::{OutputError, check_writable, write_output};
use crate::sim::Simulator;
use crate::sim::continuation::ContParam;

/// The model's flags (docs/model.md), angles in radians, declared once for
/// every command: given one by one, or `--preset NAME` with any of them
/// overriding the preset's value. Each is optional at the parser: a
/// command may do without them (`work-precision`: its default sample) or
/// set one itself (`continue` and `bifurcation`: the varied parameter's,
/// from --from); [`ModelArgs::params`] requires the others unless
/// --preset gives them, and checks every value against the model's range
/// in one place ([`Params::validate`]), each error naming its flag.
#[derive(Debug, Clone, Default, Args)]
pub struct ModelArgs {
    /// Start from a named parameter set: fig3a, fig3b, fig4, creep, chaos,
    /// intermittent, hysteresis (the flags below override its values).
    #[arg(long)]
    pub preset: Option<Preset>,
    /// κ = k_x/k_y, the spring anisotropy, in [1e-6, 1e3] (beyond, slips turn
    /// into steady sliding, which the map cannot represent).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub kappa: Option<f64>,
    /// γ, the friction weakening, in [0.1, 1e4] (outside, slips turn into
    /// steady sliding or never stop, which the map cannot represent).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub gamma: Option<f64>,
    /// ν, the pulling speed, in [1e-12, 0.1] (beyond, slips turn into steady
    /// sliding, which the map cannot represent; the model assumes ν ≤ 1e-2).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub nu: Option<f64>,
    /// θν, the pulling direction in radians.
    #[arg(long = "theta-nu", allow_hyphen_values = true, value_parser = parse_number)]
    pub theta_nu: Option<f64>,
    /// Ω, the memory of the friction direction, in (0, 1e8] (the model
    /// assumes [1, 1e4]) [default: 50, or the preset's].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub omega: Option<f64>,
}

impl ModelArgs {
    /// The parameters, checked; each error names its flag (one that
    /// neither its flag nor the preset gives, too).
    pub fn params(&self) -> Result<Params, CliError> {
        let p = self.given()?;
        p.validate().map_err(param_error)?;
        Ok(p)
    }

    /// The parameters as given (each from its flag, else the preset's; Ω
    /// 50 by default), not yet checked against the model's ranges; an
    /// error names a flag that neither gives.
    pub fn given(&self) -> Result<Params, CliError> {
        let base = preset_params(self.preset);
        Ok(Params {
            kappa: given_or_preset("kappa", self.kappa, base.map(|b| b.kappa))?,
            gamma: given_or_preset("gamma", self.gamma, base.map(|b| b.gamma))?,
            nu: given_or_preset("nu", self.nu, base.map(|b| b.nu))?,
            theta_nu: given_or_preset("theta-nu", self.theta_nu, base.map(|b| b.theta_nu))?,
            omega: self.omega.or(base.map(|b| b.omega)).unwrap_or(50.0),
        })
    }

    /// The flag of `param`.
    pub fn flag_mut(&mut self, param: ContParam) -> &mut Option<f64> {
        match param {
            ContParam::ThetaNu => &mut self.theta_nu,
            ContParam::Kappa => &mut self.kappa,
            ContParam::Gamma => &mut self.gamma,
            ContParam::Nu => &mut self.nu,
            ContParam::Omega => &mut self.omega,
        }
    }

    /// The value `param`'s flag gave, if any.
    pub fn flag(&self, param: ContParam) -> Option<f64> {
        *self.clone().flag_mut(param)
    }

    /// Whether a preset or any parameter but Ω is given.
    pub fn any(&self) -> bool {
        self.preset.is_some()
            || self.kappa.is_some()
            || self.gamma.is_some()
            || self.nu.is_some()
            || self.theta_nu.is_some()
    }
}

/// Prints the model-validity warnings of `params` (model::validity) on
/// stderr, one line each.
pub fn warn_validity(params: &Params) {
    for w in validity(params) {
        eprintln!("warning: {w}");
    }
}

/// Prints a warning for a slip event outside the model (a negative energy
/// released, θ' = θ − π).
pub fn warn_event(ev: &crate::sim::SlipEvent) {
    for a in event_anomalies(ev.theta, ev.theta_next, ev.energy_released) {
        eprintln!("warning: {a}");
    }
}

/// The integration method and its accuracy.
#[derive(Debug, Clone, Args)]
pub struct SolverArgs {
    /// Integration method: dp54, dop853, rk4 or euler.
    #[arg(long, value_enum, ignore_case = true, default_value_t = Method::Dop853)]
    pub method: Method,
    /// Tolerance of the adaptive methods (rtol = atol), in [1e-14, 1e-2]
    /// [default: 1e-10].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number, conflicts_with = "step")]
    pub tol: Option<f64>,
    /// Step of the fixed-step methods (rk4, euler), in (0, 1] [default: 1e-3].
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub step: Option<f64>,
}

impl SolverArgs {
    pub fn settings(&self) -> Result<SolverSettings, CliError> {
        let method = self.method;
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
        s.validate().map_err(super::values::settings_error)?;
        Ok(s)
    }
}

/// Checks a user-given finite number.
pub fn finite(name: &str, v: f64) -> Result<f64, CliError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(CliError::Usage(format!(
            "--{name} = {v} is out of range: must be a finite number"
        )))
    }
}

/// Fails early (before any simulation) when the `--out` path cannot be
/// written (or is a closed stdout); the message names the flag.
pub fn check_out(path: &Path, force: bool) -> Result<(), CliError> {
    if path.as_os_str() == "-" {
        return super::run_control::check_stdout();
    }
    check_writable(path, force).map_err(out_error)
}

/// Checks a second output `--{flag}` as [`check_out`] does, and that it
/// does not name the same file as `--out` (one would overwrite the other).
pub fn check_second_out(flag: &str, path: &Path, out: &Path, force: bool) -> Result<(), CliError> {
    if crate::output::same_output(path, out) {
        return Err(CliError::Usage(format!(
            "--{flag}: {} is also the --out file: give the two outputs different names",
            path.display()
        )));
    }
    check_writable(path, force).map_err(|e| CliError::Usage(format!("--{flag}: {e}")))
}

/// Checks `--max-seconds`.
pub fn max_seconds(v: Option<f64>) -> Result<Option<f64>, CliError> {
    v.map(|s| super::values::seconds("max-seconds", s))
        .transpose()
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
            "--{name} = {v} is out of range: must lie in [1, {}]",
            short_count(max)
        )))
    }
}

/// The most rows a CSV may have: the rows are held in memory until the
/// file is written atomically, ~50 bytes of text each (a few hundred MB).
pub const MAX_ROWS: usize = 10_000_000;

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
                "--transient = {transient} with --{kept_flag} = {keep} is out of range: the run would ask for more than {MAX_ITERATES:e} iterates (bound the time with --max-seconds)"
            ))
        })
}

/// More iterates than any run could finish (years at 1e5 iterates/s);
/// `--max-seconds` bounds a run's time.
pub const MAX_ITERATES: u64 = 1_000_000_000_000;

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
                "--{flag} = {} {what}: for kappa = {}, theta-nu = {} it must lie in ({:.6}, {:.6}) radians (mod 2π), where a stick phase can end",
                short(theta),
                short(p.kappa),
                short(p.theta_nu),
                psi - half,
                psi + half
            )))
        }
    }
}

/// Writes `bytes` to `--out` (or stdout for "-"). A closed pipe on stdout
/// (`| head`) is not an error: the reader has what it wanted.
pub fn emit(path: &Path, bytes: &[u8], force: bool) -> Result<(), CliError> {
    emit_as("out", path, bytes, force)
}

/// Writes a finished output given by `--{flag}` (stdout for "-"). Every
/// output was checked before the run (exit 2 for what the user can fix
/// then); a write that fails now is a failure of the run: exit 1, the
/// message naming the flag.
pub fn emit_as(flag: &str, path: &Path, bytes: &[u8], force: bool) -> Result<(), CliError> {
    if path.as_os_str() == "-" {
        return write_stdout(bytes);
    }
    match write_output(path, bytes, force) {
        // A pipe given by name (/dev/stdout) whose reader has gone.
        Err(OutputError::Io { source, .. }) if source.kind() == std::io::ErrorKind::BrokenPipe => {
            Ok(())
        }
        Err(e) => Err(CliError::Failed(format!(
            "--{flag}: {}",
            super::values::escape_controls(&e.to_string())
        ))),
        Ok(()) => Ok(()),
    }
}

/// Writes a command's outputs, each given by its flag, all or none: when
/// one fails, the files this call created before it are removed again, so
/// a failed run never leaves its first output behind. (A file replaced
/// with `--force` is not brought back.)
pub fn emit_all(outputs: &[(&str, &Path, &[u8])], force: bool) -> Result<(), CliError> {
    let mut created: Vec<&Path> = Vec::new();
    for &(flag, path, bytes) in outputs {
        let is_new = path.as_os_str() != "-"
            && crate::output::resolve_links(path)
                .map(|t| std::fs::symlink_metadata(t).is_err())
                .unwrap_or(false);
        if let Err(e) = emit_as(flag, path, bytes, force) {
            for p in created {
                if let Ok(t) = crate::output::resolve_links(p) {
                    std::fs::remove_file(t).ok();
                }
            }
            return Err(e);
        }
        if is_new {
            created.push(path);
        }
    }
    Ok(())
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
    crate::provenance::model_line(params, settings, theta_nu)
}

/// `csv` after the `#` lines saying where it came from
/// ([`crate::provenance`]): the program, this command line, `model` (the
/// parameters and accuracy, as [`describe`] says them) and every flag's
/// value.
pub fn with_provenance(model: &str, csv: &str) -> String {
    use crate::provenance::{header, with_header};
    with_header(&header(None, model, None), csv)
}

/// The solver settings as JSON, for summaries.
pub fn settings_json(settings: &SolverSettings) -> serde_json::Value {
    if settings.method.is_adaptive() {
        serde_json::json!({ "method": settings.method.name(), "tol": settings.rtol })
    } else {
        serde_json::json!({ "method": settings.method.name(), "step": settings.step })
    }
}
