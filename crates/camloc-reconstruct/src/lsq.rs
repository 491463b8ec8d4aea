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

use nalgebra::{DMatrix, DVector, SymmetricEigen};

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
        // Reduced problem min |A~ z - b~|^2, |z| = rho, with A~ = A L^-T: its normal matrix
        // H = L^-1 (A^T A) L^-T and g = L^-1 A^T b~ need triangular solves on n columns only.
        let b_tilde = b - a * &self.centre;
        let normal = a.tr_mul(a);
        let half = self
            .l
            .solve_lower_triangular(&normal)
            .ok_or(ReconstructError::NotPositiveDefinite)?; // L^-1 A^T A
        let h = self
            .l
            .solve_lower_triangular(&half.transpose())
            .ok_or(ReconstructError::NotPositiveDefinite)?;
        let h = (&h + h.transpose()) * 0.5;
        let g = self
            .l
            .solve_lower_triangular(&a.tr_mul(&b_tilde))
            .ok_or(ReconstructError::NotPositiveDefinite)?;
        let eig = SymmetricEigen::try_new(h, f64::EPSILON, 0).ok_or(
            ReconstructError::Numerical("eigen-decomposition of A~^T A~ failed"),
        )?;
        let d: Vec<f64> = eig.eigenvalues.iter().map(|&v| v.max(0.0)).collect();
        let g_eig: Vec<f64> = (eig.eigenvectors.transpose() * g).iter().copied().collect();
        let secular = solve_secular(&d, &g_eig, self.rho)?;
        let z = &eig.eigenvectors * DVector::from_vec(secular.coords);
        let w = &self.centre
            + self
                .l
                .tr_solve_lower_triangular(&z)
                .ok_or(ReconstructError::NotPositiveDefinite)?;
        if !w.iter().all(|v| v.is_finite()) {
            return Err(ReconstructError::Numerical(
                "non-finite constrained least-squares solution",
            ));
        }
        let objective = (a * &w - b).norm_squared();
        Ok(ConstrainedSolution {
            w,
            multiplier: secular.lambda,
            objective,
            hard_case: secular.hard_case,
        })
    }
}

/// Root of the secular equation in eigen-coordinates.
struct Secular {
    /// Solution coordinates in the eigenbasis, of norm exactly `rho` (to rounding).
    coords: Vec<f64>,
    /// Multiplier `lambda`.
    lambda: f64,
    /// Whether the hard case applied.
    hard_case: bool,
}

