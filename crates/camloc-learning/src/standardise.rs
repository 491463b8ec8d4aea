//! Per-feature standardisation `(x - mean) / scale`, fitted on training data and stored in
//! the model so that predictions take raw features.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::kernel::PackedLinear;
use crate::{DesignRows, Features, LearningError};

/// Relative spread below which a feature column counts as constant: a column whose standard
/// deviation is at most this times its largest absolute value gets scale 1 (rounding in the
/// mean would otherwise turn a constant column into amplified noise).
const CONSTANT_COLUMN_RELATIVE_SPREAD: f64 = 1e-10;

/// Columns one parallel task of [`Standardiser::fit_rows`] sums.
const COLUMN_TASK: usize = 64;

/// Per-feature affine map `x -> (x - means[j]) / scales[j]`, in the units of the raw
/// features. Every scale is finite and positive.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Standardiser {
    means: Vec<f64>,
    scales: Vec<f64>,
}

impl Standardiser {
    /// The identity map on `n_features` features (means 0, scales 1).
    pub fn identity(n_features: usize) -> Self {
        Self {
            means: vec![0.0; n_features],
            scales: vec![1.0; n_features],
        }
    }

    /// Fits means and population standard deviations (divisor `n`) column by column.
    /// Constant columns (standard deviation at most 1e-10 times the column's largest
    /// absolute value) get scale 1 so that they standardise to 0 instead of to noise. With zero rows
    /// the identity is returned.
    pub fn fit(x: &Features<'_>) -> Self {
        Self::fit_rows(&DesignRows::plain(*x))
    }

    /// [`fit`](Self::fit) on rows read one at a time (the same numbers as on the rows stored
    /// whole).
    pub fn fit_rows(x: &DesignRows<'_>) -> Self {
        Self::fit_selected(x, 0..x.n_samples())
    }

    /// [`fit`](Self::fit) on the rows of `x` that `selected` names (the same numbers as on
    /// a copy of those rows, in that order).
    pub(crate) fn fit_selected(
        x: &DesignRows<'_>,
        selected: impl IntoIterator<Item = usize> + Clone,
    ) -> Self {
        let d = x.n_features();
        let n = selected.clone().into_iter().count();
        if n == 0 {
            return Self::identity(d);
        }
        // Per column: the sum and the largest absolute value, then the squared deviations.
        let mut first_pass = vec![(0.0, 0.0_f64); d];
        sum_columns(x, selected.clone(), &mut first_pass, |sums, first, row| {
            for ((m, a), &v) in sums.iter_mut().zip(&row[first..]) {
                *m += v;
                *a = a.max(v.abs());
            }
        });
        let inv_n = 1.0 / n as f64;
        let (mut means, max_abs): (Vec<f64>, Vec<f64>) = first_pass.into_iter().unzip();
        means.iter_mut().for_each(|m| *m *= inv_n);
        // The deviations in units of the column's largest value, so that their squares
        // neither overflow (columns of 1e155) nor underflow (1e-200).
        let units: Vec<f64> = max_abs
            .iter()
            .map(|&a| if a > 0.0 && a.is_finite() { a } else { 1.0 })
            .collect();
        let mut variances = vec![0.0; d];
        sum_columns(x, selected, &mut variances, |sums, first, row| {
            for (((s, m), u), &v) in sums
                .iter_mut()
                .zip(&means[first..])
                .zip(&units[first..])
                .zip(&row[first..])
            {
                let c = (v - m) / u;
                *s += c * c;
            }
        });
        let scales = variances
            .iter()
            .zip(&max_abs)
            .zip(&units)
            .map(|((&var, &a), &unit)| {
                let sd = (var * inv_n).sqrt() * unit;
                if sd > CONSTANT_COLUMN_RELATIVE_SPREAD * a && sd.is_finite() {
                    sd
                } else {
                    1.0
                }
            })
            .collect();
        Self { means, scales }
    }

    /// Builds a standardiser from stored parts, checking them.
    ///
    /// # Errors
    /// [`LearningError::SizeMismatch`] if the lengths differ, [`LearningError::InvalidParameter`]
    /// if a mean is not finite or a scale is not finite and positive.
    pub fn from_parts(means: Vec<f64>, scales: Vec<f64>) -> Result<Self, LearningError> {
        let s = Self { means, scales };
        s.validate()?;
        Ok(s)
    }

