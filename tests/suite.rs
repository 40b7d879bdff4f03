//! Every integration test that can share a process, as one test binary:
//! one link instead of seventy, and its tests spread over the cores
//! together instead of one file's at a time (CI builds and runs them in a
//! fraction of the time). Each file stays as it was, a module here; the
//! files that need a process of their own are their own binaries in
//! Cargo.toml: what they measure is the process's (peak memory, the
//! largest child waited for) or they start Xvfb, whose `xvfb-run -a`
//! picks a display racily. `every_test_file_runs_once` (below) fails if a
//! file is in neither list, or in both.
//!
//! One file's tests: `cargo test --release --test suite cli_figure::`.

// The helpers the files share, loaded once for the whole suite (each
// file names them with `use crate::…`).
mod cli_support;
mod common;
#[cfg(feature = "gui")]
#[path = "common/window.rs"]
mod window;

#[path = "attractor_tracks.rs"]
mod attractor_tracks;
#[path = "attractors.rs"]
mod attractors;
#[path = "attractors_cells.rs"]
mod attractors_cells;
#[path = "attractors_proofs.rs"]
mod attractors_proofs;
#[path = "basins.rs"]
mod basins;
#[path = "branch_birth.rs"]
mod branch_birth;
#[path = "cascade_reach.rs"]
mod cascade_reach;
#[path = "cascade_switch.rs"]
mod cascade_switch;
#[path = "cli.rs"]
mod cli;
#[path = "cli_bench_pieces.rs"]
mod cli_bench_pieces;
#[path = "cli_continue.rs"]
mod cli_continue;
#[path = "cli_docs.rs"]
mod cli_docs;
#[path = "cli_docs_ranges.rs"]
mod cli_docs_ranges;
#[path = "cli_figure.rs"]
mod cli_figure;
#[path = "cli_figure_journal.rs"]
mod cli_figure_journal;
#[path = "cli_figure_play.rs"]
mod cli_figure_play;
#[path = "cli_input.rs"]
mod cli_input;
#[path = "cli_jobs.rs"]
mod cli_jobs;
#[path = "cli_props.rs"]
mod cli_props;
#[path = "cli_provenance.rs"]
mod cli_provenance;
#[path = "cli_reliability.rs"]
mod cli_reliability;
#[path = "cli_small_things.rs"]
mod cli_small_things;
#[path = "continuation.rs"]
mod continuation;
#[path = "criticality.rs"]
mod criticality;
#[path = "criticality_born.rs"]
mod criticality_born;
#[path = "cycles.rs"]
mod cycles;
#[path = "derivatives.rs"]
mod derivatives;
#[path = "docs_auto_table.rs"]
mod docs_auto_table;
#[path = "docs_counts.rs"]
mod docs_counts;
#[path = "docs_names.rs"]
mod docs_names;
#[path = "figure_csv.rs"]
mod figure_csv;
#[path = "figure_font.rs"]
mod figure_font;
#[path = "figure_legend.rs"]
mod figure_legend;
#[path = "figure_points.rs"]
mod figure_points;
#[path = "figure_referee.rs"]
mod figure_referee;
#[path = "figure_titles.rs"]
mod figure_titles;
#[path = "figure_wellformed.rs"]
mod figure_wellformed;
#[path = "flip_accuracy.rs"]
mod flip_accuracy;
#[path = "function_lengths.rs"]
mod function_lengths;
#[path = "gui_accuracy.rs"]
mod gui_accuracy;
#[path = "gui_axes.rs"]
mod gui_axes;
#[path = "gui_basin_events.rs"]
mod gui_basin_events;
#[path = "gui_bifurcation.rs"]
mod gui_bifurcation;
#[path = "gui_continuation.rs"]
mod gui_continuation;
#[path = "gui_controls.rs"]
mod gui_controls;
#[path = "gui_diagram_param.rs"]
mod gui_diagram_param;
#[path = "gui_docs.rs"]
mod gui_docs;
#[path = "gui_lambda.rs"]
mod gui_lambda;
#[path = "gui_layout_budget.rs"]
mod gui_layout_budget;
#[path = "gui_numerics.rs"]
mod gui_numerics;
#[path = "gui_overlap.rs"]
mod gui_overlap;
#[path = "gui_phase.rs"]
mod gui_phase;
#[path = "gui_play.rs"]
mod gui_play;
#[path = "gui_presentation.rs"]
mod gui_presentation;
#[path = "gui_record_play.rs"]
mod gui_record_play;
#[path = "gui_return_map.rs"]
mod gui_return_map;
#[path = "gui_session.rs"]
mod gui_session;
#[path = "gui_session_results.rs"]
mod gui_session_results;
#[path = "gui_settings.rs"]
mod gui_settings;
#[path = "gui_single_thread.rs"]
mod gui_single_thread;
#[path = "gui_streaming.rs"]
mod gui_streaming;
#[path = "intermittency.rs"]
mod intermittency;
#[path = "intermittency_interp.rs"]
mod intermittency_interp;
#[path = "interpolant.rs"]
mod interpolant;
#[path = "jobs_hosts.rs"]
mod jobs_hosts;
#[path = "method_agreement.rs"]
mod method_agreement;
#[path = "orbit_summary.rs"]
mod orbit_summary;
#[path = "paper_checks.rs"]
mod paper_checks;
#[path = "phase.rs"]
mod phase;
#[path = "phase_csv_fields.rs"]
mod phase_csv_fields;
#[path = "phase_interp.rs"]
mod phase_interp;
#[path = "phase_multistable.rs"]
mod phase_multistable;
#[path = "phase_picture.rs"]
mod phase_picture;
#[path = "phase_shards.rs"]
mod phase_shards;
#[path = "ranges_run.rs"]
mod ranges_run;
#[path = "reference_map.rs"]
mod reference_map;
#[path = "robustness.rs"]
mod robustness;
#[path = "setup_docs.rs"]
mod setup_docs;
#[path = "special_points.rs"]
mod special_points;
#[path = "stability.rs"]
mod stability;
#[path = "symmetry.rs"]
mod symmetry;
#[path = "work_precision.rs"]
mod work_precision;
#[path = "worked_examples.rs"]
mod worked_examples;
#[path = "worker_continuation.rs"]
mod worker_continuation;
#[path = "worker_failures.rs"]
mod worker_failures;
#[path = "worker_generations.rs"]
mod worker_generations;
#[path = "worker_phase.rs"]
mod worker_phase;
#[path = "worker_results.rs"]
mod worker_results;
#[path = "worker_sweep_interp.rs"]
mod worker_sweep_interp;
#[path = "worker_work_precision.rs"]
mod worker_work_precision;

/// Each file of tests/ is a module of this suite or a test binary of its
/// own in Cargo.toml, and not both: a file in neither would never run
/// (Cargo.toml sets `autotests = false`).
#[test]
fn every_test_file_runs_once() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let read = |p: &str| std::fs::read_to_string(root.join(p)).expect(p);
    let (suite, manifest) = (read("tests/suite.rs"), read("Cargo.toml"));
    let mut files: Vec<String> = std::fs::read_dir(root.join("tests"))
        .expect("tests/")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|f| f.ends_with(".rs") && f != "suite.rs")
        .collect();
    files.sort();
    assert!(files.len() > 50, "found {files:?}");
    for f in files {
        let in_suite = suite.contains(&format!("#[path = \"{f}\"]"));
        let own = manifest.contains(&format!("path = \"tests/{f}\""));
        assert!(
            in_suite != own,
            "tests/{f}: in the suite {in_suite}, its own binary {own}: exactly one"
        );
    }
}