/// Minimises `sum_i d_i x_i^2 - 2 g_i x_i` on the sphere `|x| = rho` (the eigen-coordinate form
/// of the reduced problem), `d_i >= 0`.
fn solve_secular(d: &[f64], g: &[f64], rho: f64) -> Result<Secular, ReconstructError> {
    let n = d.len();
    if rho == 0.0 {
        return Ok(Secular {
            coords: vec![0.0; n],
            lambda: 0.0,
            hard_case: false,
        });
    }
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
            return Ok(Secular {
                coords,
                lambda: -d_min,
                hard_case: true,
            });
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
    let mut lo = -d_min;
    let mut hi = g_norm_sq.sqrt() / rho - d_min;
    let mut lambda = hi;
    for _ in 0..MAX_SECULAR_STEPS {
        let (n2, n3) = norms(lambda);
        let norm = n2.sqrt();
        let psi = 1.0 / norm - 1.0 / rho;
        if (norm - rho).abs() <= 4.0 * f64::EPSILON * rho {
            break;
        }
        if psi < 0.0 {
            lo = lambda;
        } else {
            hi = lambda;
        }
        let dpsi = n3 / (n2 * norm);
        let newton = lambda - psi / dpsi;
        let next = if newton > lo && newton < hi && newton.is_finite() {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if next == lambda || hi - lo <= 2.0 * f64::EPSILON * (lo.abs() + hi.abs()) {
            break;
        }
        lambda = next;
    }
    let mut coords: Vec<f64> = d.iter().zip(g).map(|(di, gi)| gi / (di + lambda)).collect();
    let norm = coords.iter().map(|v| v * v).sum::<f64>().sqrt();
    if !is_positive_finite(norm) {
        return Err(ReconstructError::Numerical(
            "secular equation gave a zero or non-finite solution",
        ));
    }
    // Put the solution exactly on the sphere (removes the last rounding of the root).
    coords.iter_mut().for_each(|v| *v *= rho / norm);
    Ok(Secular {
        coords,
        lambda,
        hard_case: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Value of the constraint `w^T Q w + 2 c^T w + e`.
    fn constraint(q: &DMatrix<f64>, c: &DVector<f64>, e: f64, w: &DVector<f64>) -> f64 {
        (w.transpose() * q * w)[(0, 0)] + 2.0 * c.dot(w) + e
    }

    /// Brute force: the feasible set is the ellipsoid `{w_c + t u : t = rho / sqrt(u^T Q u)}`
    /// over unit directions `u`; scan directions densely, then refine the best by a shrinking
    /// pattern search. Uses no eigen-decomposition and no multiplier.
    fn brute_force(
        a: &DMatrix<f64>,
        b: &DVector<f64>,
        q: &DMatrix<f64>,
        c: &DVector<f64>,
        e: f64,
    ) -> f64 {
        let n = q.nrows();
        let q_inv = q.clone().try_inverse().unwrap();
        let w_c = -(&q_inv * c);
        let rho_sq = c.dot(&(&q_inv * c)) - e;
        let point = |u: &DVector<f64>| {
            let u = u.normalize();
            let t = (rho_sq / (u.transpose() * q * &u)[(0, 0)]).sqrt();
            &w_c + u * t
        };
        let f = |u: &DVector<f64>| (a * point(u) - b).norm_squared();
        // Dense scan of directions: angles on a circle (n = 2) or a latitude/longitude grid
        // (n = 3); n = 1 has two feasible points.
        let mut candidates: Vec<DVector<f64>> = Vec::new();
        match n {
            1 => {
                candidates.push(DVector::from_vec(vec![1.0]));
                candidates.push(DVector::from_vec(vec![-1.0]));
            }
            2 => {
                for i in 0..20_000 {
                    let t = i as f64 / 20_000.0 * std::f64::consts::TAU;
                    candidates.push(DVector::from_vec(vec![t.cos(), t.sin()]));
                }
            }
            _ => {
                for i in 0..300 {
                    let th = (i as f64 + 0.5) / 300.0 * std::f64::consts::PI;
                    for j in 0..600 {
                        let ph = j as f64 / 600.0 * std::f64::consts::TAU;
                        candidates.push(DVector::from_vec(vec![
                            th.sin() * ph.cos(),
                            th.sin() * ph.sin(),
                            th.cos(),
                        ]));
                    }
                }
            }
        }
        let mut best = candidates
            .into_iter()
            .min_by(|x, y| f(x).total_cmp(&f(y)))
            .unwrap();
        let mut step = 0.05;
        while step > 1e-12 && n > 1 {
            let mut improved = false;
            for k in 0..n {
                for sgn in [-1.0, 1.0] {
                    let mut trial = best.clone();
                    trial[k] += sgn * step;
                    if f(&trial) < f(&best) {
                        best = trial;
                        improved = true;
                    }
                }
            }
            if !improved {
                step *= 0.5;
            }
        }
        f(&best)
    }

    fn spd(n: usize, entries: &[f64]) -> DMatrix<f64> {
        let m = DMatrix::from_iterator(n, n, entries.iter().copied());
        &m * m.transpose() + DMatrix::identity(n, n) * 0.2
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]

        /// The solver matches a brute-force search over the feasible ellipsoid on small random
        /// problems, and the constraint holds to 1e-9.
        #[test]
        fn matches_brute_force(n in 1usize..=3, m in 1usize..=5,
                               raw_a in proptest::collection::vec(-2.0f64..2.0, 15),
                               raw_b in proptest::collection::vec(-2.0f64..2.0, 5),
                               raw_q in proptest::collection::vec(-1.0f64..1.0, 9),
                               raw_c in proptest::collection::vec(-1.0f64..1.0, 3),
                               e in -2.0f64..0.5) {
            let a = DMatrix::from_iterator(m, n, raw_a.iter().copied().take(m * n));
            let b = DVector::from_iterator(m, raw_b.iter().copied().take(m));
            let q = spd(n, &raw_q[..n * n]);
            let c = DVector::from_iterator(n, raw_c.iter().copied().take(n));
            match constrained_least_squares(&a, &b, &q, &c, e) {
                Ok(sol) => {
                    prop_assert!(constraint(&q, &c, e, &sol.w).abs() < 1e-9);
                    prop_assert!((sol.objective - (&a * &sol.w - &b).norm_squared()).abs() < 1e-12);
                    let bf = brute_force(&a, &b, &q, &c, e);
                    // Ours is a global minimum: never above brute force, and brute force gets
                    // within its resolution of it.
                    prop_assert!(sol.objective <= bf + 1e-9 * (1.0 + bf), "ours {} > brute {}", sol.objective, bf);
                    prop_assert!(bf - sol.objective <= 1e-6 * (1.0 + bf), "brute {} << ours {}", bf, sol.objective);
                    // Stationarity: (A^T A + lambda Q) w = A^T b - lambda c.
                    if !sol.hard_case {
                        let lhs = (a.transpose() * &a + &q * sol.multiplier) * &sol.w;
                        let rhs = a.transpose() * &b - &c * sol.multiplier;
                        prop_assert!((lhs - &rhs).norm() < 1e-7 * (1.0 + rhs.norm() + sol.multiplier.abs()));
                    }
                }
                Err(ReconstructError::InfeasibleConstraint { radius_sq }) => {
                    let q_inv = q.clone().try_inverse().unwrap();
                    prop_assert!(c.dot(&(&q_inv * &c)) - e < 0.0, "refused a feasible problem ({radius_sq})");
                }
                Err(other) => prop_assert!(false, "unexpected error {other}"),
            }
        }
    }

    #[test]
    fn hard_case_is_solved() {
        // A = diag(1, 2), b = 0: g = 0, the minimum on the circle |w| = 1 is at +-e1 with
        // value 1, lambda = -1.
        let a = DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 2.0]));
        let b = DVector::zeros(2);
        let q = DMatrix::identity(2, 2);
        let c = DVector::zeros(2);
        let sol = constrained_least_squares(&a, &b, &q, &c, -1.0).unwrap();
        assert!(sol.hard_case);
        assert!((sol.objective - 1.0).abs() < 1e-12);
        assert!((sol.multiplier + 1.0).abs() < 1e-12);
        assert!((sol.w[0].abs() - 1.0).abs() < 1e-12 && sol.w[1].abs() < 1e-12);
        // Fewer equations than unknowns: A~^T A~ is singular.
        let wide = DMatrix::from_row_slice(1, 3, &[1.0, 2.0, -1.0]);
        let sol = constrained_least_squares(
            &wide,
            &DVector::from_vec(vec![0.3]),
            &DMatrix::identity(3, 3),
            &DVector::zeros(3),
            -4.0,
        )
        .unwrap();
        assert!((sol.w.norm_squared() - 4.0).abs() < 1e-12);
        assert!(
            (sol.objective
                - brute_force(
                    &wide,
                    &DVector::from_vec(vec![0.3]),
                    &DMatrix::identity(3, 3),
                    &DVector::zeros(3),
                    -4.0
                ))
            .abs()
                < 1e-9
        );
        assert!(
            sol.objective < 1e-20,
            "a zero-residual point exists on the sphere"
        );
    }

    #[test]
    fn errors_are_typed() {
        let a = DMatrix::identity(2, 2);
        let b = DVector::zeros(2);
        let q = DMatrix::identity(2, 2);
        let c = DVector::zeros(2);
        assert!(matches!(
            constrained_least_squares(&a, &b, &q, &c, 1.0),
            Err(ReconstructError::InfeasibleConstraint { .. })
        ));
        assert!(matches!(
            constrained_least_squares(&a, &b, &(-&q), &c, -1.0),
            Err(ReconstructError::NotPositiveDefinite)
        ));
        assert!(matches!(
            constrained_least_squares(&a, &DVector::zeros(3), &q, &c, -1.0),
            Err(ReconstructError::DimensionMismatch { .. })
        ));
        let mut bad = b.clone();
        bad[1] = f64::NAN;
        assert!(matches!(
            constrained_least_squares(&a, &bad, &q, &c, -1.0),
            Err(ReconstructError::Numerical(_))
        ));
    }
}
