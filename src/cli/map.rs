//! `oneblock map`: one iterate θ → θ' of the map, with the slip event's
//! details and the map's exact derivatives f'(θ) and ∂f/∂(θν, κ, γ, ν, Ω),
//! as text or as one JSON object.

use std::path::Path;

use clap::Args;

use super::CliError;
use super::common::{
    ModelArgs, SolverArgs, check_theta, describe, emit, settings_json, warn_event, warn_validity,
};
use super::run_control::check_stdout;
use super::values::parse_number;
use crate::integrate::SolverSettings;
use crate::model::Params;
use crate::model::{OnsetCharacter, Regime, onset_character};
use crate::sim::variational::{MapDerivatives, NotDifferentiable};
use crate::sim::{Simulator, SlipEvent};

/// One map iterate from the onset at `--theta`.
#[derive(Debug, Clone, Args)]
pub struct MapArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    #[command(flatten)]
    pub solver: SolverArgs,
    /// θ of the slip onset, in radians (on the exit arc).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_number)]
    pub theta: f64,
    /// Print one JSON object (the slip event, the parameters, the regime)
    /// instead of the text summary.
    #[arg(long)]
    pub json: bool,
}

/// The checked inputs of `map`: the simulator and the onset.
pub struct Plan {
    sim: Simulator,
    theta: f64,
}

/// Checks the flags (parameters, solver, onset) before any work.
pub fn check(args: &MapArgs) -> Result<Plan, CliError> {
    let params = args.model.params()?;
    let settings = args.solver.settings()?;
    let sim = Simulator::new(params, settings)?;
    let theta = check_theta(&sim, "theta", args.theta)?;
    check_stdout()?;
    Ok(Plan { sim, theta })
}

pub fn run(args: MapArgs) -> Result<(), CliError> {
    let Plan { sim, theta } = check(&args)?;
    let (params, settings) = (*sim.params(), *sim.settings());
    warn_validity(&params);
    let (ev, derivs, _) = sim.cycle_derivatives(theta, 0.0)?;
    warn_event(&ev);
    let regime = Regime::of(params.kappa, params.gamma);
    let onset = onset_character(params.kappa, params.gamma, theta);
    let onset_name = match onset {
        OnsetCharacter::Creep => "creep",
        OnsetCharacter::StickSlip => "stick-slip",
    };
    let derivs = &derivs;
    let text = if args.json {
        json_text(&ev, &params, &settings, regime, onset_name, derivs)?
    } else {
        let what = describe(&params, &settings);
        plain_text(&ev, &what, regime, theta, onset_name, derivs)
    };
    emit(Path::new("-"), text.as_bytes(), false)
}

/// The event, the regime and the derivatives as one JSON object.
fn json_text(
    ev: &SlipEvent,
    params: &Params,
    settings: &SolverSettings,
    regime: Regime,
    onset_name: &str,
    derivs: &Result<MapDerivatives, NotDifferentiable>,
) -> Result<String, CliError> {
    let mut obj = serde_json::to_value(*ev)
        .map_err(|e| CliError::Failed(format!("cannot encode the event as JSON: {e}")))?;
    if let Some(m) = obj.as_object_mut() {
        m.insert("regime".into(), regime.name().into());
        if let Regime::Mixed { theta_c } = regime {
            m.insert("theta_c".into(), theta_c.into());
        }
        m.insert("onset_character".into(), onset_name.into());
        m.insert(
            "params".into(),
            serde_json::to_value(params).unwrap_or_default(),
        );
        m.insert("solver".into(), settings_json(settings));
        // Where f has no derivative the keys are null and the reason
        // is given, rather than a meaningless number.
        match derivs {
            Ok(d) => {
                for (name, value) in d.named() {
                    m.insert(name.into(), value.into());
                }
            }
            Err(reason) => {
                for (name, _) in MapDerivatives::default().named() {
                    m.insert(name.into(), serde_json::Value::Null);
                }
                m.insert("not_differentiable".into(), reason.to_string().into());
            }
        }
    }
    Ok(format!("{obj}\n"))
}

/// The event, the regime and the derivatives as aligned lines.
fn plain_text(
    ev: &SlipEvent,
    what: &str,
    regime: Regime,
    theta: f64,
    onset_name: &str,
    derivs: &Result<MapDerivatives, NotDifferentiable>,
) -> String {
    let regime_line = match regime {
        Regime::Mixed { theta_c } => format!("{} (theta_c = {theta_c})", regime.name()),
        _ => regime.name().to_string(),
    };
    format!(
        "map: {describe}\n\
         regime           {regime_line}\n\
         theta            {theta}  ({onset_name} onset, to linear order)\n\
         theta_next       {theta_next}\n\
         onset (x, y)     ({ox}, {oy})\n\
         accel duration   {accel}\n\
         slip duration    {slip}\n\
         stop (x, y)      ({sx}, {sy})\n\
         slip distance    {dist}\n\
         peak v_r         {peak}\n\
         energy released  {energy}\n\
         stick duration   {stick}\n\
         restarted        {restarted}\n\
         rhs evaluations  {evals} in {steps} steps\n\
         {derivatives}",
        describe = what,
        theta_next = ev.theta_next,
        ox = ev.onset_x,
        oy = ev.onset_y,
        accel = ev.accel_duration,
        slip = ev.slip_duration,
        sx = ev.stop_x,
        sy = ev.stop_y,
        dist = ev.slip_distance,
        peak = ev.peak_vr,
        energy = ev.energy_released,
        stick = ev.stick_duration,
        restarted = if ev.restarted {
            "yes (the stop was on or outside C)"
        } else {
            "no"
        },
        evals = ev.rhs_evals,
        steps = ev.steps,
        derivatives = derivative_lines(derivs),
    )
}

/// The text output's lines for the derivatives, or for their absence.
fn derivative_lines(d: &Result<MapDerivatives, NotDifferentiable>) -> String {
    match d {
        Ok(d) => d
            .named()
            .iter()
            .map(|(name, v)| format!("{:<17}{v}\n", name.replace('_', " ")))
            .collect(),
        Err(reason) => format!("derivative       none: {reason}\n"),
    }
}
