//! Exact gradient and Hessian of the Newton solver against central finite differences of
//! its objective (and of its gradient), for both modes.

mod support;

use camloc_learning::{DirectionSolver, Features, LogisticRegression, Mode, NewtonProblem};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const N: usize = 60;
const D: usize = 3;
const K: usize = 4;

fn problem(mode: Mode, lambda: f64) -> (NewtonProblem, Vec<f64>) {
    let (x, y) = support::gaussian_classes(N, D, K, 1.0, 2.0, 11);
    let features = Features::new(&x, D).expect("valid features");
    let config = LogisticRegression::default()
        .with_mode(mode)
        .with_lambda(lambda);
    let problem = NewtonProblem::new(&features, &y, K, &config).expect("valid problem");
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let theta: Vec<f64> = (0..problem.n_parameters())
        .map(|_| rng.random_range(-1.0..1.0))
        .collect();
    (problem, theta)
}

fn objective_at(problem: &mut NewtonProblem, theta: &[f64]) -> f64 {
    problem.set_parameters(theta).expect("finite parameters");
    problem.objective()
}

fn gradient_at(problem: &mut NewtonProblem, theta: &[f64]) -> Vec<f64> {
    problem.set_parameters(theta).expect("finite parameters");
    problem.gradient().to_vec()
}

fn check_gradient(mode: Mode) {
    let (mut problem, theta) = problem(mode, 0.7);
    let gradient = gradient_at(&mut problem, &theta);
    let h = 1e-5;
    for i in 0..theta.len() {
        let mut plus = theta.clone();
        let mut minus = theta.clone();
        plus[i] += h;
        minus[i] -= h;
        let fd =
            (objective_at(&mut problem, &plus) - objective_at(&mut problem, &minus)) / (2.0 * h);
        let tol = 1e-6 * (1.0 + fd.abs());
        assert!(
            (fd - gradient[i]).abs() <= tol,
            "{mode:?}: parameter {i}: finite difference {fd} vs gradient {}",
            gradient[i]
        );
    }
}

fn check_hessian(mode: Mode, zero_weights: bool) {
    let (mut problem, mut theta) = problem(mode, 0.7);
    if zero_weights {
        // Only biases: every sample has the same logits (the Gram-matrix shortcut).
        for (i, v) in theta.iter_mut().enumerate() {
            if i % (D + 1) != D {
                *v = 0.0;
            }
        }
    }
    problem.set_parameters(&theta).expect("finite parameters");
    problem.assemble_hessian();
    let hessian = problem.hessian().to_vec();
    let p = theta.len();
    assert_eq!(hessian.len(), p * p);
    let h = 1e-5;
    for j in 0..p {
        let mut plus = theta.clone();
        let mut minus = theta.clone();
        plus[j] += h;
        minus[j] -= h;
        let gp = gradient_at(&mut problem, &plus);
        let gm = gradient_at(&mut problem, &minus);
        for i in 0..p {
            let fd = (gp[i] - gm[i]) / (2.0 * h);
            let exact = hessian[j * p + i];
            assert!(
                (fd - exact).abs() <= 1e-5 * (1.0 + fd.abs()),
                "{mode:?}: H[{i}][{j}]: finite difference {fd} vs exact {exact}"
            );
            assert_eq!(
                exact,
                hessian[i * p + j],
                "Hessian not symmetric at ({i}, {j})"
            );
        }
    }
}

#[test]
fn multinomial_gradient_matches_finite_differences() {
    check_gradient(Mode::Multinomial);
}

#[test]
fn one_vs_rest_gradient_matches_finite_differences() {
    check_gradient(Mode::OneVsRest);
}

#[test]
fn multinomial_hessian_matches_finite_differences() {
    check_hessian(Mode::Multinomial, false);
}

#[test]
fn multinomial_hessian_with_zero_weights_matches_finite_differences() {
    check_hessian(Mode::Multinomial, true);
}

#[test]
fn one_vs_rest_hessian_matches_finite_differences() {
    check_hessian(Mode::OneVsRest, false);
}

#[test]
fn one_vs_rest_hessian_with_zero_weights_matches_finite_differences() {
    check_hessian(Mode::OneVsRest, true);
}

