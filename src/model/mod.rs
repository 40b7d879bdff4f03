//! The one-block model as `docs/model.md` states it: parameters, the
//! regimes, the curve C and the critical ellipse, and the closed-form stick
//! phase. Nothing here integrates and nothing here knows about screens.

mod geometry;
mod params;
pub mod presets;
mod regime;
mod stick;
pub mod validity;

pub use geometry::{
    MAX_ABS_THETA, critical_ellipse_point, elastic_energy, ellipse_c_point, exit_arc,
    is_on_exit_arc, point_from_theta, project_onto_exit_arc, theta_from_point, wrap_angle,
};
pub use params::{GAMMA_RANGE, KAPPA_RANGE, NU_RANGE, ParamError, Params};
pub use presets::{PRESETS, Preset, preset, preset_keys};
pub use regime::{OnsetCharacter, Regime, critical_angles, onset_character, onset_stiffness};
pub use stick::{stick_exit_point, stick_exit_time};
pub use validity::{EventAnomaly, ValidityWarning, event_anomalies, validity};
