//! The documented ranges are the ranges that work (docs/cli.md, "Common
//! flags"): with κ, γ or ν at either end of its range and the others a
//! preset's, one map iterate finishes from points across the whole exit
//! arc, at every preset. Past the ends slips turn into steady sliding (at
//! κ = 2e3, γ = 0 or ν = 1 some presets' slips never stop), so a value just
//! past an end is refused before any work: exit 2, naming the flag.

#![allow(clippy::unwrap_used)]

use crate::cli_support;

use cli_support::*;
use oneblock::model::{GAMMA_RANGE, KAPPA_RANGE, NU_RANGE, PRESETS, exit_arc, wrap_angle};
use oneblock::{Method, Params, Simulator, SolverSettings};

/// A range's flag, one of its ends, and how to set it in `Params`.
type End = (&'static str, f64, fn(&mut Params, f64));

/// Each range's ends.
fn ends() -> Vec<End> {
    let kappa: fn(&mut Params, f64) = |p, v| p.kappa = v;
    let gamma: fn(&mut Params, f64) = |p, v| p.gamma = v;
    let nu: fn(&mut Params, f64) = |p, v| p.nu = v;
    vec![
        ("kappa", *KAPPA_RANGE.start(), kappa),
        ("kappa", *KAPPA_RANGE.end(), kappa),
        ("gamma", *GAMMA_RANGE.start(), gamma),
        ("gamma", *GAMMA_RANGE.end(), gamma),
        ("nu", *NU_RANGE.start(), nu),
        ("nu", *NU_RANGE.end(), nu),
    ]
}

#[test]
fn the_map_runs_at_each_end_of_every_range_at_every_preset() {
    // The command line's defaults: DOP853 at tol 1e-10, the default step bound.
    let settings = SolverSettings::adaptive(Method::Dop853, 1e-10);
    let mut failures = Vec::new();
    for preset in PRESETS {
        for (name, value, set) in ends() {
            let mut p = preset.params;
            set(&mut p, value);
            let sim = Simulator::new(p, settings).unwrap();
            // Onsets across the exit arc, near both of its ends too.
            let (psi, half) = exit_arc(p.kappa, p.theta_nu);
            for frac in [-0.9, -0.5, 0.0, 0.5, 0.9] {
                let theta = wrap_angle(psi + frac * half);
                match sim.cycle(theta, 0.0, None) {
                    Ok(ev) => {
                        let ok = ev.theta_next.is_finite()
                            && ev.theta_next.abs() <= std::f64::consts::PI
                            && ev.slip_duration > 0.0
                            && ev.stick_duration.is_finite()
                            && ev.stick_duration >= 0.0;
                        if !ok {
                            failures.push(format!(
                                "{} {name} = {value} θ = {theta}: {ev:?}",
                                preset.key
                            ));
                        }
                    }
                    Err(e) => {
                        failures.push(format!("{} {name} = {value} θ = {theta}: {e}", preset.key))
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_map_command_runs_at_the_ends() {
    for (name, value, _) in ends() {
        let args: Vec<String> = ["map", "--preset", "fig3b", "--theta", "1"]
            .into_iter()
            .map(String::from)
            .chain([format!("--{name}"), format!("{value:e}")])
            .collect();
        let o = run(&args);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {}", stderr(&o));
        assert!(stdout(&o).contains("theta_next"), "{args:?}");
    }
}

#[test]
fn just_past_each_end_is_refused_naming_the_flag_and_why() {
    for (name, value, _) in ends() {
        let flag = format!("--{name}");
        // 1 % past the end, outward.
        let lower = ends()
            .iter()
            .filter(|(n, _, _)| *n == name)
            .all(|(_, v, _)| value <= *v);
        let past = if lower { value * 0.99 } else { value * 1.01 };
        let args: Vec<String> = ["map", "--preset", "fig3b", "--theta", "1"]
            .into_iter()
            .map(String::from)
            .chain([flag.clone(), format!("{past:e}")])
            .collect();
        assert_bad_input(&args, &flag);
        // The steady-sliding ends say so (κ's and ν's upper, γ's lower).
        let sliding = matches!(
            (name, lower),
            ("kappa", false) | ("gamma", true) | ("nu", false)
        );
        if sliding {
            assert!(stderr(&run(&args)).contains("steady sliding"), "{args:?}");
        }
    }
}
