//! Why the hot loops (`integrate`, `variational`) stay on `[f64; 4]`
//! arrays: one Runge–Kutta step of DOP853's shape (12 stages, each stage's
//! argument a sum over all earlier stages) on the slip's acceleration field,
//! written twice, with arrays and index loops as `integrate` is, and with
//! nalgebra's `Vector4` and its operators. Both run alternately in the same
//! process (21 rounds, medians), so the ratio holds on a loaded host even
//! where the absolute times do not; it also says whether the two give the
//! same bits.
//!
//! `cargo bench --features bench --no-default-features --bench arrays_vs_nalgebra`

use std::hint::black_box;
use std::time::Instant;

use nalgebra::Vector4;
use oneblock::model::Params;
use oneblock::sim::field::SlipField;

const STAGES: usize = 12;

/// A lower-triangular tableau of DOP853's size (the coefficients' values do
/// not matter for the cost, only that each stage sums all earlier ones).
fn tableau() -> [[f64; STAGES]; STAGES] {
    let mut a = [[0.0; STAGES]; STAGES];
    for i in 1..STAGES {
        for j in 0..i {
            a[i][j] = 1.0 / ((i + j + 2) as f64 * i as f64);
        }
    }
    a
}

fn step_arrays(f: &SlipField, a: &[[f64; STAGES]; STAGES], y: &[f64; 4], h: f64) -> [f64; 4] {
    let mut k = [[0.0; 4]; STAGES];
    k[0] = f.accel(y);
    for i in 1..STAGES {
        let mut t = *y;
        for j in 0..i {
            let c = h * a[i][j];
            for n in 0..4 {
                t[n] += c * k[j][n];
            }
        }
        k[i] = f.accel(&t);
    }
    let mut out = *y;
    for (j, kj) in k.iter().enumerate() {
        let c = h / (j + 2) as f64;
        for n in 0..4 {
            out[n] += c * kj[n];
        }
    }
    out
}

fn step_nalgebra(
    f: &SlipField,
    a: &[[f64; STAGES]; STAGES],
    y: &Vector4<f64>,
    h: f64,
) -> Vector4<f64> {
    let rhs = |v: &Vector4<f64>| Vector4::from(f.accel(&(*v).into()));
    let mut k = [Vector4::zeros(); STAGES];
    k[0] = rhs(y);
    for i in 1..STAGES {
        let mut t = *y;
        for j in 0..i {
            t += k[j] * (h * a[i][j]);
        }
        k[i] = rhs(&t);
    }
    let mut out = *y;
    for (j, kj) in k.iter().enumerate() {
        out += kj * (h / (j + 2) as f64);
    }
    out
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let p = Params {
        kappa: 18.95,
        gamma: 6.5,
        nu: 1e-3,
        theta_nu: 1.25,
        omega: 50.0,
    };
    let field = SlipField::new(&p);
    let a = tableau();
    // A growing slip from near rest, as the acceleration phase runs.
    let y0 = [0.02, 0.45, 1e-5, 2e-5];
    let (steps, h) = (2000, 1e-3);
    let (mut t_arr, mut t_na) = (Vec::new(), Vec::new());
    let (mut last_arr, mut last_na) = ([0.0; 4], Vector4::zeros());
    for _ in 0..21 {
        let start = Instant::now();
        let mut y = y0;
        for _ in 0..steps {
            y = step_arrays(&field, &a, black_box(&y), h);
        }
        t_arr.push(start.elapsed().as_secs_f64() / steps as f64);
        last_arr = y;

        let start = Instant::now();
        let mut y = Vector4::from(y0);
        for _ in 0..steps {
            y = step_nalgebra(&field, &a, black_box(&y), h);
        }
        t_na.push(start.elapsed().as_secs_f64() / steps as f64);
        last_na = y;
    }
    let (ta, tn) = (median(t_arr), median(t_na));
    let same = (0..4).all(|n| last_arr[n].to_bits() == last_na[n].to_bits());
    println!(
        "one 12-stage step on the acceleration field, {steps} chained steps, 21 alternated rounds (medians):"
    );
    println!("  arrays          {:.0} ns per step", ta * 1e9);
    println!("  nalgebra Vector4 {:.0} ns per step", tn * 1e9);
    println!("  ratio nalgebra / arrays: {:.3}", tn / ta);
    println!(
        "  after {steps} steps the states are {}",
        if same {
            "bitwise the same".to_string()
        } else {
            let d = (0..4)
                .map(|n| (last_arr[n] - last_na[n]).abs())
                .fold(0.0, f64::max);
            format!("different (max difference {d:e})")
        }
    );
}
