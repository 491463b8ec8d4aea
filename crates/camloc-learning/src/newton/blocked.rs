//! Products of the `n x D` design matrix `X` with thin matrices, blocked over the samples:
//! `X V` (`n x D` times `D x K`: logits, and the first half of a Hessian-vector product) and
//! `X^T M` (`D x n` times `n x K`: gradients, and the second half), at close to the
//! machine's GEMM rate.
//!
//! The samples are split into tasks of [`ROWS_PER_TASK`] rows (run in parallel, each
//! summing into its own `D x K` partial, the partials then added in task order, so that
//! results do not depend on the thread schedule), and each task into chunks of
//! [`CHUNK_ROWS`] rows whose slice of `X` stays in the core's cache between the two
//! halves of a fused Hessian-vector product ([`BlockedProducts::hessian_product`]): `X` is
//! read from memory once per product instead of twice, and the per-sample Jacobians are
//! applied in between without storing anything per sample. A generated design matrix
//! (module `design_matrix`) forms each chunk in its thread's buffer when it is read, and both
//! halves of a fused product read it there.
//!
//! The kernels keep a register tile of `TILE_ROWS` rows (of `X`, or of `X^T`) by
//! `TILE_VECTORS` SIMD vectors of classes, with the instruction set chosen at run time
//! (`pulp`, safe code); classes are padded with zeros to whole vectors. `X V` walks the
//! columns of `X` in panels of [`PANEL_COLUMNS`], so that few memory streams are open at
//! once (the columns of a column-major `X` are `n` apart). Sums over samples are formed per
//! chunk, then per task, then over tasks.

use std::ops::Range;

use pulp::{Arch, Simd, WithSimd};
use rayon::prelude::*;

use super::design_matrix::{ChunkView, DesignMatrix};
use super::kernels::ROWS_PER_TASK;

/// Rows per chunk: the chunk's slice of `X` (`CHUNK_ROWS x D`, 300 kB for `D = 75`) stays
/// in L2 between the two halves of a product. Measured best among 64..512 on a 2-core
/// AVX2/AVX-512 machine; it divides [`ROWS_PER_TASK`].
pub(super) const CHUNK_ROWS: usize = 512;
/// Columns of `X` per pass of the `X V` kernel. Measured best among 8, 16, 32 and 75.
const PANEL_COLUMNS: usize = 16;
/// Rows of the register tile (samples for `X V`, features for `X^T M`).
const TILE_ROWS: usize = 3;
/// SIMD vectors of classes in the register tile: 3 x 3 accumulators, 3 right-hand vectors
/// and a broadcast fit the 16 vector registers of AVX2.
const TILE_VECTORS: usize = 3;

/// The instruction set, the class padding and the work buffers of the blocked products,
/// allocated once per fit.
#[derive(Debug)]
pub(super) struct BlockedProducts {
    arch: Arch,
    /// `K` rounded up to a whole number of SIMD vectors.
    padded: usize,
    /// `D x padded` row-major right-hand matrix of `X V` (`V^T`, zero-padded).
    weights: Vec<f64>,
    /// Per task, `CHUNK_ROWS x padded` row-major: one chunk's rows of `X V`, or of `M`.
    chunks: Vec<f64>,
    /// Per task, `D x padded` row-major partial sums of `X^T M`.
    partials: Vec<f64>,
}

/// [`Simd::F64_LANES`] of the instruction set `pulp` chose.
struct Lanes;

impl WithSimd for Lanes {
    type Output = usize;

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) -> usize {
        S::F64_LANES
    }
}

impl BlockedProducts {
    /// Buffers for `n` samples, `dim = D` design columns and `k` classes.
    pub(super) fn new(n: usize, dim: usize, k: usize) -> Self {
        let arch = Arch::new();
        let padded = k.next_multiple_of(arch.dispatch(Lanes).max(1));
        let tasks = n.div_ceil(ROWS_PER_TASK);
        Self {
            arch,
            padded,
            weights: vec![0.0; dim * padded],
            chunks: vec![0.0; tasks * CHUNK_ROWS * padded],
            partials: vec![0.0; tasks * dim * padded],
        }
    }

