//! Named parameter sets: the paper's figures and a few teaching examples.
//! Every command takes `--preset KEY`, and the window offers them as
//! buttons, so a figure is named the same way everywhere.

use super::Params;

/// A named parameter set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Preset {
    /// The command-line name (`--preset`).
    pub key: &'static str,
    /// The button's label.
    pub label: &'static str,
    pub params: Params,
}

/// A preset's parameters at Ω = 50, the value every figure of the paper uses.
const fn p(kappa: f64, gamma: f64, nu: f64, theta_nu: f64) -> Params {
    Params {
        kappa,
        gamma,
        nu,
        theta_nu,
        omega: 50.0,
    }
}

/// The presets: the paper's figures, a creep example, one chaotic and
/// one intermittent orbit, and two coexisting cycles.
pub const PRESETS: [Preset; 7] = [
    Preset {
        key: "fig3a",
        label: "Fig. 3a: mixed regime (κ = 50, γ = 6.5, ν = 1e-4)",
        params: p(50.0, 6.5, 1e-4, 0.3),
    },
    Preset {
        key: "fig3b",
        label: "Fig. 3b: stick-slip (κ = 18.95, γ = 6.5, ν = 1e-3)",
        params: p(18.95, 6.5, 1e-3, 1.0),
    },
    Preset {
        key: "fig4",
        label: "Fig. 4: phase diagram settings (κ = 16, γ = 6.5, ν = 1e-3)",
        params: p(16.0, 6.5, 1e-3, 1.0),
    },
    Preset {
        key: "creep",
        label: "Pure creep (γ = 0.5 < 1, κ = 3)",
        params: p(3.0, 0.5, 1e-3, 0.7),
    },
    Preset {
        key: "chaos",
        label: "Chaotic orbit (κ = 18.95, θν = 1.25)",
        params: p(18.95, 6.5, 1e-3, 1.25),
    },
    Preset {
        key: "intermittent",
        label: "Intermittent orbit (κ = 50, θν = 1.4)",
        params: p(50.0, 6.5, 1e-4, 1.4),
    },
    Preset {
        key: "hysteresis",
        label: "Hysteresis (κ = 10, θν = 1.4)",
        params: p(10.0, 6.5, 1e-3, 1.4),
    },
];

/// The preset called `key`.
pub fn preset(key: &str) -> Option<&'static Preset> {
    PRESETS.iter().find(|p| p.key == key)
}

/// The preset names, for error messages.
pub fn preset_keys() -> String {
    PRESETS.iter().map(|p| p.key).collect::<Vec<_>>().join(", ")
}
