//! Accuracy of a [`CameraLocalizer`] on a labelled dataset.

use camloc_dataset::Dataset;
use camloc_geometry::{CameraLabel, Level};
use camloc_skeleton::PartialPose2;
use camloc_store::Validate;
use serde::Serialize;

use rayon::prelude::*;

use crate::localizer::most_probable;
use crate::rows::sample_pose;
use crate::{CameraLocalizer, CamlocError};

/// Accuracy of one camera (by true label).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CameraAccuracy {
    /// The camera.
    pub label: CameraLabel,
    /// Its level and side in words, e.g. `"lower front"`.
    pub name: String,
    /// Samples whose true camera is this one.
    pub samples: usize,
    /// Share of them classified correctly; `None` (null in JSON) when there are none.
    pub accuracy: Option<f64>,
}

/// Accuracy of one level (by true label).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LevelAccuracy {
    /// The level.
    pub level: Level,
    /// Samples of that level.
    pub samples: usize,
    /// Share classified with the exact camera.
    pub accuracy: f64,
    /// Share classified with the right level (any side).
    pub level_accuracy: f64,
}

/// Results of [`evaluate`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Evaluation {
    /// Number of samples evaluated.
    pub samples: usize,
    /// Share classified with the exact camera (all classes).
    pub accuracy: f64,
    /// Share correct after mirror folding both truth and prediction (back -> front).
    pub accuracy_folded: f64,
    /// Per level.
    pub per_level: Vec<LevelAccuracy>,
    /// Per camera.
    pub per_camera: Vec<CameraAccuracy>,
    /// `confusion[t][p]`: samples of true label `t + 1` predicted as `p + 1` (0-based
    /// [`CameraLabel::index`] on both axes).
    pub confusion: Vec<Vec<usize>>,
}

/// Localizes every sample of `dataset` (using its missing-landmark masks) and compares with
/// the true labels.
///
/// # Errors
/// [`CamlocError::Dataset`] for a sample whose label is not a camera of the dataset or whose
/// clip index is out of range; [`CamlocError::Inconsistent`] when the dataset's cameras differ
/// from the model's, or it is empty; descriptor or prediction errors naming the sample.
pub fn evaluate(localizer: &CameraLocalizer, dataset: &Dataset) -> Result<Evaluation, CamlocError> {
    dataset.validate()?;
    let cameras = localizer.cameras();
    if dataset.header.cameras != *cameras {
        return Err(CamlocError::Inconsistent {
            what: "dataset",
            detail: format!(
                "its {} cameras differ from the model's {} cameras",
                dataset.header.cameras.len(),
                cameras.len()
            ),
        });
    }
    if dataset.samples.is_empty() {
        return Err(CamlocError::Inconsistent {
            what: "dataset",
            detail: "no samples to evaluate".into(),
        });
    }
    let poses: Vec<PartialPose2> = dataset.samples.iter().map(sample_pose).collect();
    let predicted = localizer.predict_labels(&poses)?;
    let k = cameras.len();
    let mut confusion = vec![vec![0usize; k]; k];
    for (s, &p) in dataset.samples.iter().zip(&predicted) {
        let t = usize::from(s.label) - 1;
        confusion[t][p.index()] += 1;
    }
    let n = dataset.samples.len();
    let share = |hits: usize, total: usize| {
        if total == 0 {
            0.0
        } else {
            hits as f64 / total as f64
        }
    };
    let correct: usize = (0..k).map(|t| confusion[t][t]).sum();
    let folded = dataset
        .samples
        .iter()
        .zip(&predicted)
        .filter(|(s, p)| cameras.fold_back_to_front(s.label) == cameras.fold_back_to_front(p.get()))
        .count();
    let views = cameras.viewpoints();
    let per_camera = views
        .iter()
        .map(|v| {
            let label = cameras.label(v.label)?;
            let row = &confusion[label.index()];
            Ok(CameraAccuracy {
                label,
                name: format!("{} {}", v.level.name(), v.side.name()),
                samples: row.iter().sum(),
                accuracy: (row.iter().sum::<usize>() > 0)
                    .then(|| share(row[label.index()], row.iter().sum())),
            })
        })
        .collect::<Result<_, CamlocError>>()?;
    let per_level = [Level::Lower, Level::Middle, Level::Upper]
        .into_iter()
        .filter_map(|level| {
            let (mut total, mut exact, mut same_level) = (0, 0, 0);
            for t in views.iter().filter(|v| v.level == level) {
                for p in views {
                    let c = confusion[usize::from(t.label) - 1][usize::from(p.label) - 1];
                    total += c;
                    if p.label == t.label {
                        exact += c;
                    }
                    if p.level == level {
                        same_level += c;
                    }
                }
            }
            (total > 0).then(|| LevelAccuracy {
                level,
                samples: total,
                accuracy: share(exact, total),
                level_accuracy: share(same_level, total),
            })
        })
        .collect();
    Ok(Evaluation {
        samples: n,
        accuracy: share(correct, n),
        accuracy_folded: share(folded, n),
        per_level,
        per_camera,
        confusion,
    })
}

impl CameraLocalizer {
    /// Most probable label of each pose, in parallel, one pose at a time in each thread's
    /// reused rows (nothing the size of the input but the labels is allocated); each label is
    /// the one [`localize_partial`](Self::localize_partial) gives.
    ///
    /// # Errors
    /// Descriptor errors naming the sample (its index in `poses`); prediction errors.
    pub fn predict_labels(&self, poses: &[PartialPose2]) -> Result<Vec<CameraLabel>, CamlocError> {
        poses
            .par_iter()
            .enumerate()
            .map(|(i, pose)| {
                self.with_pose_rows(
                    pose,
                    || format!("sample {i}"),
                    |rows| {
                        let mut probabilities = vec![0.0; self.cameras().len()];
                        self.camera_probabilities_into(
                            rows.classifier,
                            rows.classes,
                            &mut probabilities,
                        )?;
                        Ok(CameraLabel::from_index(most_probable(&probabilities).0)?)
                    },
                )
            })
            .collect()
    }
}
