//! Rows in image pairs ([`DesignRows::in_image_pairs`]): a fit whose Hessian-vector products
//! read a subsample of the rows keeps the symmetry of a problem whose second half is the
//! image of its first, as the exact fit does.

mod support;

use camloc_learning::{DesignRows, DirectionSolver, Features, LogisticModel, LogisticRegression};

/// Classes 0 and 1 swap under the symmetry, class 2 stays.
const IMAGE_CLASS: [usize; 3] = [1, 0, 2];

/// A problem symmetric under `x -> -x` with classes 0 and 1 swapped: `n` rows, the second
/// half the images of the first, row for row.
fn symmetric_problem(n: usize, d: usize) -> (Vec<f64>, Vec<usize>) {
    let (mut x, mut y) = support::gaussian_classes(n / 2, d, 3, 0.8, 2.0, 21);
    let images: Vec<f64> = x.iter().map(|v| -v).collect();
    let image_labels: Vec<usize> = y.iter().map(|&c| IMAGE_CLASS[c]).collect();
    x.extend(images);
    y.extend(image_labels);
    (x, y)
}

/// Largest difference between the probability of class `c` at `x` and of its image class
/// at `-x`, over the rows of `x`.
fn asymmetry(model: &LogisticModel, x: &[f64], d: usize) -> f64 {
    x.chunks(d)
        .map(|row| {
            let image: Vec<f64> = row.iter().map(|v| -v).collect();
            let (p, q) = (
                model.predict_proba(row).unwrap(),
                model.predict_proba(&image).unwrap(),
            );
            (0..3)
                .map(|c| (p[c] - q[IMAGE_CLASS[c]]).abs())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

#[test]
fn subsampled_products_on_image_pairs_keep_the_symmetry() {
    let (n, d) = (20_000, 6);
    let (x, y) = symmetric_problem(n, d);
    let config = LogisticRegression::default()
        .with_lambda(1e-2)
        .with_gradient_tolerance(1e-7)
        .with_direction_solver(DirectionSolver::TruncatedCg {
            preconditioner_rows: 600,
            product_rows: n / 8,
        });
    let rows = DesignRows::plain(Features::new(&x, d).unwrap());
    let fit = |rows: &DesignRows<'_>| {
        let (model, report) = config.fit_rows_with_progress(rows, &y, 3, |_| {}).unwrap();
        assert!(report.converged, "{report:?}");
        model
    };
    let paired = fit(&rows.in_image_pairs().unwrap());
    let unpaired = fit(&rows);
    let test = &x[..2000 * d];
    let (kept, lost) = (asymmetry(&paired, test, d), asymmetry(&unpaired, test, d));
    assert!(kept < 1e-10, "image pairs: asymmetry {kept:e}");
    // The same subsample size without the pairs: the products split pairs, and the path
    // (stopped at the same tolerance) leaves the symmetry by far more.
    assert!(
        lost > 1e3 * kept.max(1e-14),
        "without pairs: {lost:e} vs {kept:e}"
    );
}

#[test]
fn an_odd_number_of_rows_cannot_be_image_pairs() {
    let x = vec![0.5; 3 * 2];
    let rows = DesignRows::plain(Features::new(&x, 2).unwrap());
    assert!(rows.in_image_pairs().is_err());
    assert!(!rows.has_image_pairs());
}