    /// Checks the invariants (equal lengths, finite means, finite positive scales).
    pub(crate) fn validate(&self) -> Result<(), LearningError> {
        if self.means.len() != self.scales.len() {
            return Err(LearningError::SizeMismatch {
                what: "standardiser scales (one per mean)",
                expected: self.means.len(),
                found: self.scales.len(),
            });
        }
        if let Some(m) = self.means.iter().find(|m| !m.is_finite()) {
            return Err(LearningError::InvalidParameter {
                name: "standardiser mean",
                value: format!("{m:?}"),
                reason: "must be finite",
            });
        }
        if let Some(s) = self.scales.iter().find(|s| !(s.is_finite() && **s > 0.0)) {
            return Err(LearningError::InvalidParameter {
                name: "standardiser scale",
                value: format!("{s:?}"),
                reason: "must be finite and positive",
            });
        }
        Ok(())
    }

    /// Number of features.
    pub fn n_features(&self) -> usize {
        self.means.len()
    }

    /// Per-feature means subtracted first (raw feature units).
    pub fn means(&self) -> &[f64] {
        &self.means
    }

    /// Per-feature divisors applied after centring (raw feature units).
    pub fn scales(&self) -> &[f64] {
        &self.scales
    }

    /// Writes the standardised `row` into `out` (both of length
    /// [`n_features`](Self::n_features); the caller checks the lengths), dividing by the
    /// scales (the quadratic expansion's fit).
    pub(crate) fn transform_into(&self, row: &[f64], out: &mut [f64]) {
        for (((o, &v), &m), &s) in out.iter_mut().zip(row).zip(&self.means).zip(&self.scales) {
            *o = (v - m) / s;
        }
    }

    /// Standardises one raw value with its column's mean and the reciprocal of its scale
    /// ([`inverse_scales`](Self::inverse_scales)): a multiplication, not a division, as
    /// a fit forms hundreds of millions of them (the Newton solver's design matrix goes
    /// through this function; prediction uses the same map folded into the weights,
    /// [`RawLinear`]).
    #[inline(always)]
    pub(crate) fn apply(mean: f64, inverse_scale: f64, raw: f64) -> f64 {
        (raw - mean) * inverse_scale
    }

    /// `1 / scale` of every column, for [`apply`](Self::apply).
    pub(crate) fn inverse_scales(&self) -> Vec<f64> {
        self.scales.iter().map(|s| 1.0 / s).collect()
    }
}

/// A linear map on standardised features, `y_k = b_k + sum_j W[j][k] (x_j - mean_j) / scale_j`,
/// re-expressed on raw features as `y_k = c_k + sum_j V[j][k] x_j` with `V[j][k] =
/// W[j][k] / scale_j` and `c_k = b_k - sum_j V[j][k] mean_j`. It is what prediction runs:
/// one multiply-add per weight, no division, on the packed kernel of [`crate::kernel`]. It
/// is derived from the stored model, never stored itself, and equals the standardised form
/// up to rounding.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RawLinear {
    map: PackedLinear,
}

impl RawLinear {
    /// Folds `standardiser` into the map whose weight of standardised feature `j` for output
    /// `k` is `weight(j, k)` (`n_weights` stored weights) and whose biases are `biases` (one
    /// per output). Sizes are not checked here: the models validate theirs, and unless the
    /// stored weights are one per feature and output the map reads no feature (a decoded
    /// file's sizes are not trusted with an allocation of their product before they are
    /// validated).
    pub(crate) fn fold(
        standardiser: &Standardiser,
        weight: impl Fn(usize, usize) -> f64,
        n_weights: usize,
        biases: &[f64],
    ) -> Self {
        let scales = &standardiser.scales;
        let m = biases.len();
        // A decoded standardiser may have fewer scales than means until it is validated.
        let d = standardiser.means.len().min(scales.len());
        let d = if d.checked_mul(m) == Some(n_weights) {
            d
        } else {
            0
        };
        // `V[j][k]`, feature-major, each divided once.
        let folded: Vec<f64> = (0..d)
            .flat_map(|j| (0..m).map(move |k| (j, k)))
            .map(|(j, k)| weight(j, k) / scales[j])
            .collect();
        let mut folded_biases = biases.to_vec();
        for (k, c) in folded_biases.iter_mut().enumerate() {
            for (j, &mean) in standardiser.means.iter().take(d).enumerate() {
                *c -= folded[j * m + k] * mean;
            }
        }
        let map = PackedLinear::pack(d, |j, k| folded[j * m + k], folded_biases);
        RawLinear { map }
    }

    /// Writes the outputs for the raw feature row `x` into `out` (one per output; the caller
    /// checks both lengths).
    #[inline]
    pub(crate) fn apply_into(&self, x: &[f64], out: &mut [f64]) {
        self.map.apply_into(x, out);
    }
}

