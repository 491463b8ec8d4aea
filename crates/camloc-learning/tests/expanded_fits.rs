//! Fits on expanded features: rows expanded as the solver reads them
//! ([`DesignRows::expanded`]) give the fit on the same rows expanded and stored whole, to
//! the bit, and the expansion's own fit does not depend on the thread schedule.

mod support;

use camloc_learning::{DesignRows, Features, LogisticRegression, QuadraticExpansion};

#[test]
fn expanded_rows_fit_the_same_model_as_stored_expanded_rows() {
    let (d, k) = (6, 4);
    let (x, y) = support::gaussian_classes(3000, d, k, 0.8, 2.0, 11);
    let features = Features::new(&x, d).unwrap();
    let expansion = QuadraticExpansion::fit(&features, 4).unwrap();
    let stored = expansion.expand_rows(&features).unwrap();
    let config = LogisticRegression::default();
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
    assert!(whole_report.converged);
    assert_eq!(whole_report.iterations, streamed_report.iterations);
    assert_eq!(whole, streamed);
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
