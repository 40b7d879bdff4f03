//! The window's slots, one per kind of job, from one table: what every job
//! has (its [`SlotHead`]: generation, state, progress, status line and the
//! parameters it was computed for) and the data its updates build.

use super::basins::{BasinsData, MapBasinsData};
use super::{Answer, JobKind, NO_GENERATION, stale};
use crate::app::branches::{BranchData, CurveData};
use crate::app::data::{IterateData, SweepData, TrajectoryData, WorkPrecisionData};
use crate::app::phase_data::PhaseData;
use crate::sim::intermittency::{Passage, Scaling};
use crate::worker::Generation;

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

/// The window's slots, one per kind of job: its field, and the data its
/// updates build. `head(kind)` is the slot of a kind, whatever its data.
macro_rules! slots {
    ($( $(#[$doc:meta])* $kind:ident => $field:ident: $data:ty, )*) => {
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
        }
    };
}

slots! {
    Trajectory => trajectory: TrajectoryData,
    Sweep => sweep: SweepData,
    Iterate => iterate: IterateData,
    Phase => phase: PhaseData,
    Numerics => numerics: WorkPrecisionData,
    /// "Find bifurcations": the bifurcation view's overlay.
    Branches => branches: BranchData,
    /// "Boundaries": the phase view's overlay.
    Curves => curves: CurveData,
    /// The Events view's channel passage and tangency scan.
    Passage => passage: Answer<Passage>,
    Scan => scan: Answer<Scaling>,
    /// The Basins view's diagram and the return map's basins.
    Basins => basins: BasinsData,
    MapBasins => map_basins: MapBasinsData,
}
