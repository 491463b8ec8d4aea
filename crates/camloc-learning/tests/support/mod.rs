//! Synthetic classification data shared by the tests and the benchmarks.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// `n` samples of `d` features in `k` Gaussian classes: class means drawn from
/// `N(0, separation^2 I)`, samples `mean_y + N(0, I)`, labels `i % k` (balanced), features
/// then shifted by `offset` and scaled per column by `1 + column` so that standardisation
/// matters. Row-major features and labels; deterministic for a seed.
pub fn gaussian_classes(
    n: usize,
    d: usize,
    k: usize,
    separation: f64,
    offset: f64,
    seed: u64,
) -> (Vec<f64>, Vec<usize>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let unit = Normal::new(0.0, 1.0).expect("unit normal");
    let means: Vec<f64> = (0..k * d)
        .map(|_| separation * unit.sample(&mut rng))
        .collect();
    let mut x = Vec::with_capacity(n * d);
    let mut y = Vec::with_capacity(n);
    for i in 0..n {
        let label = i % k;
        y.push(label);
        for j in 0..d {
            let v = means[label * d + j] + unit.sample(&mut rng);
            x.push(offset + v * (1.0 + j as f64));
        }
    }
    (x, y)
}
