//! Numerically stable softmax, log-sum-exp and logistic helpers.

/// Largest element, ignoring NaN; `-inf` for an empty slice or one of NaNs only.
#[inline]
fn max_of(values: impl Iterator<Item = f64>) -> f64 {
    values.fold(f64::NEG_INFINITY, f64::max)
}

/// Replaces `logits` by `softmax(logits)` in place: `exp(z_k - max z) / sum_j exp(z_j - max z)`.
///
/// Stable for logits of any finite magnitude (±1e300 included): the largest entry becomes
/// `exp(0) = 1` before normalising, so the denominator is at least 1 and the result sums to
/// 1 within rounding. Infinite logits are handled as limits: if some entries are `+inf`
/// they share the probability equally; if all are `-inf` the result is uniform. A NaN
/// logit makes every output NaN. An empty slice is left unchanged.
pub fn softmax_in_place(logits: &mut [f64]) {
    if logits.is_empty() {
        return;
    }
    if logits.iter().any(|z| z.is_nan()) {
        logits.fill(f64::NAN);
        return;
    }
    let max = max_of(logits.iter().copied());
    if max.is_infinite() {
        // Either some entries are +inf (they share the mass) or all are -inf (uniform).
        let count = logits.iter().filter(|&&z| z == max).count() as f64;
        logits
            .iter_mut()
            .for_each(|z| *z = if *z == max { 1.0 / count } else { 0.0 });
        return;
    }
    let mut sum = 0.0;
    for z in logits.iter_mut() {
        *z = (*z - max).exp();
        sum += *z;
    }
    let inv = 1.0 / sum;
    logits.iter_mut().for_each(|z| *z *= inv);
}

/// `log(sum_k exp(z_k))` of the logits produced by `logit(k)` for `k in 0..n`, computed
/// stably as `max + log(sum exp(z - max))`. Takes a closure so that callers can form the
/// logits on the fly (for a line-search trial) with exactly the same rounding as when they
/// are stored.
#[inline]
pub(crate) fn log_sum_exp(n: usize, logit: impl Fn(usize) -> f64) -> f64 {
    let max = max_of((0..n).map(&logit));
    if max.is_infinite() {
        return max;
    }
    let sum: f64 = (0..n).map(|k| (logit(k) - max).exp()).sum();
    max + sum.ln()
}

/// `log(1 + exp(z))` without overflow or loss of precision for large `|z|`.
#[inline]
pub(crate) fn softplus(z: f64) -> f64 {
    z.max(0.0) + (-z.abs()).exp().ln_1p()
}

/// Logistic function `1 / (1 + exp(-z))`, accurate in both tails.
#[inline]
pub(crate) fn sigmoid(z: f64) -> f64 {
    if z >= 0.0 {
        1.0 / (1.0 + (-z).exp())
    } else {
        let e = z.exp();
        e / (1.0 + e)
    }
}

/// `sigmoid(z) * (1 - sigmoid(z))`, the logistic curvature, without the cancellation of
/// `1 - sigmoid(z)` when `z` is large.
#[inline]
pub(crate) fn sigmoid_curvature(z: f64) -> f64 {
    let e = (-z.abs()).exp();
    let d = 1.0 + e;
    e / (d * d)
}

/// One-vs-rest probabilities (eq. 9): `sigmoid(z_k) / sum_j sigmoid(z_j)`, computed as a
/// softmax of `log sigmoid(z_k) = -softplus(-z_k)` so that it stays finite and sums to 1
/// even when every `sigmoid(z_k)` underflows.
pub(crate) fn one_vs_rest_in_place(logits: &mut [f64]) {
    logits.iter_mut().for_each(|z| *z = -softplus(-*z));
    softmax_in_place(logits);
}
