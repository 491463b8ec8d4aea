//! The secular equation solved by Newton's method on Cholesky factorisations of `H + lambda I`
//! (Moré & Sorensen 1983), without an eigen-decomposition: the fast path of the reduced
//! problem `min z^T H z - 2 g^T z` on the sphere `|z| = rho`.
//!
//! Each step factorises `H + lambda I = R R^T` (about `n^3 / 6` operations against some
//! `9 n^3` for the eigen-decomposition), gives `z(lambda) = (H + lambda I)^-1 g` and the
//! derivative of `psi(lambda) = 1/|z| - 1/rho` from `|R^-1 z|^2 = z^T (H + lambda I)^-1 z`. The
//! bracket, the Newton step, the bisection fallback and the stopping rule are those of the
//! eigen-decomposition path ([`super::eigen`]), so both stop at the same root to rounding. A
//! failed factorisation means `lambda <= -d_min` and raises the bracket's lower end. The path
//! declines (returns `None`, and the caller uses the eigen-decomposition) where it could
//! differ from it: `g = 0`, the hard case (the root not reached: `|z|` stays below `rho` as
//! `lambda` falls to `-d_min`), a root so close to `-d_min` that `H + lambda I` is nearly
//! singular along the solution, or no convergence.

use super::{Bracket, MAX_SECULAR_STEPS};
use crate::dense::{cholesky_in_place, forward_solve, norm_squared, transposed_back_solve};

/// Largest `(|lambda| + max_i H_ii) z^T (H + lambda I)^-1 z / |z|^2` (a lower bound on the
/// condition number of `H + lambda I` along the solution) accepted from this path.
const MAX_CONDITION: f64 = 1e10;

/// Buffers of [`solve`], reused between calls.
#[derive(Clone, Debug, Default)]
pub(super) struct NewtonBuffers {
    factor: Vec<f64>,
    q: Vec<f64>,
}

/// Solves the secular equation of `H` (column-major `n x n`, symmetric positive
/// semidefinite), `g` and `rho > 0`, starting from `warm` when it lies inside the bracket.
/// Returns the multiplier with `z` (resized to `n`) set to the solution, not yet put exactly
/// on the sphere; `None` where the eigen-decomposition path must decide (see the module
/// documentation).
pub(super) fn solve(
    h: &[f64],
    g: &[f64],
    rho: f64,
    warm: Option<f64>,
    buffers: &mut NewtonBuffers,
    z: &mut Vec<f64>,
) -> Option<f64> {
    let n = g.len();
    let g_norm = norm_squared(g).sqrt();
    if !(g_norm > 0.0 && g_norm.is_finite()) {
        return None;
    }
    let diagonal = (0..n).map(|i| h[i + i * n]);
    let min_diagonal = diagonal.clone().fold(f64::INFINITY, f64::min);
    let max_diagonal = diagonal.fold(0.0, f64::max);
    // -d_min >= -min_i H_ii, and |z| <= |g| / (d_min + lambda) <= rho at |g| / rho.
    let mut bracket = Bracket {
        lo: -min_diagonal,
        hi: g_norm / rho,
    };
    let mut lambda = match warm {
        Some(w) if w > bracket.lo && w < bracket.hi => w,
        _ => bracket.hi,
    };
    let NewtonBuffers { factor, q } = buffers;
    let mut condition = f64::INFINITY;
    let mut norm = 0.0;
    for _ in 0..MAX_SECULAR_STEPS {
        factor.clear();
        factor.extend_from_slice(h);
        for i in 0..n {
            factor[i + i * n] += lambda;
        }
        if !cholesky_in_place(factor, n) {
            // lambda <= -d_min (to rounding): the root is above.
            norm = 0.0;
            match bracket.below(lambda) {
                Some(next) => lambda = next,
                None => break,
            }
            continue;
        }
        z.clear();
        z.extend_from_slice(g);
        forward_solve(factor, n, z);
        transposed_back_solve(factor, n, z);
        let n2 = norm_squared(z);
        norm = n2.sqrt();
        q.clear();
        q.extend_from_slice(z);
        forward_solve(factor, n, q);
        let n3 = norm_squared(q);
        condition = (lambda.abs() + max_diagonal) * n3 / n2;
        match bracket.step(lambda, n2, n3, rho) {
            Some(next) => lambda = next,
            None => break,
        }
    }
    // |z| reaches rho to 1e-10, or to the rounding of the factorisation where the bracket has
    // shrunk to adjacent multipliers (|z| then moves by about `condition * eps` per step).
    let tolerance = 1e-10_f64.max(16.0 * f64::EPSILON * condition);
    let converged = (norm - rho).abs() <= tolerance * rho;
    (converged && condition <= MAX_CONDITION).then_some(lambda)
}
