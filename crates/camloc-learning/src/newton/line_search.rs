//! Backtracking (Armijo) line search along the Newton direction, one step length per
//! line-search block (the whole model for multinomial, each class for one-vs-rest).

use rayon::prelude::*;

use super::NewtonProblem;
use super::kernels::{ROWS_PER_TASK, block_of_class, block_totals, ridge, row_loss, shifted};

/// Sufficient-decrease constant of the Armijo condition `f(t) <= f(0) + c t g.d`.
const ARMIJO_C1: f64 = 1e-4;
/// Maximum number of step halvings in one line search (smallest step `2^-50`).
const MAX_HALVINGS: usize = 50;

impl NewtonProblem {
    /// Backtracking line search along `direction`, one step length per block, halving from
    /// 1 until the Armijo condition holds. Blocks whose direction is not a descent direction
    /// or that find no decrease get step 0. Leaves the result in `block_steps` and
    /// `class_steps`.
    pub(super) fn line_search(&mut self) {
        let dim = self.dim;
        self.directional_derivatives.fill(0.0);
        for (class, (g, d)) in self
            .gradient
            .chunks_exact(dim)
            .zip(self.direction.chunks_exact(dim))
            .enumerate()
        {
            let dot: f64 = g.iter().zip(d).map(|(a, b)| a * b).sum();
            let block = block_of_class(self.mode, class);
            debug_assert!(block < self.directional_derivatives.len(), "block {block}");
            self.directional_derivatives[block] += dot;
        }
        for ((step, done), &dd) in self
            .block_steps
            .iter_mut()
            .zip(self.block_done.iter_mut())
            .zip(&self.directional_derivatives)
        {
            // Not a descent direction (only possible through rounding at the optimum).
            let descent = dd < 0.0;
            *step = if descent { 1.0 } else { 0.0 };
            *done = !descent;
        }
        for _ in 0..=MAX_HALVINGS {
            self.sync_class_steps();
            self.trial_pass();
            let mut all_done = true;
            for (((step, done), &trial), (&f0, &dd)) in self
                .block_steps
                .iter_mut()
                .zip(self.block_done.iter_mut())
                .zip(&self.trial_objectives)
                .zip(
                    self.block_objectives
                        .iter()
                        .zip(&self.directional_derivatives),
                )
            {
                if *done {
                    continue;
                }
                if trial <= f0 + ARMIJO_C1 * *step * dd {
                    *done = true;
                } else {
                    *step *= 0.5;
                    all_done = false;
                }
            }
            if all_done {
                break;
            }
        }
        for (step, &done) in self.block_steps.iter_mut().zip(&self.block_done) {
            if !done {
                *step = 0.0;
            }
        }
        self.sync_class_steps();
    }

    /// `class_steps[c] = block_steps[block of c]`.
    fn sync_class_steps(&mut self) {
        let mode = self.mode;
        for (class, s) in self.class_steps.iter_mut().enumerate() {
            let block = block_of_class(mode, class);
            debug_assert!(block < self.block_steps.len(), "block {block}");
            *s = self.block_steps[block];
        }
    }

    /// Objective of every block at `theta + class_steps * direction`, into
    /// `trial_objectives`, without changing the state.
    fn trial_pass(&mut self) {
        let k = self.n_classes;
        let mode = self.mode;
        let n_blocks = self.block_objectives.len();
        let steps = &self.class_steps;
        self.logits
            .par_chunks(ROWS_PER_TASK * k)
            .zip(self.direction_logits.par_chunks(ROWS_PER_TASK * k))
            .zip(self.labels.par_chunks(ROWS_PER_TASK))
            .zip(self.partial_losses.par_chunks_mut(n_blocks))
            .for_each(|(((z, dz), labels), partial)| {
                partial.fill(0.0);
                for ((z, dz), &y) in z.chunks_exact(k).zip(dz.chunks_exact(k)).zip(labels) {
                    row_loss(mode, y, k, |c| shifted(z[c], dz[c], steps[c]), partial);
                }
            });
        let dim = self.dim;
        let lambda = self.lambda;
        let ridges = self
            .theta
            .chunks_exact(dim)
            .zip(self.direction.chunks_exact(dim))
            .zip(steps)
            .map(|((t, d), &s)| {
                ridge(
                    lambda,
                    t[..dim - 1]
                        .iter()
                        .zip(d)
                        .map(|(&tv, &dv)| shifted(tv, dv, s)),
                )
            });
        block_totals(
            &self.partial_losses,
            mode,
            ridges,
            &mut self.trial_objectives,
        );
    }
}
