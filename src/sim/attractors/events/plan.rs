//! What to locate over a range's columns (each track's ends inside it,
//! each change of its period), and the located events put together: one
//! per place, in increasing parameter, with each track's start and end.

use super::super::Found;
use super::super::tracks::Identities;
use super::{Bound, Cause, Event, Events, FOLD_NEAR, Span, Task};

/// Each track's first and last column and the computed columns beside
/// them.
pub(super) fn spans(
    found: &[Option<&Found>],
    ids: &Identities,
) -> Vec<(usize, usize, Option<usize>, Option<usize>)> {
    let n = found.len();
    let mut reach: Vec<Option<(usize, usize)>> = vec![None; ids.tracks.len()];
    for (c, of) in ids.of.iter().enumerate() {
        for &t in of.iter().flatten() {
            let r = reach[t].get_or_insert((c, c));
            r.1 = c;
        }
    }
    reach
        .into_iter()
        .map(|r| {
            let (first, last) = r.unwrap_or((0, 0));
            let before = (0..first).rev().find(|&i| found[i].is_some());
            let after = (last + 1..n).find(|&i| found[i].is_some());
            (first, last, before, after)
        })
        .collect()
}

/// The things to locate: each track's start and end inside the range,
/// and each change of its period between neighbouring computed columns.
pub(super) fn tasks(
    found: &[Option<&Found>],
    ids: &Identities,
    spans: &[(usize, usize, Option<usize>, Option<usize>)],
) -> Vec<Task> {
    let index = |c: usize, t: usize| {
        ids.of[c]
            .as_ref()
            .and_then(|v| v.iter().position(|&x| x == t))
    };
    let mut out = Vec::new();
    for (t, &(first, last, before, after)) in spans.iter().enumerate() {
        if let (Some(b), Some(a)) = (before, index(first, t)) {
            out.push(Task::End {
                track: t,
                inside: first,
                a,
                beyond: b,
            });
        }
        if let (Some(b), Some(a)) = (after, index(last, t)) {
            out.push(Task::End {
                track: t,
                inside: last,
                a,
                beyond: b,
            });
        }
        let mut prev: Option<(usize, usize)> = None;
        for c in first..=last {
            let Some(a) = index(c, t) else { continue };
            if let Some((pc, pa)) = prev {
                let (x, y) = (
                    found[pc].expect("computed").attractors[pa].period,
                    found[c].expect("computed").attractors[a].period,
                );
                if let (Some(p), Some(q)) = (x, y)
                    && (q == 2 * p || p == 2 * q)
                {
                    out.push(Task::Change {
                        track: t,
                        c: pc,
                        a: pa,
                        d: c,
                        b: a,
                    });
                }
            }
            prev = Some((c, a));
        }
    }
    out
}

/// Whether `e` is the event `x` already found: the same cause and period
/// within their errors, or a crisis at a fold.
fn same_place(x: &Event, e: &Event) -> bool {
    let close =
        (x.value - e.value).abs() <= 2.0 * (x.error + e.error) + 1e-12 * e.value.abs().max(1.0);
    // A chaotic set that ends where a cycle is born or dies in a fold (a
    // window's edge: the set gives way to the cycle) ends in that fold:
    // the bisection on the cells sees the new pair apart only a little
    // past it.
    let window = e.cause == Cause::Crisis
        && x.cause == Cause::Fold
        && (x.value - e.value).abs() <= FOLD_NEAR * e.value.abs().max(1.0);
    close && x.cause == e.cause && x.period == e.period || window
}

/// `e`, found again at `x`'s place: its tracks join `x`'s, and a crisis
/// says so in `x`'s detail.
fn merge(x: &mut Event, e: Event) {
    if e.cause == Cause::Crisis {
        let what = if e.detail.contains("appears") {
            "begins"
        } else {
            "ends"
        };
        let tracks: Vec<String> = e.tracks.iter().map(|t| format!("#{t}")).collect();
        let d = format!(
            "; the chaotic set of track {} {what} here (the cell graph's bisection puts it {:.1e} away)",
            tracks.join(", "),
            (e.value - x.value).abs()
        );
        x.detail.push_str(&d);
    }
    for t in e.tracks {
        if !x.tracks.contains(&t) {
            x.tracks.push(t);
        }
    }
}

/// The located events, one per place (a crisis at a fold is the fold's),
/// in increasing parameter, and each track's start and end.
pub(super) fn assemble(
    tasks: &[Task],
    done: Vec<Option<Event>>,
    spans: Vec<(usize, usize, Option<usize>, Option<usize>)>,
    ids: Identities,
) -> Events {
    // Task i's event, and which task each merged into.
    let mut events: Vec<Event> = Vec::new();
    let mut of_task: Vec<Option<usize>> = vec![None; tasks.len()];
    let mut order: Vec<usize> = (0..tasks.len()).filter(|&i| done[i].is_some()).collect();
    // Located causes first, so that a crisis joins the fold it is.
    order.sort_by_key(|&i| done[i].as_ref().map(|e| e.cause == Cause::Crisis));
    for i in order {
        let e = done[i].clone().expect("filtered");
        let same = events.iter().position(|x| same_place(x, &e));
        match same {
            Some(k) => {
                merge(&mut events[k], e);
                of_task[i] = Some(k);
            }
            None => {
                events.push(e);
                of_task[i] = Some(events.len() - 1);
            }
        }
    }
    let mut idx: Vec<usize> = (0..events.len()).collect();
    idx.sort_by(|&a, &b| events[a].value.total_cmp(&events[b].value));
    let mut rank = vec![0; events.len()];
    for (r, &k) in idx.iter().enumerate() {
        rank[k] = r;
    }
    let sorted: Vec<Event> = idx.iter().map(|&k| events[k].clone()).collect();
    let mut out: Vec<Span> = spans
        .iter()
        .map(|&(first, last, ..)| Span {
            first,
            last,
            start: Bound::Edge,
            end: Bound::Edge,
        })
        .collect();
    for (i, t) in tasks.iter().enumerate() {
        let Some(k) = of_task[i] else { continue };
        if let Task::End {
            track,
            inside,
            beyond,
            ..
        } = *t
        {
            let b = Bound::Event(rank[k]);
            if beyond < inside {
                out[track].start = b;
            } else {
                out[track].end = b;
            }
        }
    }
    Events {
        ids,
        events: sorted,
        spans: out,
    }
}
