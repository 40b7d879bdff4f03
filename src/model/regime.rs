//! The linear stability of a slip onset (paper, section 3): an onset at θ is
//! creep if γ² < A(θ) = κ cos²θ + sin²θ and stick-slip if γ² > A(θ).

use serde::{Deserialize, Serialize};

/// Which onsets on C are creep and which are stick-slip.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Regime {
    /// γ² < min(1, κ): every onset is creep.
    PureCreep,
    /// min(1, κ) < γ² < max(1, κ): creep on part of C, stick-slip on the
    /// rest, separated at the critical angles ±θc, π ± θc.
    Mixed {
        /// θc ∈ (0, π/2) with tan²θc = (κ − γ²)/(γ² − 1).
        theta_c: f64,
    },
    /// γ² > max(1, κ): every onset is stick-slip.
    PureStickSlip,
}

impl Regime {
    /// The regime of (κ, γ).
    pub fn of(kappa: f64, gamma: f64) -> Regime {
        let g2 = gamma * gamma;
        let (amin, amax) = (kappa.min(1.0), kappa.max(1.0));
        if g2 < amin {
            Regime::PureCreep
        } else if g2 > amax {
            Regime::PureStickSlip
        } else {
            match critical_angles(kappa, gamma) {
                Some(theta_c) => Regime::Mixed { theta_c },
                // γ² = κ = 1 exactly: A ≡ γ², the degenerate boundary case.
                None => Regime::PureStickSlip,
            }
        }
    }

    /// A short name for badges and CSV.
    pub fn name(&self) -> &'static str {
        match self {
            Regime::PureCreep => "pure creep",
            Regime::Mixed { .. } => "mixed",
            Regime::PureStickSlip => "pure stick-slip",
        }
    }
}

/// θc ∈ [0, π/2] with tan²θc = (κ − γ²)/(γ² − 1), when it exists (mixed
/// regime, boundaries included).
pub fn critical_angles(kappa: f64, gamma: f64) -> Option<f64> {
    let g2 = gamma * gamma;
    let num = kappa - g2;
    let den = g2 - 1.0;
    if den == 0.0 {
        return if num == 0.0 {
            None
        } else {
            Some(std::f64::consts::FRAC_PI_2)
        };
    }
    let t2 = num / den;
    if t2 >= 0.0 && t2.is_finite() {
        Some(t2.sqrt().atan())
    } else {
        None
    }
}

/// Whether a slip starting at θ is creep or stick-slip, to linear order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum OnsetCharacter {
    Creep,
    StickSlip,
}

/// A(θ) = κ cos²θ + sin²θ, the stiffness the onset at θ sees along the
/// elastic force: the onset is creep if γ² < A(θ), stick-slip if γ² > A(θ).
pub fn onset_stiffness(kappa: f64, theta: f64) -> f64 {
    let (s, c) = theta.sin_cos();
    kappa * c * c + s * s
}

/// The character of an onset at θ: creep if γ² < κ cos²θ + sin²θ.
pub fn onset_character(kappa: f64, gamma: f64, theta: f64) -> OnsetCharacter {
    if gamma * gamma < onset_stiffness(kappa, theta) {
        OnsetCharacter::Creep
    } else {
        OnsetCharacter::StickSlip
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_critical_angle() {
        // docs/model.md: γ = 6.5, κ = 50 gives θc = 0.4090.
        let tc = critical_angles(50.0, 6.5).unwrap();
        assert!((tc - 0.4090).abs() < 5e-5, "{tc}");
        assert_eq!(Regime::of(50.0, 6.5), Regime::Mixed { theta_c: tc });
        // On the critical angle A(θc) = γ² exactly.
        let a = 50.0 * tc.cos().powi(2) + tc.sin().powi(2);
        assert!((a - 42.25).abs() < 1e-10);
    }

    #[test]
    fn regimes_follow_the_inequalities() {
        assert_eq!(Regime::of(3.0, 0.5), Regime::PureCreep);
        assert_eq!(Regime::of(18.95, 6.5), Regime::PureStickSlip);
        assert!(matches!(Regime::of(0.5, 0.9), Regime::Mixed { .. }));
        assert_eq!(onset_character(50.0, 6.5, 0.1), OnsetCharacter::Creep);
        assert_eq!(onset_character(50.0, 6.5, 1.0), OnsetCharacter::StickSlip);
    }
}
