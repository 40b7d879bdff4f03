//! `oneblock orbit` with 10⁶ kept iterates and no CSV runs in memory that
//! does not grow with the orbit (issue 56): it held every kept event and
//! ln|f'| (157 MB at 10⁶). One test in this file: the peak is read from the
//! process's waited-for children (getrusage), which must be this command
//! alone.
#![cfg(target_os = "linux")]
#![allow(clippy::unwrap_used)]

mod cli_support;

use cli_support::*;

#[test]
fn a_million_kept_iterates_for_a_summary_stay_under_40_mb() {
    let o = oneblock(&[
        "orbit",
        "--preset",
        "fig3b",
        "--theta-nu",
        "1.25",
        "--theta0",
        "0.4",
        "--transient",
        "1000",
        "--keep",
        "1000000",
        "--json",
    ]);
    assert_ok(&o);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["keep"], 1_000_000);
    assert!(v["lyapunov_stderr"].as_f64().is_some_and(|e| e > 0.0));
    let peak = children_peak_kb();
    assert!(peak < 40 * 1024, "peak {peak} KB");
}
