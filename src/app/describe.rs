//! Plain words for a lecture audience: the regime badge and the "what you
//! are seeing" line, from the regime (docs/model.md, linear stability of an
//! onset) and the orbit's detected period and Lyapunov exponent.

use crate::model::{OnsetCharacter, Regime, onset_character};
use crate::sim::Period;

/// The badge text: the regime, with θc when it exists.
pub fn regime_badge(kappa: f64, gamma: f64) -> String {
    match Regime::of(kappa, gamma) {
        Regime::PureCreep => "pure creep (γ² < min(1, κ))".to_string(),
        Regime::Mixed { theta_c } => format!("mixed: θc = {theta_c:.4}"),
        Regime::PureStickSlip => "pure stick-slip (γ² > max(1, κ))".to_string(),
    }
}

/// A one-line hover explanation of the regime.
pub fn regime_explanation(kappa: f64, gamma: f64) -> &'static str {
    match Regime::of(kappa, gamma) {
        Regime::PureCreep => {
            "Friction weakens too slowly (γ small): wherever the block starts to slip, \
             it creeps along smoothly. The critical ellipse lies inside C."
        }
        Regime::Mixed { .. } => {
            "Onsets with |θ| < θc creep, the others are stick-slip earthquakes. \
             The critical ellipse crosses C at the four critical angles."
        }
        Regime::PureStickSlip => {
            "Every slip is a stick-slip event (an earthquake): friction drops fast \
             once the block moves. The critical ellipse lies outside C."
        }
    }
}

/// What the current attractor is, in words.
pub fn attractor_line(
    kappa: f64,
    gamma: f64,
    thetas: &[f64],
    period: Option<Period>,
    (lyapunov, stderr): (Option<f64>, Option<f64>),
) -> String {
    let Some(period) = period else {
        return "Computing the orbit…".into();
    };
    let exact = matches!(period, Period::Periodic(_));
    let lyap = lyapunov
        .map(|l| {
            format!(
                " (Lyapunov exponent {})",
                crate::text::lyapunov(l, stderr, exact)
            )
        })
        .unwrap_or_default();
    match period {
        Period::Periodic(1) => {
            let theta = thetas.last().copied().unwrap_or(0.0);
            match onset_character(kappa, gamma, theta) {
                OnsetCharacter::Creep => format!(
                    "Creep fixed point: the block slides smoothly, every slip tiny and identical, \
                     starting at θ* = {theta:.3}{lyap}."
                ),
                OnsetCharacter::StickSlip => format!(
                    "Stick-slip fixed point: the block sticks, then slips by the same amount \
                     at the same place (θ* = {theta:.3}) every cycle: regular earthquakes{lyap}."
                ),
            }
        }
        Period::Periodic(n) => format!(
            "Period {n}: a repeating pattern of {n} different earthquakes, then it starts over{lyap}."
        ),
        Period::Aperiodic => {
            // Chaos is claimed only where λ is clearly above 0: three
            // standard errors (or 1e-3 while too few iterates give one).
            let l = lyapunov.unwrap_or(0.0);
            let margin = stderr.map_or(1e-3, |e| 3.0 * e);
            if l > margin {
                if is_intermittent(kappa, gamma, thetas) {
                    format!(
                        "Intermittency: long stretches of creep (tiny slips just inside θc) \
                         broken by occasional large earthquakes{lyap}."
                    )
                } else {
                    format!(
                        "Chaos: no two earthquakes repeat, and nearby starts drift apart \
                         every cycle{lyap}: long-term prediction is impossible."
                    )
                }
            } else {
                format!("Not settled yet: the orbit is still converging{lyap}.")
            }
        }
    }
}

/// Mostly creep onsets with a few stick-slip ones: intermittent creep and
/// large slips (docs/model.md, Fig. 3a for larger θν).
pub fn is_intermittent(kappa: f64, gamma: f64, thetas: &[f64]) -> bool {
    if !matches!(Regime::of(kappa, gamma), Regime::Mixed { .. }) || thetas.len() < 20 {
        return false;
    }
    let creep = thetas
        .iter()
        .filter(|&&t| onset_character(kappa, gamma, t) == OnsetCharacter::Creep)
        .count();
    creep * 2 > thetas.len() && creep < thetas.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_follow_period_and_lyapunov() {
        assert!(
            attractor_line(18.95, 6.5, &[0.2], Some(Period::Periodic(1)), (None, None))
                .starts_with("Stick-slip fixed point")
        );
        assert!(
            attractor_line(3.0, 0.5, &[0.7], Some(Period::Periodic(1)), (None, None))
                .starts_with("Creep fixed point")
        );
        assert!(
            attractor_line(
                18.95,
                6.5,
                &[],
                Some(Period::Periodic(4)),
                (Some(-0.2), None)
            )
            .starts_with("Period 4")
        );
        assert!(
            attractor_line(
                18.95,
                6.5,
                &[0.1; 30],
                Some(Period::Aperiodic),
                (Some(0.4), None)
            )
            .starts_with("Chaos")
        );
        let mut th = vec![0.3; 25];
        th.extend([1.2; 5]);
        assert!(
            attractor_line(50.0, 6.5, &th, Some(Period::Aperiodic), (Some(0.3), None))
                .starts_with("Intermittency")
        );
        assert!(regime_badge(50.0, 6.5).contains("0.409"));
    }
}
