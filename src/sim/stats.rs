//! The sample statistics the core, the numerics and the benchmarks share:
//! the mean with its standard error, and the median.

/// Batches of the batch-means standard error.
pub const BATCHES: usize = 8;

/// Mean of a sample and its standard error by batch means (`None` for both
/// when the sample is empty).
///
/// The sample is cut into [`BATCHES`] consecutive batches (the tail that does
/// not fill a batch is dropped from the error only) and the error is the
/// spread of the batch means over √batches. Successive iterates of a map are
/// correlated, which the naive error σ/√n ignores and so understates; batch
/// means of long enough batches are nearly independent, so their spread is
/// an honest error for the Lyapunov exponent along an orbit. The error is
/// `None` below 2 values per batch.
pub fn mean_and_stderr(xs: &[f64]) -> (Option<f64>, Option<f64>) {
    if xs.is_empty() {
        return (None, None);
    }
    let mean = xs.iter().sum::<f64>() / xs.len() as f64;
    let b = xs.len() / BATCHES;
    if b < 2 {
        return (Some(mean), None);
    }
    let means: Vec<f64> = xs
        .chunks_exact(b)
        .take(BATCHES)
        .map(|c| c.iter().sum::<f64>() / b as f64)
        .collect();
    let m = means.iter().sum::<f64>() / BATCHES as f64;
    let var = means.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (BATCHES - 1) as f64;
    (Some(mean), Some((var / BATCHES as f64).sqrt()))
}

/// The median of `xs` (NaN if empty; the mean of the middle two for an even
/// count).
pub fn median(xs: &[f64]) -> f64 {
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_mean_and_stderr_of_a_constant_has_no_spread() {
        let (m, se) = mean_and_stderr(&[0.25; 64]);
        assert_eq!(m, Some(0.25));
        assert_eq!(se, Some(0.0));
        assert_eq!(mean_and_stderr(&[1.0; 10]), (Some(1.0), None));
        assert_eq!(mean_and_stderr(&[]), (None, None));
    }

    #[test]
    fn batch_means_see_the_correlation_the_naive_error_ignores() {
        // An AR(1) sequence x_{i+1} = 0.9 x_i + e_i with e_i = ±1 from a
        // fixed LCG: the variance of its mean is (1+φ)/(1−φ) = 19 times the
        // naive estimate's, so the honest error is about √19 ≈ 4.4 times
        // larger.
        let mut state: u64 = 12345;
        let mut x = 0.0;
        let xs: Vec<f64> = (0..80_000)
            .map(|_| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let e = if state >> 63 == 0 { -1.0 } else { 1.0 };
                x = 0.9 * x + e;
                x
            })
            .collect();
        let n = xs.len() as f64;
        let mean = xs.iter().sum::<f64>() / n;
        let var = xs.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
        let naive = (var / n).sqrt();
        let (m, se) = mean_and_stderr(&xs);
        assert_eq!(m, Some(mean));
        let ratio = se.expect("an error") / naive;
        // Eight batches estimate a spread to about ±25 % (1/√(2·7)).
        assert!((2.5..7.0).contains(&ratio), "ratio {ratio}");
    }

    #[test]
    fn median_of_odd_even_and_empty_samples() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert!(median(&[]).is_nan());
    }
}
