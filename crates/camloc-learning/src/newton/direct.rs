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

use super::NewtonProblem;
use super::design_matrix::DesignMatrix;
use crate::{LearningError, Mode};

/// First diagonal damping, relative to the largest diagonal entry, if Cholesky fails.
const FIRST_DAMPING: f64 = 1e-10;
/// Number of damping attempts (each 100 times the previous one) before giving up.
const DAMPING_ATTEMPTS: usize = 8;

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
    fn unpack_hessian(&mut self, scale: f64) {
        let dim = self.dim;
        let p = self.theta.len();
        let class_pairs = &self.packed.class_pairs;
        let h = &mut self.hessian;
        h.fill(0.0);
        // Accumulate the upper triangle of every block (a <= b within blocks, j <= l across).
        for (&(a, b), column) in self
            .packed
            .feature_pairs
            .iter()
            .zip(self.packed.packed.chunks_exact(class_pairs.len().max(1)))
        {
            for (&g, &(j, l)) in column.iter().zip(class_pairs) {
                let g = scale * g;
                if j == l {
                    h[(j * dim + b) * p + j * dim + a] += g;
                } else {
                    // Off-diagonal block (j, l): -G, both (a, b) and (b, a) entries.
                    h[(l * dim + b) * p + j * dim + a] = -g;
                    h[(l * dim + a) * p + j * dim + b] = -g;
                    h[(j * dim + b) * p + j * dim + a] += g;
                    h[(l * dim + b) * p + l * dim + a] += g;
                }
            }
        }
        // Mirror the upper triangle into the lower one.
        for col in 0..p {
            for row in col + 1..p {
                h[col * p + row] = h[row * p + col];
            }
        }
        let two_lambda = 2.0 * self.lambda;
        for class in 0..self.n_classes {
            for a in 0..dim - 1 {
                let i = class * dim + a;
                h[i * p + i] += two_lambda;
            }
        }
    }
}
