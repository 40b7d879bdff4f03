//! One map evaluation's memory is bounded whatever the slip costs: near
//! κ = 16,570 at Fig. 3b a slip took about 150,000 DOP853 steps, whose
//! derivatives' tape once peaked at over 160 MB (about 1 KB a step). κ is
//! now at most 1e3, where the longest slips are the creep preset's near
//! the exit arc's end: about 60,000 steps, over 60 MB of tape unbounded.
//! The tape now stops at a few MB and the slip ends without derivatives,
//! saying why; θ' is still computed. One test in this file: the peak is read from the process's
//! waited-for children (getrusage), which must be this command alone.
#![cfg(target_os = "linux")]
#![allow(clippy::unwrap_used)]

mod cli_support;

use cli_support::*;

#[test]
fn a_long_slip_ends_without_derivatives_in_bounded_memory() {
    let o = oneblock(&[
        "map", "--preset", "creep", "--kappa", "1e3", "--theta", "1.5",
    ]);
    assert_ok(&o);
    let out = stdout(&o);
    assert!(
        out.contains("derivative       none: the slip took more than"),
        "{out}"
    );
    let theta_next = out
        .lines()
        .find_map(|l| l.strip_prefix("theta_next"))
        .map(|v| num(v.split_whitespace().next().unwrap()))
        .unwrap_or_else(|| panic!("no theta_next line: {out}"));
    assert!(theta_next.is_finite());
    let peak_mb = children_peak_kb() as f64 / 1024.0;
    // The tape's 4 MB (8 at most while its buffer doubles) on top of the
    // program itself; unbounded, the tape alone would pass 60 MB here.
    assert!(peak_mb < 40.0, "peak {peak_mb:.0} MB");
}
