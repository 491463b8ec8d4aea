//! The solver's `n x D` design matrix `X` (standardised features, then a column of ones):
//! stored whole, or, for features expanded by a [`QuadraticExpansion`], generated chunk by
//! chunk from what the products are made of.
//!
//! An expanded row holds the `d` input values and the `k (k + 1) / 2` products `z_a z_b` of
//! its `k` clamped components, so that nearly all of a quadratic design matrix is products
//! (465 of 520 columns for the default model). [`DesignMatrix::Generated`] stores only the
//! standardised inputs and the components (`d + k` values per row, a fifth of the whole)
//! and forms each chunk's standardised products when a product with `X` reads the chunk:
//! the same values to the bit as the stored matrix (the same multiplication and the same
//! standardisation), at a fifth of the memory and of the memory traffic that bounds the
//! products' speed.

use std::cell::RefCell;

use crate::standardise::Standardiser;
use crate::{DesignRows, QuadraticExpansion};

/// Rows `first..` of a column-major matrix whose columns are `stride` apart: a chunk of the
/// design matrix as the blocked kernels read it.
#[derive(Clone, Copy)]
pub(super) struct ChunkView<'a> {
    /// Column-major values; column `a` of the chunk starts at `a * stride + first`.
    pub(super) x: &'a [f64],
    pub(super) stride: usize,
    pub(super) first: usize,
}

impl<'a> ChunkView<'a> {
    /// Column `a` of the chunk, `count` rows.
    #[inline(always)]
    pub(super) fn column(&self, a: usize, count: usize) -> &'a [f64] {
        &self.x[a * self.stride + self.first..][..count]
    }
}

thread_local! {
    /// Each thread's buffer for the chunks of generated design matrices.
    static CHUNK_BUFFER: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
}

/// The design matrix of a fit.
pub(super) enum DesignMatrix {
    /// `n x D` column-major, every value stored.
    Stored { x: Vec<f64>, n: usize },
    /// Quadratic products formed per chunk.
    Generated(GeneratedDesign),
}

/// A quadratic design matrix stored as its inputs and components (see the module doc).
pub(super) struct GeneratedDesign {
    n: usize,
    /// `d`: standardised input columns, the first columns of `X`.
    inputs: usize,
    /// `k` components per row.
    components: usize,
    /// `n x (d + k)` column-major: the standardised inputs, then the clamped components.
    base: Vec<f64>,
    /// Mean and scale of each product column, in the expansion's order.
    product_means: Vec<f64>,
    product_scales: Vec<f64>,
}

impl DesignMatrix {
    /// The design matrix of `rows` standardised by `standardiser` (fitted on those rows).
    pub(super) fn new(rows: &DesignRows<'_>, standardiser: &Standardiser) -> Self {
        let n = rows.n_samples();
        match rows.expansion() {
            Some(expansion) => Self::Generated(GeneratedDesign::new(rows, expansion, standardiser)),
            None => {
                let dim = rows.n_features() + 1;
                let mut x = vec![1.0; n * dim];
                rows.for_each_row(|i, row| put_standardised(row, standardiser, i, n, &mut x));
                Self::Stored { x, n }
            }
        }
    }

