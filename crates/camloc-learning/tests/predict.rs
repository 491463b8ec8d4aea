//! Prediction, softmax stability and input validation.

mod support;

use camloc_learning::{
    Features, LearningError, LogisticModel, LogisticRegression, Mode, Standardiser,
    softmax_in_place,
};
use proptest::prelude::*;

fn fitted(mode: Mode) -> (LogisticModel, Vec<f64>, Vec<usize>) {
    let (x, y) = support::gaussian_classes(150, 4, 3, 1.0, 2.0, 40);
    let features = Features::new(&x, 4).expect("valid");
    let (model, _) = LogisticRegression::default()
        .with_mode(mode)
        .fit(&features, &y, 3)
        .expect("fit");
    (model, x, y)
}

/// A model with huge coefficients, so that logits reach about ±1e300.
fn extreme_model(mode: Mode) -> LogisticModel {
    LogisticModel::new(
        mode,
        0.0,
        Standardiser::identity(2),
        vec![1e300, -1e300, 0.5, -0.7, 0.2, 1e299],
        vec![0.0, 1e300, -1e300],
    )
    .expect("valid model")
}

proptest! {
    #[test]
    fn softmax_is_a_distribution_for_huge_logits(
        logits in prop::collection::vec(-1e300f64..1e300, 1..16)
    ) {
        let mut p = logits.clone();
        softmax_in_place(&mut p);
        let sum: f64 = p.iter().sum();
        prop_assert!((sum - 1.0).abs() <= 1e-12, "sum {}", sum);
        prop_assert!(p.iter().all(|v| (0.0..=1.0).contains(v)));
        // The largest logit keeps the largest probability.
        let arg = |v: &[f64]| v.iter().enumerate().fold(0, |b, (i, &x)| if x > v[b] { i } else { b });
        prop_assert_eq!(p[arg(&logits)], p[arg(&p)]);
    }

    #[test]
    fn softmax_is_shift_invariant(
        logits in prop::collection::vec(-50.0f64..50.0, 2..12),
        shift in -1e3f64..1e3,
    ) {
        let mut a = logits.clone();
        let mut b: Vec<f64> = logits.iter().map(|z| z + shift).collect();
        softmax_in_place(&mut a);
        softmax_in_place(&mut b);
        for (x, y) in a.iter().zip(&b) {
            prop_assert!((x - y).abs() <= 1e-9);
        }
    }

    #[test]
    fn probabilities_sum_to_one_for_any_finite_input(
        x0 in -1e6f64..1e6, x1 in -1e6f64..1e6, one_vs_rest in any::<bool>(),
    ) {
        let mode = if one_vs_rest { Mode::OneVsRest } else { Mode::Multinomial };
        let model = extreme_model(mode);
        match model.predict_proba(&[x0, x1]) {
            Ok(p) => {
                let sum: f64 = p.iter().sum();
                prop_assert!((sum - 1.0).abs() <= 1e-12, "{:?}", p);
                prop_assert!(p.iter().all(|v| (0.0..=1.0).contains(v)));
            }
            // Opposite overflows (inf - inf) are reported, never returned as NaN.
            Err(e) => prop_assert!(matches!(e, LearningError::NanLogit { .. }), "{}", e),
        }
    }
}

#[test]
fn softmax_handles_infinite_logits() {
    let mut p = [f64::INFINITY, 1.0, f64::INFINITY];
    softmax_in_place(&mut p);
    assert_eq!(p, [0.5, 0.0, 0.5]);
    let mut p = [f64::NEG_INFINITY; 4];
    softmax_in_place(&mut p);
    assert_eq!(p, [0.25; 4]);
}

