//! The job list, declared once. Each line of [`declare_jobs!`]'s table
//! names a kind of job: its spec's type, the worker lane it runs on, its
//! labels, how it is built from its spec, and what new parameters do to
//! it. [`Spec`], [`Kind`], [`Lane`], `From<…Spec> for Spec` and the
//! kind's labels are all made from that table, so a new kind of job is
//! one line here, its definition (the job's module) and its command and
//! view.

use super::basins::{BasinsJob, BasinsSpec, MapBasinsSpec};
use super::continuation::{boundaries_job, find_job};
use super::events::{PassageSpec, ScanSpec, passage_job, scan_job};
use super::iterate::IterateJob;
use super::numerics::WorkPrecisionJob;
use super::orbit::{PanicJob, TrajectoryJob};
use super::phase::PhaseJob;
use super::specs::{
    BoundarySpec, ContinuationSpec, IterateSpec, PhaseSpec, SweepSpec, TrajectorySpec,
    WorkPrecisionSpec,
};
use super::sweep::SweepJob;
use super::{Job, JobError, Shape};
use crate::integrate::SolverSettings;
use crate::model::Params;

/// What a new parameter set does to a lane's latest job.
#[derive(Clone, Debug, PartialEq)]
pub enum OnParams {
    /// Run it again with the new parameters.
    Rerun(Box<Spec>),
    /// Stop it if it runs (it was asked for; it is not run again).
    Cancel,
    /// Leave it be.
    Keep,
}

/// What new parameters do to a kind of job, as its table entry says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NewParams {
    /// It runs again with them (its result is replaced then).
    Rerun,
    /// It is stopped; its result is of other parameters.
    Cancel,
    /// It is left alone (a measurement of the parameters it names).
    Keep,
}

/// The [`NewParams`] of a table entry's `new_params`.
macro_rules! new_params {
    (rerun) => {
        NewParams::Rerun
    };
    (cancel) => {
        NewParams::Cancel
    };
    (keep) => {
        NewParams::Keep
    };
}

/// A spec whose parameters and solver new parameters replace (a job that
/// is run again).
pub trait Rerun: Clone + Into<Spec> {
    /// Its parameters and solver settings.
    fn params_mut(&mut self) -> (&mut Params, &mut SolverSettings);

    /// Whether new `params` (and `settings`, if given) change it: by
    /// default any change does.
    fn changed_by(&self, _params: &Params, _settings: Option<SolverSettings>) -> bool {
        true
    }

    /// This spec with the new parameters (and settings), to run again.
    fn with(&self, params: Params, settings: Option<SolverSettings>) -> Spec {
        let mut spec = self.clone();
        let (p, s) = spec.params_mut();
        *p = params;
        if let Some(settings) = settings {
            *s = settings;
        }
        spec.into()
    }
}

/// What new parameters do to a job of the policy named in the table.
macro_rules! on_params {
    (rerun, $s:expr, $p:expr, $n:expr) => {
        if $s.changed_by(&$p, $n) {
            OnParams::Rerun(Box::new($s.with($p, $n)))
        } else {
            OnParams::Keep
        }
    };
    (cancel, $s:expr, $p:expr, $n:expr) => {{
        let _ = ($s, $p, $n);
        OnParams::Cancel
    }};
    (keep, $s:expr, $p:expr, $n:expr) => {{
        let _ = ($s, $p, $n);
        OnParams::Keep
    }};
}