#[test]
fn one_vs_rest_hessian_is_block_diagonal() {
    let (mut problem, theta) = problem(Mode::OneVsRest, 0.7);
    problem.set_parameters(&theta).expect("finite parameters");
    problem.assemble_hessian();
    let p = theta.len();
    let dim = D + 1;
    for (index, &v) in problem.hessian().iter().enumerate() {
        let (row, col) = (index % p, index / p);
        if row / dim != col / dim {
            assert_eq!(v, 0.0, "coupling between classes at ({row}, {col})");
        }
    }
}

#[test]
fn objective_matches_direct_formula() {
    // Unstandardised, so that the direct formula needs no standardiser.
    let (x, y) = support::gaussian_classes(N, D, K, 1.0, 0.0, 3);
    let features = Features::new(&x, D).expect("valid features");
    let lambda = 0.25;
    let config = LogisticRegression::default()
        .with_lambda(lambda)
        .with_standardise(false);
    let mut problem = NewtonProblem::new(&features, &y, K, &config).expect("valid problem");
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let theta: Vec<f64> = (0..problem.n_parameters())
        .map(|_| rng.random_range(-2.0..2.0))
        .collect();
    problem.set_parameters(&theta).expect("finite parameters");
    let dim = D + 1;
    let mut expected = 0.0;
    for (row, &label) in x.chunks_exact(D).zip(&y) {
        let logits: Vec<f64> = (0..K)
            .map(|k| {
                let p = &theta[k * dim..(k + 1) * dim];
                p[D] + row.iter().zip(p).map(|(a, b)| a * b).sum::<f64>()
            })
            .collect();
        let norm: f64 = logits.iter().map(|z| z.exp()).sum();
        expected -= (logits[label].exp() / norm).ln();
    }
    for k in 0..K {
        expected += lambda
            * theta[k * dim..k * dim + D]
                .iter()
                .map(|w| w * w)
                .sum::<f64>();
    }
    let got = problem.objective();
    assert!(
        (got - expected).abs() <= 1e-10 * expected.abs(),
        "objective {got} vs direct {expected}"
    );
}

/// Hessian-vector products computed from the data equal the assembled Hessian times the
/// vector, for both modes, on enough samples to span several row tasks and a partial
/// last chunk; a vector of the wrong size is an error.
#[test]
fn hessian_vector_products_match_the_assembled_hessian() {
    let (n, d, k) = (5003, 6, 5);
    let (x, y) = support::gaussian_classes(n, d, k, 1.0, 2.0, 17);
    let features = Features::new(&x, d).expect("valid features");
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    for mode in [Mode::Multinomial, Mode::OneVsRest] {
        // The direct solver assembles the Hessian on every sample.
        let config = LogisticRegression::default()
            .with_mode(mode)
            .with_lambda(0.3)
            .with_direction_solver(DirectionSolver::Cholesky);
        let mut problem = NewtonProblem::new(&features, &y, k, &config).expect("valid problem");
        let p = problem.n_parameters();
        let theta: Vec<f64> = (0..p).map(|_| rng.random_range(-0.5..0.5)).collect();
        problem.set_parameters(&theta).expect("finite parameters");
        problem.assemble_hessian();
        let hessian = problem.hessian().to_vec();
        for _ in 0..3 {
            let v: Vec<f64> = (0..p).map(|_| rng.random_range(-1.0..1.0)).collect();
            let mut product = vec![0.0; p];
            problem
                .hessian_vector_product(&v, &mut product)
                .expect("sizes match");
            let scale = product.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for (i, &got) in product.iter().enumerate() {
                let expected: f64 = (0..p).map(|j| hessian[j * p + i] * v[j]).sum();
                assert!(
                    (got - expected).abs() <= 1e-12 * scale,
                    "{mode:?}: (H v)[{i}] = {got}, assembled {expected}"
                );
            }
        }
        let mut short = vec![0.0; p - 1];
        assert!(problem.hessian_vector_product(&theta, &mut short).is_err());
        assert!(
            problem
                .hessian_vector_product(&short, &mut vec![0.0; p])
                .is_err()
        );
    }
}
