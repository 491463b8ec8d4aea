//! Behaviour of whole fits: monotone objective, convergence, optimality, standardisation.

mod support;

use camloc_learning::{
    DirectionSolver, Features, FitReport, LogisticRegression, Mode, NewtonProblem, Termination,
};
use proptest::prelude::*;

/// Gradient of the objective at the fitted model, computed directly from its
/// probabilities on the standardised features (independent of the solver's code).
fn model_gradient(
    model: &camloc_learning::LogisticModel,
    x: &[f64],
    y: &[usize],
    d: usize,
) -> Vec<f64> {
    let k = model.n_classes();
    let s = model.standardiser();
    let mut g = vec![0.0; (d + 1) * k];
    for (row, &label) in x.chunks_exact(d).zip(y) {
        let p = model.predict_proba(row).expect("valid sample");
        let residual: Vec<f64> = (0..k)
            .map(|c| {
                let pc = match model.mode() {
                    Mode::Multinomial => p[c],
                    // One-vs-rest gradients use each class's own sigmoid.
                    Mode::OneVsRest => {
                        let z = model.decision_function(row).expect("valid sample")[c];
                        1.0 / (1.0 + (-z).exp())
                    }
                };
                pc - if c == label { 1.0 } else { 0.0 }
            })
            .collect();
        for c in 0..k {
            for j in 0..d {
                let v = (row[j] - s.means()[j]) / s.scales()[j];
                g[c * (d + 1) + j] += v * residual[c];
            }
            g[c * (d + 1) + d] += residual[c];
        }
    }
    for c in 0..k {
        for j in 0..d {
            g[c * (d + 1) + j] += 2.0 * model.lambda() * model.weights()[j * k + c];
        }
    }
    g
}

fn check_optimal(mode: Mode, n: usize) {
    let (d, k) = (5, 4);
    let (x, y) = support::gaussian_classes(n, d, k, 1.0, 4.0, 21);
    let features = Features::new(&x, d).expect("valid features");
    let config = LogisticRegression::default()
        .with_mode(mode)
        .with_lambda(0.2);
    let (model, report) = config.fit(&features, &y, k).expect("fit");
    assert!(report.converged, "{mode:?}: {:?}", report.termination);
    let g = model_gradient(&model, &x, &y, d);
    let norm = g.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    assert!(
        norm <= 1e-6 * n as f64,
        "{mode:?}: gradient norm {norm} at the optimum"
    );
    let last = report.iterations.last().expect("at least the start");
    assert!(last.gradient_norm <= config.gradient_tolerance * n as f64);
    let objective = model.objective(&features, &y).expect("objective");
    assert!(
        (objective - last.objective).abs() <= 1e-10 * objective,
        "model objective {objective} vs solver {}",
        last.objective
    );
}

#[test]
fn multinomial_fit_reaches_a_stationary_point() {
    check_optimal(Mode::Multinomial, 300);
}

#[test]
fn fits_split_over_many_row_tasks_reach_a_stationary_point() {
    // More samples than one parallel task of rows holds (2048): partial sums of the
    // gradient, logits and Hessian over tasks must add up.
    check_optimal(Mode::Multinomial, 5000);
    check_optimal(Mode::OneVsRest, 5000);
}

#[test]
fn one_vs_rest_fit_reaches_a_stationary_point() {
    check_optimal(Mode::OneVsRest, 300);
}

#[test]
fn multinomial_biases_sum_to_zero() {
    // The bias shift common to all classes is a null direction: the solver must take the
    // minimum-norm step, so from zero the biases keep summing to zero.
    let (x, y) = support::gaussian_classes(200, 3, 5, 1.5, 1.0, 8);
    let features = Features::new(&x, 3).expect("valid features");
    let (model, _) = LogisticRegression::default()
        .fit(&features, &y, 5)
        .expect("fit");
    let sum: f64 = model.biases().iter().sum();
    let scale: f64 = model.biases().iter().map(|b| b.abs()).sum();
    assert!(sum.abs() <= 1e-9 * (1.0 + scale), "biases sum to {sum}");
    for j in 0..3 {
        let s: f64 = model.weights()[j * 5..(j + 1) * 5].iter().sum();
        assert!(s.abs() <= 1e-9, "weights of feature {j} sum to {s}");
    }
}

