//! Grouped k-fold cross-validation: every sample of a group (a subject) lands in the same
//! fold, so that no subject is both trained and tested on.

use std::collections::HashMap;
use std::hash::Hash;

use crate::data::check_labels;
use crate::{Features, LearningError, LogisticRegression};

/// Assigns every sample to one of `folds` folds so that all samples of a group share a
/// fold, balancing the number of samples per fold.
///
/// Deterministic: groups are taken from the largest to the smallest (ties in order of first
/// appearance), each into the fold that currently has the fewest samples (lowest index on
/// ties), as scikit-learn's `GroupKFold` does. Every fold receives at least one group.
///
/// # Errors
/// [`LearningError::InvalidParameter`] if `folds < 2`; [`LearningError::TooFewGroups`] if
/// there are fewer distinct groups than folds.
pub fn group_k_fold<G: Hash + Eq>(groups: &[G], folds: usize) -> Result<Vec<usize>, LearningError> {
    if folds < 2 {
        return Err(LearningError::InvalidParameter {
            name: "folds",
            value: folds.to_string(),
            reason: "cross-validation needs at least 2 folds",
        });
    }
    // Distinct groups in order of first appearance, with their sizes.
    let mut index_of: HashMap<&G, usize> = HashMap::new();
    let mut sizes: Vec<usize> = Vec::new();
    let sample_group: Vec<usize> = groups
        .iter()
        .map(|g| {
            let next = sizes.len();
            let gi = *index_of.entry(g).or_insert(next);
            if gi == next {
                sizes.push(0);
            }
            if let Some(s) = sizes.get_mut(gi) {
                *s += 1;
            }
            gi
        })
        .collect();
    if sizes.len() < folds {
        return Err(LearningError::TooFewGroups {
            groups: sizes.len(),
            folds,
        });
    }
    let mut order: Vec<usize> = (0..sizes.len()).collect();
    order.sort_by_key(|&g| std::cmp::Reverse(sizes[g]));
    let mut fold_sizes = vec![0usize; folds];
    let mut fold_of_group = vec![0usize; sizes.len()];
    for g in order {
        let (fold, _) = fold_sizes
            .iter()
            .enumerate()
            .min_by_key(|&(f, &s)| (s, f))
            .unwrap_or((0, &0));
        fold_sizes[fold] += sizes[g];
        fold_of_group[g] = fold;
    }
    Ok(sample_group.iter().map(|&g| fold_of_group[g]).collect())
}

/// Cross-validated score of one candidate configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct CandidateScore {
    /// The configuration.
    pub config: LogisticRegression,
    /// Test accuracy (fraction in `[0, 1]`) on each fold, in fold order.
    pub fold_accuracies: Vec<f64>,
    /// Whether each fold's fit met its gradient tolerance.
    pub fold_converged: Vec<bool>,
    /// Unweighted mean of `fold_accuracies`.
    pub mean_accuracy: f64,
}

/// Result of [`cross_validate_grouped`].
#[derive(Clone, Debug, PartialEq)]
pub struct CvReport {
    /// Fold of every sample (from [`group_k_fold`]).
    pub fold_of_sample: Vec<usize>,
    /// One score per candidate, in the order given.
    pub candidates: Vec<CandidateScore>,
    /// Index into `candidates` of the best mean accuracy (first one on ties).
    pub best: usize,
}

impl CvReport {
    /// The best candidate's score.
    pub fn best_candidate(&self) -> Option<&CandidateScore> {
        self.candidates.get(self.best)
    }
}

/// Grouped k-fold cross-validation of several configurations.
///
/// Folds come from [`group_k_fold`] (all samples of a group in one fold). For each candidate
/// and each fold, the candidate is fitted on the other folds (standardisation included, so
/// nothing of the test fold leaks) and its accuracy measured on the fold.
///
/// # Errors
/// [`LearningError::NoCandidates`], label errors as in [`LogisticRegression::fit`],
/// [`LearningError::SizeMismatch`] if there is not one group per sample, fold errors as in
/// [`group_k_fold`], and any fitting error.
pub fn cross_validate_grouped<G: Hash + Eq>(
    x: &Features<'_>,
    y: &[usize],
    n_classes: usize,
    groups: &[G],
    folds: usize,
    candidates: &[LogisticRegression],
) -> Result<CvReport, LearningError> {
    if candidates.is_empty() {
        return Err(LearningError::NoCandidates);
    }
    check_labels(y, x.n_samples(), n_classes)?;
    if groups.len() != x.n_samples() {
        return Err(LearningError::SizeMismatch {
            what: "number of groups (one per sample)",
            expected: x.n_samples(),
            found: groups.len(),
        });
    }
    let fold_of_sample = group_k_fold(groups, folds)?;
    let splits: Vec<(Vec<usize>, Vec<usize>)> = (0..folds)
        .map(|f| (0..x.n_samples()).partition(|&i| fold_of_sample[i] != f))
        .collect();
    let mut scores = Vec::with_capacity(candidates.len());
    for config in candidates {
        let mut fold_accuracies = Vec::with_capacity(folds);
        let mut fold_converged = Vec::with_capacity(folds);
        for (train, test) in &splits {
            let train_x = x.select_rows(train);
            let train_y: Vec<usize> = train.iter().map(|&i| y[i]).collect();
            let test_x = x.select_rows(test);
            let test_y: Vec<usize> = test.iter().map(|&i| y[i]).collect();
            let train_x = Features::new(&train_x, x.n_features())?;
            let test_x = Features::new(&test_x, x.n_features())?;
            let (model, report) = config.fit(&train_x, &train_y, n_classes)?;
            fold_accuracies.push(model.accuracy(&test_x, &test_y)?);
            fold_converged.push(report.converged);
        }
        let mean_accuracy = fold_accuracies.iter().sum::<f64>() / folds as f64;
        scores.push(CandidateScore {
            config: config.clone(),
            fold_accuracies,
            fold_converged,
            mean_accuracy,
        });
    }
    let best = scores
        .iter()
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |(bi, bv), (i, s)| {
            if s.mean_accuracy > bv {
                (i, s.mean_accuracy)
            } else {
                (bi, bv)
            }
        })
        .0;
    Ok(CvReport {
        fold_of_sample,
        candidates: scores,
        best,
    })
}
