//! The window's slots, one per kind of job, from one table: what every job
//! has (its [`SlotHead`]: generation, state, progress, status line and the
//! parameters it was computed for) and the data its updates build.

use super::basins::{BasinsData, BasinsKey, MapBasinsData};
use super::{Answer, JobKind, Jobs, NO_GENERATION, Shown, stale};
use crate::app::branches::{BranchData, CurveData};
use crate::app::data::{IterateData, SweepData, TrajectoryData, WorkPrecisionData};
use crate::app::phase_data::PhaseData;
use crate::app::settings::{Settings, ViewKind};
use crate::sim::intermittency::{Passage, Scaling};
use crate::worker::Generation;
use crate::worker::Update;

/// Where a job stands.
#[derive(Clone, Debug, PartialEq, Default)]
pub enum JobState {
    #[default]
    Idle,
    Running,
    Done,
    Cancelled,
    Failed(String),
}

/// Progress of a job, as the worker last reported it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LaneProgress {
    pub fraction: f64,
    pub iterates_per_second: f64,
}

/// What every job has, whatever its data: the generation it runs under,
/// where it stands, and its progress.
#[derive(Clone, Debug, PartialEq)]
pub struct SlotHead {
    pub generation: Generation,
    pub state: JobState,
    pub progress: LaneProgress,
    /// What it found and why it stopped, as it (or the window) last said:
    /// its status line.
    pub summary: Option<String>,
    /// What its result was computed for ([`stale`]).
    pub bound: Option<stale::Bound>,
    /// Its result is of other parameters; a new run is on its way.
    pub stale: bool,
}

impl Default for SlotHead {
    fn default() -> Self {
        SlotHead {
            generation: NO_GENERATION,
            state: JobState::Idle,
            progress: LaneProgress::default(),
            summary: None,
            bound: None,
            stale: false,
        }
    }
}

/// One job: its [`SlotHead`] (reached through the slot, as `slot.state`)
/// and what it has sent.
#[derive(Clone, Debug, Default)]
pub struct Slot<T> {
    pub head: SlotHead,
    pub data: T,
}

impl<T> std::ops::Deref for Slot<T> {
    type Target = SlotHead;
    fn deref(&self) -> &SlotHead {
        &self.head
    }
}

impl<T> std::ops::DerefMut for Slot<T> {
    fn deref_mut(&mut self) -> &mut SlotHead {
        &mut self.head
    }
}

impl<T> Slot<T> {
    /// A new job under `generation`, starting from `data`.
    pub(super) fn start(&mut self, generation: Generation, data: T) {
        self.head = SlotHead {
            generation,
            state: JobState::Running,
            ..SlotHead::default()
        };
        self.data = data;
    }

    /// Whether it has run or runs (a generation was issued for it).
    pub fn issued(&self) -> bool {
        self.generation != NO_GENERATION
    }
}

/// What a kind's data take of the worker's updates: its job module's own
/// variants (the status updates, and the orbit lane's, which the window
/// holds while θν plays, are applied by [`super::Jobs::apply`]).
pub trait Receive {
    /// Takes `u` if it is of this data's kind; gives it back if not.
    fn receive(&mut self, u: Update) -> Option<Update> {
        Some(u)
    }
}

/// The window's slots, one per kind of job: its field, the data its
/// updates build, the views it feeds (a figure waits for their lanes), and
/// how the window starts it (`j` the jobs, `s` the settings, `v` what is
/// shown). `head(kind)` is the slot of a kind, whatever its data.
macro_rules! slots {
    ($(
        $(#[$doc:meta])*
        $kind:ident => $field:ident: $data:ty, feeds [$($view:ident),*],
            start |$j:ident, $s:ident, $v:ident| $start:expr,
    )*) => {
        /// One slot per kind of job.
        #[derive(Default)]
        pub struct Slots {
            $( $(#[$doc])* pub $field: Slot<$data>, )*
        }

        impl Slots {
            /// The bookkeeping of the job of `kind`, whatever its data.
            pub fn head(&self, kind: JobKind) -> &SlotHead {
                match kind { $( JobKind::$kind => &self.$field.head, )* }
            }

            /// [`Slots::head`], to change.
            pub fn head_mut(&mut self, kind: JobKind) -> &mut SlotHead {
                match kind { $( JobKind::$kind => &mut self.$field.head, )* }
            }

            /// Clears the result of the job of `kind`.
            pub fn clear(&mut self, kind: JobKind) {
                match kind { $( JobKind::$kind => self.$field.data = Default::default(), )* }
            }

            /// Gives `u`, an update of the job of `kind`, to its data; gives
            /// it back if they do not take it.
            pub fn receive(&mut self, kind: JobKind, u: Update) -> Option<Update> {
                match kind { $( JobKind::$kind => self.$field.data.receive(u), )* }
            }
        }

        impl JobKind {
            /// The views its results feed.
            pub fn feeds(self) -> &'static [ViewKind] {
                match self { $( JobKind::$kind => &[$(ViewKind::$view),*], )* }
            }
        }

        impl Jobs {
            /// Starts the job of `kind` for the settings `s`, with what is
            /// `shown` (the diagram's zoom, the time).
            pub fn start(&mut self, kind: JobKind, s: &Settings, shown: &Shown) {
                match kind { $( JobKind::$kind => {
                    let ($j, $s, $v) = (self, s, shown);
                    $start
                } )* }
            }
        }
    };
}

slots! {
    Trajectory => trajectory: TrajectoryData,
        feeds [Plane, Block, Events, TimeSeries, Numerics],
        start |j, s, v| j.restart_orbit(s, v.now),
    Sweep => sweep: SweepData, feeds [Bifurcation],
        start |j, s, v| j.restart_sweep(s, v.sweep_zoom),
    Iterate => iterate: IterateData, feeds [ReturnMap],
        start |j, s, v| j.restart_orbit(s, v.now),
    /// Compute: a grid now, that goes on while its view is hidden.
    Phase => phase: PhaseData, feeds [Phase],
        start |j, s, _v| j.compute_phase(s),
    Numerics => numerics: WorkPrecisionData, feeds [Numerics],
        start |j, s, _v| j.start_work_precision(s),
    /// "Find bifurcations" over the diagram's range (its zoom's): the
    /// bifurcation view's overlay.
    Branches => branches: BranchData, feeds [],
        start |j, s, v| j.find_bifurcations(s, super::diagram_range(s, v.sweep_zoom)),
    /// "Boundaries": the phase view's overlay.
    Curves => curves: CurveData, feeds [],
        start |j, s, _v| j.compute_boundaries(s),
    /// The Events view's channel passage (near the trajectory's first slip
    /// onset; the view itself asks near its first creep onset) and
    /// tangency scan.
    Passage => passage: Answer<Passage>, feeds [],
        start |j, s, _v| {
            let near = j.trajectory.data.events.first().map_or(s.params.theta_nu, |e| e.theta);
            j.start_passage(s.params, near)
        },
    Scan => scan: Answer<Scaling>, feeds [],
        start |j, s, _v| j.start_scan(s.params),
    /// The Basins view's diagram and the return map's basins.
    Basins => basins: BasinsData, feeds [Basins],
        start |j, s, v| j.restart_basins(s, BasinsKey::of(s, v.sweep_zoom)),
    MapBasins => map_basins: MapBasinsData, feeds [ReturnMap],
        start |j, s, _v| j.restart_map_basins(s, super::solver(JobKind::MapBasins, s)),
}

impl Receive for TrajectoryData {}
impl Receive for IterateData {}
