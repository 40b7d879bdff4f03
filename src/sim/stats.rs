//! The sample statistics the core, the numerics and the benchmarks share:
//! the mean with its standard error (of a slice, or in one pass), and the
//! median.

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
    let mut means = [0.0; BATCHES];
    for (m, c) in means.iter_mut().zip(xs.chunks_exact(b)) {
        *m = c.iter().sum::<f64>() / b as f64;
    }
    (Some(mean), Some(batch_error(&means)))
}

/// The standard error of a mean from its [`BATCHES`] batch means: their
/// spread over √batches.
fn batch_error(means: &[f64; BATCHES]) -> f64 {
    let m = means.iter().sum::<f64>() / BATCHES as f64;
    let var = means.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (BATCHES - 1) as f64;
    (var / BATCHES as f64).sqrt()
}

/// [`mean_and_stderr`] of a sample whose size `n` is known before its
/// values, in one pass and constant memory: each value is added to the
/// running sum and to its batch's as it comes, in the same order as the
/// slice's sums add them, so that once all `n` are in, the mean and the
/// error are [`mean_and_stderr`]'s bit for bit (a long orbit's λ without
/// keeping its ln|f'|).
#[derive(Clone, Debug, PartialEq)]
pub struct BatchMeans {
    n: usize,
    /// Values in a batch (n / [`BATCHES`]).
    batch: usize,
    count: usize,
    sum: f64,
    batch_sum: f64,
    means: [f64; BATCHES],
}

impl BatchMeans {
    /// For a sample of `n` values.
    pub fn new(n: usize) -> Self {
        BatchMeans {
            n,
            batch: n / BATCHES,
            count: 0,
            // As `Iterator::sum` of f64 starts.
            sum: -0.0,
            batch_sum: -0.0,
            means: [0.0; BATCHES],
        }
    }

    /// The next value.
    pub fn push(&mut self, x: f64) {
        self.sum += x;
        if self.batch == 0 || self.count >= BATCHES * self.batch {
            self.count += 1;
            return;
        }
        self.batch_sum += x;
        self.count += 1;
        if self.count.is_multiple_of(self.batch) {
            self.means[self.count / self.batch - 1] = self.batch_sum / self.batch as f64;
            self.batch_sum = -0.0;
        }
    }

    /// Values pushed so far.
    pub fn len(&self) -> usize {
        self.count
    }

    /// Whether none was.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// The mean of the values so far (`None` before the first).
    pub fn mean(&self) -> Option<f64> {
        (self.count > 0).then(|| self.sum / self.count as f64)
    }

    /// [`mean_and_stderr`] of the sample: the error only once all `n`
    /// values are in (and, as there, `None` below 2 values a batch).
    pub fn mean_and_stderr(&self) -> (Option<f64>, Option<f64>) {
        let error = (self.count == self.n && self.batch >= 2).then(|| batch_error(&self.means));
        (self.mean(), self.mean().and(error))
    }
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
    fn batch_means_in_one_pass_are_the_slices_bit_for_bit() {
        let mut state: u64 = 7;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 * 3.0 - 1.0
        };
        let bits = |(m, e): (Option<f64>, Option<f64>)| (m.map(f64::to_bits), e.map(f64::to_bits));
        for n in (0..200).chain([1000, 4099, 100_003]) {
            let xs: Vec<f64> = (0..n).map(|_| next()).collect();
            let mut bm = BatchMeans::new(n);
            for (i, &x) in xs.iter().enumerate() {
                if n <= 1000 {
                    let so_far = mean_and_stderr(&xs[..i]).0;
                    assert_eq!(bm.mean().map(f64::to_bits), so_far.map(f64::to_bits));
                }
                bm.push(x);
            }
            assert_eq!(bm.len(), n);
            assert_eq!(
                bits(bm.mean_and_stderr()),
                bits(mean_and_stderr(&xs)),
                "n = {n}"
            );
        }
        assert_eq!(BatchMeans::new(0).mean_and_stderr(), (None, None));
        // Short of its size: the mean so far, no error.
        let mut bm = BatchMeans::new(64);
        (0..40).for_each(|_| bm.push(1.0));
        assert_eq!(bm.mean_and_stderr(), (Some(1.0), None));
    }

    #[test]
    fn median_of_odd_even_and_empty_samples() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert!(median(&[]).is_nan());
    }
}
