use oneblock::{Method, Params, Simulator, SolverSettings};
fn main() {
    let cases = [
        (18.95, 6.5, 1e-3, 1.0, 0.5, 0.2037551562),
        (50.0, 6.5, 1e-4, 0.3, 0.3, 0.2995442543),
        (3.0, 0.5, 1e-3, 0.7, 0.9, 0.8971492439),
        (10.0, 6.5, 1e-3, 1.2, 1.0, -0.2667076065),
    ];
    for m in [Method::Dop853, Method::Dp54] {
        for tol in [1e-6, 1e-8, 1e-10, 1e-12, 1e-13] {
            let mut line = format!("{m} {tol:e}:");
            for &(k, g, nu, tn, th, want) in &cases {
                let p = Params {
                    kappa: k,
                    gamma: g,
                    nu,
                    theta_nu: tn,
                    omega: 50.0,
                };
                let sim = Simulator::new(p, SolverSettings::adaptive(m, tol)).unwrap();
                let ev = sim.cycle(th, 0.0, None).unwrap();
                line += &format!(
                    "  err {:.1e} ev {} st {}",
                    (ev.theta_next - want).abs(),
                    ev.rhs_evals,
                    ev.steps
                );
            }
            println!("{line}");
        }
    }
}