    /// `weights = params^T`, padded, for `params` `D x K` class-major.
    fn load_weights(&mut self, dim: usize, params: &[f64]) {
        let padded = self.padded;
        for (class, column) in params.chunks_exact(dim).enumerate() {
            for (a, &v) in column.iter().enumerate() {
                debug_assert!(
                    a * padded + class < self.weights.len(),
                    "weight ({a}, {class})"
                );
                self.weights[a * padded + class] = v;
            }
        }
    }

    /// `out = params^T X^T` (`K x n`, each sample's `K` values together): the logits of
    /// every sample for parameters `params` (`D x K` class-major).
    pub(super) fn logits(&mut self, x: &DesignMatrix, params: &[f64], out: &mut [f64]) {
        let dim = self.weights.len() / self.padded;
        let k = params.len() / dim.max(1);
        self.load_weights(dim, params);
        let (padded, weights) = (self.padded, &self.weights);
        let kernels = self.kernels();
        out.par_chunks_mut(ROWS_PER_TASK * k)
            .zip(self.chunks.par_chunks_mut(CHUNK_ROWS * padded))
            .enumerate()
            .for_each(|(task, (out, chunk))| {
                for (c, out) in out.chunks_mut(CHUNK_ROWS * k).enumerate() {
                    let rows = out.len() / k;
                    let first = task * ROWS_PER_TASK + c * CHUNK_ROWS;
                    let chunk = &mut chunk[..rows * padded];
                    x.with_chunk(first, rows, dim, |view| {
                        kernels.times_weights(view, weights, chunk)
                    });
                    for (o, s) in out.chunks_exact_mut(k).zip(chunk.chunks_exact(padded)) {
                        o.copy_from_slice(&s[..k]);
                    }
                }
            });
    }

    /// `out = X^T M^T` as a `D x K` class-major matrix (`out[k * D + a] = sum_i m_ki x_ia`)
    /// for the `K x n` matrix `M` whose column `i` `values(i, column)` writes (`K` values
    /// for row `i`, called once per row): the gradient of the loss for residuals `M`, made
    /// as the rows are read.
    pub(super) fn transpose_product(
        &mut self,
        x: &DesignMatrix,
        values: impl Fn(usize, &mut [f64]) + Sync,
        out: &mut [f64],
    ) {
        let dim = self.weights.len() / self.padded;
        let k = out.len() / dim.max(1);
        let n = x.n_rows();
        let padded = self.padded;
        let kernels = self.kernels();
        self.chunks
            .par_chunks_mut(CHUNK_ROWS * padded)
            .zip(self.partials.par_chunks_mut(dim * padded))
            .enumerate()
            .for_each(|(task, (chunk, partial))| {
                partial.fill(0.0);
                let rows_of_task = task_rows(task, n);
                for first in rows_of_task.clone().step_by(CHUNK_ROWS) {
                    let rows = CHUNK_ROWS.min(rows_of_task.end - first);
                    let chunk = &mut chunk[..rows * padded];
                    for (r, s) in chunk.chunks_exact_mut(padded).enumerate() {
                        values(first + r, &mut s[..k]);
                        s[k..].fill(0.0);
                    }
                    x.with_chunk(first, rows, dim, |view| {
                        kernels.accumulate_transposed(view, chunk, &mut *partial)
                    });
                }
            });
        self.sum_partials(dim, k, out);
    }