#[test]
fn unregularised_multinomial_converges_on_overlapping_classes() {
    let (x, y) = support::gaussian_classes(400, 3, 3, 0.5, 0.0, 4);
    let features = Features::new(&x, 3).expect("valid features");
    let (_, report) = LogisticRegression::default()
        .with_lambda(0.0)
        .fit(&features, &y, 3)
        .expect("fit");
    assert!(report.converged, "{:?}", report.termination);
}

#[test]
fn separable_problem_is_fitted_perfectly() {
    for mode in [Mode::Multinomial, Mode::OneVsRest] {
        let (x, y) = support::gaussian_classes(240, 4, 3, 12.0, 0.0, 2);
        let features = Features::new(&x, 4).expect("valid features");
        let (model, report) = LogisticRegression::default()
            .with_mode(mode)
            .with_lambda(1e-3)
            .fit(&features, &y, 3)
            .expect("fit");
        assert!(report.converged, "{mode:?}: {:?}", report.termination);
        let accuracy = model.accuracy(&features, &y).expect("accuracy");
        assert_eq!(accuracy, 1.0, "{mode:?}");
    }
}

#[test]
fn max_iter_zero_returns_the_starting_point() {
    let (x, y) = support::gaussian_classes(50, 2, 3, 1.0, 0.0, 1);
    let features = Features::new(&x, 2).expect("valid features");
    let (model, report) = LogisticRegression::default()
        .with_max_iter(0)
        .fit(&features, &y, 3)
        .expect("fit");
    assert_eq!(report.termination, Termination::MaxIterations);
    assert!(!report.converged);
    assert_eq!(report.iterations.len(), 1);
    let p = model.predict_proba(&x[..2]).expect("valid sample");
    for v in p {
        assert!((v - 1.0 / 3.0).abs() < 1e-15);
    }
}

#[test]
fn progress_callback_sees_every_logged_iteration() {
    let (x, y) = support::gaussian_classes(120, 3, 3, 1.0, 0.0, 6);
    let features = Features::new(&x, 3).expect("valid features");
    let mut seen = Vec::new();
    let (_, report) = LogisticRegression::default()
        .fit_with_progress(&features, &y, 3, |log| seen.push(*log))
        .expect("fit");
    assert_eq!(seen, report.iterations);
    for (i, log) in seen.iter().enumerate() {
        assert_eq!(log.iteration, i);
    }
}

#[test]
fn standardisation_makes_the_fit_invariant_to_feature_units() {
    // Fitting on x and on a per-column affine image of x must give the same predictions
    // when each model is fed features in its own units: the standardiser is inside.
    let (n, d, k) = (200, 3, 3);
    let (x, y) = support::gaussian_classes(n, d, k, 1.0, 0.0, 12);
    let affine = |v: f64, j: usize| 1000.0 + v * [0.001, 50.0, 3.0][j];
    let x2: Vec<f64> = x
        .iter()
        .enumerate()
        .map(|(i, &v)| affine(v, i % d))
        .collect();
    let config = LogisticRegression::default();
    let (m1, _) = config
        .fit(&Features::new(&x, d).expect("valid"), &y, k)
        .expect("fit");
    let (m2, _) = config
        .fit(&Features::new(&x2, d).expect("valid"), &y, k)
        .expect("fit");
    for (r1, r2) in x.chunks_exact(d).zip(x2.chunks_exact(d)) {
        let p1 = m1.predict_proba(r1).expect("valid");
        let p2 = m2.predict_proba(r2).expect("valid");
        for (a, b) in p1.iter().zip(&p2) {
            assert!((a - b).abs() < 1e-7, "{p1:?} vs {p2:?}");
        }
    }
    let means = m2.standardiser().means();
    for (j, &stored) in means.iter().enumerate() {
        let mean = x2.iter().skip(j).step_by(d).sum::<f64>() / n as f64;
        assert!((stored - mean).abs() <= 1e-9 * mean.abs());
    }
}

