//! The work-precision job on the worker, headless: one row per setting equal
//! to the core's, cancelled by a stop or a newer job, a bad parameter named.

use crate::common;
use common::jobs::*;
use common::{recv, until_finished};
use std::time::Duration;

use oneblock::integrate::{Method, SolverSettings};
use oneblock::model::Params;
use oneblock::numerics::quick::{current_attractor, quick_subjects};
use oneblock::numerics::{Row, Subject, build_sample, measure};
use oneblock::worker::{
    Command, Generation, Lane, Outcome, Timing, Update, WorkPrecisionSpec, Worker,
};

fn work_precision(generation: Generation, params: Params, subjects: Vec<Subject>) -> Command {
    Command::run(
        generation,
        WorkPrecisionSpec {
            attractors: vec![current_attractor(params, None, 100)],
            points: 4,
            timing: Timing::PerSetting(Duration::ZERO),
            subjects,
        },
    )
}

fn dop853(tol: f64) -> Subject {
    Subject::Own(SolverSettings::adaptive(Method::Dop853, tol))
}

/// The rows of a work-precision job's updates, checking they come in order.
fn rows_of(ups: &[Update]) -> Vec<Row> {
    let mut rows = Vec::new();
    for u in ups {
        if let Update::WorkPrecisionRow { index, row, .. } = u {
            assert_eq!(*index, rows.len(), "rows arrive in the subjects' order");
            rows.push(row.clone());
        }
    }
    rows
}

#[test]
fn work_precision_streams_a_row_per_setting_equal_to_the_core() {
    let (w, _) = spawn(256, 2, 64);
    let params = fig3b(1.25);
    let subjects = vec![
        dop853(1e-4),
        dop853(1e-7),
        dop853(1e-10),
        Subject::Own(SolverSettings::fixed(Method::Rk4, 0.02)),
        Subject::Peer(oneblock::numerics::peer::PeerMethod::Dop853, 1e-8),
    ];
    assert!(w.send(work_precision(1, params, subjects.clone())));
    let (ups, outcome) = until_finished(&w, 1, Lane::Numerics);
    assert_eq!(outcome, Outcome::Completed);
    let first_row = ups
        .iter()
        .position(|u| matches!(u, Update::WorkPrecisionRow { .. }));
    let sample_at = ups
        .iter()
        .position(|u| matches!(u, Update::WorkPrecisionSample { points: 4, .. }));
    assert!(
        sample_at < first_row,
        "the sample is announced first: {ups:?}"
    );
    let rows = rows_of(&ups);
    assert_eq!(rows.len(), subjects.len(), "one row per setting");
    for u in &ups {
        assert_eq!(u.generation(), 1);
        if let Update::WorkPrecisionRow { total, .. } = u {
            assert_eq!(*total, subjects.len());
        }
    }
    // DOP853: the error falls and the cost rises with the tolerance.
    assert!(rows[2].max_error < rows[1].max_error && rows[1].max_error < rows[0].max_error);
    assert!(rows[2].max_error < 1e-8, "{:?}", rows[2]);
    assert!(rows[0].evals_per_iterate < rows[1].evals_per_iterate);
    assert!(rows[1].evals_per_iterate < rows[2].evals_per_iterate);
    // The same numbers as measuring the same sample in the core.
    let sample = build_sample(&[current_attractor(params, None, 100)], 4).expect("sample");
    for (row, subject) in rows.iter().zip(&subjects) {
        let core = measure(&sample, subject, Duration::ZERO);
        assert_eq!(
            (row.method, row.points, row.failed),
            (core.method, 4, core.failed)
        );
        assert_eq!(row.max_error.to_bits(), core.max_error.to_bits(), "{row:?}");
        assert_eq!(row.median_error.to_bits(), core.median_error.to_bits());
        assert_eq!(row.evals_per_iterate, core.evals_per_iterate);
    }
    w.shutdown();
}

