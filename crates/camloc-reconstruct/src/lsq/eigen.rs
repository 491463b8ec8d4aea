//! The secular equation solved in the eigenbasis of `H`: the reference path, which also
//! covers the hard case. [`super::newton`] gives the same root faster wherever it applies.

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use super::{Bracket, MAX_SECULAR_STEPS};
use crate::ReconstructError;

/// Root of the secular equation.
pub(super) struct Secular {
    /// The solution `z`, of norm `rho` (to rounding) once put on the sphere.
    pub(super) z: Vec<f64>,
    /// Multiplier `lambda`.
    pub(super) lambda: f64,
    /// Whether the hard case applied.
    pub(super) hard_case: bool,
}

/// Minimises `z^T H z - 2 g^T z` on the sphere `|z| = rho > 0` with the eigen-decomposition of
/// `H` (column-major `n x n`, symmetric positive semidefinite; eigenvalues are clamped at 0).
/// The regular case's `z` is returned before it is put exactly on the sphere.
pub(super) fn solve(h: &[f64], g: &[f64], rho: f64) -> Result<Secular, ReconstructError> {
    let n = g.len();
    let eig = SymmetricEigen::try_new(DMatrix::from_column_slice(n, n, h), f64::EPSILON, 0).ok_or(
        ReconstructError::Numerical("eigen-decomposition of A~^T A~ failed"),
    )?;
    let d: Vec<f64> = eig.eigenvalues.iter().map(|&v| v.max(0.0)).collect();
    let g_eig: Vec<f64> = (eig.eigenvectors.transpose() * DVector::from_column_slice(g))
        .iter()
        .copied()
        .collect();
    let (coords, lambda, hard_case) = solve_secular(&d, &g_eig, rho)?;
    let z = &eig.eigenvectors * DVector::from_vec(coords);
    Ok(Secular {
        z: z.iter().copied().collect(),
        lambda,
        hard_case,
    })
}

/// Minimises `sum_i d_i x_i^2 - 2 g_i x_i` on the sphere `|x| = rho > 0` (the eigen-coordinate
/// form of the reduced problem), `d_i >= 0`: the coordinates, the multiplier and whether the
/// hard case applied.
fn solve_secular(
    d: &[f64],
    g: &[f64],
    rho: f64,
) -> Result<(Vec<f64>, f64, bool), ReconstructError> {
    let n = d.len();
    let d_min = d.iter().copied().fold(f64::INFINITY, f64::min);
    let d_max = d.iter().copied().fold(0.0, f64::max);
    let g_norm_sq: f64 = g.iter().map(|v| v * v).sum();
    // Eigenvalues within rounding of the smallest form its eigenspace J.
    let gap = 1e-13 * d_max.max(f64::MIN_POSITIVE);
    let in_j = |i: usize| d[i] - d_min <= gap;
    let g_j_sq: f64 = (0..n).filter(|&i| in_j(i)).map(|i| g[i] * g[i]).sum();

    if g_j_sq <= 1e-28 * g_norm_sq {
        // Possible hard case: the part of the solution off J at lambda = -d_min.
        let off: Vec<f64> = (0..n)
            .map(|i| if in_j(i) { 0.0 } else { g[i] / (d[i] - d_min) })
            .collect();
        let off_sq: f64 = off.iter().map(|v| v * v).sum();
        if off_sq <= rho * rho {
            let j = (0..n)
                .filter(|&i| in_j(i))
                .max_by(|&p, &q| g[p].abs().total_cmp(&g[q].abs()))
                .ok_or(ReconstructError::Numerical("empty eigenspace"))?;
            let mut coords = off;
            let sign = if g[j] < 0.0 { -1.0 } else { 1.0 };
            coords[j] = sign * (rho * rho - off_sq).sqrt();
            return Ok((coords, -d_min, true));
        }
    }

    // Regular case: psi(lambda) = 1/|x(lambda)| - 1/rho, increasing and concave on
    // (-d_min, inf), negative near -d_min and >= 0 at the upper bracket end.
    let norms = |lambda: f64| {
        let (mut n2, mut n3) = (0.0, 0.0);
        for (di, gi) in d.iter().zip(g) {
            let t = di + lambda;
            n2 += gi * gi / (t * t);
            n3 += gi * gi / (t * t * t);
        }
        (n2, n3)
    };
    let mut bracket = Bracket {
        lo: -d_min,
        hi: g_norm_sq.sqrt() / rho - d_min,
    };
    let mut lambda = bracket.hi;
    for _ in 0..MAX_SECULAR_STEPS {
        let (n2, n3) = norms(lambda);
        match bracket.step(lambda, n2, n3, rho) {
            Some(next) => lambda = next,
            None => break,
        }
    }
    let coords: Vec<f64> = d.iter().zip(g).map(|(di, gi)| gi / (di + lambda)).collect();
    Ok((coords, lambda, false))
}
