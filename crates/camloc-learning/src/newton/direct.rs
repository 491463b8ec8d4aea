//! The direct direction solver: exact Hessian assembly (packed blocks, see the module
//! documentation of [`newton`](super)), then a Cholesky solve of the Newton system with the
//! singular-direction correction and, if needed, diagonal damping. The other solver,
//! conjugate gradients preconditioned by the last factor, is in the `cg` module.

use faer::MatMut;
use faer::Par;
use faer::dyn_stack::MemStack;
use faer::linalg::cholesky::llt::factor::{LltRegularization, cholesky_in_place};
use faer::linalg::cholesky::llt::solve::solve_in_place;
use faer::prelude::{Reborrow, ReborrowMut};
use rayon::prelude::*;

use super::NewtonProblem;
use super::design_matrix::DesignMatrix;
use crate::{LearningError, Mode};

/// First diagonal damping, relative to the largest diagonal entry, if Cholesky fails.
const FIRST_DAMPING: f64 = 1e-10;
/// Number of damping attempts (each 100 times the previous one) before giving up.
const DAMPING_ATTEMPTS: usize = 8;
/// Feature pairs per tile when the packed blocks are laid out per class pair.
const TRANSPOSE_TILE: usize = 64;

impl NewtonProblem {
    /// Assembles the exact Hessian of `f` at the current parameters into
    /// [`hessian`](Self::hessian) (with a preconditioner on `m` rows, fewer than the
    /// samples, see [`hessian_rows`](Self::hessian_rows): the Hessian of the loss on those
    /// rows scaled by `n / m`, plus the exact ridge term, an approximation used only as a
    /// preconditioner). This is the costliest step of an iteration
    /// ([`hessian_flops`](Self::hessian_flops) flops).
    pub fn assemble_hessian(&mut self) {
        let k = self.n_classes;
        let source = match self.mode {
            Mode::Multinomial => &self.probabilities,
            Mode::OneVsRest => &self.logits,
        };
        for (out, &i) in self.sub_per_sample.chunks_exact_mut(k).zip(&self.sub_rows) {
            out.copy_from_slice(&source[i * k..(i + 1) * k]);
        }
        // A generated design matrix always has gathered rows (`use_preconditioner_rows`).
        let (x, rows, per_sample) = match (&self.x, self.sub_rows.is_empty()) {
            (DesignMatrix::Stored { x, .. }, true) => (&x[..], self.n_samples, &source[..]),
            _ => (
                &self.sub_x[..],
                self.sub_rows.len(),
                &self.sub_per_sample[..],
            ),
        };
        let dim = self.dim;
        let weights_are_zero = self
            .theta
            .chunks_exact(dim)
            .all(|params| params[..dim - 1].iter().all(|&w| w == 0.0));
        match per_sample.get(..self.n_classes) {
            // Same logits for every sample (e.g. the starting point): one Gram matrix.
            Some(shared) if weights_are_zero => {
                self.packed.accumulate_uniform(x, rows, self.mode, shared)
            }
            _ => self
                .packed
                .accumulate(x, rows, self.n_classes, self.mode, per_sample),
        }
        self.unpack_hessian(self.n_samples as f64 / rows as f64);
    }

    /// `direction = -H^-1 grad` (per class block for one-vs-rest), with the singular-direction
    /// correction of the multinomial model and, if needed, diagonal damping.
    pub(super) fn solve_newton_system(&mut self) -> Result<(), LearningError> {
        let p = self.theta.len();
        let dim = self.dim;
        let k = self.n_classes;
        let (block_size, n_blocks) = match self.mode {
            Mode::Multinomial => (p, 1),
            Mode::OneVsRest => (dim, k),
        };
        for (d, g) in self.direction.iter_mut().zip(&self.gradient) {
            *d = -g;
        }
        // Features whose all-classes shift is a null direction of the Hessian.
        let null_features = match (self.mode, self.lambda == 0.0) {
            (Mode::OneVsRest, _) => 0..0,
            (Mode::Multinomial, false) => dim - 1..dim,
            (Mode::Multinomial, true) => 0..dim,
        };
        self.factor_ready = false;
        self.null_shifts.fill(0.0);
        for block in 0..n_blocks {
            let offset = block * block_size;
            let max_diagonal = (offset..offset + block_size)
                .map(|i| self.hessian[i * p + i])
                .fold(0.0, f64::max);
            let mut damping = 0.0;
            let mut attempt = 0;
            loop {
                let factor = &mut self.factor[..block_size * block_size];
                for (c, column) in factor.chunks_exact_mut(block_size).enumerate() {
                    let start = (offset + c) * p + offset;
                    column.copy_from_slice(&self.hessian[start..start + block_size]);
                    debug_assert!(c < column.len(), "diagonal entry {c} of a block column");
                    column[c] += damping;
                }
                for a in null_features.clone() {
                    let mean_curvature = (0..k)
                        .map(|j| self.hessian[(j * dim + a) * p + j * dim + a])
                        .sum::<f64>()
                        / (k * k) as f64;
                    debug_assert!(a < self.null_shifts.len(), "null feature {a}");
                    self.null_shifts[a] = mean_curvature;
                    for j in 0..k {
                        for l in 0..k {
                            factor[(l * dim + a) * block_size + j * dim + a] += mean_curvature;
                        }
                    }
                }
                let mut factor =
                    MatMut::from_column_major_slice_mut(factor, block_size, block_size);
                let stack = MemStack::new(&mut self.cholesky_scratch);
                let result = cholesky_in_place(
                    factor.rb_mut(),
                    LltRegularization::default(),
                    Par::rayon(0),
                    stack,
                    Default::default(),
                );
                if result.is_ok() {
                    solve_in_place(
                        factor.rb(),
                        MatMut::from_column_major_slice_mut(
                            &mut self.direction[offset..offset + block_size],
                            block_size,
                            1,
                        ),
                        Par::rayon(0),
                        stack,
                    );
                    // A damped factor is no exact solve, but still serves truncated CG.
                    self.factor_ready =
                        self.mode == Mode::Multinomial && (damping == 0.0 || self.is_truncated());
                    break;
                }
                if attempt == DAMPING_ATTEMPTS {
                    return Err(LearningError::Singular {
                        iteration: self.iteration + 1,
                        damping,
                    });
                }
                attempt += 1;
                damping = if damping == 0.0 {
                    FIRST_DAMPING * max_diagonal.max(f64::MIN_POSITIVE)
                } else {
                    damping * 100.0
                };
            }
        }
        Ok(())
    }