#[test]
fn one_vs_rest_normalises_underflowing_sigmoids() {
    // Every class logit is hugely negative: all sigmoids underflow to 0, yet the
    // normalised probabilities stay a distribution favouring the largest logit.
    let model = LogisticModel::new(
        Mode::OneVsRest,
        0.0,
        Standardiser::identity(1),
        vec![0.0; 3],
        vec![-1e300, -5e299, -1e299],
    )
    .expect("valid model");
    let p = model.predict_proba(&[1.0]).expect("finite");
    assert!((p.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{p:?}");
    assert_eq!(model.predict(&[1.0]).expect("finite"), 2);
}

#[test]
fn batch_prediction_equals_single_predictions_bitwise() {
    for mode in [Mode::Multinomial, Mode::OneVsRest] {
        let (model, x, _) = fitted(mode);
        let features = Features::new(&x, 4).expect("valid");
        let batch = model.predict_proba_batch(&features).expect("batch");
        let labels = model.predict_batch(&features).expect("batch");
        for ((row, p), &label) in x.chunks_exact(4).zip(batch.chunks_exact(3)).zip(&labels) {
            let single = model.predict_proba(row).expect("single");
            assert_eq!(single.as_slice(), p);
            let mut into = [0.0; 3];
            model.predict_proba_into(row, &mut into).expect("into");
            assert_eq!(into.as_slice(), p);
            assert_eq!(model.predict(row).expect("single"), label);
            let best = p.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
            assert_eq!(p[label], best);
        }
    }
}

#[test]
fn predictions_beat_chance_on_separated_classes() {
    let (model, x, y) = fitted(Mode::Multinomial);
    let accuracy = model
        .accuracy(&Features::new(&x, 4).expect("valid"), &y)
        .expect("accuracy");
    assert!(accuracy > 0.7, "accuracy {accuracy}");
}

#[test]
fn nan_input_is_rejected_with_its_position() {
    let data = [1.0, 2.0, 3.0, f64::NAN, 5.0, 6.0];
    match Features::new(&data, 2) {
        Err(LearningError::NonFinite { row, column, .. }) => assert_eq!((row, column), (1, 1)),
        other => panic!("expected NonFinite, got {other:?}"),
    }
    let (model, _, _) = fitted(Mode::Multinomial);
    match model.predict_proba(&[0.0, f64::INFINITY, 0.0, 0.0]) {
        Err(LearningError::NonFinite {
            row: 0, column: 1, ..
        }) => {}
        other => panic!("expected NonFinite, got {other:?}"),
    }
}

#[test]
fn wrong_sizes_are_rejected() {
    assert!(matches!(
        Features::new(&[1.0, 2.0, 3.0], 2),
        Err(LearningError::RaggedFeatures {
            len: 3,
            n_features: 2
        })
    ));
    assert!(matches!(
        Features::new(&[1.0], 0),
        Err(LearningError::NoFeatures)
    ));
    let (model, _, _) = fitted(Mode::Multinomial);
    assert!(matches!(
        model.predict_proba(&[1.0, 2.0]),
        Err(LearningError::SizeMismatch {
            expected: 4,
            found: 2,
            ..
        })
    ));
    let mut out = [0.0; 2];
    assert!(matches!(
        model.predict_proba_into(&[1.0; 4], &mut out),
        Err(LearningError::SizeMismatch {
            expected: 3,
            found: 2,
            ..
        })
    ));
    let three = Features::new(&[1.0; 6], 3).expect("valid");
    assert!(matches!(
        model.predict_proba_batch(&three),
        Err(LearningError::SizeMismatch { .. })
    ));
    let x = Features::new(&[1.0; 8], 4).expect("valid");
    assert!(matches!(
        LogisticRegression::default().fit(&x, &[0], 2),
        Err(LearningError::SizeMismatch {
            expected: 2,
            found: 1,
            ..
        })
    ));
}

#[test]
fn bad_labels_and_parameters_are_rejected() {
    let x = Features::new(&[0.0, 1.0, 2.0, 3.0], 1).expect("valid");
    assert!(matches!(
        LogisticRegression::default().fit(&x, &[0, 1, 3, 0], 3),
        Err(LearningError::LabelOutOfRange {
            row: 2,
            label: 3,
            n_classes: 3
        })
    ));
    assert!(matches!(
        LogisticRegression::default().fit(&x, &[0, 0, 0, 0], 1),
        Err(LearningError::TooFewClasses { n_classes: 1 })
    ));
    let empty = Features::new(&[], 3).expect("empty is valid data");
    assert_eq!(empty.n_samples(), 0);
    assert!(matches!(
        LogisticRegression::default().fit(&empty, &[], 2),
        Err(LearningError::NoSamples)
    ));
    for lambda in [-1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            LogisticRegression::default()
                .with_lambda(lambda)
                .fit(&x, &[0, 1, 0, 1], 2),
            Err(LearningError::InvalidParameter { name: "lambda", .. })
        ));
    }
    assert!(matches!(
        LogisticRegression::default()
            .with_gradient_tolerance(-1.0)
            .fit(&x, &[0, 1, 0, 1], 2),
        Err(LearningError::InvalidParameter {
            name: "gradient_tolerance",
            ..
        })
    ));
}

#[test]
fn model_constructor_checks_its_parts() {
    let s = Standardiser::identity(2);
    assert!(matches!(
        LogisticModel::new(
            Mode::Multinomial,
            0.1,
            s.clone(),
            vec![0.0; 5],
            vec![0.0; 3]
        ),
        Err(LearningError::SizeMismatch {
            expected: 6,
            found: 5,
            ..
        })
    ));
    assert!(matches!(
        LogisticModel::new(
            Mode::Multinomial,
            0.1,
            s.clone(),
            vec![0.0; 2],
            vec![0.0; 1]
        ),
        Err(LearningError::TooFewClasses { .. })
    ));
    assert!(matches!(
        LogisticModel::new(Mode::Multinomial, 0.1, s, vec![f64::NAN; 4], vec![0.0; 2]),
        Err(LearningError::InvalidParameter { .. })
    ));
    assert!(Standardiser::from_parts(vec![0.0], vec![0.0]).is_err());
}

/// A bias shift reweights the multinomial probabilities by `exp(shift)` and renormalises;
/// a shift of the wrong length or to a non-finite bias is refused.
#[test]
fn a_bias_shift_changes_the_class_priors() {
    let (model, x, _) = fitted(Mode::Multinomial);
    let shift = [0.7, -0.3, 0.0];
    let shifted = model.clone().with_bias_shift(&shift).unwrap();
    for row in x.chunks_exact(4).take(20) {
        let p = model.predict_proba(row).unwrap();
        let q = shifted.predict_proba(row).unwrap();
        let weighted: Vec<f64> = p.iter().zip(&shift).map(|(p, s)| p * s.exp()).collect();
        let total: f64 = weighted.iter().sum();
        for (w, q) in weighted.iter().zip(&q) {
            assert!((w / total - q).abs() < 1e-12, "{w} {q}");
        }
    }
    assert!(matches!(
        model.clone().with_bias_shift(&[0.0; 2]),
        Err(LearningError::SizeMismatch { .. })
    ));
    assert!(model.with_bias_shift(&[f64::NAN, 0.0, 0.0]).is_err());
}
