//! Exact Hessian-vector products `H v`, without assembling `H`: the inner loop of the
//! conjugate-gradient solvers (module `cg`), public for tests and benchmarks.
//!
//! `H v = X^T [J_i V^T x_i]_i + 2 lambda [V; 0]` with `J_i` the Jacobian of sample `i`'s
//! probabilities with respect to its logits: `diag(p_i) - p_i p_i^T` (multinomial) or
//! `diag(sigma'(z_i))` (one-vs-rest). That is two products with the design matrix `X`
//! (`n x D` times `D x K`, then `D x n` times `n x K`), `4 n D K` flops, fused per chunk of
//! samples so that `X` is read once (module `blocked`).

use super::NewtonProblem;
use super::kernels::{ROWS_PER_TASK, add_ridge_curvature};
use crate::hessian::dot;
use crate::softmax::sigmoid_curvature;
use crate::{LearningError, Mode};

impl NewtonProblem {
    /// `out = H v`: the exact Hessian of `f` at the current parameters times `v`, both in
    /// the layout of [`parameters`](Self::parameters), computed from the data without
    /// assembling `H` ([`hessian_vector_product_flops`](Self::hessian_vector_product_flops)
    /// flops). Equal, to rounding, to [`hessian`](Self::hessian) times `v` after an
    /// [`assemble_hessian`](Self::assemble_hessian) at the same parameters (on all samples).
    ///
    /// # Errors
    /// [`LearningError::SizeMismatch`] if `v` or `out` does not have
    /// [`n_parameters`](Self::n_parameters) entries.
    pub fn hessian_vector_product(
        &mut self,
        v: &[f64],
        out: &mut [f64],
    ) -> Result<(), LearningError> {
        let p = self.theta.len();
        for (what, found) in [
            ("Hessian-vector product input", v.len()),
            ("Hessian-vector product output", out.len()),
        ] {
            if found != p {
                return Err(LearningError::SizeMismatch {
                    what,
                    expected: p,
                    found,
                });
            }
        }
        self.cg.search.copy_from_slice(v);
        self.multiply_by_hessian(1);
        out.copy_from_slice(&self.cg.product);
        Ok(())
    }

    /// Floating-point operations of one [`hessian_vector_product`](Self::hessian_vector_product)
    /// as counted for rates: `4 n D K` (the two products with the design matrix; the
    /// per-sample Jacobians and the ridge term are of lower order).
    pub fn hessian_vector_product_flops(&self) -> f64 {
        4.0 * self.n_samples as f64 * self.dim as f64 * self.n_classes as f64
    }

    /// Tasks of `ROWS_PER_TASK` rows between two that a conjugate-gradient product reads:
    /// the largest stride that still reads at least `product_rows` rows (1, every row, when
    /// `product_rows >= n`).
    pub(super) fn task_stride_for(n_samples: usize, product_rows: usize) -> usize {
        let tasks = n_samples.div_ceil(ROWS_PER_TASK);
        let wanted = product_rows.div_ceil(ROWS_PER_TASK).max(1);
        (tasks / wanted).max(1)
    }

    /// `cg.product = H cg.search`, the Hessian at the current parameters: one fused pass
    /// over the samples (module `blocked`). With `task_stride` 1 the exact Hessian; with a
    /// larger stride the loss part is summed over the rows of every `task_stride`-th task
    /// only and rescaled to all samples (the subsampled Hessian of
    /// [`DirectionSolver::TruncatedCg`](crate::DirectionSolver::TruncatedCg)'s
    /// `product_rows`).
    pub(super) fn multiply_by_hessian(&mut self, task_stride: usize) {
        let k = self.n_classes;
        let mode = self.mode;
        let per_sample = match mode {
            Mode::Multinomial => &self.probabilities,
            Mode::OneVsRest => &self.logits,
        };
        let jacobian = |i: usize, s: &mut [f64]| {
            apply_jacobian(mode, &per_sample[i * k..(i + 1) * k], s);
        };
        let (v, product) = (&self.cg.search, &mut self.cg.product);
        let rows = self
            .blocked
            .hessian_product(&self.x, v, jacobian, task_stride, product);
        if rows < self.n_samples {
            let scale = self.n_samples as f64 / rows as f64;
            product.iter_mut().for_each(|value| *value *= scale);
        }
        add_ridge_curvature(self.lambda, self.dim, v, product);
    }
}

/// `s = J s` for one sample whose probabilities (multinomial) or logits (one-vs-rest) are
/// `p`: `p (s - p . s)` elementwise, or `sigma'(z) s`.
#[inline]
fn apply_jacobian(mode: Mode, p: &[f64], s: &mut [f64]) {
    match mode {
        Mode::Multinomial => {
            let mean = dot(s, p);
            for (sc, &pc) in s.iter_mut().zip(p) {
                *sc = pc * (*sc - mean);
            }
        }
        Mode::OneVsRest => {
            for (sc, &zc) in s.iter_mut().zip(p) {
                *sc *= sigmoid_curvature(zc);
            }
        }
    }
}
