//! The shared to-do list of a laned job (a bifurcation sweep, a phase
//! diagram): a fixed plan of items, each continued from one named, earlier
//! item (its parent), run by a pool of threads.
//!
//! The plan fixes the order and every item's parent in advance, so the
//! results do not depend on thread timing: an item may start only once its
//! parent is done, and it starts from what its parent left (its *seed*).
//! Items of the coarse pass all come before any refinement item may start,
//! so that a coarse picture is complete as early as it can be.

use std::sync::{Condvar, Mutex};
use std::time::Duration;

use super::JobError;
use super::lock;

/// An item of a plan, as the schedule needs to see it.
pub(crate) trait PlanItem: Copy {
    /// Its slot: a distinct index below the schedule's slot count.
    fn slot(&self) -> usize;
    /// Its parent's slot (`None`: it starts afresh).
    fn parent(&self) -> Option<usize>;
    /// Whether it belongs to the coarse pass.
    fn coarse(&self) -> bool;
}

/// Where an item stands.
#[derive(Clone, Copy, Debug)]
enum Slot<S> {
    Waiting,
    Running,
    /// Done, with what its children start from.
    Done(S),
}

/// The to-do list of one job: items of type `P`, each leaving a seed `S`.
pub(crate) struct Schedule<P, S> {
    plan: Vec<P>,
    slots: Vec<Slot<S>>,
    coarse_left: usize,
    done: usize,
    /// First plan position that may still be waiting.
    scan_from: usize,
}

impl<P: PlanItem, S: Copy> Schedule<P, S> {
    /// A schedule of `plan`, whose items' slots lie below `slots`.
    pub fn new(plan: Vec<P>, slots: usize) -> Self {
        let coarse_left = plan.iter().filter(|p| p.coarse()).count();
        Schedule {
            plan,
            slots: vec![Slot::Waiting; slots],
            coarse_left,
            done: 0,
            scan_from: 0,
        }
    }

    /// Items done so far.
    pub fn done(&self) -> usize {
        self.done
    }

    fn waiting(&self, slot: usize) -> bool {
        matches!(self.slots[slot], Slot::Waiting)
    }

    /// The next item that may start, with its parent's seed (`None` for an
    /// item without a parent), marked running. `Err(true)`: none is ready
    /// yet; `Err(false)`: none is left.
    pub fn next(&mut self) -> Result<(P, Option<S>), bool> {
        while self.scan_from < self.plan.len() && !self.waiting(self.plan[self.scan_from].slot()) {
            self.scan_from += 1;
        }
        if self.scan_from == self.plan.len() {
            return Err(false);
        }
        for k in self.scan_from..self.plan.len() {
            let p = self.plan[k];
            // Refinement waits for the whole coarse pass.
            if !p.coarse() && self.coarse_left > 0 {
                break;
            }
            if !self.waiting(p.slot()) {
                continue;
            }
            let start = match p.parent() {
                None => Some(None),
                Some(q) => match self.slots[q] {
                    Slot::Done(seed) => Some(Some(seed)),
                    _ => None,
                },
            };
            if let Some(seed) = start {
                self.slots[p.slot()] = Slot::Running;
                return Ok((p, seed));
            }
        }
        Err(true)
    }

    /// Marks `p` done, leaving `seed` for its children; true if it was the
    /// last item of the coarse pass.
    pub fn complete(&mut self, p: P, seed: S) -> bool {
        self.slots[p.slot()] = Slot::Done(seed);
        self.done += 1;
        if p.coarse() {
            self.coarse_left -= 1;
            return self.coarse_left == 0;
        }
        false
    }
}

/// Waits for the next item of `schedule` that may start: `Ok(None)` once
/// none is left, `Err(Stop)` as soon as `stale()` says the job must stop.
/// `ready` is notified whenever an item completes; the wait also times out
/// now and then, so that a cancellation is seen even if none does.
pub(crate) fn wait_next<P: PlanItem, S: Copy>(
    schedule: &Mutex<Schedule<P, S>>,
    ready: &Condvar,
    stale: impl Fn() -> bool,
) -> Result<Option<(P, Option<S>)>, JobError> {
    let mut sch = lock(schedule);
    loop {
        if stale() {
            return Err(JobError::Stop);
        }
        match sch.next() {
            Ok(next) => return Ok(Some(next)),
            Err(false) => return Ok(None),
            Err(true) => {
                sch = ready
                    .wait_timeout(sch, Duration::from_millis(20))
                    .map(|(g, _)| g)
                    .unwrap_or_else(|e| e.into_inner().0);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Clone, Copy, Debug, PartialEq)]
    struct Item {
        slot: usize,
        parent: Option<usize>,
        coarse: bool,
    }

    impl PlanItem for Item {
        fn slot(&self) -> usize {
            self.slot
        }
        fn parent(&self) -> Option<usize> {
            self.parent
        }
        fn coarse(&self) -> bool {
            self.coarse
        }
    }

    fn item(slot: usize, parent: Option<usize>, coarse: bool) -> Item {
        Item {
            slot,
            parent,
            coarse,
        }
    }

    #[test]
    fn items_wait_for_their_parent_and_refinement_for_the_coarse_pass() {
        // Coarse 0 → 2, and 1 continued from 0 but not coarse.
        let plan = vec![
            item(0, None, true),
            item(2, Some(0), true),
            item(1, Some(0), false),
        ];
        let mut s: Schedule<Item, f64> = Schedule::new(plan.clone(), 3);
        assert_eq!(s.next(), Ok((plan[0], None)));
        // Item 2 waits for 0; item 1 for the coarse pass.
        assert_eq!(s.next(), Err(true));
        assert!(!s.complete(plan[0], 0.5));
        assert_eq!(s.next(), Ok((plan[1], Some(0.5))));
        assert_eq!(s.next(), Err(true));
        assert!(s.complete(plan[1], 0.7), "the last coarse item");
        assert_eq!(s.next(), Ok((plan[2], Some(0.5))));
        assert_eq!(s.next(), Err(false));
        s.complete(plan[2], 0.6);
        assert_eq!(s.done(), 3);
    }

    #[test]
    fn waiting_stops_when_the_job_is_stale_and_ends_when_nothing_is_left() {
        let plan = vec![item(0, None, true), item(1, Some(0), true)];
        let sch: Mutex<Schedule<Item, ()>> = Mutex::new(Schedule::new(plan, 2));
        let ready = Condvar::new();
        let first = wait_next(&sch, &ready, || false);
        assert!(matches!(first, Ok(Some((Item { slot: 0, .. }, None)))));
        // Item 1 waits for item 0, which never completes: only the stop ends
        // the wait.
        let calls = std::cell::Cell::new(0);
        let stopped = wait_next(&sch, &ready, || {
            calls.set(calls.get() + 1);
            calls.get() > 3
        });
        assert!(matches!(stopped, Err(JobError::Stop)));
        lock(&sch).complete(item(0, None, true), ());
        assert!(matches!(
            wait_next(&sch, &ready, || false),
            Ok(Some((Item { slot: 1, .. }, Some(()))))
        ));
        lock(&sch).complete(item(1, Some(0), true), ());
        assert!(matches!(wait_next(&sch, &ready, || false), Ok(None)));
    }
}
