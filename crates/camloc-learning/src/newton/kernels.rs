//! The per-sample kernels of the Newton solver: probabilities, residuals, losses, and the
//! ridge terms (the products with the design matrix are in module `blocked`). Every sum
//! runs in a fixed order so that fits are bit-for-bit reproducible.

use crate::Mode;
use crate::softmax::{log_sum_exp, sigmoid, softmax_in_place, softplus};

/// Rows per task in the parallel passes over samples (probabilities, losses, products).
pub(super) const ROWS_PER_TASK: usize = 2048;

/// `totals[b] = sum over tasks of partials[task][b]` (in task order), then plus the ridge
/// term of each class in its block.
pub(super) fn block_totals(
    partials: &[f64],
    mode: Mode,
    ridges: impl Iterator<Item = f64>,
    totals: &mut [f64],
) {
    totals.fill(0.0);
    for partial in partials.chunks_exact(totals.len().max(1)) {
        for (b, &v) in totals.iter_mut().zip(partial) {
            *b += v;
        }
    }
    for (class, r) in ridges.enumerate() {
        let block = block_of_class(mode, class);
        debug_assert!(block < totals.len(), "block {block} of class {class}");
        totals[block] += r;
    }
}

/// Line-search block of a class: 0 for multinomial, the class itself for one-vs-rest.
#[inline]
pub(super) fn block_of_class(mode: Mode, class: usize) -> usize {
    match mode {
        Mode::Multinomial => 0,
        Mode::OneVsRest => class,
    }
}

/// `lambda * sum w^2` over the weights of one class.
#[inline]
pub(super) fn ridge(lambda: f64, weights: impl Iterator<Item = f64>) -> f64 {
    weights.map(|w| w * w).sum::<f64>() * lambda
}

/// `out += 2 lambda [V; 0]`: the ridge term's gradient at `v` (or, equally, its Hessian
/// times `v`), biases excluded; `v` and `out` are `D x K` class-major.
pub(super) fn add_ridge_curvature(lambda: f64, dim: usize, v: &[f64], out: &mut [f64]) {
    let two_lambda = 2.0 * lambda;
    for (o, t) in out.chunks_exact_mut(dim).zip(v.chunks_exact(dim)) {
        for (ov, tv) in o[..dim - 1].iter_mut().zip(&t[..dim - 1]) {
            *ov += two_lambda * tv;
        }
    }
}

/// Probabilities `p` of one sample with logits `z`.
#[inline]
fn probabilities_of_row(mode: Mode, z: &[f64], p: &mut [f64]) {
    match mode {
        Mode::Multinomial => {
            p.copy_from_slice(z);
            softmax_in_place(p);
        }
        Mode::OneVsRest => {
            for (pc, &zc) in p.iter_mut().zip(z) {
                *pc = sigmoid(zc);
            }
        }
    }
}

/// Residuals `r = p - onehot(y)` of one sample with label `y`, logits `z` and probabilities
/// `p` (as [`evaluate_row`] leaves them). The residual of the true class is computed without
/// cancellation: `-sum_{c != y} p_c` (multinomial) or `-sigmoid(-z_y)` (one-vs-rest), not
/// `p_y - 1`, so the gradient stays accurate when the model is confident.
#[inline]
pub(super) fn residuals_of_row(mode: Mode, y: usize, z: &[f64], p: &[f64], r: &mut [f64]) {
    match mode {
        Mode::Multinomial => multinomial_residuals(y, p, r),
        Mode::OneVsRest => {
            r.copy_from_slice(p);
            debug_assert!(y < r.len(), "label {y} of {} classes", r.len());
            r[y] = -sigmoid(-z[y]);
        }
    }
}

/// Multinomial residuals `r = p - onehot(y)` from the probabilities `p`, the true class's as
/// `-sum_{c != y} p_c`.
#[inline]
fn multinomial_residuals(y: usize, p: &[f64], r: &mut [f64]) {
    r.copy_from_slice(p);
    let others: f64 = p
        .iter()
        .enumerate()
        .filter(|&(c, _)| c != y)
        .map(|(_, v)| v)
        .sum();
    debug_assert!(y < r.len(), "label {y} of {} classes", r.len());
    r[y] = -others;
}

/// Where [`evaluate_row`] writes one sample's trial logits and probabilities (`K` values
/// each).
pub(super) struct RowOutput<'a> {
    pub(super) trial: &'a mut [f64],
    pub(super) p: &'a mut [f64],
}

/// One sample with label `y` and logits `z` at the trial logits `z + s_c dz` (`s_c` =
/// `steps[c]`, see [`shifted`]): writes them and the probabilities to `out`,
/// and adds the loss to `partial` as [`row_loss`] does. In multinomial mode the loss and the
/// softmax share one exponential per class (the numbers are those of [`row_loss`] and
/// [`softmax_in_place`], which handle non-finite logits).
#[inline]
pub(super) fn evaluate_row(
    mode: Mode,
    y: usize,
    (z, dz): (&[f64], &[f64]),
    steps: &[f64],
    out: RowOutput<'_>,
    partial: &mut [f64],
) {
    let RowOutput { trial, p } = out;
    for (((t, &zc), &dc), &s) in trial.iter_mut().zip(z).zip(dz).zip(steps) {
        *t = shifted(zc, dc, s);
    }
    if mode == Mode::Multinomial {
        let max = trial.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if max.is_finite() && !trial.iter().any(|v| v.is_nan()) {
            let mut sum = 0.0;
            for (pc, &tc) in p.iter_mut().zip(trial.iter()) {
                *pc = (tc - max).exp();
                sum += *pc;
            }
            debug_assert!(!partial.is_empty(), "one line-search block");
            partial[0] += max + sum.ln() - trial[y];
            let inv = 1.0 / sum;
            p.iter_mut().for_each(|v| *v *= inv);
            return;
        }
    }
    row_loss(mode, y, trial.len(), |c| trial[c], partial);
    probabilities_of_row(mode, trial, p);
}

/// `z + s dz`, leaving `z` untouched (even if `dz` is not finite) when `s == 0`.
#[inline]
pub(super) fn shifted(z: f64, dz: f64, s: f64) -> f64 {
    if s == 0.0 { z } else { z + s * dz }
}

/// Adds the loss of one sample with label `y` and logits `logit(0..k)` to its line-search
/// block(s): `lse(z) - z_y` (multinomial, block 0) or `softplus(z_c) - [y = c] z_c` for each
/// class `c` (one-vs-rest, block `c`).
#[inline]
pub(crate) fn row_loss(
    mode: Mode,
    y: usize,
    k: usize,
    logit: impl Fn(usize) -> f64,
    partial: &mut [f64],
) {
    match mode {
        Mode::Multinomial => {
            debug_assert!(!partial.is_empty(), "one line-search block");
            partial[0] += log_sum_exp(k, &logit) - logit(y);
        }
        Mode::OneVsRest => {
            for (c, b) in partial.iter_mut().enumerate() {
                let z = logit(c);
                *b += if c == y { softplus(-z) } else { softplus(z) };
            }
        }
    }
}