    /// `out = X^T [J_i (V^T x_i)]_i` as a `D x K` class-major matrix, for `v` `D x K`
    /// class-major: the loss part of a Hessian-vector product, summed over the rows of every
    /// `task_stride`-th task of [`ROWS_PER_TASK`] rows (every row for 1); returns the number
    /// of rows summed. `jacobian(i, s)` replaces the `K` values `s = V^T x_i` of sample `i`
    /// by `J_i s`. Each chunk's slice of `X` is used by both products while it is in cache.
    pub(super) fn hessian_product(
        &mut self,
        x: &DesignMatrix,
        v: &[f64],
        jacobian: impl Fn(usize, &mut [f64]) + Sync,
        task_stride: usize,
        out: &mut [f64],
    ) -> usize {
        let dim = self.weights.len() / self.padded;
        let k = v.len() / dim.max(1);
        let n = x.n_rows();
        self.load_weights(dim, v);
        let (padded, weights) = (self.padded, &self.weights);
        let kernels = self.kernels();
        self.chunks
            .par_chunks_mut(CHUNK_ROWS * padded)
            .zip(self.partials.par_chunks_mut(dim * padded))
            .enumerate()
            .for_each(|(task, (chunk, partial))| {
                partial.fill(0.0);
                if task % task_stride != 0 {
                    return;
                }
                let rows_of_task = task_rows(task, n);
                for first in rows_of_task.clone().step_by(CHUNK_ROWS) {
                    let rows = CHUNK_ROWS.min(rows_of_task.end - first);
                    let chunk = &mut chunk[..rows * padded];
                    x.with_chunk(first, rows, dim, |view| {
                        kernels.times_weights(view, weights, &mut *chunk);
                        for (i, s) in chunk.chunks_exact_mut(padded).enumerate() {
                            jacobian(first + i, &mut s[..k]);
                        }
                        kernels.accumulate_transposed(view, chunk, &mut *partial);
                    });
                }
            });
        self.sum_partials(dim, k, out);
        (0..n.div_ceil(ROWS_PER_TASK))
            .step_by(task_stride)
            .map(|task| task_rows(task, n).len())
            .sum()
    }

    /// The kernels with this instruction set and class padding.
    fn kernels(&self) -> Kernels {
        Kernels {
            arch: self.arch,
            padded: self.padded,
        }
    }

    /// `out[k * D + a] = sum over tasks of partial[a][k]`, in task order.
    fn sum_partials(&self, dim: usize, k: usize, out: &mut [f64]) {
        out.fill(0.0);
        for partial in self.partials.chunks_exact(dim * self.padded) {
            for (a, row) in partial.chunks_exact(self.padded).enumerate() {
                for (class, &value) in row[..k].iter().enumerate() {
                    debug_assert!(class * dim + a < out.len(), "parameter ({class}, {a})");
                    out[class * dim + a] += value;
                }
            }
        }
    }
}

/// `count` rows of a design-matrix chunk.
#[derive(Clone, Copy)]
struct Rows<'a> {
    view: ChunkView<'a>,
    count: usize,
}

impl<'a> Rows<'a> {
    /// Column `a` of these rows.
    #[inline(always)]
    fn column(&self, a: usize) -> &'a [f64] {
        self.view.column(a, self.count)
    }
}

/// The rows of task `task` of a pass over `n` rows ([`ROWS_PER_TASK`] each, the last one
/// shorter).
fn task_rows(task: usize, n: usize) -> Range<usize> {
    task * ROWS_PER_TASK..n.min((task + 1) * ROWS_PER_TASK)
}

/// The two products on chunks of a design matrix, with the instruction set and the class
/// padding.
#[derive(Clone, Copy)]
struct Kernels {
    arch: Arch,
    padded: usize,
}

impl Kernels {
    /// `out = X_rows W` for the rows of `view` ([`Kind::TimesWeights`]).
    fn times_weights(self, view: ChunkView<'_>, weights: &[f64], out: &mut [f64]) {
        let product = Product::new(Kind::TimesWeights, view, weights, self.padded, out);
        self.arch.dispatch(product);
    }

    /// `sums += X_rows^T M` for the rows of `view` ([`Kind::AccumulateTransposed`]).
    fn accumulate_transposed(self, view: ChunkView<'_>, m: &[f64], sums: &mut [f64]) {
        let product = Product::new(Kind::AccumulateTransposed, view, m, self.padded, sums);
        self.arch.dispatch(product);
    }
}

/// Which product a [`Product`] computes.
#[derive(Clone, Copy)]
enum Kind {
    /// `out = X_rows W`: `out` row-major with `padded` columns (one row per row of `rows`),
    /// the operand `W` the `D x padded` row-major weights.
    TimesWeights,
    /// `out += X_rows^T M`: the operand `M` row-major with `padded` columns (one row per row
    /// of `rows`), `out` the `D x padded` row-major partial sums.
    AccumulateTransposed,
}

