#![allow(clippy::unwrap_used)]
//! Temporary driver: plain vs derivatives iterates over the fig3b sample.
use oneblock::numerics::sample::default_attractors;
use oneblock::{Method, Simulator, SolverSettings};
use std::hint::black_box;
fn cpu() -> f64 {
    let mut ts = libc_timespec { s: 0, ns: 0 };
    unsafe { clock_gettime(3, &mut ts) };
    ts.s as f64 + ts.ns as f64 * 1e-9
}
#[repr(C)]
struct libc_timespec { s: i64, ns: i64 }
unsafe extern "C" { fn clock_gettime(c: i32, t: *mut libc_timespec) -> i32; }
fn main() {
    let mode = std::env::args().nth(1).unwrap_or("both".into());
    let n: usize = std::env::args().nth(2).map(|s| s.parse().unwrap()).unwrap_or(4000);
    let a = default_attractors().into_iter().find(|a| a.name == "stick-slip chaos").unwrap();
    let sim = Simulator::new(a.params, SolverSettings::adaptive(Method::Dop853, 1e-9)).unwrap();
    let th = a.fixed.unwrap().to_vec();
    let (mut s1, mut s2) = (0u64, 0u64);
    for t in &th { let e = sim.cycle(*t, 0.0, None).unwrap(); s1 += e.steps as u64; s2 += e.rhs_evals; }
    let mut ex = 0; for t in &th { ex += sim.cycle_derivatives(*t, 0.0).unwrap().2; }
    eprintln!("steps/iter {:.1} evals/iter {:.1} extra evals/iter {:.2}", s1 as f64/200.0, s2 as f64/200.0, ex as f64/200.0);
    let plain = |n: usize| { let t0 = cpu(); for i in 0..n { black_box(sim.map(black_box(th[i % 200])).unwrap()); } cpu() - t0 };
    let der = |n: usize| { let t0 = cpu(); for i in 0..n { let _ = black_box(sim.cycle_derivatives(black_box(th[i % 200]), 0.0).unwrap()); } cpu() - t0 };
    let sl = |n: usize| { let t0 = cpu(); for i in 0..n { let _ = black_box(sim.cycle_slope(black_box(th[i % 200]), 0.0).unwrap()); } cpu() - t0 };
    match mode.as_str() {
        "plain" => { plain(n); }
        "deriv" => { der(n); }
        "slope" => { sl(n); }
        "zero" => { let mut r = vec![]; for _ in 0..5 { let p = plain(n); let t0 = cpu(); for i in 0..n { let _ = black_box(sim.cycle_partials(black_box(th[i % 200]), 0.0, [])); } r.push((cpu() - t0) / p); } r.sort_by(f64::total_cmp); eprintln!("zero-dir/plain {:.3}", r[2]); }
        _ => {
            let mut r = vec![]; let mut r1 = vec![]; let mut pp = vec![]; let mut dd = vec![]; let mut ss = vec![];
            for _ in 0..7 { let p = plain(n); let d = der(n); let s = sl(n); pp.push(p); dd.push(d); ss.push(s); r.push(d / p); r1.push(s / p); }
            for v in [&mut r, &mut r1, &mut pp, &mut dd, &mut ss] { v.sort_by(f64::total_cmp); }
            eprintln!("plain {:.2} us deriv {:.2} us slope {:.2} us; deriv/plain median {:.3} (min {:.3} max {:.3}); slope/plain median {:.3} (min {:.3} max {:.3})", pp[3]/n as f64*1e6, dd[3]/n as f64*1e6, ss[3]/n as f64*1e6, r[3], r[0], r[6], r1[3], r1[0], r1[6]);
        }
    }
}
