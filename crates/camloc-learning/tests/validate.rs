//! A decoded model is checked by [`LogisticModel::validate`]: every inconsistency a hostile
//! file can hold is an error, never a panic or wrong probabilities.

mod support;

use camloc_learning::{Features, LearningError, LogisticModel, LogisticRegression, Mode};
use serde::{Deserialize, Serialize};

/// The serde layout of a `LogisticModel`, with public fields to tamper with.
#[derive(Clone, Serialize, Deserialize)]
struct RawModel {
    mode: Mode,
    lambda: f64,
    standardiser: RawStandardiser,
    n_classes: usize,
    weights: Vec<f64>,
    biases: Vec<f64>,
}

#[derive(Clone, Serialize, Deserialize)]
struct RawStandardiser {
    means: Vec<f64>,
    scales: Vec<f64>,
}

fn convert<A: Serialize, B: for<'de> Deserialize<'de>>(value: &A) -> B {
    let config = bincode::config::standard();
    let bytes = bincode::serde::encode_to_vec(value, config).expect("encode");
    bincode::serde::decode_from_slice(&bytes, config)
        .expect("same layout")
        .0
}

/// A fitted model of 54 features and 12 classes (648 weights), as raw parts.
fn raw() -> RawModel {
    let (x, y) = support::gaussian_classes(240, 54, 12, 1.0, 4.0, 5);
    let features = Features::new(&x, 54).expect("valid");
    let (model, _) = LogisticRegression::default()
        .with_lambda(1.0)
        .fit(&features, &y, 12)
        .expect("fit");
    let raw: RawModel = convert(&model);
    assert_eq!(raw.weights.len(), 648);
    raw
}

fn check(tamper: impl FnOnce(&mut RawModel)) -> LearningError {
    let mut r = raw();
    tamper(&mut r);
    let model: LogisticModel = convert(&r);
    model
        .validate()
        .expect_err("tampered model must be refused")
}

#[test]
fn the_untouched_model_is_valid_and_round_trips() {
    let r = raw();
    let model: LogisticModel = convert(&r);
    model.validate().expect("valid");
    assert_eq!(model.n_features(), 54);
}

#[test]
fn bias_vector_of_11_or_13_entries_is_refused() {
    for n in [11, 13] {
        let err = check(|r| r.biases.resize(n, 0.5));
        assert!(
            matches!(err, LearningError::SizeMismatch { expected: 12, found, .. } if found == n),
            "{err:?}"
        );
    }
}

#[test]
fn empty_weights_are_refused() {
    let err = check(|r| r.weights.clear());
    assert!(
        matches!(
            err,
            LearningError::SizeMismatch {
                expected: 648,
                found: 0,
                ..
            }
        ),
        "{err:?}"
    );
    let err = check(|r| {
        r.weights.clear();
        r.standardiser.means.clear();
        r.standardiser.scales.clear();
    });
    assert!(matches!(err, LearningError::NoFeatures), "{err:?}");
}

#[test]
fn weights_one_short_are_refused() {
    let err = check(|r| {
        r.weights.pop();
    });
    assert!(
        matches!(
            err,
            LearningError::SizeMismatch {
                expected: 648,
                found: 647,
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn scale_vector_one_short_is_refused() {
    let err = check(|r| {
        r.standardiser.scales.pop();
    });
    assert!(
        matches!(
            err,
            LearningError::SizeMismatch {
                expected: 54,
                found: 53,
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn non_finite_or_non_positive_numbers_are_refused() {
    let tampers: [fn(&mut RawModel); 6] = [
        |r| r.standardiser.means[3] = f64::INFINITY,
        |r| r.standardiser.means[0] = f64::NAN,
        |r| r.standardiser.scales[1] = 0.0,
        |r| r.biases[7] = f64::NEG_INFINITY,
        |r| r.weights[100] = f64::NAN,
        |r| r.lambda = -1.0,
    ];
    for (i, tamper) in tampers.into_iter().enumerate() {
        let err = check(tamper);
        assert!(
            matches!(err, LearningError::InvalidParameter { .. }),
            "case {i}: {err:?}"
        );
    }
}

#[test]
fn class_counts_that_overflow_are_refused() {
    let err = check(|r| r.n_classes = usize::MAX / 2);
    assert!(matches!(err, LearningError::SizeMismatch { .. }), "{err:?}");
    let err = check(|r| r.n_classes = 1);
    assert!(
        matches!(err, LearningError::TooFewClasses { .. }),
        "{err:?}"
    );
}
