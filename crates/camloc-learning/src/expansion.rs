//! The quadratic feature expansion: more capacity for the same linear learner.
//!
//! A linear model on `[x, z_a z_b (a <= b)]`, where `z` are the leading whitened principal
//! components of the standardised `x`, is a quadratic function of `x` restricted to the
//! directions in which the training data vary most. With `k` components the expansion adds
//! `k (k + 1) / 2` values to the `d` of `x`; the multinomial regression on top stays the
//! paper's learner (Newton's method on the expanded features).

use pulp::{Arch, Simd, WithSimd};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::standardise::RawLinear;
use crate::{Features, LearningError, Standardiser};

/// Most principal components a [`QuadraticExpansion`] may keep (its products then number
/// 2080): the expansion works on the stack without allocating.
pub const MAX_EXPANSION_COMPONENTS: usize = 64;

/// Eigenvalues at most this fraction of the total variance count as zero: such directions
/// cannot be whitened.
const NEGLIGIBLE_VARIANCE: f64 = 1e-12;

/// Largest magnitude of a whitened component before the products are taken, in standard
/// deviations of the training rows: a component beyond it is clamped to it. Without the
/// clamp a few atypical views (a component 10 standard deviations out gives a product of 100)
/// dominate the products; the Newton solver's quadratic model could not follow them and the
/// default quadratic fit did not converge in 100 iterations (issue 21; with the clamp it
/// converges in about 20, docs/RESULTS.md).
pub const COMPONENT_LIMIT: f64 = 3.0;

/// Rows per parallel task of [`QuadraticExpansion::expand_rows`].
const ROWS_PER_TASK: usize = 1024;

/// A fitted quadratic expansion `x -> [x, z_a z_b for a <= b]` with
/// `z = clamp(W ((x - mean) / scale), -c, c)`: `W` holds the `k` leading principal directions
/// of the standardised training rows, each divided by the square root of its variance (so
/// that `z` has unit variance on the training rows before the clamp), and `c` is
/// [`COMPONENT_LIMIT`]. Units: `x` as given; `z` is unit-free.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(from = "Stored")]
pub struct QuadraticExpansion {
    standardiser: Standardiser,
    /// `k x d`, row-major: whitened principal direction `a` in row `a`.
    projection: Vec<f64>,
    n_components: usize,
    /// `x -> W ((x - mean) / scale)` on raw `x` (standardisation folded in), derived from the
    /// rest: what [`expand_into`](Self::expand_into) runs.
    raw: RawLinear,
}

/// What a [`QuadraticExpansion`] stores (and serialises, in this order); the rest is derived
/// on decoding.
#[derive(Deserialize)]
struct Stored {
    standardiser: Standardiser,
    projection: Vec<f64>,
    n_components: usize,
}

impl From<Stored> for QuadraticExpansion {
    fn from(stored: Stored) -> Self {
        QuadraticExpansion::from_parts(stored.standardiser, stored.projection, stored.n_components)
    }
}

impl Serialize for QuadraticExpansion {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut stored = serializer.serialize_struct("QuadraticExpansion", 3)?;
        stored.serialize_field("standardiser", &self.standardiser)?;
        stored.serialize_field("projection", &self.projection)?;
        stored.serialize_field("n_components", &self.n_components)?;
        stored.end()
    }
}

impl QuadraticExpansion {
    /// Number of values of the expansion of `n_inputs` values with `n_components`
    /// components: `n_inputs + n_components (n_components + 1) / 2`.
    pub const fn output_len(n_inputs: usize, n_components: usize) -> usize {
        n_inputs + n_components * (n_components + 1) / 2
    }

