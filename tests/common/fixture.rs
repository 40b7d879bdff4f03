//! Parameter fixtures by name: the presets of `oneblock::model`, changed
//! field by field where a test needs another point, e.g.
//! `preset("fig3b").with_theta_nu(1.2)` or
//! `Params { kappa: 10.0, ..preset("fig4") }`.

use oneblock::Params;

/// The parameters of the preset called `key` (Ω = 50, as in the paper).
///
/// # Panics
/// If there is no such preset: a typo in a test.
pub fn preset(key: &str) -> Params {
    match oneblock::model::preset(key) {
        Some(p) => p.params,
        None => panic!(
            "no preset {key:?}; the keys are {}",
            oneblock::model::preset_keys()
        ),
    }
}
