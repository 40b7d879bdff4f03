//! Why a track starts or ends, and where its period changes: each such
//! place between two columns located and named (docs/attractors.md,
//! "Births and deaths").
//!
//! - A **cycle** is followed from the column where it is last (first)
//!   seen towards the next column by the one-parameter continuation
//!   ([`crate::sim::continuation::continue_branch`]), whose folds and
//!   flips are located with the tighter solver to ~1e-10 in the parameter.
//!   The first special point met names the cause: a **fold** (m = +1),
//!   a **flip** (m = −1, with its criticality), a **border** where the
//!   multiplier jumps across ±1 at a kink of f (the cycle goes on, its
//!   stability changed) or where a cycle point reaches a jump of f or the
//!   arc's edge (the cycle ends there).
//! - A **chaotic** set that vanishes or appears is located by bisection
//!   on the cell graph (does the set still have a partner across the
//!   bisection point?) to 1e-8 in the parameter: a **crisis**. Where the
//!   same place is a fold of a cycle (a window opening in chaos), the two
//!   are one event, the fold's.
//! - A period change inside a track (p ↔ 2p) is the flip of the shorter
//!   cycle, located on its branch.
//!
//! Anything else is "unresolved", with the reason: never a guess.

use super::tracks::Identities;
use super::{Attractor, CellOptions, Found};
use crate::integrate::SolverSettings;
use crate::model::Params;
use crate::sim::continuation::ContParam;
use std::sync::atomic::{AtomicUsize, Ordering};

mod cycle;
mod plan;

use plan::{assemble, spans, tasks};

/// What starts, ends or changes a track.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cause {
    Fold,
    Flip,
    Border,
    Crisis,
    Unresolved,
}

impl Cause {
    /// The JSON's and the text's name.
    pub fn name(self) -> &'static str {
        match self {
            Cause::Fold => "fold",
            Cause::Flip => "flip",
            Cause::Border => "border",
            Cause::Crisis => "crisis",
            Cause::Unresolved => "unresolved",
        }
    }
}

/// One located event.
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    pub cause: Cause,
    /// The parameter's value.
    pub value: f64,
    /// How well `value` is known (a bound on its error, parameter units).
    pub error: f64,
    /// The two columns it lies between (increasing).
    pub between: (f64, f64),
    /// A point of the cycle there (folds, flips, borders).
    pub theta: Option<f64>,
    /// The period of the cycle it happens to.
    pub period: Option<usize>,
    /// A flip's criticality: "supercritical", "subcritical", "undecided".
    pub criticality: Option<&'static str>,
    /// A border's multipliers on the parameter's lower and upper side.
    pub multipliers: Option<[Option<f64>; 2]>,
    /// A border's type: "persists" (the cycle goes on, its stability
    /// changed across a kink of f) or "ends" (a cycle point meets a jump
    /// of f or the arc's edge).
    pub border_type: Option<&'static str>,
    /// The tracks it starts, ends or changes.
    pub tracks: Vec<usize>,
    /// One sentence on what happens.
    pub detail: String,
}

impl Event {
    /// Its value to the digits its error leaves it, as the command line,
    /// the window and the figures print it.
    pub fn value_text(&self) -> String {
        to_error(self.value, self.error)
    }
}

/// `v` to the decimals its error `err` leaves it (at most 12).
pub fn to_error(v: f64, err: f64) -> String {
    let decimals = if err > 0.0 && err.is_finite() {
        (-err.log10()).floor().clamp(0.0, 12.0) as usize
    } else {
        12
    };
    format!("{v:.decimals$}")
}

impl Events {
    /// How track `t` starts (`start`) or ends, in words: "born at θν =
    /// 1.363980195 in a fold", "from the range's start", "dies between
    /// 1.4165 and 1.41675 (unresolved)".
    pub fn bound_words(&self, t: usize, start: bool, symbol: &str) -> String {
        let Some(sp) = self.spans.get(t) else {
            return String::new();
        };
        let b = if start { sp.start } else { sp.end };
        let verb = if start { "born" } else { "dies" };
        match b {
            Bound::Edge if start => "from the range's start".into(),
            Bound::Edge => "to the range's end".into(),
            Bound::Event(k) => {
                let e = &self.events[k];
                match e.cause {
                    Cause::Unresolved => format!(
                        "{verb} between {symbol} = {} and {} (cause unresolved)",
                        e.between.0, e.between.1
                    ),
                    c => format!("{verb} at {symbol} = {} in a {}", e.value_text(), c.name()),
                }
            }
        }
    }
}

/// Where a track starts or ends: the range's edge, or an event.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bound {
    Edge,
    Event(usize),
}

/// The events of a range and each track's start and end.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Events {
    /// The tracks, as the cell graph matched them and the cycles' own
    /// continuation joined them where the graph did not.
    pub ids: Identities,
    /// In increasing parameter.
    pub events: Vec<Event>,
    /// Per track: its first and last column, and its start and end.
    pub spans: Vec<Span>,
}

/// A track's columns and its two ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    pub first: usize,
    pub last: usize,
    pub start: Bound,
    pub end: Bound,
}

/// The fixed inputs of the locating: the model at every column but for
/// the varied parameter, the solver and the cell graph's options.
#[derive(Clone, Copy, Debug)]
pub struct Locator {
    pub base: Params,
    pub settings: SolverSettings,
    pub param: ContParam,
    pub cells: CellOptions,
}