    /// Fits the standardisation and the `n_components` leading principal directions of the
    /// rows of `x` (population covariance of the standardised rows; eigenvectors with a fixed
    /// sign, their largest-magnitude entry positive, so that the fit is deterministic).
    ///
    /// # Errors
    /// [`LearningError::NoSamples`] for no rows; [`LearningError::InvalidParameter`] when
    /// `n_components` is 0, above [`MAX_EXPANSION_COMPONENTS`] or above the number of
    /// directions in which the rows vary; [`LearningError::Numerical`] when the
    /// eigendecomposition fails.
    pub fn fit(x: &Features<'_>, n_components: usize) -> Result<Self, LearningError> {
        let (n, d) = (x.n_samples(), x.n_features());
        if n == 0 {
            return Err(LearningError::NoSamples);
        }
        let invalid = |reason| LearningError::InvalidParameter {
            name: "expansion components",
            value: n_components.to_string(),
            reason,
        };
        if n_components == 0 || n_components > MAX_EXPANSION_COMPONENTS.min(d) {
            return Err(invalid(
                "must be at least 1 and at most the number of features (and 64)",
            ));
        }
        let standardiser = Standardiser::fit(x);
        // Covariance of the standardised rows (lower triangle), accumulated per task, the
        // tasks' sums then added in task order (not as the threads finish), so that the
        // result does not depend on the thread schedule.
        let partials: Vec<Vec<f64>> = x
            .data()
            .par_chunks(ROWS_PER_TASK * d)
            .map(|rows| {
                let mut c = vec![0.0; d * d];
                let mut z = vec![0.0; d];
                for row in rows.chunks_exact(d) {
                    standardiser.transform_into(row, &mut z);
                    for a in 0..d {
                        let za = z[a];
                        for (cell, &zb) in c[a * d..a * d + a + 1].iter_mut().zip(&z) {
                            *cell += za * zb;
                        }
                    }
                }
                c
            })
            .collect();
        let mut covariance = vec![0.0; d * d];
        for partial in &partials {
            covariance
                .iter_mut()
                .zip(partial)
                .for_each(|(sum, v)| *sum += v);
        }
        let inv_n = 1.0 / n as f64;
        let matrix = faer::Mat::<f64>::from_fn(d, d, |r, c| {
            let (hi, lo) = if r >= c { (r, c) } else { (c, r) };
            covariance[hi * d + lo] * inv_n
        });
        let eigen = matrix.self_adjoint_eigen(faer::Side::Lower).map_err(|_| {
            LearningError::Numerical("eigendecomposition of the feature covariance")
        })?;
        let values = eigen.S().column_vector();
        let vectors = eigen.U();
        let total: f64 = (0..d).map(|i| values[i].max(0.0)).sum();
        let mut projection = Vec::with_capacity(n_components * d);
        // Eigenvalues come in nondecreasing order: the leading ones are last.
        for a in 0..n_components {
            let j = d - 1 - a;
            let variance = values[j];
            if !(variance > NEGLIGIBLE_VARIANCE * total) {
                return Err(invalid(
                    "exceeds the number of directions in which the training rows vary",
                ));
            }
            let column: Vec<f64> = (0..d).map(|r| vectors[(r, j)]).collect();
            let largest = column
                .iter()
                .copied()
                .fold(0.0_f64, |m, v| if v.abs() > m.abs() { v } else { m });
            let sign = if largest < 0.0 { -1.0 } else { 1.0 };
            let whiten = sign / variance.sqrt();
            projection.extend(column.iter().map(|v| v * whiten));
        }
        Ok(Self::from_parts(standardiser, projection, n_components))
    }

    /// The expansion of its stored parts, with the projection on raw features derived from
    /// them (sizes are checked by [`validate`](Self::validate); with a mismatch the derived map
    /// reads nothing, and a decoded component count is not trusted with an allocation).
    fn from_parts(standardiser: Standardiser, projection: Vec<f64>, n_components: usize) -> Self {
        let d = standardiser.n_features();
        let raw = RawLinear::fold(
            &standardiser,
            |j, a| projection.get(a * d + j).copied().unwrap_or(0.0),
            projection.len(),
            &[0.0; MAX_EXPANSION_COMPONENTS][..n_components.min(MAX_EXPANSION_COMPONENTS)],
        );
        Self {
            standardiser,
            projection,
            n_components,
            raw,
        }
    }

    /// Number of input values `d`.
    pub fn n_inputs(&self) -> usize {
        self.standardiser.means().len()
    }

    /// Number of principal components `k`.
    pub fn n_components(&self) -> usize {
        self.n_components
    }

    /// Number of output values, [`output_len`](Self::output_len) of `d` and `k`.
    pub fn n_outputs(&self) -> usize {
        Self::output_len(self.n_inputs(), self.n_components)
    }