/// One blocked product of rows of `X` with a thin matrix, run with the instruction set
/// `pulp` chose.
struct Product<'a> {
    kind: Kind,
    rows: Rows<'a>,
    operand: &'a [f64],
    padded: usize,
    out: &'a mut [f64],
}

impl<'a> Product<'a> {
    /// The product `kind` of the rows of `view` with `operand`, into `out` (both with
    /// `padded` columns; the number of rows is that of `out` or of `operand`, whichever has
    /// one row per sample).
    fn new(
        kind: Kind,
        view: ChunkView<'a>,
        operand: &'a [f64],
        padded: usize,
        out: &'a mut [f64],
    ) -> Self {
        let per_sample = match kind {
            Kind::TimesWeights => out.len(),
            Kind::AccumulateTransposed => operand.len(),
        };
        let count = per_sample / padded.max(1);
        let rows = Rows { view, count };
        Self {
            kind,
            rows,
            operand,
            padded,
            out,
        }
    }
}

impl WithSimd for Product<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, simd: S) {
        let Self {
            kind,
            rows,
            operand,
            padded,
            out,
        } = self;
        let vectors = padded / S::F64_LANES;
        let operand = S::as_simd_f64s(operand).0;
        let out = S::as_mut_simd_f64s(out).0;
        match kind {
            Kind::TimesWeights => {
                let dim = operand.len() / vectors.max(1);
                for start in (0..dim).step_by(PANEL_COLUMNS) {
                    let columns = start..(start + PANEL_COLUMNS).min(dim);
                    let out = &mut *out;
                    let mut panel = Panel {
                        rows,
                        columns,
                        weights: operand,
                        out,
                    };
                    over_tile_columns(simd, vectors, &mut panel);
                }
            }
            Kind::AccumulateTransposed => {
                let mut sums = Sums {
                    rows,
                    m: operand,
                    sums: out,
                };
                over_tile_columns(simd, vectors, &mut sums);
            }
        }
    }
}

/// `X V` on one panel of columns of `X` (see [`Tile::times_weights`]).
struct Panel<'a, 'b, S: Simd> {
    rows: Rows<'a>,
    columns: Range<usize>,
    weights: &'a [S::f64s],
    out: &'b mut [S::f64s],
}

impl<S: Simd> TileColumn<S> for Panel<'_, '_, S> {
    #[inline(always)]
    fn run<const VB: usize>(&mut self, tile: Tile<S>) {
        tile.times_weights::<VB>(self.rows, self.columns.clone(), self.weights, self.out);
    }
}

/// `X^T M` into the partial sums (see [`Tile::accumulate`]).
struct Sums<'a, 'b, S: Simd> {
    rows: Rows<'a>,
    m: &'a [S::f64s],
    sums: &'b mut [S::f64s],
}

impl<S: Simd> TileColumn<S> for Sums<'_, '_, S> {
    #[inline(always)]
    fn run<const VB: usize>(&mut self, tile: Tile<S>) {
        tile.accumulate::<VB>(self.rows, self.m, self.sums);
    }
}

/// A kernel that runs one column of register tiles at a time.
trait TileColumn<S: Simd> {
    /// Runs the tiles of `VB` SIMD vectors of classes from `tile.first_vector`.
    fn run<const VB: usize>(&mut self, tile: Tile<S>);
}

/// Runs `kernel` over rows of `vectors` SIMD vectors of classes, [`TILE_VECTORS`] at a time
/// (fewer for the last column).
#[inline(always)]
fn over_tile_columns<S: Simd>(simd: S, vectors: usize, kernel: &mut impl TileColumn<S>) {
    let mut first_vector = 0;
    while first_vector < vectors {
        let tile = Tile {
            simd,
            vectors,
            first_vector,
        };
        let width = (vectors - first_vector).min(TILE_VECTORS);
        match width {
            1 => kernel.run::<1>(tile),
            2 => kernel.run::<2>(tile),
            _ => kernel.run::<TILE_VECTORS>(tile),
        }
        first_vector += width;
    }
}

/// A column of register tiles: `VB` SIMD vectors of classes from `first_vector`, in rows
/// that are `vectors` vectors wide.
#[derive(Clone, Copy)]
struct Tile<S> {
    simd: S,
    vectors: usize,
    first_vector: usize,
}

