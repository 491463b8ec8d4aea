//! Tests of the constrained least squares against brute force and of its two secular paths.

use super::*;
use crate::dense::norm_squared;
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

/// A random symmetric positive semidefinite `n x n` matrix `M M^T` (column-major) of rank
/// at most `rank`, plus `ridge` on the diagonal.
fn random_gram(n: usize, rank: usize, raw: &[f64], ridge: f64) -> Vec<f64> {
    let m = DMatrix::from_iterator(n, rank, raw.iter().copied().cycle().take(n * rank));
    let h = &m * m.transpose() + DMatrix::identity(n, n) * ridge;
    h.as_slice().to_vec()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// The Newton path on Cholesky factorisations reaches the eigen-decomposition path's
    /// solution and multiplier (to 1e-9, the solution also to the rounding of its condition
    /// number) on random reduced problems of the pursuit's sizes, from a cold start and from
    /// any warm start, and does not decline them.
    #[test]
    fn newton_path_matches_eigen_path(n in 1usize..=12, rank in 1usize..=12,
                                      raw in proptest::collection::vec(-1.0f64..1.0, 144),
                                      raw_g in proptest::collection::vec(-1.0f64..1.0, 12),
                                      ridge in 1e-3f64..1.0, rho in 0.05f64..20.0,
                                      warm in -2.0f64..50.0) {
        let h = random_gram(n, rank, &raw, ridge);
        let g: Vec<f64> = raw_g[..n].to_vec();
        prop_assume!(norm_squared(&g) > 1e-6);
        let reference = eigen::solve(&h, &g, rho).unwrap();
        prop_assert!(!reference.hard_case);
        let on_sphere = |z: &[f64]| {
            let norm = norm_squared(z).sqrt();
            z.iter().map(|v| v * rho / norm).collect::<Vec<f64>>()
        };
        let expected = on_sphere(&reference.z);
        // Near -d_min the solution is as sensitive as H + lambda I is ill-conditioned along
        // it: both paths agree to 1e-9 plus that condition number's rounding.
        let d_min = DMatrix::from_column_slice(n, n, &h).symmetric_eigenvalues().min();
        let d_max = (0..n).map(|i| h[i + i * n]).fold(0.0, f64::max);
        let condition = (reference.lambda.abs() + d_max) / (reference.lambda + d_min);
        let z_tolerance = (1e-9 + f64::EPSILON * condition) * rho;
        for start in [None, Some(warm)] {
            let mut buffers = newton::NewtonBuffers::default();
            let mut z = Vec::new();
            let lambda = newton::solve(&h, &g, rho, start, &mut buffers, &mut z);
            prop_assert!(lambda.is_some(), "declined a regular problem");
            let lambda = lambda.unwrap_or(f64::NAN);
            prop_assert!((lambda - reference.lambda).abs() <= 1e-9 * (1.0 + reference.lambda.abs()),
                "lambda {} vs {}", lambda, reference.lambda);
            for (a, b) in on_sphere(&z).iter().zip(&expected) {
                prop_assert!((a - b).abs() <= z_tolerance, "z {} vs {}", a, b);
            }
        }
    }
}

#[test]
fn newton_path_declines_the_hard_case() {
    // H = diag(1, 4), g on the second axis only, rho beyond g_2 / (4 - 1): the hard case.
    let h = [1.0, 0.0, 0.0, 4.0];
    let g = [0.0, 0.3];
    let mut buffers = newton::NewtonBuffers::default();
    let mut z = Vec::new();
    assert_eq!(newton::solve(&h, &g, 1.0, None, &mut buffers, &mut z), None);
    let reference = eigen::solve(&h, &g, 1.0).unwrap();
    assert!(reference.hard_case && (reference.lambda + 1.0).abs() < 1e-12);
    // g = 0 leaves only the hard case too.
    assert_eq!(
        newton::solve(&h, &[0.0, 0.0], 1.0, None, &mut buffers, &mut z),
        None
    );
}
