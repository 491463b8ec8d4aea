//! Least squares under one quadratic equality constraint, solved exactly with one Lagrange
//! multiplier.
//!
//! Problem: `min ||A w - b||^2` subject to `w^T Q w + 2 c^T w + e = 0`, with `Q` symmetric
//! positive definite. This is the coefficient step of projected matching pursuit: `A` holds the
//! projected basis poses, and the constraint says that the pose `mu + B w` has the prescribed
//! sum of squared limb lengths.
//!
//! Derivation. With the Cholesky factor `Q = L L^T`, the centre `w_c = -Q^-1 c` and
//! `z = L^T (w - w_c)`, the constraint becomes the sphere `|z|^2 = rho^2`,
//! `rho^2 = c^T Q^-1 c - e`, and the objective `|A~ z - b~|^2` with `A~ = A L^-T`,
//! `b~ = b - A w_c`. A global minimiser of a quadratic on a sphere satisfies
//! `(H + lambda I) z = g`, `H = A~^T A~`, `g = A~^T b~`, with `H + lambda I` positive semidefinite
//! (Gander 1981; Moré & Sorensen 1983). In the eigenbasis `H = V diag(d) V^T`, `g' = V^T g`, the
//! multiplier solves the secular equation `sum_i g'_i^2 / (d_i + lambda)^2 = rho^2` on
//! `lambda > -d_min`, where the left side falls strictly from +inf to 0, so the root is unique.
//! It is found by Newton's method on `1/|z(lambda)| - 1/rho` (nearly linear, concave) inside a
//! bracket `(-d_min, |g|/rho - d_min]`, falling back to bisection whenever a step leaves the
//! bracket. When `g'` has no component on the smallest eigenvalue's eigenspace and the rest of
//! the solution is shorter than `rho` (the "hard case"), `lambda = -d_min` and the missing
//! length is added along that eigenspace. The multiplier is the same `lambda` that makes
//! `(A^T A + lambda Q) w = A^T b - lambda c`.
//!
//! Computation. The same Newton iteration runs on Cholesky factorisations of `H + lambda I`
//! (`newton`), with no eigen-decomposition; the eigenbasis (`eigen`) is used only where that
//! path declines: `g = 0`, the hard case and roots next to `-d_min`. `H` and `g` need only
//! `A^T A` and `A^T b`, so the pursuit, which solves many small problems, hands those in with
//! reusable buffers ([`QuadraticConstraint::solve_normal`]) and allocates nothing per solve.

mod eigen;
mod newton;
#[cfg(test)]
mod tests;

use nalgebra::{DMatrix, DVector};

use crate::dense::{forward_solve, norm_squared, transposed_back_solve};
use crate::{ReconstructError, is_positive_finite};

/// Solution of [`constrained_least_squares`].
#[derive(Clone, Debug, PartialEq)]
pub struct ConstrainedSolution {
    /// The minimiser `w`.
    pub w: DVector<f64>,
    /// The Lagrange multiplier `lambda` of the constraint (`(A^T A + lambda Q) w = A^T b -
    /// lambda c`); `0` when the constraint set is a single point.
    pub multiplier: f64,
    /// The objective `|A w - b|^2` at `w`.
    pub objective: f64,
    /// `true` when the solution came from the hard case (`lambda = -d_min`, non-unique
    /// minimiser; one of them is returned).
    pub hard_case: bool,
}

/// Maximum number of Newton/bisection steps on the secular equation. Bisection alone halves
/// the bracket each step, so 200 steps exhaust f64 precision from any starting bracket.
const MAX_SECULAR_STEPS: usize = 200;

/// Solves `min ||A w - b||^2` subject to `w^T Q w + 2 c^T w + e = 0` exactly (see the module
/// documentation for the method). `A` is `m x n`, `b` has `m` entries, `Q` is `n x n` symmetric
/// positive definite, `c` has `n` entries. Units are the caller's; the constraint holds to
/// rounding error of the order of `1e-15 * (|e| + c^T Q^-1 c)`. Solving several problems
/// with the same constraint: [`QuadraticConstraint`].
///
/// # Errors
/// [`ReconstructError::DimensionMismatch`] for inconsistent sizes or `n = 0`,
/// [`ReconstructError::Numerical`] for non-finite input, [`ReconstructError::NotPositiveDefinite`]
/// when the Cholesky factorisation of `Q` fails, [`ReconstructError::InfeasibleConstraint`] when
/// `c^T Q^-1 c - e < 0` (no real `w` satisfies the constraint).
pub fn constrained_least_squares(
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    q: &DMatrix<f64>,
    c: &DVector<f64>,
    e: f64,
) -> Result<ConstrainedSolution, ReconstructError> {
    QuadraticConstraint::new(q, c, e)?.solve(a, b)
}

/// The constraint `w^T Q w + 2 c^T w + e = 0` of [`constrained_least_squares`], factorised
/// once (Cholesky factor of `Q`, centre and radius of the sphere it becomes) for many
/// least-squares problems.
#[derive(Clone, Debug)]
pub struct QuadraticConstraint {
    /// Lower Cholesky factor `L` of `Q`.
    l: DMatrix<f64>,
    /// Centre `w_c = -Q^-1 c`.
    centre: DVector<f64>,
    /// Radius `rho` of the sphere `|L^T (w - w_c)| = rho`.
    rho: f64,
}

