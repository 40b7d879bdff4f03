//! The bench room: what times the jobs rather than runs them. The job
//! layer ([`crate::jobs`]) holds only jobs; the measurements of them live
//! here, beside each other:
//!
//! - [`diagram`]: the paper's Fig. 3b diagram on the single-threaded host
//!   (the browser's), in the page's slices of time (`oneblock bench-worker
//!   --single-thread`, the page's `bench_diagram`);
//! - [`pieces`]: every kind of job on that host, counted in pieces
//!   (`oneblock bench-worker --pieces`).
//!
//! The command that prints them is `src/cli/bench_worker/`; the criterion
//! benchmarks (`cargo bench --features bench`) are `benches/`. Not behind
//! the `bench` feature: `bench-worker` is part of every build, and the
//! browser build times its diagram with [`diagram`] too.

pub mod diagram;
pub mod pieces;