/// The table: lanes first (each with its thread name), then one entry per
/// kind of job.
macro_rules! declare_jobs {
    (
        lanes { $( $(#[$ldoc:meta])* $lane:ident = $lname:literal, )* }
        kinds { $(
            $(#[$doc:meta])*
            $kind:ident($spec:ty) {
                lane: $klane:ident,
                label: $label:literal,
                short: $short:literal,
                new_params: $policy:ident,
                start: |$s:ident, $shape:pat_param| $start:expr,
            }
        )* }
    ) => {
        /// Which lane a job runs on: one thread of the worker each, where
        /// a newer job supersedes the lane's running one.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
        pub enum Lane { $( $(#[$ldoc])* $lane, )* }

        impl Lane {
            /// Every lane, in the order of [`Lane::index`].
            pub const ALL: [Lane; [$(Lane::$lane),*].len()] = [$(Lane::$lane),*];

            /// Its position in [`Lane::ALL`] (a lane table's index).
            pub fn index(self) -> usize {
                self as usize
            }

            /// Its name in thread names.
            pub fn name(self) -> &'static str {
                match self { $( Lane::$lane => $lname, )* }
            }
        }

        /// Every kind of job, with its typed spec.
        #[derive(Clone, Debug, PartialEq)]
        pub enum Spec {
            $( $(#[$doc])* $kind($spec), )*
            /// Test-only fault injection: a few cycles, then a panic.
            #[doc(hidden)]
            Panic { after_cycles: usize },
        }

        /// Every kind of job, by what its results are: the key of a front
        /// end's job table (the window's `Jobs`).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
        pub enum Kind { $( $(#[$doc])* $kind, )* }

        impl Kind {
            /// Every kind, in the order of [`Kind::index`].
            pub const ALL: [Kind; [$(Kind::$kind),*].len()] = [$(Kind::$kind),*];
            /// How many kinds there are.
            pub const COUNT: usize = Kind::ALL.len();

            /// Its position in [`Kind::ALL`] (a job table's index).
            pub fn index(self) -> usize {
                self as usize
            }

            /// The worker lane it runs on.
            pub fn lane(self) -> Lane {
                match self { $( Kind::$kind => Lane::$klane, )* }
            }

            /// A short name for the window's panel and status lines.
            pub fn label(self) -> &'static str {
                match self { $( Kind::$kind => $label, )* }
            }

            /// What new parameters do to it.
            pub fn new_params(self) -> NewParams {
                match self { $( Kind::$kind => new_params!($policy), )* }
            }

            /// A one-word name for the side panel's table.
            pub fn short_label(self) -> &'static str {
                match self { $( Kind::$kind => $short, )* }
            }
        }

        $(
            impl From<$spec> for Spec {
                fn from(s: $spec) -> Spec {
                    Spec::$kind(s)
                }
            }
        )*

        impl Spec {
            /// Its kind (the fault injection counts as a trajectory).
            pub fn kind(&self) -> Kind {
                match self {
                    $( Spec::$kind(_) => Kind::$kind, )*
                    Spec::Panic { .. } => Kind::Trajectory,
                }
            }

            /// Checks the spec and builds its job (nothing is computed yet
            /// but what validation needs).
            pub fn start(self, shape: Shape) -> Result<Box<dyn Job>, JobError> {
                match self {
                    $( Spec::$kind($s) => {
                        let $shape = shape;
                        $start
                    } )*
                    Spec::Panic { after_cycles } => Ok(Box::new(PanicJob::new(after_cycles))),
                }
            }

            /// What new parameters (and solver settings, if given) do to
            /// this job when it is its lane's latest (the table's
            /// `new_params`).
            pub fn on_params(&self, params: Params, settings: Option<SolverSettings>) -> OnParams {
                match self {
                    $( Spec::$kind(s) => on_params!($policy, s, params, settings), )*
                    Spec::Panic { .. } => OnParams::Keep,
                }
            }
        }
    };
}

use serde::{Deserialize, Serialize};

declare_jobs! {
    lanes {
        /// Trajectories and map iterates, one job at a time.
        Orbit = "orbit",
        /// Bifurcation diagrams.
        Sweep = "sweep",
        /// Work-precision measurements.
        Numerics = "numerics",
        /// Phase diagrams in (θν, κ).
        Phase = "phase",
        /// Branches of cycles continued in one parameter.
        Continuation = "continuation",
        /// Bifurcation curves in (θν, κ).
        Curves = "curves",
        /// The Events view's creep channel passage.
        Passage = "passage",
        /// The Events view's tangency scan.
        Scan = "scan",
        /// Attractors and basins over θν (the Basins view).
        Basins = "basins",
        /// Attractors and basins at the current parameters.
        MapBasins = "map-basins",
    }
    kinds {
        /// The block's path and slip events: the plane, the block and the
        /// event catalogue.
        Trajectory(TrajectorySpec) {
            lane: Orbit, label: "trajectory", short: "path", new_params: rerun,
            start: |s, _| Ok(Box::new(TrajectoryJob::new(s)?)),
        }
        /// The bifurcation diagram over θν.
        Sweep(SweepSpec) {
            lane: Sweep, label: "diagram", short: "diagram", new_params: rerun,
            start: |s, shape| Ok(Box::new(SweepJob::new(s, shape)?)),
        }
        /// Map iterates, their period and Lyapunov exponent, the map's
        /// graph: the return map.
        Iterate(IterateSpec) {
            lane: Orbit, label: "map iterates", short: "map", new_params: rerun,
            start: |s, _| Ok(Box::new(IterateJob::new(s)?)),
        }
        /// A phase diagram over (θν, κ): run again only if γ, ν, Ω or the
        /// solver changed (κ and θν are its axes).
        Phase(PhaseSpec) {
            lane: Phase, label: "phase diagram", short: "phase", new_params: rerun,
            start: |s, _| Ok(Box::new(PhaseJob::new(s)?)),
        }
        /// A work-precision measurement (it runs every method, so it has
        /// no solver setting of its own; new parameters leave it be).
        Numerics(WorkPrecisionSpec) {
            lane: Numerics, label: "work-precision", short: "numerics", new_params: keep,
            start: |s, _| Ok(Box::new(WorkPrecisionJob::new(s)?)),
        }
        /// Find bifurcations: a branch and its cascade.
        Branches(ContinuationSpec) {
            lane: Continuation, label: "bifurcations", short: "branches", new_params: cancel,
            start: |s, _| Ok(Box::new(find_job(s))),
        }
        /// Boundaries: doubling curves in (θν, κ).
        Curves(BoundarySpec) {
            lane: Curves, label: "boundaries", short: "curves", new_params: cancel,
            start: |s, _| Ok(Box::new(boundaries_job(s))),
        }
        /// The Events view's creep channel passage.
        Passage(PassageSpec) {
            lane: Passage, label: "channel passage", short: "passage", new_params: cancel,
            start: |s, _| passage_job(s),
        }
        /// The Events view's tangency scan.
        Scan(ScanSpec) {
            lane: Scan, label: "tangency scan", short: "scan", new_params: cancel,
            start: |s, _| scan_job(s),
        }
        /// Attractors and basins over θν (the Basins view).
        Basins(BasinsSpec) {
            lane: Basins, label: "basins", short: "basins", new_params: rerun,
            start: |s, _| Ok(Box::new(BasinsJob::new(s, Lane::Basins)?)),
        }
        /// Attractors and basins at the current parameters (the return
        /// map's band).
        MapBasins(MapBasinsSpec) {
            lane: MapBasins, label: "map basins", short: "map basins", new_params: cancel,
            start: |s, _| Ok(Box::new(BasinsJob::new(s.0, Lane::MapBasins)?)),
        }
    }
}

impl Spec {
    /// The lane it runs on.
    pub fn lane(&self) -> Lane {
        self.kind().lane()
    }

    /// Whether a cancelled job of this kind is forgotten, so that new
    /// parameters do not start it again (a grid the user stopped stays
    /// stopped).
    pub fn forgotten_when_cancelled(&self) -> bool {
        matches!(self, Spec::Phase(_))
    }

    /// Whether new parameters may run it again at all (the fault injection
    /// is never remembered).
    pub fn remembered(&self) -> bool {
        !matches!(self, Spec::Panic { .. })
    }
}

macro_rules! rerun_with_params {
    ($($spec:ty),*) => {
        $(
            impl Rerun for $spec {
                fn params_mut(&mut self) -> (&mut Params, &mut SolverSettings) {
                    (&mut self.params, &mut self.settings)
                }
            }
        )*
    };
}

rerun_with_params!(TrajectorySpec, SweepSpec, IterateSpec, BasinsSpec);

impl Rerun for PhaseSpec {
    fn params_mut(&mut self) -> (&mut Params, &mut SolverSettings) {
        (&mut self.params, &mut self.settings)
    }

    /// A grid keeps both its ranges (κ and θν are its axes): only γ, ν, Ω
    /// or the solver change it.
    fn changed_by(&self, params: &Params, settings: Option<SolverSettings>) -> bool {
        let p = &self.params;
        (p.gamma, p.nu, p.omega) != (params.gamma, params.nu, params.omega)
            || settings.is_some_and(|n| n != self.settings)
    }
}