/// Buffers of [`QuadraticConstraint::solve_normal`], reused between solves, and its result.
#[derive(Clone, Debug, Default)]
pub(crate) struct NormalSolve {
    h: Vec<f64>,
    g: Vec<f64>,
    z: Vec<f64>,
    newton: newton::NewtonBuffers,
    /// The last solution `w`.
    pub(crate) w: Vec<f64>,
    /// The last multiplier: the next solve starts its Newton iteration there (the same root
    /// is reached from any start; a nearby one saves steps).
    lambda: Option<f64>,
}

impl NormalSolve {
    /// Buffers whose first solve starts its Newton iteration at `lambda`.
    pub(crate) fn starting_from(lambda: Option<f64>) -> NormalSolve {
        NormalSolve {
            lambda,
            ..NormalSolve::default()
        }
    }

    /// The multiplier of the last solve (or the start given).
    pub(crate) fn multiplier(&self) -> Option<f64> {
        self.lambda
    }
}

impl QuadraticConstraint {
    /// Factorises the constraint.
    ///
    /// # Errors
    /// As [`constrained_least_squares`], for `Q`, `c` and `e`.
    pub fn new(q: &DMatrix<f64>, c: &DVector<f64>, e: f64) -> Result<Self, ReconstructError> {
        let n = q.nrows();
        for (what, expected, got) in [("Q columns", n, q.ncols()), ("c length", n, c.len())] {
            if expected != got {
                return Err(ReconstructError::DimensionMismatch {
                    what,
                    expected,
                    got,
                });
            }
        }
        if n == 0 {
            return Err(ReconstructError::DimensionMismatch {
                what: "number of unknowns",
                expected: 1,
                got: 0,
            });
        }
        if !q
            .iter()
            .chain(c.iter())
            .copied()
            .chain([e])
            .all(f64::is_finite)
        {
            return Err(ReconstructError::Numerical(
                "non-finite input to least squares",
            ));
        }
        let l = q
            .clone()
            .cholesky()
            .ok_or(ReconstructError::NotPositiveDefinite)?
            .unpack();
        // Sphere radius: rho^2 = c^T Q^-1 c - e = |L^-1 c|^2 - e.
        let y = l
            .solve_lower_triangular(c)
            .ok_or(ReconstructError::NotPositiveDefinite)?;
        let y2 = y.norm_squared();
        let mut radius_sq = y2 - e;
        if radius_sq < 0.0 {
            // Accept rounding-level negatives as the single feasible point.
            if radius_sq < -1e-12 * (y2 + e.abs()) {
                return Err(ReconstructError::InfeasibleConstraint { radius_sq });
            }
            radius_sq = 0.0;
        }
        let centre = -l
            .tr_solve_lower_triangular(&y)
            .ok_or(ReconstructError::NotPositiveDefinite)?;
        Ok(QuadraticConstraint {
            l,
            centre,
            rho: radius_sq.sqrt(),
        })
    }

    /// `min ||A w - b||^2` under this constraint (`A` with as many columns as the constraint
    /// has unknowns).
    ///
    /// # Errors
    /// As [`constrained_least_squares`], for `A` and `b`.
    pub fn solve(
        &self,
        a: &DMatrix<f64>,
        b: &DVector<f64>,
    ) -> Result<ConstrainedSolution, ReconstructError> {
        let n = self.l.nrows();
        for (what, expected, got) in [
            ("A columns", n, a.ncols()),
            ("b length (rows of A)", a.nrows(), b.len()),
        ] {
            if expected != got {
                return Err(ReconstructError::DimensionMismatch {
                    what,
                    expected,
                    got,
                });
            }
        }
        if !a.iter().chain(b.iter()).all(|v| v.is_finite()) {
            return Err(ReconstructError::Numerical(
                "non-finite input to least squares",
            ));
        }
        let mut solve = NormalSolve::default();
        let hard_case =
            self.solve_normal(a.tr_mul(a).as_slice(), a.tr_mul(b).as_slice(), &mut solve)?;
        let w = DVector::from_column_slice(&solve.w);
        let objective = (a * &w - b).norm_squared();
        Ok(ConstrainedSolution {
            w,
            multiplier: solve.lambda.unwrap_or(0.0),
            objective,
            hard_case,
        })
    }