#[test]
fn constant_columns_get_unit_scale_and_do_not_break_the_fit() {
    let (n, d, k) = (90, 3, 3);
    let (mut x, y) = support::gaussian_classes(n, d, k, 2.0, 0.0, 30);
    for row in x.chunks_exact_mut(d) {
        row[1] = 0.1; // constant column (its mean is not exactly 0.1 in floating point)
    }
    let features = Features::new(&x, d).expect("valid");
    let (model, report) = LogisticRegression::default()
        .fit(&features, &y, k)
        .expect("fit");
    assert!(report.converged);
    assert_eq!(model.standardiser().scales()[1], 1.0);
    for c in 0..k {
        assert!(
            model.weights()[k + c].abs() < 1e-12,
            "constant column got a weight"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn objective_never_increases(
        seed in 0u64..10_000,
        n in 12usize..80,
        d in 1usize..5,
        k in 2usize..5,
        separation in 0.0f64..6.0,
        lambda in prop_oneof![Just(0.0), 1e-4f64..10.0],
        one_vs_rest in any::<bool>(),
        solver in prop_oneof![
            Just(DirectionSolver::PreconditionedCg),
            Just(DirectionSolver::Cholesky),
            (1usize..20, 1usize..100).prop_map(|(preconditioner_rows, product_rows)| {
                DirectionSolver::TruncatedCg { preconditioner_rows, product_rows }
            }),
        ],
    ) {
        let (x, y) = support::gaussian_classes(n, d, k, separation, 1.0, seed);
        let features = Features::new(&x, d).expect("valid");
        let mode = if one_vs_rest { Mode::OneVsRest } else { Mode::Multinomial };
        let config = LogisticRegression::default()
            .with_mode(mode)
            .with_lambda(lambda)
            .with_max_iter(30)
            .with_direction_solver(solver);
        let mut problem = NewtonProblem::new(&features, &y, k, &config).expect("valid");
        let mut previous = problem.objective();
        for _ in 0..config.max_iter {
            let log = problem.newton_step().expect("step");
            prop_assert!(log.objective <= previous, "objective rose from {} to {}", previous, log.objective);
            prop_assert_eq!(log.objective, problem.objective());
            previous = log.objective;
            if log.step == 0.0 || log.gradient_norm <= 1e-10 * n as f64 {
                break;
            }
        }
    }
}

#[test]
fn duplicated_columns_without_ridge_still_fit() {
    // Two identical columns and lambda = 0: the Hessian is singular along (e_a - e_b) for
    // every class; the solver must still return a model (damping or minimum-norm steps)
    // whose objective is below the starting one.
    for mode in [Mode::Multinomial, Mode::OneVsRest] {
        let (base, y) = support::gaussian_classes(150, 2, 3, 1.0, 0.0, 13);
        let x: Vec<f64> = base
            .chunks_exact(2)
            .flat_map(|r| [r[0], r[1], r[1]])
            .collect();
        let features = Features::new(&x, 3).expect("valid");
        let (model, report) = LogisticRegression::default()
            .with_mode(mode)
            .with_lambda(0.0)
            .with_standardise(false)
            .with_max_iter(50)
            .fit(&features, &y, 3)
            .expect("fit");
        let first = report.iterations.first().expect("start").objective;
        let last = report.iterations.last().expect("end").objective;
        assert!(last < first, "{mode:?}: objective {first} -> {last}");
        assert!(model.weights().iter().all(|w| w.is_finite()));
        assert!(model.accuracy(&features, &y).expect("accuracy") > 0.5);
    }
}

#[test]
fn fits_are_bit_for_bit_reproducible() {
    let (x, y) = support::gaussian_classes(5000, 4, 3, 0.7, 1.0, 99);
    let features = Features::new(&x, 4).expect("valid");
    let config = LogisticRegression::default();
    let (m1, r1) = config.fit(&features, &y, 3).expect("fit");
    let (m2, r2) = config.fit(&features, &y, 3).expect("fit");
    assert_eq!(m1, m2);
    assert_eq!(r1, r2);
}

/// Every step of `report` lowers the objective, and its last objective is within `relative`
/// of `reference`'s last one.
fn assert_descends_to(report: &FitReport, reference: &FitReport, relative: f64, what: &str) {
    for pair in report.iterations.windows(2) {
        assert!(
            pair[1].objective <= pair[0].objective,
            "{what}: objective rose at iteration {}",
            pair[1].iteration
        );
    }
    let (a, b) = (
        report.iterations.last().expect("log").objective,
        reference.iterations.last().expect("log").objective,
    );
    assert!((a - b).abs() <= relative * b, "{what}: optimum {a} vs {b}");
}

/// The problems of the solver-comparison tests: `(lambda, n, d, k, features, labels)` for
/// a ridge of 1, a weak one and none (lambda = 0 makes every feature's all-classes shift a
/// singular direction), on overlapping Gaussian classes.
fn solver_test_problems() -> impl Iterator<Item = (f64, usize, usize, usize, Vec<f64>, Vec<usize>)>
{
    [(1.0, 5), (1e-3, 6), (0.0, 7)]
        .into_iter()
        .map(|(lambda, seed)| {
            let (n, d, k) = (3000, 8, 5);
            let (x, y) = support::gaussian_classes(n, d, k, 0.8, 2.0, seed);
            (lambda, n, d, k, x, y)
        })
}

/// The default solver (truncated Newton-CG on a subsampled preconditioner) reaches the
/// optimum of exact Newton (fresh Hessian and Cholesky every iteration): same objective to
/// rounding, same probabilities to the solver tolerance, every step descending; with and
/// without the ridge, on more samples than the preconditioner's rows.
#[test]
fn default_solver_reaches_the_direct_optimum() {
    let (n, d, k) = (6000, 8, 5);
    for (lambda, seed) in [(1.0, 5), (1e-3, 6), (0.0, 7)] {
        let (x, y) = support::gaussian_classes(n, d, k, 0.8, 2.0, seed);
        let features = Features::new(&x, d).expect("valid");
        let config = LogisticRegression::default().with_lambda(lambda);
        assert_eq!(config.direction_solver, DirectionSolver::PreconditionedCg);
        let rows = config.direction_solver.preconditioner_rows(n, (d + 1) * k);
        assert!(
            rows < n,
            "the preconditioner should be subsampled: {rows} rows"
        );
        let direct = config
            .clone()
            .with_direction_solver(DirectionSolver::Cholesky);
        let (model, report) = config.fit(&features, &y, k).expect("fit");
        let (reference, direct_report) = direct.fit(&features, &y, k).expect("fit");
        assert!(
            report.converged && direct_report.converged,
            "lambda {lambda}: {report:?} {direct_report:?}"
        );
        assert!(report.cg_products() > 0 && report.iterations.iter().any(|l| l.truncated));
        assert_descends_to(
            &report,
            &direct_report,
            1e-12,
            &format!("lambda {lambda}, default vs direct"),
        );
        let mut largest = 0.0f64;
        for row in x.chunks_exact(d) {
            let p = model.predict_proba(row).expect("valid");
            let q = reference.predict_proba(row).expect("valid");
            for (pv, qv) in p.iter().zip(&q) {
                largest = largest.max((pv - qv).abs());
            }
        }
        assert!(
            largest <= 1e-6,
            "lambda {lambda}: probabilities differ by {largest:e}"
        );
    }
}

/// With a tolerance no fit can meet, the solver stops once the objective has stopped
/// changing (rounding floor) instead of taking tiny steps until `max_iter`.
#[test]
fn an_unreachable_tolerance_ends_in_no_progress_not_max_iterations() {
    for (lambda, n, d, k, x, y) in solver_test_problems() {
        let features = Features::new(&x, d).expect("valid");
        for solver in [DirectionSolver::PreconditionedCg, DirectionSolver::Cholesky] {
            let (_, report) = LogisticRegression::default()
                .with_lambda(lambda)
                .with_gradient_tolerance(0.0)
                .with_max_iter(200)
                .with_direction_solver(solver)
                .fit(&features, &y, k)
                .expect("fit");
            let steps = report.newton_iterations();
            assert_eq!(
                report.termination,
                Termination::NoProgress,
                "lambda {lambda}, {solver:?}: {steps} iterations"
            );
            assert!(
                steps < 40,
                "lambda {lambda}, {solver:?}: {steps} iterations"
            );
            // The last gradient is at the rounding floor of a converged fit.
            let last = report.iterations.last().expect("log");
            assert!(last.gradient_norm <= 1e-8 * n as f64, "{last:?}");
        }
    }
}

/// Truncated Newton-CG with a preconditioner assembled on a tenth of the samples: every
/// step lowers the objective, early steps spend few products, and the fit reaches the
/// optimum of the exact Newton fit (with and without the ridge).
#[test]
fn truncated_cg_on_a_subsampled_preconditioner_reaches_the_exact_optimum() {
    for (lambda, n, d, k, x, y) in solver_test_problems() {
        let features = Features::new(&x, d).expect("valid");
        let exact = LogisticRegression::default()
            .with_lambda(lambda)
            .with_gradient_tolerance(1e-9)
            .with_direction_solver(DirectionSolver::Cholesky);
        let truncated = exact
            .clone()
            .with_direction_solver(DirectionSolver::TruncatedCg {
                preconditioner_rows: n / 10,
                product_rows: n,
            });
        let problem = NewtonProblem::new(&features, &y, k, &truncated).expect("valid");
        assert_eq!(problem.hessian_rows(), n / 10);
        let (_, report) = truncated.fit(&features, &y, k).expect("fit");
        let (_, reference) = exact.fit(&features, &y, k).expect("fit");
        assert!(report.converged, "lambda {lambda}: {report:?}");
        assert_descends_to(
            &report,
            &reference,
            1e-9,
            &format!("lambda {lambda}, truncated vs exact"),
        );
        assert!(report.hessian_assemblies() >= 1 && report.cg_products() > 0);
    }
    for (preconditioner_rows, product_rows) in [(0, 10), (10, 0)] {
        let zero =
            LogisticRegression::default().with_direction_solver(DirectionSolver::TruncatedCg {
                preconditioner_rows,
                product_rows,
            });
        assert!(zero.validate().is_err());
    }
}

/// Subsampled Newton-CG: conjugate gradients on the Hessian of a quarter of the samples
/// (every fourth task of rows), the gradient and the line search exact. Every step lowers the
/// objective and the fit reaches the optimum of the exact Newton fit; its products are
/// cheaper, so more of them fit the budget, but the directions differ from the exact
/// products' (the subsample is used).
#[test]
fn truncated_cg_on_subsampled_products_reaches_the_exact_optimum() {
    let (n, d, k) = (20_000, 6, 4);
    for (lambda, seed) in [(1.0, 11), (1e-3, 12)] {
        let (x, y) = support::gaussian_classes(n, d, k, 0.8, 2.0, seed);
        let features = Features::new(&x, d).expect("valid");
        let exact = LogisticRegression::default()
            .with_lambda(lambda)
            .with_gradient_tolerance(1e-8)
            .with_max_iter(200)
            .with_direction_solver(DirectionSolver::Cholesky);
        let solver = |product_rows| DirectionSolver::TruncatedCg {
            preconditioner_rows: 500,
            product_rows,
        };
        let subsampled = exact.clone().with_direction_solver(solver(n / 4));
        assert_eq!(subsampled.direction_solver.product_rows(n), n / 4);
        let (_, report) = subsampled.fit(&features, &y, k).expect("fit");
        let (_, reference) = exact.fit(&features, &y, k).expect("fit");
        let (_, whole) = exact
            .clone()
            .with_direction_solver(solver(n))
            .fit(&features, &y, k)
            .expect("fit");
        assert!(report.converged, "lambda {lambda}: {report:?}");
        assert_ne!(
            report.iterations, whole.iterations,
            "lambda {lambda}: the products did not use the subsample"
        );
        assert_descends_to(
            &report,
            &reference,
            1e-9,
            &format!("lambda {lambda}, subsampled vs exact"),
        );
    }
}
