//! The job list, declared once. Each line of [`declare_jobs!`]'s table
//! says everything about a kind of job: its spec's type, the worker lane
//! it runs on, its labels, what new parameters do to it, which parameters
//! its result depends on (the one rule of [`super::depends`]), the
//! accuracy its view can show, its debounce, its marker and hover in the
//! window, and how it is built from its spec. [`Spec`], [`Kind`],
//! [`Lane`], `From<…Spec> for Spec` and those accessors are all made from
//! that table, so a new kind of job is its line here, its job module, its
//! `Update` variants and its view (docs/jobs.md lists the rest).

// Every kind's spec, exported from here with the table (`jobs::*`).
pub use super::basins::{BasinsSpec, MapBasinsSpec};
pub use super::events::{PassageSpec, ScanSpec};
pub use super::specs::{
    BoundarySpec, ContinuationSpec, IterateSpec, PhaseSpec, SweepSpec, TrajectorySpec,
    WorkPrecisionSpec,
};

use super::basins::BasinsJob;
use super::continuation::{boundaries_job, find_job};
use super::depends::{Bound, Depends};
use super::events::{passage_job, scan_job};
use super::iterate::IterateJob;
use super::numerics::WorkPrecisionJob;
use super::orbit::{PanicJob, TrajectoryJob};
use super::phase::PhaseJob;
use super::sweep::SweepJob;
use super::{Job, JobError, Shape};
use crate::integrate::SolverSettings;
use crate::model::Params;
use crate::numerics::Accuracy;
use crate::sim::continuation::ContParam;

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

/// What new parameters do to a job of the policy named in the table, by
/// the one rule of [`super::depends`].
macro_rules! on_params {
    (rerun, $d:expr, $s:expr, $p:expr, $n:expr) => {
        if $s.changed_by($d, &$p, $n) {
            OnParams::Rerun(Box::new($s.with($p, $n).into()))
        } else {
            OnParams::Keep
        }
    };
    (cancel, $d:expr, $s:expr, $p:expr, $n:expr) => {
        if $s.changed_by($d, &$p, $n) {
            OnParams::Cancel
        } else {
            OnParams::Keep
        }
    };
    (keep, $d:expr, $s:expr, $p:expr, $n:expr) => {{
        let _ = ($d, $s, $p, $n);
        OnParams::Keep
    }};
}

/// The accuracy a table entry names (`none`: the kind has no solver of
/// the window's).
macro_rules! accuracy {
    (none) => {
        None
    };
    ($a:ident) => {
        Some(Accuracy::$a)
    };
}

