//! Backtracking (Armijo) line search along the Newton direction, one step length per
//! line-search block (the whole model for multinomial, each class for one-vs-rest).

use rayon::prelude::*;

use super::NewtonProblem;
use super::kernels::{
    ROWS_PER_TASK, RowOutput, block_of_class, block_totals, evaluate_row, ridge, shifted,
};

/// Sufficient-decrease constant of the Armijo condition `f(t) <= f(0) + c t g.d`.
const ARMIJO_C1: f64 = 1e-4;
/// Maximum number of step halvings in one line search (smallest step `2^-50`).
const MAX_HALVINGS: usize = 50;

impl NewtonProblem {
    /// Backtracking line search along `direction`, one step length per block, halving from
    /// 1 until the Armijo condition holds. Blocks whose direction is not a descent direction
    /// or that find no decrease get step 0. Leaves the result in `block_steps` and
    /// `class_steps`, and the state of the last trial (module docs of
    /// [`newton`](super)) in place; returns whether that trial was at the final steps, so
    /// that it can be accepted as it is (always when the unit step, or any step of every
    /// block, is accepted).
    pub(super) fn line_search(&mut self) -> bool {
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
            self.evaluate_trial();
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
        let mut evaluated = true;
        for (step, &done) in self.block_steps.iter_mut().zip(&self.block_done) {
            if !done && *step != 0.0 {
                *step = 0.0;
                evaluated = false;
            }
        }
        self.sync_class_steps();
        evaluated
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

    /// Evaluates every sample at `theta + class_steps * direction` (the trial logits
    /// `z + s dz`, their probabilities into `probabilities`) and the objective of every block
    /// into `trial_objectives`; `logits`, `theta` and `block_objectives` are left as they were.
    pub(super) fn evaluate_trial(&mut self) {
        let k = self.n_classes;
        let mode = self.mode;
        let n_blocks = self.block_objectives.len();
        let steps = &self.class_steps;
        let rows = ROWS_PER_TASK * k;
        self.logits
            .par_chunks(rows)
            .zip(self.direction_logits.par_chunks(rows))
            .zip(self.probabilities.par_chunks_mut(rows))
            .zip(self.labels.par_chunks(ROWS_PER_TASK))
            .zip(self.partial_losses.par_chunks_mut(n_blocks))
            .for_each(|((((z, dz), p), labels), partial)| {
                partial.fill(0.0);
                let mut trial = vec![0.0; k];
                for (((z, dz), p), &y) in z
                    .chunks_exact(k)
                    .zip(dz.chunks_exact(k))
                    .zip(p.chunks_exact_mut(k))
                    .zip(labels)
                {
                    let out = RowOutput {
                        trial: &mut trial,
                        p,
                    };
                    evaluate_row(mode, y, (z, dz), steps, out, partial);
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

    /// Makes the last [`evaluate_trial`](Self::evaluate_trial) the current state: moves
    /// `theta` by `class_steps` along `direction`, takes the trial logits and objectives, and
    /// computes the gradient there.
    pub(super) fn accept_trial(&mut self) {
        let dim = self.dim;
        for ((t, d), &s) in self
            .theta
            .chunks_exact_mut(dim)
            .zip(self.direction.chunks_exact(dim))
            .zip(&self.class_steps)
        {
            for (tv, &dv) in t.iter_mut().zip(d) {
                *tv = shifted(*tv, dv, s);
            }
        }
        // The trial's logits, made again as the trial made them.
        let (k, steps) = (self.n_classes, &self.class_steps);
        self.logits
            .par_chunks_mut(ROWS_PER_TASK * k)
            .zip(self.direction_logits.par_chunks(ROWS_PER_TASK * k))
            .for_each(|(z, dz)| {
                for (z, dz) in z.chunks_exact_mut(k).zip(dz.chunks_exact(k)) {
                    for ((zc, &dc), &s) in z.iter_mut().zip(dz).zip(steps) {
                        *zc = shifted(*zc, dc, s);
                    }
                }
            });
        self.block_objectives
            .copy_from_slice(&self.trial_objectives);
        self.compute_gradient();
    }
}