/// Adds the rows of `x` that `selected` names to per-column sums: `add(sums, first, row)`
/// adds `row[first..]` to the sums of the columns `first..` it is given. Blocks of rows are
/// made in parallel, then each block's columns summed in parallel tasks of [`COLUMN_TASK`],
/// each column's values added row after row: the sums of one pass over the rows, to the bit.
fn sum_columns<T: Send>(
    x: &DesignRows<'_>,
    selected: impl IntoIterator<Item = usize>,
    sums: &mut [T],
    add: impl Fn(&mut [T], usize, &[f64]) + Sync,
) {
    let d = x.n_features();
    x.for_each_block(selected, |rows| {
        sums.par_chunks_mut(COLUMN_TASK)
            .enumerate()
            .for_each(|(t, sums)| {
                for row in rows.chunks_exact(d) {
                    add(sums, t * COLUMN_TASK, row);
                }
            });
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The folded map gives the standardised map's outputs (up to rounding) for every
        /// feature count (odd ones leave a remainder) and output count (partial blocks).
        #[test]
        fn folded_map_equals_the_standardised_one(
            d in 1usize..12,
            m in 1usize..10,
            seed in prop::collection::vec(-3.0f64..3.0, 4 * 12 * 10),
        ) {
            let at = |k: usize| seed[k % seed.len()];
            let means: Vec<f64> = (0..d).map(|j| 10.0 * at(j)).collect();
            let scales: Vec<f64> = (0..d).map(|j| 0.1 + at(d + j).abs()).collect();
            let standardiser = Standardiser::from_parts(means.clone(), scales.clone()).unwrap();
            let weight = |j: usize, k: usize| at(2 * d + j * m + k);
            let biases: Vec<f64> = (0..m).map(|k| at(3 * d + d * m + k)).collect();
            let x: Vec<f64> = (0..d).map(|j| 5.0 * at(7 * j + 1) + means[j]).collect();
            let folded = RawLinear::fold(&standardiser, weight, d * m, &biases);
            let mut out = vec![f64::NAN; m];
            folded.apply_into(&x, &mut out);
            for (k, o) in out.iter().enumerate() {
                let direct = biases[k]
                    + (0..d)
                        .map(|j| weight(j, k) * Standardiser::apply(means[j], 1.0 / scales[j], x[j]))
                        .sum::<f64>();
                prop_assert!((o - direct).abs() <= 1e-10 * (1.0 + direct.abs()), "output {k}: {o} vs {direct}");
            }
        }
    }

    /// Rows in blocks and columns in parallel tasks give, to the bit, the sums of one pass
    /// over the rows (several blocks and a partial one, several tasks and a partial one).
    #[test]
    fn blocks_and_column_tasks_give_the_sums_of_one_pass() {
        let (n, d) = (2 * crate::design::BLOCK_ROWS + 5, 2 * COLUMN_TASK + 6);
        let x: Vec<f64> = (0..n * d)
            .map(|i| (i as f64 * 0.618).sin() * (1.0 + (i % 7) as f64))
            .collect();
        let fitted = Standardiser::fit(&Features::new(&x, d).unwrap());
        let mut means = vec![0.0; d];
        for row in x.chunks_exact(d) {
            for (m, v) in means.iter_mut().zip(row) {
                *m += v;
            }
        }
        means.iter_mut().for_each(|m| *m *= 1.0 / n as f64);
        let mut variances = vec![0.0; d];
        for row in x.chunks_exact(d) {
            for ((s, m), v) in variances.iter_mut().zip(&means).zip(row) {
                *s += (v - m) * (v - m);
            }
        }
        let scales: Vec<f64> = variances
            .iter()
            .map(|v| (v * (1.0 / n as f64)).sqrt())
            .collect();
        assert_eq!(fitted.means, means);
        // (The deviations are summed in units of each column's largest value.)
        for (f, s) in fitted.scales.iter().zip(&scales) {
            assert!((f - s).abs() <= 1e-14 * s, "{f} vs {s}");
        }
    }

    /// Columns of huge or tiny values are standardised as the same values at unit scale (a
    /// review found the variance infinite at 1e155 and zero at 1e-200).
    #[test]
    fn the_scale_follows_the_column_at_any_magnitude() {
        let base: Vec<f64> = (0..40).map(|i| (i as f64 * 0.37).sin() + 0.2).collect();
        let unit = Standardiser::fit(&Features::new(&base, 1).unwrap());
        for factor in [1e160, 1e-200, 1e300, 1e-300] {
            let x: Vec<f64> = base.iter().map(|v| v * factor).collect();
            let fitted = Standardiser::fit(&Features::new(&x, 1).unwrap());
            let expected = unit.scales[0] * factor;
            assert!(
                (fitted.scales[0] - expected).abs() <= 1e-12 * expected,
                "{factor}: {} vs {expected}",
                fitted.scales[0]
            );
        }
    }
}
