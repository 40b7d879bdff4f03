//! Speed against accuracy: the work-precision measurement, a peer
//! integrator from another crate on the same slip equations, the chart, an
//! a-posteriori reliability check for the fixed-step methods, and the
//! accuracy budget that picks the cheapest setting a view needs, the
//! committed chart the app shows and estimates from, and the quick run the
//! app's Numerics panel makes on the current parameters.
//!
//! Nothing here changes how a slip is integrated: it measures the
//! integrators of [`crate::integrate`] as [`crate::sim`] drives them.

pub mod budget;
pub mod chart;
pub mod committed;
pub mod fixed_sample;
pub mod peer;
pub mod quick;
pub mod reliability;
pub mod sample;
pub mod work_precision;

pub use budget::{Accuracy, Budget, budget_for, settings_for};
pub use committed::{Estimate, estimate};
pub use reliability::{Checked, checked_cycle};

pub use sample::{
    Attractor, Iterate, SamplePoint, build_sample, build_sample_until, default_attractors,
};
pub use work_precision::{Row, Subject, default_subjects, measure};