/// Something to locate between two columns.
#[derive(Clone, Copy, Debug)]
enum Task {
    /// Track `track`'s attractor `a` of column `inside` has no partner
    /// in column `beyond` (its start when `beyond` < `inside`).
    End {
        track: usize,
        inside: usize,
        a: usize,
        beyond: usize,
    },
    /// Track `track` goes from period p in column `c` (attractor `a`) to
    /// 2p or p/2 in column `d` (attractor `b`).
    Change {
        track: usize,
        c: usize,
        a: usize,
        d: usize,
        b: usize,
    },
}

/// A crisis this close to a fold (relative to max(1, |λ|)) is that fold.
const FOLD_NEAR: f64 = 1e-7;

/// A parameter value located to this, relative to max(1, |λ|).
pub const LOCATE_TOL: f64 = 1e-8;

impl Locator {
    /// The events of the columns at `values` (their cell graphs `found`,
    /// `None` where a column failed) with their tracks `ids`, located on
    /// up to `threads` threads.
    pub fn locate(
        &self,
        values: &[f64],
        found: &[Option<&Found>],
        mut ids: Identities,
        threads: usize,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Events {
        self.join_continued(values, found, &mut ids, cancel);
        let spans = spans(found, &ids);
        let tasks = tasks(found, &ids, &spans);
        let next = AtomicUsize::new(0);
        let mut done: Vec<Option<Event>> = vec![None; tasks.len()];
        let results = std::thread::scope(|s| {
            let workers: Vec<_> = (0..threads.clamp(1, tasks.len().max(1)))
                .map(|_| {
                    s.spawn(|| {
                        let mut mine = Vec::new();
                        loop {
                            let i = next.fetch_add(1, Ordering::Relaxed);
                            let Some(t) = tasks.get(i) else { break };
                            mine.push((i, self.task(*t, values, found, cancel)));
                        }
                        mine
                    })
                })
                .collect();
            workers
                .into_iter()
                .flat_map(|w| w.join().unwrap_or_default())
                .collect::<Vec<_>>()
        });
        for (i, e) in results {
            done[i] = Some(e);
        }
        assemble(&tasks, done, spans, ids)
    }

    fn task(
        &self,
        t: Task,
        values: &[f64],
        found: &[Option<&Found>],
        cancel: &dyn Fn() -> bool,
    ) -> Event {
        let between = |i: usize, j: usize| (values[i].min(values[j]), values[i].max(values[j]));
        if cancel() {
            let (i, j) = match t {
                Task::End { inside, beyond, .. } => (inside, beyond),
                Task::Change { c, d, .. } => (c, d),
            };
            let (lo, hi) = between(i, j);
            let mut e = unresolved(
                0.5 * (lo + hi),
                0.5 * (hi - lo),
                "not located: cancelled".into(),
            );
            e.between = (lo, hi);
            return e;
        }
        match t {
            Task::End {
                track,
                inside,
                a,
                beyond,
            } => {
                let f = found[inside].expect("a track's column was computed");
                let at = &f.attractors[a];
                let (l0, l1) = (values[inside], values[beyond]);
                let role = if beyond < inside {
                    Role::Start
                } else {
                    Role::End
                };
                let mut e = match at.period {
                    Some(p) => self.cycle_end(at, p, l0, l1, role, cancel),
                    None => self.set_end(f, a, l0, l1, role, cancel),
                };
                e.between = between(inside, beyond);
                e.tracks = vec![track];
                e
            }
            Task::Change { track, c, a, d, b } => {
                let (ac, ad) = (
                    &found[c].expect("computed").attractors[a],
                    &found[d].expect("computed").attractors[b],
                );
                let mut e = self.period_change(ac, ad, (values[c], values[d]), cancel);
                e.between = between(c, d);
                e.tracks = vec![track];
                e
            }
        }
    }

    /// The flip where a track's period goes from `ac`'s (at `vc`) to
    /// `ad`'s (at `vd`), located on the shorter cycle's branch.
    fn period_change(
        &self,
        ac: &Attractor,
        ad: &Attractor,
        (vc, vd): (f64, f64),
        cancel: &dyn Fn() -> bool,
    ) -> Event {
        // The shorter cycle's branch holds the flip.
        let (short, l0, l1) = if ac.period < ad.period {
            (ac, vc, vd)
        } else {
            (ad, vd, vc)
        };
        let p = short.period.unwrap_or(1);
        let mut e = self.cycle_end(short, p, l0, l1, Role::Change, cancel);
        if e.cause == Cause::Flip {
            let crit = e.criticality.unwrap_or("undecided");
            e.detail = if ac.period < ad.period {
                format!(
                    "the P{p} cycle doubles into the track's P{} (m = −1, {crit} flip)",
                    2 * p
                )
            } else {
                format!(
                    "the track's P{} shrinks onto the P{p} cycle (m = −1, {crit} flip)",
                    2 * p
                )
            };
        } else {
            e = unresolved(
                0.5 * (l0 + l1),
                (l1 - l0).abs(),
                format!(
                    "the period goes from {} to {} here, but the P{p} cycle's branch shows no flip between the columns ({})",
                    name(ac.period),
                    name(ad.period),
                    e.detail
                ),
            );
        }
        e
    }
}

/// What the event is to the track whose cycle it was located on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    /// Its first column is next (along the columns).
    Start,
    /// Its last column is next.
    End,
    /// Its period changes here.
    Change,
}
/// An unresolved event at `value` ± `error`.
fn unresolved(value: f64, error: f64, detail: String) -> Event {
    Event {
        cause: Cause::Unresolved,
        value,
        error,
        between: (0.0, 0.0),
        theta: None,
        period: None,
        criticality: None,
        multipliers: None,
        border_type: None,
        tracks: Vec::new(),
        detail,
    }
}

fn name(period: Option<usize>) -> String {
    period.map_or("aperiodic".into(), |p| format!("P{p}"))
}
