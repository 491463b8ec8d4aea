//! Grouped cross-validation.

mod support;

use std::collections::HashMap;

use camloc_learning::{
    Features, LearningError, LogisticRegression, cross_validate_grouped, group_k_fold,
};
use proptest::prelude::*;

proptest! {
    #[test]
    fn a_group_never_spans_two_folds(
        groups in prop::collection::vec(0u8..20, 1..200),
        folds in 2usize..6,
    ) {
        let distinct = groups.iter().collect::<std::collections::HashSet<_>>().len();
        match group_k_fold(&groups, folds) {
            Ok(fold_of) => {
                prop_assert_eq!(fold_of.len(), groups.len());
                let mut seen: HashMap<u8, usize> = HashMap::new();
                for (g, &f) in groups.iter().zip(&fold_of) {
                    prop_assert!(f < folds);
                    let first = *seen.entry(*g).or_insert(f);
                    prop_assert_eq!(first, f, "group {} in folds {} and {}", g, first, f);
                }
                for f in 0..folds {
                    prop_assert!(fold_of.contains(&f), "fold {} is empty", f);
                }
            }
            Err(LearningError::TooFewGroups { groups: g, folds: f }) => {
                prop_assert!(distinct < folds);
                prop_assert_eq!((g, f), (distinct, folds));
            }
            Err(e) => prop_assert!(false, "unexpected error {}", e),
        }
    }
}

#[test]
fn folds_are_balanced_for_equal_groups() {
    let groups: Vec<usize> = (0..100).map(|i| i / 10).collect(); // 10 groups of 10
    let fold_of = group_k_fold(&groups, 5).expect("enough groups");
    for f in 0..5 {
        assert_eq!(fold_of.iter().filter(|&&x| x == f).count(), 20);
    }
}

#[test]
fn too_few_groups_or_folds_are_errors() {
    assert!(matches!(
        group_k_fold(&["a", "b", "a"], 3),
        Err(LearningError::TooFewGroups {
            groups: 2,
            folds: 3
        })
    ));
    assert!(matches!(
        group_k_fold(&[1, 2, 3], 1),
        Err(LearningError::InvalidParameter { name: "folds", .. })
    ));
}

#[test]
fn cross_validation_scores_every_candidate_and_picks_the_best() {
    let (n, d, k) = (240, 3, 3);
    let (x, y) = support::gaussian_classes(n, d, k, 1.0, 0.0, 19);
    let subjects: Vec<String> = (0..n).map(|i| format!("subject{}", i % 8)).collect();
    let features = Features::new(&x, d).expect("valid");
    let candidates = [
        LogisticRegression::default().with_lambda(1e4),
        LogisticRegression::default().with_lambda(0.1),
    ];
    let report = cross_validate_grouped(&features, &y, k, &subjects, 4, &candidates)
        .expect("cross-validation");
    assert_eq!(report.candidates.len(), 2);
    for (score, config) in report.candidates.iter().zip(&candidates) {
        assert_eq!(&score.config, config);
        assert_eq!(score.fold_accuracies.len(), 4);
        let mean = score.fold_accuracies.iter().sum::<f64>() / 4.0;
        assert!((score.mean_accuracy - mean).abs() < 1e-15);
        assert!(
            score
                .fold_accuracies
                .iter()
                .all(|a| (0.0..=1.0).contains(a))
        );
    }
    let best = report.best_candidate().expect("a best candidate");
    assert!(
        report
            .candidates
            .iter()
            .all(|c| c.mean_accuracy <= best.mean_accuracy)
    );
    // The huge ridge shrinks every weight to about zero: it cannot win.
    assert_eq!(report.best, 1);
    // Each subject is in one fold.
    let mut fold_of_subject = HashMap::new();
    for (s, &f) in subjects.iter().zip(&report.fold_of_sample) {
        assert_eq!(*fold_of_subject.entry(s).or_insert(f), f);
    }
}

#[test]
fn cross_validation_input_errors() {
    let (x, y) = support::gaussian_classes(20, 2, 2, 1.0, 0.0, 1);
    let features = Features::new(&x, 2).expect("valid");
    let groups: Vec<u32> = (0..20).map(|i| i % 2).collect();
    assert!(matches!(
        cross_validate_grouped(
            &features,
            &y,
            2,
            &groups,
            3,
            &[LogisticRegression::default()]
        ),
        Err(LearningError::TooFewGroups {
            groups: 2,
            folds: 3
        })
    ));
    assert!(matches!(
        cross_validate_grouped(&features, &y, 2, &groups, 2, &[]),
        Err(LearningError::NoCandidates)
    ));
    assert!(matches!(
        cross_validate_grouped(
            &features,
            &y,
            2,
            &groups[..5],
            2,
            &[LogisticRegression::default()]
        ),
        Err(LearningError::SizeMismatch { .. })
    ));
}
