//! docs/model.md's worked examples: one map iterate each, from two independent
//! high-accuracy implementations (trust 10 digits). They pin the
//! conventions: the angle wrap, the phase switch, the stop, the stick phase.

#![allow(clippy::unwrap_used)]

use oneblock::{Method, Params, Simulator, SolverSettings};

struct Example {
    kappa: f64,
    gamma: f64,
    nu: f64,
    theta_nu: f64,
    theta: f64,
    theta_next: f64,
    accel_end: f64,
    slip_duration: f64,
    stop: [f64; 2],
    stick: f64,
}

const EXAMPLES: [Example; 4] = [
    Example {
        kappa: 18.95,
        gamma: 6.5,
        nu: 1e-3,
        theta_nu: 1.0,
        theta: 0.5,
        theta_next: 0.2037551562,
        accel_end: 1.125355434,
        slip_duration: 3.123143632,
        stop: [-0.003275131363, 0.1167625165],
        stick: 101.7096366,
    },
    Example {
        kappa: 50.0,
        gamma: 6.5,
        nu: 1e-4,
        theta_nu: 0.3,
        theta: 0.3,
        theta_next: 0.2995442543,
        accel_end: 0.8136794637,
        slip_duration: 0.9852905504,
        stop: [0.01219639680, 0.2929463363],
        stick: 72.36219612,
    },
    Example {
        kappa: 3.0,
        gamma: 0.5,
        nu: 1e-3,
        theta_nu: 0.7,
        theta: 0.9,
        theta_next: 0.8971492439,
        accel_end: 2.542307918,
        slip_duration: 3.629856483,
        stop: [0.2042770278, 0.7784606323],
        stick: 4.798127107,
    },
    Example {
        kappa: 10.0,
        gamma: 6.5,
        nu: 1e-3,
        theta_nu: 1.2,
        theta: 1.0,
        theta_next: -0.2667076065,
        accel_end: 2.333676717,
        slip_duration: 3.782995674,
        stop: [-0.02635567172, -0.5794686934],
        stick: 338.9469545,
    },
];

fn check(method: Method, tol: f64, digits: f64) {
    for ex in &EXAMPLES {
        let p = Params {
            kappa: ex.kappa,
            gamma: ex.gamma,
            nu: ex.nu,
            theta_nu: ex.theta_nu,
            omega: 50.0,
        };
        let sim = Simulator::new(p, SolverSettings::adaptive(method, tol)).unwrap();
        let ev = sim.cycle(ex.theta, 0.0, None).unwrap();
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-3);
        let tolr = 10f64.powf(-digits);
        let msg = format!("{method} tol {tol} at kappa {}: {ev:#?}", ex.kappa);
        assert!((ev.theta_next - ex.theta_next).abs() < tolr, "theta' {msg}");
        assert!(
            rel(ev.accel_duration, ex.accel_end) < tolr,
            "accel end {msg}"
        );
        assert!(
            rel(ev.slip_duration, ex.slip_duration) < tolr,
            "slip duration {msg}"
        );
        assert!(
            (ev.stop_x - ex.stop[0]).abs() < tolr * 0.1 && (ev.stop_y - ex.stop[1]).abs() < tolr,
            "stop {msg}"
        );
        assert!(rel(ev.stick_duration, ex.stick) < tolr, "stick {msg}");
        assert!(!ev.restarted);
    }
}

#[test]
fn dop853_reproduces_the_worked_examples() {
    check(Method::Dop853, 1e-13, 9.0);
}

#[test]
fn dp54_reproduces_the_worked_examples() {
    check(Method::Dp54, 1e-12, 8.0);
}
