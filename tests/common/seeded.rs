//! Direct orbits from seeds spread over the exit arc: the independent
//! count of attractors that the seeded tests (`attractors.rs`,
//! `phase_multistable.rs`) check the exit arc's cell graph against. Full
//! integrated orbits, periods from their iterates. The κ = 10 hysteresis
//! range, which both files check, is computed once per process, on every
//! core.

use std::sync::OnceLock;

use oneblock::model::{Params, exit_arc};
use oneblock::sim::{OrbitOptions, Period, Simulator, default_settings};

/// Where one seed's orbit ended.
#[derive(Clone, Debug)]
pub struct Ended {
    pub period: Period,
    /// The onset after its last kept event (a cycle is solved from it).
    pub theta_last: f64,
    /// Its kept onsets, in order.
    pub kept: Vec<f64>,
}

/// The orbits from `n` θ₀ spread evenly over the exit arc, each 3000
/// transient and 64 kept iterates at DOP853 1e-10.
pub fn orbits(p: Params, n: usize) -> Vec<Ended> {
    let sim = Simulator::new(p, default_settings(1e-10)).expect("valid parameters");
    let opts = OrbitOptions {
        transient: 3000,
        keep: 64,
        lyapunov: false,
        period_tol: OrbitOptions::period_tol_for(1e-10),
    };
    let (psi, half) = exit_arc(p.kappa, p.theta_nu);
    (0..n)
        .map(|i| {
            let t0 = psi - half + 2.0 * half * (i as f64 + 0.5) / n as f64;
            let o = sim.orbit(t0, &opts, &|| false).expect("a seed orbit");
            Ended {
                period: o.period,
                theta_last: o.theta_last,
                kept: o.thetas(),
            }
        })
        .collect()
}

/// κ = 10, γ = 6.5, ν = 1e-3, Ω = 50 at `theta_nu`.
pub fn kappa10_params(theta_nu: f64) -> Params {
    Params {
        kappa: 10.0,
        gamma: 6.5,
        nu: 1e-3,
        theta_nu,
        omega: 50.0,
    }
}

/// The thirteen θν of the κ = 10 hysteresis range (1.33 to 1.45 in steps
/// of 0.01) with the orbits from 32 seeds at each.
fn kappa10() -> &'static [(f64, Vec<Ended>)] {
    static TABLE: OnceLock<Vec<(f64, Vec<Ended>)>> = OnceLock::new();
    TABLE.get_or_init(|| {
        let thetas: Vec<f64> = (0..13).map(|i| 1.33 + 0.12 * i as f64 / 12.0).collect();
        let cores = std::thread::available_parallelism().map_or(2, |n| n.get());
        let next = std::sync::atomic::AtomicUsize::new(0);
        let mut table: Vec<(f64, Vec<Ended>)> = std::thread::scope(|s| {
            let workers: Vec<_> = (0..cores)
                .map(|_| {
                    s.spawn(|| {
                        let mut mine = vec![];
                        loop {
                            let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                            let Some(&tn) = thetas.get(i) else { break mine };
                            mine.push((tn, orbits(kappa10_params(tn), 32)));
                        }
                    })
                })
                .collect();
            workers
                .into_iter()
                .flat_map(|w| w.join().expect("a reference thread"))
                .collect()
        });
        table.sort_by(|a, b| a.0.total_cmp(&b.0));
        table
    })
}

/// The orbits from 32 seeds at a θν of the κ = 10 range (a command's θν,
/// printed to the precision it writes, or a grid's).
pub fn kappa10_at(theta_nu: f64) -> &'static [Ended] {
    let (t, ended) = kappa10()
        .iter()
        .min_by(|a, b| (a.0 - theta_nu).abs().total_cmp(&(b.0 - theta_nu).abs()))
        .expect("thirteen columns");
    assert!(
        (t - theta_nu).abs() < 1e-9,
        "θν {theta_nu} is no column of the κ = 10 reference"
    );
    ended
}
