//! Design matrices read row by row: the rows of a [`Features`] as they are, or expanded by a
//! [`QuadraticExpansion`] as they are read, so that a fit on expanded features never holds
//! them whole beside the solver's own copy of the design matrix.

use rayon::prelude::*;

use crate::{Features, LearningError, QuadraticExpansion};

/// Rows [`DesignRows::for_each_block`] makes at a time.
pub(crate) const BLOCK_ROWS: usize = 1024;

/// The rows a model is fitted on, produced one at a time: a [`Features`] matrix, optionally
/// expanded row by row by a [`QuadraticExpansion`].
#[derive(Clone, Copy, Debug)]
pub struct DesignRows<'a> {
    x: Features<'a>,
    expansion: Option<&'a QuadraticExpansion>,
    /// The second half of the rows are images of the first half's, row `i + n/2` of row `i`
    /// ([`in_image_pairs`](Self::in_image_pairs)).
    image_pairs: bool,
}

impl<'a> DesignRows<'a> {
    /// The rows of `x` as they are.
    pub fn plain(x: Features<'a>) -> Self {
        Self {
            x,
            expansion: None,
            image_pairs: false,
        }
    }

    /// These rows, declared to come in image pairs: `n_samples` is even and row `i + n/2`
    /// is the image of row `i` under a symmetry of the problem (for instance the mirror
    /// image of a pose, with the mirrored label), so that the problem, and its exact
    /// optimum, are invariant under it. A fit whose Hessian-vector products read a subsample
    /// of the rows then reads each row with its image, so that its iterates keep the
    /// symmetry as the exact ones do (the products of a subsample that split pairs do not).
    ///
    /// # Errors
    /// [`LearningError::InvalidParameter`] for an odd number of rows.
    pub fn in_image_pairs(self) -> Result<Self, LearningError> {
        if !self.n_samples().is_multiple_of(2) {
            return Err(LearningError::InvalidParameter {
                name: "image pairs",
                value: self.n_samples().to_string(),
                reason: "rows in image pairs must be an even number",
            });
        }
        Ok(Self {
            image_pairs: true,
            ..self
        })
    }

    /// Whether the rows were declared to come in image pairs
    /// ([`in_image_pairs`](Self::in_image_pairs)).
    pub fn has_image_pairs(&self) -> bool {
        self.image_pairs
    }

    /// The rows of `x` expanded by `expansion` as they are read
    /// ([`QuadraticExpansion::expand_into`]).
    ///
    /// # Errors
    /// [`LearningError::SizeMismatch`] when `x` does not have the expansion's
    /// [`n_inputs`](QuadraticExpansion::n_inputs) columns.
    pub fn expanded(
        x: Features<'a>,
        expansion: &'a QuadraticExpansion,
    ) -> Result<Self, LearningError> {
        expansion.check_inputs(x.n_features())?;
        Ok(Self {
            x,
            expansion: Some(expansion),
            image_pairs: false,
        })
    }

    /// The rows of `x`, expanded by `expansion` as they are read when there is one
    /// ([`expanded`](Self::expanded)), else as they are ([`plain`](Self::plain)).
    ///
    /// # Errors
    /// As [`expanded`](Self::expanded).
    pub fn with_expansion(
        x: Features<'a>,
        expansion: Option<&'a QuadraticExpansion>,
    ) -> Result<Self, LearningError> {
        match expansion {
            Some(e) => Self::expanded(x, e),
            None => Ok(Self::plain(x)),
        }
    }

    /// Number of rows (samples).
    pub fn n_samples(&self) -> usize {
        self.x.n_samples()
    }

    /// Number of values per row (the features the model sees).
    pub fn n_features(&self) -> usize {
        self.expansion
            .map_or(self.x.n_features(), QuadraticExpansion::n_outputs)
    }

    /// The expansion the rows go through, if any.
    pub(crate) fn expansion(&self) -> Option<&'a QuadraticExpansion> {
        self.expansion
    }

    /// Row `i` before any expansion (`i < n_samples`).
    pub(crate) fn raw_row(&self, i: usize) -> &'a [f64] {
        let d = self.x.n_features();
        &self.x.data()[i * d..(i + 1) * d]
    }

    /// Calls `visit` with every row in order (row index and its
    /// [`n_features`](Self::n_features) values; expanded rows share one buffer).
    pub fn for_each_row(&self, mut visit: impl FnMut(usize, &[f64])) {
        let Ok(()) = self.try_for_each_row(|i, row| {
            visit(i, row);
            Ok::<(), std::convert::Infallible>(())
        });
    }

    /// [`for_each_row`](Self::for_each_row) until `visit` fails: its first error.
    ///
    /// # Errors
    /// The first error `visit` returns (no row after it is visited).
    pub fn try_for_each_row<E>(
        &self,
        visit: impl FnMut(usize, &[f64]) -> Result<(), E>,
    ) -> Result<(), E> {
        self.for_each_selected(0..self.n_samples(), visit)
    }

    /// [`try_for_each_row`](Self::try_for_each_row) on the rows `selected` names, in its
    /// order (each index below [`n_samples`](Self::n_samples)).
    pub(crate) fn for_each_selected<E>(
        &self,
        selected: impl IntoIterator<Item = usize>,
        mut visit: impl FnMut(usize, &[f64]) -> Result<(), E>,
    ) -> Result<(), E> {
        match self.expansion {
            None => selected
                .into_iter()
                .try_for_each(|i| visit(i, self.raw_row(i))),
            Some(e) => {
                let mut buffer = vec![0.0; e.n_outputs()];
                selected.into_iter().try_for_each(|i| {
                    e.expand_sized(self.raw_row(i), &mut buffer);
                    visit(i, &buffer)
                })
            }
        }
    }

    /// Calls `visit` with the rows `selected` names in blocks of up to [`BLOCK_ROWS`], in
    /// order, each block row-major ([`n_features`](Self::n_features) values per row) and made
    /// in parallel (expanded rows share one buffer).
    pub(crate) fn for_each_block(
        &self,
        selected: impl IntoIterator<Item = usize>,
        mut visit: impl FnMut(&[f64]),
    ) {
        let d = self.n_features();
        let mut indices = Vec::with_capacity(BLOCK_ROWS);
        let mut block = vec![0.0; BLOCK_ROWS * d];
        let mut selected = selected.into_iter();
        loop {
            indices.clear();
            indices.extend(selected.by_ref().take(BLOCK_ROWS));
            if indices.is_empty() {
                break;
            }
            let rows = &mut block[..indices.len() * d];
            rows.par_chunks_mut(d)
                .zip(indices.par_iter())
                .for_each(|(row, &i)| match self.expansion {
                    Some(e) => e.expand_sized(self.raw_row(i), row),
                    None => row.copy_from_slice(self.raw_row(i)),
                });
            visit(rows);
        }
    }
}
