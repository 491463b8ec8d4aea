//! Fits on expanded features: rows expanded as the solver reads them
//! ([`DesignRows::expanded`]) give the fit on the same rows expanded and stored whole, to
//! the bit, and the expansion's own fit does not depend on the thread schedule.

mod support;

use camloc_learning::{
    DesignRows, DirectionSolver, Features, LogisticRegression, Mode, QuadraticExpansion,
};

/// Fits `config` on `n` rows expanded and stored whole, and on the same rows expanded as the
/// solver reads them (its design matrix then generated chunk by chunk), and asserts that
/// the two models are equal to the bit.
fn assert_same_fit(n: usize, config: LogisticRegression) {
    let (d, k) = (6, 4);
    let (x, y) = support::gaussian_classes(n, d, k, 0.8, 2.0, 11);
    let features = Features::new(&x, d).unwrap();
    let expansion = QuadraticExpansion::fit(&features, 4).unwrap();
    let stored = expansion.expand_rows(&features).unwrap();
    let (whole, whole_report) = config
        .fit(
            &Features::new(&stored, expansion.n_outputs()).unwrap(),
            &y,
            k,
        )
        .unwrap();
    let rows = DesignRows::expanded(features, &expansion).unwrap();
    assert_eq!(rows.n_features(), expansion.n_outputs());
    let (streamed, streamed_report) = config.fit_rows_with_progress(&rows, &y, k, |_| {}).unwrap();
    assert!(whole_report.converged, "{config:?}");
    assert_eq!(whole_report.iterations, streamed_report.iterations);
    assert_eq!(whole, streamed, "{config:?}");
}

#[test]
fn expanded_rows_fit_the_same_model_as_stored_expanded_rows() {
    assert_same_fit(3000, LogisticRegression::default());
}

/// The generated design matrix on every path that reads it: chunks and tasks that do not
/// divide the rows, a preconditioner on a subset of the rows, Hessian-vector products on a
/// subset of the tasks, the direct Cholesky solve on all rows, and one-vs-rest.
#[test]
fn every_solver_fits_the_same_model_on_generated_rows() {
    let base = LogisticRegression::default();
    assert_same_fit(
        7_001,
        base.clone()
            .with_direction_solver(DirectionSolver::TruncatedCg {
                preconditioner_rows: 700,
                product_rows: 7_001,
            }),
    );
    assert_same_fit(
        9_001,
        base.clone()
            .with_direction_solver(DirectionSolver::TruncatedCg {
                preconditioner_rows: 900,
                product_rows: 2_100,
            }),
    );
    assert_same_fit(
        5_003,
        base.clone()
            .with_direction_solver(DirectionSolver::Cholesky),
    );
    assert_same_fit(2_500, base.with_mode(Mode::OneVsRest));
}

#[test]
fn expanded_rows_need_the_expansion_inputs() {
    let (x, _) = support::gaussian_classes(100, 5, 2, 1.0, 0.0, 3);
    let features = Features::new(&x, 5).unwrap();
    let expansion = QuadraticExpansion::fit(&features, 3).unwrap();
    let (other, _) = support::gaussian_classes(100, 4, 2, 1.0, 0.0, 3);
    let err = DesignRows::expanded(Features::new(&other, 4).unwrap(), &expansion).unwrap_err();
    assert!(err.to_string().contains("expansion input"), "{err}");
}

/// The expansion's fit (a covariance summed over parallel tasks) does not depend on how many
/// threads ran it, so that training is reproducible.
#[test]
fn the_expansion_fit_does_not_depend_on_the_thread_count() {
    let d = 12;
    let (x, _) = support::gaussian_classes(120_000, d, 5, 1.0, 2.0, 5);
    let features = Features::new(&x, d).unwrap();
    let fit_with = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| QuadraticExpansion::fit(&features, 6).unwrap())
    };
    let one = fit_with(1);
    for threads in [2, 3, 4] {
        assert!(fit_with(threads) == one, "{threads} threads");
    }
}