/// The [`Depends`] a table entry names.
macro_rules! depends {
    (all) => {
        Depends::All
    };
    (but_varied) => {
        Depends::ButVaried
    };
    (but_axes) => {
        Depends::ButAxes
    };
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
                depends: $depends:ident,
                accuracy: $accuracy:ident,
                debounce: $debounce:literal,
                marker: $marker:ident,
                hover: $hover:literal,
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

            /// Which parameters its result depends on (the one rule for
            /// stale results, [`super::depends`]).
            pub fn depends(self) -> Depends {
                match self { $( Kind::$kind => depends!($depends), )* }
            }

            /// The accuracy its view can show (its solver under the
            /// window's Auto); `None` for a kind with a solver of its own.
            pub fn accuracy(self) -> Option<Accuracy> {
                match self { $( Kind::$kind => accuracy!($accuracy), )* }
            }

            /// The quiet time (seconds) after the last change of what it
            /// depends on before the window starts it again; 0 for a kind
            /// started by hand or at once.
            pub fn debounce(self) -> f64 {
                match self { $( Kind::$kind => $debounce, )* }
            }

            /// Its marker on the Numerics view's chart.
            pub fn marker(self) -> Marker {
                match self { $( Kind::$kind => Marker::$marker, )* }
            }

            /// What it feeds and why it needs its accuracy (the side
            /// panel's hover).
            pub fn hover(self) -> &'static str {
                match self { $( Kind::$kind => $hover, )* }
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
                    $( Spec::$kind(s) => on_params!(
                        $policy, depends!($depends), s, params, settings
                    ), )*
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
            depends: all, accuracy: TrajectoryView, debounce: 0.04, marker: Square,
            hover: "The trajectory feeds the plane, the block and the event catalogue: \
                    a map error of 1e-4 is about a pixel of the (x, y) view.",
            start: |s, _| Ok(Box::new(TrajectoryJob::new(s)?)),
        }
        /// The bifurcation diagram over one parameter.
        Sweep(SweepSpec) {
            lane: Sweep, label: "diagram", short: "diagram", new_params: rerun,
            depends: but_varied, accuracy: BifurcationDiagram, debounce: 0.25,
            marker: Diamond,
            hover: "The bifurcation sweep: 1e-3 of its θ range is about a pixel. \
                    tests/work_precision.rs checks that this setting keeps every preset's \
                    period and Lyapunov sign as at tol 1e-12.",
            start: |s, shape| Ok(Box::new(SweepJob::new(s, shape)?)),
        }
        /// Map iterates, their period and Lyapunov exponent, the map's
        /// graph: the return map.
        Iterate(IterateSpec) {
            lane: Orbit, label: "map iterates", short: "map", new_params: rerun,
            depends: all, accuracy: ReturnMap, debounce: 0.04, marker: Circle,
            hover: "The map iterates feed the return map, the period and the Lyapunov \
                    exponent: 1e-10, as the command line.",
            start: |s, _| Ok(Box::new(IterateJob::new(s)?)),
        }
        /// A phase diagram over (θν, κ): run again only if γ, ν, Ω or the
        /// solver changed (κ and θν are its axes).
        Phase(PhaseSpec) {
            lane: Phase, label: "phase diagram", short: "phase", new_params: rerun,
            depends: but_axes, accuracy: PhaseDiagram, debounce: 0.25, marker: Up,
            hover: "The phase diagram's cells: a class rests on the period test at \
                    1e4·tol and on the Lyapunov sign, so the map error must stay well \
                    below the period tolerance: 1e-8.",
            start: |s, _| Ok(Box::new(PhaseJob::new(s)?)),
        }
        /// A work-precision measurement (it runs every method, so it has
        /// no solver setting of its own; new parameters leave it be, and
        /// the window marks it as of other parameters).
        Numerics(WorkPrecisionSpec) {
            lane: Numerics, label: "work-precision", short: "numerics", new_params: keep,
            depends: all, accuracy: none, debounce: 0.0, marker: Cross,
            hover: "The Numerics view's measurement runs every method against a \
                    reference at tol 1e-14.",
            start: |s, _| Ok(Box::new(WorkPrecisionJob::new(s)?)),
        }
        /// Find bifurcations: a branch and its cascade.
        Branches(ContinuationSpec) {
            lane: Continuation, label: "bifurcations", short: "branches", new_params: cancel,
            depends: but_varied, accuracy: CommandLine, debounce: 0.0, marker: Down,
            hover: "Continuation locates doublings and folds to 1e-10 in the \
                    parameter: the command line's accuracy, 1e-10.",
            start: |s, _| Ok(Box::new(find_job(s))),
        }
        /// Boundaries: doubling curves in (θν, κ).
        Curves(BoundarySpec) {
            lane: Curves, label: "boundaries", short: "curves", new_params: cancel,
            depends: but_axes, accuracy: CommandLine, debounce: 0.0, marker: Left,
            hover: "Continuation locates doublings and folds to 1e-10 in the \
                    parameter: the command line's accuracy, 1e-10.",
            start: |s, _| Ok(Box::new(boundaries_job(s))),
        }
        /// The Events view's creep channel passage.
        Passage(PassageSpec) {
            lane: Passage, label: "channel passage", short: "passage", new_params: cancel,
            depends: all, accuracy: none, debounce: 0.0, marker: Right,
            hover: "The Events view's channel passage and tangency scan evaluate \
                    the map at dop853, tol 1e-8: slip onsets to about 1e-8.",
            start: |s, _| passage_job(s),
        }
        /// The Events view's tangency scan.
        Scan(ScanSpec) {
            lane: Scan, label: "tangency scan", short: "scan", new_params: cancel,
            depends: all, accuracy: none, debounce: 0.0, marker: Asterisk,
            hover: "The Events view's channel passage and tangency scan evaluate \
                    the map at dop853, tol 1e-8: slip onsets to about 1e-8.",
            start: |s, _| scan_job(s),
        }
        /// Attractors and basins over θν (the Basins view).
        Basins(BasinsSpec) {
            lane: Basins, label: "basins", short: "basins", new_params: rerun,
            depends: but_varied, accuracy: ReturnMap, debounce: 0.25, marker: Asterisk,
            hover: "Attractors and basins from f's verified interpolant over the exit \
                    arc (a cell graph): the map at 1e-10, as `oneblock attractors`.",
            start: |s, _| Ok(Box::new(BasinsJob::new(s)?)),
        }
        /// Attractors and basins at the current parameters (the return
        /// map's band).
        MapBasins(MapBasinsSpec) {
            lane: MapBasins, label: "map basins", short: "map basins", new_params: cancel,
            depends: all, accuracy: ReturnMap, debounce: 0.25, marker: Asterisk,
            hover: "Attractors and basins from f's verified interpolant over the exit \
                    arc (a cell graph): the map at 1e-10, as `oneblock attractors`.",
            start: |s, _| Ok(Box::new(BasinsJob::new(s.0)?)),
        }
    }
}

