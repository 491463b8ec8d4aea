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

use pulp::{Arch, Simd, WithSimd};
use rayon::prelude::*;

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

/// Rows of a column-major matrix formed at a time, in parallel within the block
/// (`fill_columns`).
const BUILD_BLOCK_ROWS: usize = 1 << 15;

thread_local! {
    /// Each thread's buffer for the chunks of generated design matrices.
    static CHUNK_BUFFER: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
}

/// Where each sample's row is stored in the design matrix: in the input order, or spread by
/// the golden-ratio permutation under which stored row `r` holds input row `r b mod n` (`b`
/// the integer nearest `0.618 n` that is coprime to `n`): every block of consecutive stored
/// rows is then an evenly spread sample of the input rows (which come grouped by clip,
/// subject and augmentation), so that the blocks of rows a subsampled product reads
/// represent the whole data. Rows in image pairs (input rows `i` and `i + n/2`) are spread
/// as pairs, each pair stored in two adjacent rows (an even one and the next), so that a
/// block of an even number of rows starting at an even row holds whole pairs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct RowOrder {
    /// The units spread: rows, or pairs of rows.
    units: usize,
    /// `b^-1 mod units`: input unit `i` is stored as unit `i b^-1 mod units` (1: the input
    /// order).
    multiplier: usize,
    /// `b`: stored unit `r` holds input unit `r b mod units` (1: the input order).
    inverse: usize,
    /// The units are pairs of rows (input rows `i` and `i + units`).
    pairs: bool,
}

impl RowOrder {
    /// The input order of `n` rows.
    pub(super) fn input(n: usize) -> Self {
        Self {
            units: n,
            multiplier: 1,
            inverse: 1,
            pairs: false,
        }
    }

    /// The golden-ratio spread of `n` rows (the input order for `n <= 2`).
    pub(super) fn spread(n: usize) -> Self {
        let golden = 0.5 * (5f64.sqrt() - 1.0);
        let mut b = ((n as f64 * golden).round() as usize).max(1);
        while gcd(b, n) != 1 {
            b += 1;
        }
        Self {
            units: n,
            multiplier: inverse_modulo(b, n),
            inverse: b % n.max(1),
            pairs: false,
        }
    }

    /// The golden-ratio spread of the `n / 2` image pairs of `n` rows (`n` even; input rows
    /// `i` and `i + n/2` are stored as rows `2 q` and `2 q + 1`, `q` the pair's place in the
    /// spread).
    pub(super) fn spread_pairs(n: usize) -> Self {
        Self {
            pairs: true,
            ..Self::spread(n / 2)
        }
    }

    /// About `m` evenly spaced stored rows (`m < n`), in increasing order: rows `j n / m`;
    /// with image pairs, both rows of `m / 2` (at least one) evenly spaced pairs, so that the
    /// rows hold each other's images as the whole set does.
    pub(super) fn spaced(&self, m: usize) -> Vec<usize> {
        if self.pairs {
            let pairs = (m / 2).max(1);
            (0..pairs)
                .flat_map(|j| {
                    let q = j * self.units / pairs;
                    [2 * q, 2 * q + 1]
                })
                .collect()
        } else {
            (0..m).map(|j| j * self.units / m).collect()
        }
    }

    /// The stored row of input row `i` (`i < n`).
    pub(super) fn position(&self, i: usize) -> usize {
        if self.pairs {
            let (half, unit) = (i / self.units, i % self.units);
            2 * times_modulo(unit, self.multiplier, self.units) + half
        } else {
            times_modulo(i, self.multiplier, self.units)
        }
    }

    /// The input row stored as row `r` (`r < n`).
    pub(super) fn input_row(&self, r: usize) -> usize {
        if self.pairs {
            times_modulo(r / 2, self.inverse, self.units) + (r % 2) * self.units
        } else {
            times_modulo(r, self.inverse, self.units)
        }
    }
}

/// `i m mod n` (`i` itself for `m = 1`).
fn times_modulo(i: usize, m: usize, n: usize) -> usize {
    if m == 1 {
        i
    } else {
        ((i as u128 * m as u128) % n as u128) as usize
    }
}