impl<S: Simd> Tile<S> {
    /// `X V` on the columns `columns` of `X` (the first panel overwrites `out`, later ones
    /// add to it), `TILE_ROWS` rows at a time.
    #[inline(always)]
    fn times_weights<const VB: usize>(
        self,
        rows: Rows<'_>,
        columns: Range<usize>,
        weights: &[S::f64s],
        out: &mut [S::f64s],
    ) {
        let mut r = 0;
        while r + TILE_ROWS <= rows.count {
            self.times_weights_block::<TILE_ROWS, VB>(rows, &columns, r, weights, out);
            r += TILE_ROWS;
        }
        while r < rows.count {
            self.times_weights_block::<1, VB>(rows, &columns, r, weights, out);
            r += 1;
        }
    }

    /// One `RB x VB` tile of `X V`: rows `r..r + RB` of `rows`.
    #[inline(always)]
    fn times_weights_block<const RB: usize, const VB: usize>(
        self,
        rows: Rows<'_>,
        columns: &Range<usize>,
        r: usize,
        weights: &[S::f64s],
        out: &mut [S::f64s],
    ) {
        let simd = self.simd;
        let (vectors, first_vector) = (self.vectors, self.first_vector);
        let mut acc = [[simd.splat_f64s(0.0); VB]; RB];
        if columns.start > 0 {
            for (rr, acc) in acc.iter_mut().enumerate() {
                acc.copy_from_slice(&out[(r + rr) * vectors + first_vector..][..VB]);
            }
        }
        for a in columns.clone() {
            let x = &rows.column(a)[r..][..RB];
            let w = &weights[a * vectors + first_vector..][..VB];
            for (acc, &xv) in acc.iter_mut().zip(x) {
                let xv = simd.splat_f64s(xv);
                for (acc, &wv) in acc.iter_mut().zip(w) {
                    *acc = simd.mul_add_f64s(xv, wv, *acc);
                }
            }
        }
        for (rr, acc) in acc.iter().enumerate() {
            out[(r + rr) * vectors + first_vector..][..VB].copy_from_slice(acc);
        }
    }

    /// `sums += X^T M` over `rows`, `TILE_ROWS` features at a time.
    #[inline(always)]
    fn accumulate<const VB: usize>(self, rows: Rows<'_>, m: &[S::f64s], sums: &mut [S::f64s]) {
        let dim = sums.len() / self.vectors.max(1);
        let mut a = 0;
        while a + TILE_ROWS <= dim {
            self.accumulate_block::<TILE_ROWS, VB>(rows, a, m, sums);
            a += TILE_ROWS;
        }
        while a < dim {
            self.accumulate_block::<1, VB>(rows, a, m, sums);
            a += 1;
        }
    }

    /// One `RB x VB` tile of `X^T M`: features `a..a + RB`, summed over `rows` in
    /// registers, then added to `sums`.
    #[inline(always)]
    fn accumulate_block<const RB: usize, const VB: usize>(
        self,
        rows: Rows<'_>,
        a: usize,
        m: &[S::f64s],
        sums: &mut [S::f64s],
    ) {
        let simd = self.simd;
        let (vectors, first_vector) = (self.vectors, self.first_vector);
        let mut acc = [[simd.splat_f64s(0.0); VB]; RB];
        let columns: [&[f64]; RB] = std::array::from_fn(|ra| rows.column(a + ra));
        for i in 0..rows.count {
            let mv = &m[i * vectors + first_vector..][..VB];
            for (acc, column) in acc.iter_mut().zip(&columns) {
                let xv = simd.splat_f64s(column[i]);
                for (acc, &v) in acc.iter_mut().zip(mv) {
                    *acc = simd.mul_add_f64s(xv, v, *acc);
                }
            }
        }
        for (ra, acc) in acc.iter().enumerate() {
            let sums = &mut sums[(a + ra) * vectors + first_vector..][..VB];
            for (s, &v) in sums.iter_mut().zip(acc) {
                *s = simd.add_f64s(*s, v);
            }
        }
    }
}