    /// Writes the expansion of `x` (length [`n_inputs`](Self::n_inputs)) into `out` (length
    /// [`n_outputs`](Self::n_outputs)): `x` itself, then `z_a z_b` for `a <= b` in row-major
    /// order of the upper triangle, each component clamped to +-[`COMPONENT_LIMIT`]. The
    /// components are computed on the raw `x`, the standardisation folded into the
    /// projection (equal to the standardised form up to rounding). Does not allocate.
    ///
    /// # Errors
    /// [`LearningError::SizeMismatch`] for a wrong length of `x` or `out`.
    pub fn expand_into(&self, x: &[f64], out: &mut [f64]) -> Result<(), LearningError> {
        self.check_inputs(x.len())?;
        if out.len() != self.n_outputs() {
            return Err(LearningError::SizeMismatch {
                what: "expansion output",
                expected: self.n_outputs(),
                found: out.len(),
            });
        }
        self.expand_sized(x, out);
        Ok(())
    }

    /// Checks that a row has (or a matrix's rows have) `found` values, the expansion's
    /// [`n_inputs`](Self::n_inputs).
    ///
    /// # Errors
    /// [`LearningError::SizeMismatch`] ("expansion input") otherwise.
    pub(crate) fn check_inputs(&self, found: usize) -> Result<(), LearningError> {
        if found != self.n_inputs() {
            return Err(LearningError::SizeMismatch {
                what: "expansion input",
                expected: self.n_inputs(),
                found,
            });
        }
        Ok(())
    }

    /// [`expand_into`](Self::expand_into) for `x` and `out` whose lengths the caller has
    /// checked.
    pub(crate) fn expand_sized(&self, x: &[f64], out: &mut [f64]) {
        let (linear, products) = out.split_at_mut(self.n_inputs());
        linear.copy_from_slice(x);
        let mut z = [0.0; MAX_EXPANSION_COMPONENTS];
        let z = &mut z[..self.n_components];
        self.components_into(x, z);
        Arch::new().dispatch(Products { z, products });
    }

    /// The clamped components `z` of `x` (lengths [`n_inputs`](Self::n_inputs) and
    /// [`n_components`](Self::n_components), checked by the caller): the factors of the
    /// products [`expand_into`](Self::expand_into) writes.
    pub(crate) fn components_into(&self, x: &[f64], z: &mut [f64]) {
        self.raw.apply_into(x, z);
        for za in z.iter_mut() {
            *za = za.clamp(-COMPONENT_LIMIT, COMPONENT_LIMIT);
        }
    }

    /// The expansions of every row of `x`, row-major (`n x n_outputs`), in parallel.
    ///
    /// # Errors
    /// [`LearningError::SizeMismatch`] when `x` does not have [`n_inputs`](Self::n_inputs)
    /// features.
    pub fn expand_rows(&self, x: &Features<'_>) -> Result<Vec<f64>, LearningError> {
        self.check_inputs(x.n_features())?;
        let (d, m) = (self.n_inputs(), self.n_outputs());
        let mut out = vec![0.0; x.n_samples() * m];
        out.par_chunks_mut(m)
            .zip(x.data().par_chunks(d))
            .for_each(|(o, row)| self.expand_sized(row, o));
        Ok(out)
    }

    /// Checks the stored parts: a valid standardiser, `1 <= k <= min(d, 64)`, a `k x d`
    /// projection of finite numbers.
    ///
    /// # Errors
    /// [`LearningError::InvalidParameter`] or [`LearningError::SizeMismatch`] naming the part.
    pub fn validate(&self) -> Result<(), LearningError> {
        self.standardiser.validate()?;
        let d = self.n_inputs();
        if self.n_components == 0 || self.n_components > MAX_EXPANSION_COMPONENTS.min(d) {
            return Err(LearningError::InvalidParameter {
                name: "expansion components",
                value: self.n_components.to_string(),
                reason: "must be at least 1 and at most the number of features (and 64)",
            });
        }
        if self.projection.len() != self.n_components * d {
            return Err(LearningError::SizeMismatch {
                what: "expansion projection",
                expected: self.n_components * d,
                found: self.projection.len(),
            });
        }
        if !self.projection.iter().all(|v| v.is_finite()) {
            return Err(LearningError::InvalidParameter {
                name: "expansion projection",
                value: "non-finite".into(),
                reason: "every entry must be finite",
            });
        }
        Ok(())
    }
}

