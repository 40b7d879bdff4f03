//! Where the model's physical assumptions hold, and what a result that lies
//! outside them looks like.
//!
//! `Params::validate` says what the code can compute; this module says
//! what the computation still means. The model pictures a block pulled
//! *slowly* (ν ≪ 1: a slip, at relative speeds of order 0.1–1, is over
//! long before the surface has moved appreciably) whose friction turns
//! from the elastic force towards the slip within a slip (Ω v_r ≫ 1 for
//! most of it). Measured on the map at the paper's Fig. 3b point
//! (κ = 18.95, γ = 6.5, θν = 1, θ = 1):
//!
//! - θ' moves smoothly with ν up to ν ≈ 0.03 and jumps to another branch
//!   between 0.03 and 0.1; at ν = 10 a slip never stops (the surface
//!   outruns the block) and at ν = 1e3 the map returned θ' = θ − π with a
//!   negative "energy released". Hence [`NU_MAX`] = 1e-2.
//! - Below Ω ≈ 1 the friction direction hardly turns during a slip
//!   (θ' at Ω = 0.1 differs from Ω = 1 by 0.33 rad, and Ω = 1e-6 equals
//!   Ω = 1e-2 to 2e-3); above Ω ≈ 1e4 the turn is instantaneous and the
//!   equations stiff (Ω = 1e5 costs 18× the evaluations of Ω = 50 for the
//!   same θ' to 7 digits). Hence [`OMEGA_RANGE`] = [1, 1e4].
//!
//! Outside these the tool still computes (the equations are well defined)
//! but says so: the command line prints a warning line, the window shows a
//! badge. A single slip event whose energy released is negative, or whose
//! θ' is θ − π (the block carried straight back through the curve), is
//! flagged by [`event_anomalies`] whatever the parameters.

use super::{Params, wrap_angle};

/// The largest pulling speed ν for which slips are fast against the
/// surface ("ν ≪ 1").
pub const NU_MAX: f64 = 1e-2;

/// The range of Ω in which the friction direction turns within a slip but
/// not instantaneously.
pub const OMEGA_RANGE: (f64, f64) = (1.0, 1e4);

/// One way the parameters leave the model's assumptions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ValidityWarning {
    /// ν above [`NU_MAX`]: the slow-pulling picture does not hold.
    FastPulling { nu: f64 },
    /// Ω below [`OMEGA_RANGE`]: the friction direction barely turns.
    ShortMemory { omega: f64 },
    /// Ω above [`OMEGA_RANGE`]: an instantaneous, stiff switch.
    LongMemory { omega: f64 },
}

/// A value as a message shows it: as typed when short, else `1e-6` form.
fn short(v: f64) -> String {
    let plain = format!("{v}");
    if plain.len() <= 6 {
        plain
    } else {
        format!("{v:e}")
    }
}

impl std::fmt::Display for ValidityWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ValidityWarning::FastPulling { nu } => write!(
                f,
                "nu = {} is outside the model's slow-pulling assumption (nu <= {NU_MAX}): results are computed but not physical",
                short(*nu)
            ),
            ValidityWarning::ShortMemory { omega } => write!(
                f,
                "omega = {} is below {}: the friction direction hardly turns within a slip, outside the model's assumptions",
                short(*omega),
                OMEGA_RANGE.0
            ),
            ValidityWarning::LongMemory { omega } => write!(
                f,
                "omega = {} is above {}: the friction switches instantly, the equations are stiff and slow to integrate",
                short(*omega),
                OMEGA_RANGE.1
            ),
        }
    }
}

/// The ways `p` leaves the model's assumptions (empty when it is inside).
pub fn validity(p: &Params) -> Vec<ValidityWarning> {
    let mut out = Vec::new();
    if p.nu > NU_MAX {
        out.push(ValidityWarning::FastPulling { nu: p.nu });
    }
    if p.omega < OMEGA_RANGE.0 {
        out.push(ValidityWarning::ShortMemory { omega: p.omega });
    } else if p.omega > OMEGA_RANGE.1 {
        out.push(ValidityWarning::LongMemory { omega: p.omega });
    }
    out
}

/// A slip event that no slowly pulled block produces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EventAnomaly {
    /// The elastic energy rose during the slip.
    NegativeEnergy { energy_released: f64 },
    /// θ' = θ − π (to 1e-6 rad): the block ended opposite to where it began.
    Reversed { theta: f64, theta_next: f64 },
}

impl std::fmt::Display for EventAnomaly {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EventAnomaly::NegativeEnergy { energy_released } => write!(
                f,
                "the slip released a negative energy ({}): the block gained elastic energy, which a slowly pulled block cannot",
                short(*energy_released)
            ),
            EventAnomaly::Reversed { theta, theta_next } => write!(
                f,
                "theta' = {theta_next} is theta - pi (theta = {theta}): the block was carried straight through the curve, not a physical slip"
            ),
        }
    }
}

/// The anomalies of one slip event from `theta` to `theta_next` that
/// released `energy_released` (empty for a normal event).
pub fn event_anomalies(theta: f64, theta_next: f64, energy_released: f64) -> Vec<EventAnomaly> {
    let mut out = Vec::new();
    if energy_released < 0.0 {
        out.push(EventAnomaly::NegativeEnergy { energy_released });
    }
    if wrap_angle(theta_next - theta - std::f64::consts::PI).abs() < 1e-6 {
        out.push(EventAnomaly::Reversed { theta, theta_next });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paper_is_inside_and_each_edge_is_named() {
        for k in [
            "fig3a",
            "fig3b",
            "fig4",
            "creep",
            "chaos",
            "intermittent",
            "hysteresis",
        ] {
            let p = crate::model::preset(k).map(|p| p.params);
            assert_eq!(p.map(|p| validity(&p)), Some(vec![]), "{k}");
        }
        let p = Params::default();
        assert_eq!(
            validity(&Params { nu: 1.0, ..p }),
            vec![ValidityWarning::FastPulling { nu: 1.0 }]
        );
        assert!(validity(&Params { nu: NU_MAX, ..p }).is_empty());
        assert_eq!(
            validity(&Params { omega: 1e-6, ..p }),
            vec![ValidityWarning::ShortMemory { omega: 1e-6 }]
        );
        assert_eq!(
            validity(&Params { omega: 1e5, ..p }),
            vec![ValidityWarning::LongMemory { omega: 1e5 }]
        );
    }

    #[test]
    fn reversed_and_negative_events_are_flagged() {
        assert!(event_anomalies(0.5, 0.2, 0.1).is_empty());
        let a = event_anomalies(1.0, 1.0 - std::f64::consts::PI, -85.7);
        assert_eq!(a.len(), 2, "{a:?}");
        // θ − π wraps: θ = −2 gives θ' = −2 − π + 2π.
        let back = wrap_angle(-2.0 - std::f64::consts::PI);
        assert_eq!(
            event_anomalies(-2.0, back, 0.1),
            vec![EventAnomaly::Reversed {
                theta: -2.0,
                theta_next: back
            }]
        );
    }
}
