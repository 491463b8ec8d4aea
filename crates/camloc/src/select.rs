//! Choosing descriptor settings and lambda by cross-validation grouped by subject.

use camloc_dataset::Dataset;
use camloc_features::Descriptor;
use camloc_learning::{CvReport, Features, LogisticRegression, cross_validate_grouped};
use camloc_skeleton::PartialPose2;
use camloc_store::Validate;

use crate::CamlocError;
use crate::rows::{extract_rows, impute_rows, sample_pose};

/// Cross-validation of one descriptor over several regression settings.
#[derive(Clone, Debug)]
pub struct DescriptorCv {
    /// The descriptor.
    pub descriptor: Descriptor,
    /// Accuracy per regression candidate and fold, and the best candidate.
    pub report: CvReport,
}

/// `folds`-fold cross-validation grouped by subject (no subject in two folds) of every
/// descriptor with every regression candidate, on `dataset`, with the linear capacity
/// ([`Capacity::Linear`](crate::Capacity::Linear): the classifier on the descriptor itself). Values undefined by missing
/// landmarks are imputed with the dataset's means. Returns one report per descriptor.
///
/// # Errors
/// [`CamlocError::Dataset`] for an invalid sample label or clip index; descriptor errors
/// naming the sample, and learning errors (e.g. fewer subjects than folds).
pub fn cross_validate(
    dataset: &Dataset,
    descriptors: &[Descriptor],
    candidates: &[LogisticRegression],
    folds: usize,
) -> Result<Vec<DescriptorCv>, CamlocError> {
    dataset.validate()?;
    let poses: Vec<PartialPose2> = dataset.samples.iter().map(sample_pose).collect();
    // Labels are 1..=cameras (checked by `dataset.validate()`).
    let y: Vec<usize> = dataset
        .samples
        .iter()
        .map(|s| usize::from(s.label) - 1)
        .collect();
    let groups: Vec<&str> = dataset
        .samples
        .iter()
        .map(|s| dataset.subject_of(s))
        .collect();
    descriptors
        .iter()
        .map(|descriptor| {
            let (mut x, undefined) = extract_rows(descriptor, &poses, 0)?;
            let means = crate::rows::column_means(&x, &undefined, descriptor.len());
            impute_rows(&mut x, &undefined, &means);
            let features = Features::new(&x, descriptor.len())?;
            let report = cross_validate_grouped(
                &features,
                &y,
                dataset.header.cameras.len(),
                &groups,
                folds,
                candidates,
            )?;
            Ok(DescriptorCv {
                descriptor: *descriptor,
                report,
            })
        })
        .collect()
}