    /// `min ||A w - b||^2` under this constraint from the normal matrix `A^T A` (column-major
    /// `n x n`) and `A^T b` (`n`, finite; `n` the constraint's unknowns): the solution in
    /// `out.w`, the multiplier kept in `out` (and started from by the next solve with the same
    /// `out`); returns whether the hard case applied. Allocates nothing once `out` has held a
    /// solve of this size.
    ///
    /// # Errors
    /// [`ReconstructError::Numerical`] when the solution is not finite or the
    /// eigen-decomposition fails.
    pub(crate) fn solve_normal(
        &self,
        normal: &[f64],
        rhs: &[f64],
        out: &mut NormalSolve,
    ) -> Result<bool, ReconstructError> {
        let n = self.l.nrows();
        let l = self.l.as_slice();
        let centre = self.centre.as_slice();
        // g = L^-1 A^T b~ = L^-1 (A^T b - A^T A w_c).
        out.g.clear();
        // Row i of the symmetric A^T A is its column i.
        out.g.extend(
            normal
                .chunks_exact(n)
                .zip(rhs)
                .map(|(row, r)| r - row.iter().zip(centre).map(|(a, c)| a * c).sum::<f64>()),
        );
        forward_solve(l, n, &mut out.g);
        // H = L^-1 (A^T A) L^-T: L^-1 on the columns, transpose, L^-1 again; symmetrised.
        out.h.clear();
        out.h.extend_from_slice(normal);
        for column in out.h.chunks_exact_mut(n) {
            forward_solve(l, n, column);
        }
        transpose_in_place(&mut out.h, n);
        for column in out.h.chunks_exact_mut(n) {
            forward_solve(l, n, column);
        }
        for j in 0..n {
            for i in j + 1..n {
                let mean = 0.5 * (out.h[i + j * n] + out.h[j + i * n]);
                out.h[i + j * n] = mean;
                out.h[j + i * n] = mean;
            }
        }
        let hard_case = if self.rho == 0.0 {
            out.z.clear();
            out.z.resize(n, 0.0);
            out.lambda = Some(0.0);
            false
        } else if let Some(lambda) = newton::solve(
            &out.h,
            &out.g,
            self.rho,
            out.lambda,
            &mut out.newton,
            &mut out.z,
        ) {
            out.lambda = Some(lambda);
            false
        } else {
            let secular = eigen::solve(&out.h, &out.g, self.rho)?;
            out.z = secular.z;
            out.lambda = Some(secular.lambda);
            secular.hard_case
        };
        if !hard_case && self.rho > 0.0 {
            // Put the solution exactly on the sphere (removes the last rounding of the root).
            let norm = norm_squared(&out.z).sqrt();
            if !is_positive_finite(norm) {
                return Err(ReconstructError::Numerical(
                    "secular equation gave a zero or non-finite solution",
                ));
            }
            out.z.iter_mut().for_each(|v| *v *= self.rho / norm);
        }
        // w = w_c + L^-T z.
        transposed_back_solve(l, n, &mut out.z);
        out.w.clear();
        out.w.extend(centre.iter().zip(&out.z).map(|(c, v)| c + v));
        if !out.w.iter().all(|v| v.is_finite()) {
            return Err(ReconstructError::Numerical(
                "non-finite constrained least-squares solution",
            ));
        }
        Ok(hard_case)
    }
}

/// The bracket `(lo, hi]` of the secular equation's root and the safeguarded Newton
/// iteration on `psi(lambda) = 1/|z(lambda)| - 1/rho` (increasing and concave, so Newton's
/// steps from below approach the root monotonically), shared by both solution paths.
struct Bracket {
    lo: f64,
    hi: f64,
}

impl Bracket {
    /// Narrows the bracket with the sign of `psi(lambda)`, `n2 = |z(lambda)|^2`, and returns
    /// the next multiplier: the Newton step (`psi'` from `n3 = z^T (H + lambda I)^-1 z`) when
    /// it falls inside the bracket, else the midpoint; `None` when the iteration stops
    /// (`|z| = rho` to rounding, no progress, or the bracket exhausted).
    fn step(&mut self, lambda: f64, n2: f64, n3: f64, rho: f64) -> Option<f64> {
        let norm = n2.sqrt();
        if (norm - rho).abs() <= 4.0 * f64::EPSILON * rho {
            return None;
        }
        let psi = 1.0 / norm - 1.0 / rho;
        if psi < 0.0 {
            self.lo = lambda;
        } else {
            self.hi = lambda;
        }
        let dpsi = n3 / (n2 * norm);
        let newton = lambda - psi / dpsi;
        let next = if newton > self.lo && newton < self.hi && newton.is_finite() {
            newton
        } else {
            0.5 * (self.lo + self.hi)
        };
        self.unless_done(lambda, next)
    }

    /// `lambda` lies below the root (`H + lambda I` is not positive definite): the bracket's
    /// midpoint above it, `None` when the bracket is exhausted.
    fn below(&mut self, lambda: f64) -> Option<f64> {
        self.lo = lambda;
        self.unless_done(lambda, 0.5 * (self.lo + self.hi))
    }

    fn unless_done(&self, lambda: f64, next: f64) -> Option<f64> {
        let exhausted = self.hi - self.lo <= 2.0 * f64::EPSILON * (self.lo.abs() + self.hi.abs());
        (next != lambda && !exhausted).then_some(next)
    }
}

/// Transposes the column-major `n x n` matrix `a` in place.
fn transpose_in_place(a: &mut [f64], n: usize) {
    for j in 0..n {
        for i in j + 1..n {
            a.swap(i + j * n, j + i * n);
        }
    }
}