    /// Calls `visit` with rows `first..first + count` (`dim = D` columns): a view of the
    /// stored matrix, or the chunk generated into this thread's buffer (kept between calls,
    /// so that a pass over the samples does not allocate; it holds the largest chunk the
    /// thread has generated). `visit` must not read another chunk of a generated matrix.
    pub(super) fn with_chunk<R>(
        &self,
        first: usize,
        count: usize,
        dim: usize,
        visit: impl FnOnce(ChunkView<'_>) -> R,
    ) -> R {
        match self {
            Self::Stored { x, n } => visit(ChunkView {
                x,
                stride: *n,
                first,
            }),
            Self::Generated(g) => CHUNK_BUFFER.with_borrow_mut(|buffer| {
                let len = count * dim;
                if buffer.len() < len {
                    buffer.resize(len, 0.0);
                }
                let out = &mut buffer[..len];
                g.generate(first, count, out);
                visit(ChunkView {
                    x: out,
                    stride: count,
                    first: 0,
                })
            }),
        }
    }

    /// The rows `rows` (indices into the samples) as an `m x D` column-major matrix
    /// (`m = rows.len()`).
    pub(super) fn gather(&self, rows: &[usize], dim: usize) -> Vec<f64> {
        let m = rows.len();
        let mut out = vec![0.0; m * dim];
        for (j, &i) in rows.iter().enumerate() {
            self.with_chunk(i, 1, dim, |row| {
                for (a, o) in out.chunks_exact_mut(m).enumerate() {
                    o[j] = row.column(a, 1)[0];
                }
            });
        }
        out
    }

    /// Number of rows `n` (samples).
    pub(super) fn n_rows(&self) -> usize {
        match self {
            Self::Stored { n, .. } => *n,
            Self::Generated(g) => g.n,
        }
    }

    /// True when the chunks are generated: the whole matrix is never held, so a Hessian
    /// on every row must be assembled from gathered rows.
    pub(super) fn is_generated(&self) -> bool {
        matches!(self, Self::Generated(_))
    }
}

impl GeneratedDesign {
    /// Standardised inputs and clamped components of every row of `rows`, which `expansion`
    /// expands.
    fn new(
        rows: &DesignRows<'_>,
        expansion: &QuadraticExpansion,
        standardiser: &Standardiser,
    ) -> Self {
        let n = rows.n_samples();
        let (inputs, components) = (expansion.n_inputs(), expansion.n_components());
        let width = inputs + components;
        let mut base = vec![0.0; n * width];
        let (means, scales) = (standardiser.means(), standardiser.scales());
        let mut z = vec![0.0; components];
        for (i, row) in rows.raw_rows().enumerate() {
            put_standardised(row, standardiser, i, n, &mut base);
            expansion.components_into(row, &mut z);
            for (a, &za) in z.iter().enumerate() {
                base[(inputs + a) * n + i] = za;
            }
        }
        Self {
            n,
            inputs,
            components,
            base,
            product_means: means[inputs..].to_vec(),
            product_scales: scales[inputs..].to_vec(),
        }
    }

    /// Writes rows `first..first + count` of `X` into `out` (`count x D` column-major).
    fn generate(&self, first: usize, count: usize, out: &mut [f64]) {
        let base_column = |a: usize| &self.base[a * self.n + first..][..count];
        let (input_part, rest) = out.split_at_mut(self.inputs * count);
        for (a, o) in input_part.chunks_exact_mut(count).enumerate() {
            o.copy_from_slice(base_column(a));
        }
        let (product_part, ones) = rest.split_at_mut(rest.len() - count);
        // The pairs `a <= b` in the expansion's order (row-major upper triangle).
        let k = self.components;
        let pairs = (0..k).flat_map(|a| (a..k).map(move |b| (a, b)));
        let outputs = product_part
            .chunks_exact_mut(count)
            .zip(self.product_means.iter().zip(&self.product_scales));
        for ((o, (&m, &s)), (a, b)) in outputs.zip(pairs) {
            let (za, zb) = (base_column(self.inputs + a), base_column(self.inputs + b));
            for ((o, &va), &vb) in o.iter_mut().zip(za).zip(zb) {
                *o = Standardiser::apply(m, s, va * vb);
            }
        }
        ones.fill(1.0);
    }
}

/// Writes the standardised values of `row` (the leading columns `standardiser` knows) as row
/// `i` of the `n`-row column-major matrix `out`.
fn put_standardised(row: &[f64], standardiser: &Standardiser, i: usize, n: usize, out: &mut [f64]) {
    let (means, scales) = (standardiser.means(), standardiser.scales());
    for (a, ((&v, &m), &s)) in row.iter().zip(means).zip(scales).enumerate() {
        out[a * n + i] = Standardiser::apply(m, s, v);
    }
}