/// A kind's marker on the Numerics view's chart (drawn there as egui's
/// marker of the same name).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Marker {
    Square,
    Diamond,
    Circle,
    Up,
    Cross,
    Down,
    Left,
    Right,
    Asterisk,
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

/// [`Bound`] for specs with `params` and `settings` fields (and the
/// parameter they vary, where they vary one).
macro_rules! bound {
    ($($spec:ty $(, varies $field:ident)?;)*) => {
        $(
            impl Bound for $spec {
                fn params_mut(&mut self) -> (&mut Params, &mut SolverSettings) {
                    (&mut self.params, &mut self.settings)
                }
                $(
                    fn varied(&self) -> ContParam {
                        self.$field
                    }
                )?
            }
        )*
    };
}

bound! {
    TrajectorySpec;
    SweepSpec, varies param;
    IterateSpec;
    PhaseSpec;
    ContinuationSpec, varies param;
    BoundarySpec;
    PassageSpec;
    ScanSpec;
    BasinsSpec, varies param;
}

impl Bound for MapBasinsSpec {
    fn params_mut(&mut self) -> (&mut Params, &mut SolverSettings) {
        self.0.params_mut()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every kind of the table has a dependence rule, a debounce, and an
    /// accuracy exactly when the window runs it with a solver of its own
    /// choosing: the rule reads what the spec names (a varied parameter
    /// for the kinds that vary one).
    #[test]
    fn every_kind_has_its_rule_accuracy_and_debounce() {
        for kind in Kind::ALL {
            let d = kind.debounce();
            assert!((0.0..=1.0).contains(&d), "{kind:?}: debounce {d}");
            // What the window restarts on new parameters waits for the
            // sliders to rest.
            if kind.new_params() == NewParams::Rerun {
                assert!(d > 0.0, "{kind:?}");
            }
            let own_solver = matches!(kind, Kind::Numerics | Kind::Passage | Kind::Scan);
            assert_eq!(kind.accuracy().is_none(), own_solver, "{kind:?}");
            assert!(!kind.hover().is_empty() && !kind.label().is_empty());
        }
        let varies = |k: Kind| k.depends() == Depends::ButVaried;
        let varying: Vec<Kind> = Kind::ALL.into_iter().filter(|&k| varies(k)).collect();
        assert_eq!(varying, [Kind::Sweep, Kind::Branches, Kind::Basins]);
        let axes: Vec<Kind> = Kind::ALL
            .into_iter()
            .filter(|k| k.depends() == Depends::ButAxes)
            .collect();
        assert_eq!(axes, [Kind::Phase, Kind::Curves]);
    }
}
