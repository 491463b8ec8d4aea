//! Validated input data: a dense row-major feature matrix and class labels.

use crate::LearningError;

/// A borrowed, validated, row-major `n_samples x n_features` matrix of feature values.
///
/// Sample `i` occupies `data[i * n_features .. (i + 1) * n_features]`. Every value is finite
/// (checked by [`Features::new`]); the units are whatever the feature extractor produces.
#[derive(Clone, Copy, Debug)]
pub struct Features<'a> {
    data: &'a [f64],
    n_samples: usize,
    n_features: usize,
}

impl<'a> Features<'a> {
    /// Wraps a row-major buffer of `n_features` values per sample.
    ///
    /// # Errors
    /// [`LearningError::NoFeatures`] if `n_features == 0`, [`LearningError::RaggedFeatures`]
    /// if `data.len()` is not a multiple of `n_features`, [`LearningError::NonFinite`] (with
    /// the row and column) for the first NaN or infinite value. Zero rows are allowed here
    /// (prediction on an empty batch is fine); fitting rejects them.
    pub fn new(data: &'a [f64], n_features: usize) -> Result<Self, LearningError> {
        if n_features == 0 {
            return Err(LearningError::NoFeatures);
        }
        if !data.len().is_multiple_of(n_features) {
            return Err(LearningError::RaggedFeatures {
                len: data.len(),
                n_features,
            });
        }
        check_finite_row(data, 0, n_features)?;
        Ok(Self {
            data,
            n_samples: data.len() / n_features,
            n_features,
        })
    }

    /// Number of samples (rows).
    pub fn n_samples(&self) -> usize {
        self.n_samples
    }

    /// Number of features per sample (columns).
    pub fn n_features(&self) -> usize {
        self.n_features
    }

    /// The whole row-major buffer.
    pub fn data(&self) -> &'a [f64] {
        self.data
    }

    /// The samples, one slice of `n_features` values each, in order.
    pub fn rows(&self) -> std::slice::ChunksExact<'a, f64> {
        self.data.chunks_exact(self.n_features)
    }

    /// Copies the rows whose indices are listed into a new owned row-major buffer.
    /// Indices must be below [`n_samples`](Self::n_samples) (crate-internal callers
    /// guarantee it; out-of-range indices are skipped).
    pub(crate) fn select_rows(&self, indices: &[usize]) -> Vec<f64> {
        let mut out = Vec::with_capacity(indices.len() * self.n_features);
        for &i in indices {
            if let Some(row) = self
                .data
                .get(i * self.n_features..(i + 1) * self.n_features)
            {
                out.extend_from_slice(row);
            }
        }
        out
    }
}

/// Values [`check_finite_row`] checks together before it looks at the next ones.
const FINITE_CHECK_BLOCK: usize = 64;

/// Checks that every value of a row-major block is finite; `first_row` is the row index of
/// the block's first row, used in the error.
pub(crate) fn check_finite_row(
    data: &[f64],
    first_row: usize,
    n_features: usize,
) -> Result<(), LearningError> {
    // A pass without early exit over blocks of values (it vectorises), the position only
    // when it fails.
    let all_finite = data
        .chunks(FINITE_CHECK_BLOCK)
        .all(|block| block.iter().fold(true, |ok, v| ok & v.is_finite()));
    if all_finite {
        return Ok(());
    }
    match data.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(pos) => Err(LearningError::NonFinite {
            row: first_row + pos / n_features,
            column: pos % n_features,
            value: data[pos],
        }),
    }
}

/// Checks labels against the samples and the number of classes.
///
/// # Errors
/// [`LearningError::TooFewClasses`] if `n_classes < 2`, [`LearningError::SizeMismatch`] if
/// there is not one label per sample, [`LearningError::LabelOutOfRange`] for the first label
/// `>= n_classes`.
pub(crate) fn check_labels(
    labels: &[usize],
    n_samples: usize,
    n_classes: usize,
) -> Result<(), LearningError> {
    if n_classes < 2 {
        return Err(LearningError::TooFewClasses { n_classes });
    }
    if labels.len() != n_samples {
        return Err(LearningError::SizeMismatch {
            what: "number of labels (one per sample)",
            expected: n_samples,
            found: labels.len(),
        });
    }
    match labels.iter().position(|&l| l >= n_classes) {
        None => Ok(()),
        Some(row) => Err(LearningError::LabelOutOfRange {
            row,
            label: labels[row],
            n_classes,
        }),
    }
}
