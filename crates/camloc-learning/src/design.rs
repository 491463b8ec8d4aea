//! Design matrices read row by row: the rows of a [`Features`] as they are, or expanded by a
//! [`QuadraticExpansion`] as they are read, so that a fit on expanded features never holds
//! them whole beside the solver's own copy of the design matrix.

use crate::{Features, LearningError, QuadraticExpansion};

/// The rows a model is fitted on, produced one at a time: a [`Features`] matrix, optionally
/// expanded row by row by a [`QuadraticExpansion`].
#[derive(Clone, Copy, Debug)]
pub struct DesignRows<'a> {
    x: Features<'a>,
    expansion: Option<&'a QuadraticExpansion>,
}

impl<'a> DesignRows<'a> {
    /// The rows of `x` as they are.
    pub fn plain(x: Features<'a>) -> Self {
        Self { x, expansion: None }
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
        })
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
        match self.expansion {
            None => self.x.rows().enumerate().for_each(|(i, row)| visit(i, row)),
            Some(e) => {
                let mut buffer = vec![0.0; e.n_outputs()];
                for (i, row) in self.x.rows().enumerate() {
                    e.expand_sized(row, &mut buffer);
                    visit(i, &buffer);
                }
            }
        }
    }
}