#[test]
fn work_precision_is_cancelled_by_a_stop_and_by_a_newer_job() {
    let (w, _) = spawn(256, 2, 64);
    let mut all = Vec::new();
    // The whole panel's list, timed: seconds of work, stopped after a row.
    let long = |g| {
        Command::run(
            g,
            WorkPrecisionSpec {
                attractors: vec![current_attractor(fig3b(1.25), None, 100)],
                points: 8,
                timing: Timing::PerSetting(Duration::from_millis(40)),
                subjects: quick_subjects(),
            },
        )
    };
    let first_row_of = |w: &Worker, g: Generation, all: &mut Vec<Update>| loop {
        let u = recv(w);
        let row = matches!(u, Update::WorkPrecisionRow { generation, .. } if generation == g);
        all.push(u);
        if row {
            break;
        }
    };
    assert!(w.send(long(1)));
    first_row_of(&w, 1, &mut all);
    assert!(w.send(Command::Cancel {
        generation: 2,
        lane: Some(Lane::Numerics),
    }));
    let mut finished = false;
    loop {
        let u = recv(&w);
        if let Update::Finished {
            generation: 1,
            outcome,
            ..
        } = &u
        {
            assert_eq!(*outcome, Outcome::Cancelled);
            finished = true;
        }
        let ack = matches!(u, Update::Cancelled { generation: 2, .. });
        all.push(u);
        if ack {
            break;
        }
    }
    assert!(finished, "the stopped job got its Finished before the ack");
    // A newer job supersedes a running one.
    assert!(w.send(long(3)));
    first_row_of(&w, 3, &mut all);
    assert!(w.send(work_precision(4, fig3b(1.0), vec![dop853(1e-6)])));
    let (rest, outcome) = until_finished(&w, 4, Lane::Numerics);
    assert_eq!(outcome, Outcome::Completed);
    assert!(rest.iter().any(|u| matches!(
        u,
        Update::Finished {
            generation: 3,
            outcome: Outcome::Cancelled,
            ..
        }
    )));
    let rows_of_4 = rest
        .iter()
        .filter(|u| matches!(u, Update::WorkPrecisionRow { generation: 4, .. }))
        .count();
    assert_eq!(rows_of_4, 1);
    all.extend(rest);
    let rows_of_1 = all
        .iter()
        .filter(|u| matches!(u, Update::WorkPrecisionRow { generation: 1, .. }))
        .count();
    assert!(
        rows_of_1 < quick_subjects().len(),
        "the stopped job did not run to the end"
    );
    assert_nothing_older_after_acks(&all);
    w.shutdown();
}

#[test]
fn work_precision_names_a_bad_parameter_and_the_next_job_runs() {
    let (w, _) = spawn(256, 2, 64);
    let bad_kappa = Params {
        kappa: -1.0,
        ..fig3b(1.0)
    };
    let cases = [
        (work_precision(1, bad_kappa, vec![dop853(1e-6)]), "kappa"),
        (
            Command::run(
                2,
                WorkPrecisionSpec {
                    attractors: vec![current_attractor(fig3b(1.0), None, 100)],
                    points: 0,
                    timing: Timing::PerSetting(Duration::ZERO),
                    subjects: vec![dop853(1e-6)],
                },
            ),
            "points",
        ),
        (
            Command::run(
                3,
                WorkPrecisionSpec {
                    attractors: vec![current_attractor(fig3b(1.0), None, 100)],
                    points: 4,
                    timing: Timing::PerSetting(Duration::from_secs(60)),
                    subjects: vec![dop853(1e-6)],
                },
            ),
            "time_per_setting",
        ),
    ];
    for (g, (cmd, name)) in cases.into_iter().enumerate() {
        let g = g as Generation + 1;
        assert!(w.send(cmd));
        let (ups, outcome) = until_finished(&w, g, Lane::Numerics);
        assert!(matches!(outcome, Outcome::Failed(_)), "{ups:?}");
        let err = ups.iter().find_map(|u| match u {
            Update::Error {
                parameter, message, ..
            } => Some((*parameter, message.clone())),
            _ => None,
        });
        let (parameter, message) = err.expect("an Error update");
        assert_eq!(parameter, Some(name), "{message}");
        assert!(
            message.contains(name) && !message.contains('\n'),
            "{message}"
        );
    }
    // A setting that fails on every point is a row with its failures, not an error.
    let too_coarse = Subject::Own(SolverSettings::fixed(Method::Rk4, 0.9));
    assert!(w.send(work_precision(
        9,
        fig3b(1.0),
        vec![too_coarse, dop853(1e-6)]
    )));
    let (ups, outcome) = until_finished(&w, 9, Lane::Numerics);
    assert_eq!(outcome, Outcome::Completed);
    let rows = rows_of(&ups);
    assert_eq!((rows[0].failed, rows[1].failed), (4, 0));
    assert!(rows[0].failure.is_some());
    w.shutdown();
}