/// `z_a z_b` for `a <= b` into `products`, in row-major order of the upper triangle, run by
/// `pulp` on the SIMD vectors of the instruction set it found.
struct Products<'a> {
    z: &'a [f64],
    products: &'a mut [f64],
}

impl WithSimd for Products<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, simd: S) {
        let Products { z, products } = self;
        let mut rest = products;
        for (a, &za) in z.iter().enumerate() {
            let (row, tail) = rest.split_at_mut(z.len() - a);
            rest = tail;
            let (row_vectors, row_tail) = S::as_mut_simd_f64s(row);
            let (z_vectors, z_tail) = S::as_simd_f64s(&z[a..]);
            let za_vector = simd.splat_f64s(za);
            for (p, &zb) in row_vectors.iter_mut().zip(z_vectors) {
                *p = simd.mul_f64s(za_vector, zb);
            }
            for (p, &zb) in row_tail.iter_mut().zip(z_tail) {
                *p = za * zb;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn rows(n: usize, d: usize, seed: u64) -> Vec<f64> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut out = Vec::with_capacity(n * d);
        for _ in 0..n {
            let t: f64 = rng.random_range(-1.0..1.0);
            for j in 0..d {
                out.push(3.0 * t * (j as f64 + 1.0) + rng.random_range(-0.5..0.5) + 10.0);
            }
        }
        out
    }

    #[test]
    fn components_are_white_and_products_follow_them() {
        let (n, d, k) = (2000, 5, 3);
        let data = rows(n, d, 1);
        let x = Features::new(&data, d).unwrap();
        let e = QuadraticExpansion::fit(&x, k).unwrap();
        assert_eq!(e.n_outputs(), 5 + 6);
        let out = e.expand_rows(&x).unwrap();
        // z_a^2 are the products at positions 0, 3, 5 of the upper triangle: mean 1.
        for (a, pos) in [0usize, 3, 5].into_iter().enumerate() {
            let mean: f64 = out.chunks_exact(11).map(|r| r[d + pos]).sum::<f64>() / n as f64;
            assert!((mean - 1.0).abs() < 1e-9, "component {a}: {mean}");
        }
        // The linear part is the input itself.
        assert_eq!(&out[..d], &data[..d]);
        // Deterministic: the same fit twice.
        assert_eq!(QuadraticExpansion::fit(&x, k).unwrap(), e);
        e.validate().unwrap();
    }

    #[test]
    fn an_atypical_row_gives_bounded_products() {
        let (n, d, k) = (2000, 5, 3);
        let data = rows(n, d, 3);
        let x = Features::new(&data, d).unwrap();
        let e = QuadraticExpansion::fit(&x, k).unwrap();
        // A row far outside the training rows: its components are many deviations out.
        let far = [1000.0, -500.0, 800.0, 0.0, 300.0];
        let mut out = vec![0.0; e.n_outputs()];
        e.expand_into(&far, &mut out).unwrap();
        let limit = COMPONENT_LIMIT * COMPONENT_LIMIT;
        assert!(out[d..].iter().all(|v| v.abs() <= limit), "{:?}", &out[d..]);
        assert!(
            out[d..].iter().any(|v| v.abs() == limit),
            "no component was clamped"
        );
        assert_eq!(&out[..d], &far);
    }

    #[test]
    fn bad_sizes_and_settings_are_errors() {
        let data = rows(50, 4, 2);
        let x = Features::new(&data, 4).unwrap();
        assert!(QuadraticExpansion::fit(&x, 0).is_err());
        assert!(QuadraticExpansion::fit(&x, 5).is_err());
        let e = QuadraticExpansion::fit(&x, 2).unwrap();
        let mut out = vec![0.0; e.n_outputs()];
        assert!(e.expand_into(&[1.0; 3], &mut out).is_err());
        assert!(e.expand_into(&[1.0; 4], &mut out[1..]).is_err());
        // A constant column adds no direction of variance.
        let flat: Vec<f64> = (0..40).flat_map(|i| [i as f64, 1.0]).collect();
        let x = Features::new(&flat, 2).unwrap();
        assert!(QuadraticExpansion::fit(&x, 2).is_err());
        let mut tampered = e.clone();
        tampered.projection[0] = f64::NAN;
        assert!(tampered.validate().is_err());
        tampered.projection.pop();
        assert!(tampered.validate().is_err());
    }
}