    /// Expands the packed blocks, times `scale`, into the full symmetric `P x P` Hessian and
    /// adds the ridge curvature `2 lambda` on the weight diagonal.
    ///
    /// The packed values are first laid out per class pair (each pair's `D (D + 1) / 2`
    /// values together, times `scale`). Then, in parallel over the classes `j`, the columns
    /// of class `j` are written: for each class pair holding `j`, in packed order, its block
    /// `G` is unfolded into a dense symmetric `D x D` matrix, copied negated into block
    /// `(l, j)` (the pair's other class `l`) and added into the diagonal block `(j, j)`
    /// (one-vs-rest: its own pair `(j, j)` only), so that every write is a contiguous piece
    /// of a column.
    fn unpack_hessian(&mut self, scale: f64) {
        let dim = self.dim;
        let p = self.theta.len();
        let class_pairs = &self.packed.class_pairs;
        let q = class_pairs.len().max(1);
        let t = self.packed.feature_pairs.len();
        let mut by_pair = vec![0.0; q * t];
        // Transposed a tile of feature pairs at a time, so that the tile stays in cache.
        for first in (0..t).step_by(TRANSPOSE_TILE) {
            let count = TRANSPOSE_TILE.min(t - first);
            let tile = &self.packed.packed[first * q..(first + count) * q];
            for (c, values) in by_pair.chunks_exact_mut(t).enumerate() {
                for (v, row) in values[first..first + count]
                    .iter_mut()
                    .zip(tile.chunks_exact(q))
                {
                    *v = scale * row[c];
                }
            }
        }
        let two_lambda = 2.0 * self.lambda;
        let by_pair = &by_pair;
        self.hessian
            .par_chunks_mut(dim * p)
            .enumerate()
            .for_each(|(j, columns)| {
                columns.fill(0.0);
                let mut dense = vec![0.0; dim * dim];
                for (c, &(x, y)) in class_pairs.iter().enumerate() {
                    if x != j && y != j {
                        continue;
                    }
                    unfold_symmetric(&by_pair[c * t..][..t], dim, &mut dense);
                    let other = if x == j { y } else { x };
                    for (column, g) in columns.chunks_exact_mut(p).zip(dense.chunks_exact(dim)) {
                        for (h, &v) in column[j * dim..][..dim].iter_mut().zip(g) {
                            *h += v;
                        }
                        if other != j {
                            for (h, &v) in column[other * dim..][..dim].iter_mut().zip(g) {
                                *h = -v;
                            }
                        }
                    }
                }
                for (a, column) in columns.chunks_exact_mut(p).enumerate().take(dim - 1) {
                    column[j * dim + a] += two_lambda;
                }
            });
    }
}

/// Writes the symmetric `dim x dim` matrix whose upper triangle, row by row, is `packed`
/// into `dense` (column-major): each packed row `a` is column `a`'s lower part, copied whole,
/// and the upper part is then mirrored from it in tiles of [`TRANSPOSE_TILE`] so that both
/// sides stay in cache.
fn unfold_symmetric(packed: &[f64], dim: usize, dense: &mut [f64]) {
    let mut start = 0;
    for a in 0..dim {
        let len = dim - a;
        dense[a * dim + a..(a + 1) * dim].copy_from_slice(&packed[start..start + len]);
        start += len;
    }
    for tile_a in (0..dim).step_by(TRANSPOSE_TILE) {
        for tile_b in (0..=tile_a).step_by(TRANSPOSE_TILE) {
            for a in tile_a..(tile_a + TRANSPOSE_TILE).min(dim) {
                for b in tile_b..(tile_b + TRANSPOSE_TILE).min(a) {
                    // Column a, row b < a: the entry of column b, row a.
                    dense[a * dim + b] = dense[b * dim + a];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{TRANSPOSE_TILE, unfold_symmetric};

    /// Every entry of the unfolded matrix is its packed value, on both sides of the
    /// diagonal, for sizes below, at and across several tiles.
    #[test]
    fn unfolded_matrix_is_the_packed_symmetric_one() {
        for dim in [
            1,
            5,
            TRANSPOSE_TILE,
            TRANSPOSE_TILE + 1,
            2 * TRANSPOSE_TILE + 7,
        ] {
            let packed: Vec<f64> = (0..dim * (dim + 1) / 2).map(|v| v as f64).collect();
            let mut dense = vec![f64::NAN; dim * dim];
            unfold_symmetric(&packed, dim, &mut dense);
            let mut t = 0;
            for a in 0..dim {
                for b in a..dim {
                    assert_eq!(dense[a * dim + b], packed[t], "dim {dim}: ({a}, {b})");
                    assert_eq!(dense[b * dim + a], packed[t], "dim {dim}: ({b}, {a})");
                    t += 1;
                }
            }
        }
    }
}