/// Greatest common divisor (`gcd(a, 0) = a`).
fn gcd(mut a: usize, mut b: usize) -> usize {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// `b^-1 mod n` for `b` coprime to `n` (1 for `n <= 1`), by the extended Euclidean algorithm.
fn inverse_modulo(b: usize, n: usize) -> usize {
    let (mut r0, mut r1) = (n as i128, (b % n.max(1)) as i128);
    let (mut t0, mut t1) = (0i128, 1i128);
    while r1 != 0 {
        let q = r0 / r1;
        (r0, r1) = (r1, r0 - q * r1);
        (t0, t1) = (t1, t0 - q * t1);
    }
    t0.rem_euclid(n.max(1) as i128) as usize
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
    /// Mean and reciprocal scale of each product column, in the expansion's order.
    product_means: Vec<f64>,
    product_inverse_scales: Vec<f64>,
}

impl DesignMatrix {
    /// The design matrix of `rows` standardised by `standardiser` (fitted on those rows),
    /// input row `i` stored as row `order.position(i)`.
    pub(super) fn new(rows: &DesignRows<'_>, standardiser: &Standardiser, order: RowOrder) -> Self {
        let n = rows.n_samples();
        match rows.expansion() {
            Some(expansion) => {
                Self::Generated(GeneratedDesign::new(rows, expansion, standardiser, order))
            }
            None => {
                let d = rows.n_features();
                let mut x = vec![0.0; n * (d + 1)];
                let (means, scales) = (standardiser.means(), standardiser.inverse_scales());
                fill_columns(&mut x, n, d + 1, |r, out| {
                    let (standardised, bias) = out.split_at_mut(d);
                    standardise_row(
                        rows.raw_row(order.input_row(r)),
                        means,
                        &scales,
                        standardised,
                    );
                    bias[0] = 1.0;
                });
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
    /// (`m = rows.len()`), gathered in parallel.
    pub(super) fn gather(&self, rows: &[usize], dim: usize) -> Vec<f64> {
        let mut out = vec![0.0; rows.len() * dim];
        fill_columns(&mut out, rows.len(), dim, |j, values| {
            self.with_chunk(rows[j], 1, dim, |row| {
                for (a, v) in values.iter_mut().enumerate() {
                    *v = row.column(a, 1)[0];
                }
            })
        });
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
    /// expands, input row `i` stored as row `order.position(i)`, formed in parallel.
    fn new(
        rows: &DesignRows<'_>,
        expansion: &QuadraticExpansion,
        standardiser: &Standardiser,
        order: RowOrder,
    ) -> Self {
        let n = rows.n_samples();
        let (inputs, components) = (expansion.n_inputs(), expansion.n_components());
        let width = inputs + components;
        let mut base = vec![0.0; n * width];
        let (means, scales) = (standardiser.means(), standardiser.inverse_scales());
        fill_columns(&mut base, n, width, |r, out| {
            let row = rows.raw_row(order.input_row(r));
            let (standardised, z) = out.split_at_mut(inputs);
            standardise_row(row, means, &scales, standardised);
            expansion.components_into(row, z);
        });
        Self {
            n,
            inputs,
            components,
            base,
            product_means: means[inputs..].to_vec(),
            product_inverse_scales: scales[inputs..].to_vec(),
        }
    }

    /// Writes rows `first..first + count` of `X` into `out` (`count x D` column-major), with
    /// the instruction set chosen at run time so that the product loop is vectorised.
    fn generate(&self, first: usize, count: usize, out: &mut [f64]) {
        Arch::new().dispatch(Generate {
            design: self,
            first,
            count,
            out,
        });
    }
}

/// [`GeneratedDesign::generate`]'s work, compiled for each instruction set.
struct Generate<'a> {
    design: &'a GeneratedDesign,
    first: usize,
    count: usize,
    out: &'a mut [f64],
}

impl WithSimd for Generate<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) {
        let Self {
            design,
            first,
            count,
            out,
        } = self;
        let base_column = |a: usize| &design.base[a * design.n + first..][..count];
        let (input_part, rest) = out.split_at_mut(design.inputs * count);
        for (a, o) in input_part.chunks_exact_mut(count).enumerate() {
            o.copy_from_slice(base_column(a));
        }
        let (product_part, ones) = rest.split_at_mut(rest.len() - count);
        // The pairs `a <= b` in the expansion's order (row-major upper triangle).
        let k = design.components;
        let pairs = (0..k).flat_map(|a| (a..k).map(move |b| (a, b)));
        let outputs = product_part.chunks_exact_mut(count).zip(
            design
                .product_means
                .iter()
                .zip(&design.product_inverse_scales),
        );
        for ((o, (&m, &s)), (a, b)) in outputs.zip(pairs) {
            let (za, zb) = (
                base_column(design.inputs + a),
                base_column(design.inputs + b),
            );
            for ((o, &va), &vb) in o.iter_mut().zip(za).zip(zb) {
                *o = Standardiser::apply(m, s, va * vb);
            }
        }
        ones.fill(1.0);
    }
}

/// Fills the `n`-row, `width`-column column-major matrix `out` row by row, `fill_row(r,
/// values)` writing row `r`'s `width` values: in parallel over the rows of a block of
/// [`BUILD_BLOCK_ROWS`], the block held row-major and then copied into the columns (in
/// parallel over the columns), so that no thread writes across the columns row by row.
fn fill_columns(
    out: &mut [f64],
    n: usize,
    width: usize,
    fill_row: impl Fn(usize, &mut [f64]) + Sync,
) {
    let mut block = vec![0.0; BUILD_BLOCK_ROWS.min(n) * width];
    for first in (0..n).step_by(BUILD_BLOCK_ROWS) {
        let count = BUILD_BLOCK_ROWS.min(n - first);
        let block = &mut block[..count * width];
        block
            .par_chunks_mut(width)
            .enumerate()
            .for_each(|(j, values)| fill_row(first + j, values));
        let block = &*block;
        out.par_chunks_mut(n).enumerate().for_each(|(a, column)| {
            let rows = block.chunks_exact(width);
            for (o, row) in column[first..first + count].iter_mut().zip(rows) {
                *o = row[a];
            }
        });
    }
}

/// Writes the values of `row` standardised by `means` and `inverse_scales` (its leading
/// columns) into `out`.
fn standardise_row(row: &[f64], means: &[f64], inverse_scales: &[f64], out: &mut [f64]) {
    for ((o, &v), (&m, &s)) in out
        .iter_mut()
        .zip(row)
        .zip(means.iter().zip(inverse_scales))
    {
        *o = Standardiser::apply(m, s, v);
    }
}

#[cfg(test)]
mod tests {
    use super::RowOrder;

    /// The spread order is a permutation, and a block of consecutive stored rows holds input
    /// rows from all over the input: the first `n / 8` stored rows hit every eighth of it.
    #[test]
    fn spread_order_is_a_permutation_that_spreads_blocks() {
        for n in [1, 2, 3, 10, 97, 1000, 4096, 10_007, 65_536] {
            let order = RowOrder::spread(n);
            let mut input_of = vec![usize::MAX; n];
            for i in 0..n {
                let r = order.position(i);
                assert!(r < n && input_of[r] == usize::MAX, "n {n}: row {r} twice");
                input_of[r] = i;
            }
            if n >= 64 {
                let mut eighths = [false; 8];
                for &i in &input_of[..n / 8] {
                    eighths[i * 8 / n] = true;
                }
                assert!(eighths.iter().all(|&hit| hit), "n {n}: {eighths:?}");
            }
        }
        assert_eq!(RowOrder::input(5).position(3), 3);
    }

    /// Image pairs are spread as pairs: a permutation whose stored rows `2 q` and `2 q + 1`
    /// hold input rows `i` and `i + n/2`, the pairs spread over the input.
    #[test]
    fn spread_pairs_keeps_each_row_beside_its_image() {
        for n in [2, 4, 10, 194, 2000, 8192] {
            let order = RowOrder::spread_pairs(n);
            let mut seen = vec![false; n];
            for r in 0..n {
                let i = order.input_row(r);
                assert_eq!(order.position(i), r, "n {n}, row {r}");
                assert!(!seen[i], "n {n}: input row {i} twice");
                seen[i] = true;
            }
            for q in 0..n / 2 {
                let (a, b) = (order.input_row(2 * q), order.input_row(2 * q + 1));
                assert_eq!(b, a + n / 2, "n {n}: pair {q}");
            }
            let spaced = order.spaced(n / 3);
            assert!(spaced.windows(2).all(|w| w[0] < w[1]), "n {n}: {spaced:?}");
            for pair in spaced.chunks(2) {
                assert_eq!((pair[0] % 2, pair[1]), (0, pair[0] + 1), "n {n}");
            }
            if n >= 128 {
                let mut eighths = [false; 8];
                for r in 0..n / 8 {
                    eighths[order.input_row(r) % (n / 2) * 8 / (n / 2)] = true;
                }
                assert!(eighths.iter().all(|&hit| hit), "n {n}: {eighths:?}");
            }
        }
    }
}
