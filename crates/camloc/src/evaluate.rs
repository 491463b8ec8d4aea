//! Accuracy of a [`CameraLocalizer`] on a labelled dataset.

use camloc_dataset::{Dataset, Sample, angle_between_deg, camera_direction_deg};
use camloc_geometry::{CameraLabel, Level};
use camloc_reconstruct::{Reconstructor, median};
use camloc_skeleton::PartialPose2;
use camloc_store::Validate;
use serde::Serialize;

use rayon::prelude::*;

use crate::localizer::most_probable;
use crate::rows::sample_pose;
use crate::{CameraLocalizer, CamlocError};

/// How far the continuous viewpoints (`Localization::azimuth_deg`, `elevation_deg`) of a
/// group of samples lie from each sample's true camera direction (from its camera rotation:
/// docs/conventions.md section 2).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ViewpointAccuracy {
    /// Median angle between the answered viewpoint and the true direction, degrees.
    pub median_error_deg: f64,
    /// Share of samples answered more than 45 deg from the true direction.
    pub beyond_45: f64,
    /// Mean answered minus true elevation, degrees (positive: read as seen from higher up).
    pub mean_elevation_error_deg: f64,
    /// Share of samples whose error is within the `uncertainty_deg` answered with them
    /// (calibrated to hold about 68%).
    pub within_uncertainty: f64,
}

/// Accuracy of one camera (by true label).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CameraAccuracy {
    /// The camera.
    pub label: CameraLabel,
    /// Its level and side in words, e.g. `"lower front"` (a sphere of more than 4 azimuths
    /// has several cameras of one side: their angles tell them apart).
    pub name: String,
    /// Its azimuth, degrees (docs/conventions.md section 2).
    pub azimuth_deg: f64,
    /// Its elevation, degrees.
    pub elevation_deg: f64,
    /// Samples whose true camera is this one.
    pub samples: usize,
    /// Share of them classified correctly; `None` (null in JSON) when there are none.
    pub accuracy: Option<f64>,
    /// Their continuous viewpoints' errors; `None` when there are none or the model has no
    /// viewpoint heads.
    pub viewpoint: Option<ViewpointAccuracy>,
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
    /// Their continuous viewpoints' errors; `None` when the model has no viewpoint heads.
    pub viewpoint: Option<ViewpointAccuracy>,
}

/// Accuracy of one ring of cameras, one elevation (by true label): the levels' lines split
/// where a camera set has several rings in one level (Table 1's rings are its levels).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RingAccuracy {
    /// The ring's elevation, degrees.
    pub elevation_deg: f64,
    /// Its level.
    pub level: Level,
    /// Samples of its cameras.
    pub samples: usize,
    /// Share classified with the exact camera.
    pub accuracy: f64,
    /// Share classified with a camera of the right ring (any azimuth).
    pub ring_accuracy: f64,
    /// Their continuous viewpoints' errors; `None` when the model has no viewpoint heads.
    pub viewpoint: Option<ViewpointAccuracy>,
}

/// The bands of true camera elevation [`Evaluation::per_elevation_band`] reports, degrees
/// (`[lo, hi)`, the last one closed): edges at +-7.5, +-22.5 (Table 1's ring borders), +-37.5,
/// +-52.5 and +-67.5, and at 15, which splits the middle ring's upper half (where room cameras
/// stand, 4-20 deg above a pelvis) in two.
pub const ELEVATION_BANDS_DEG: [(f64, f64); 12] = [
    (-90.0, -67.5),
    (-67.5, -52.5),
    (-52.5, -37.5),
    (-37.5, -22.5),
    (-22.5, -7.5),
    (-7.5, 7.5),
    (7.5, 15.0),
    (15.0, 22.5),
    (22.5, 37.5),
    (37.5, 52.5),
    (52.5, 67.5),
    (67.5, 90.0),
];

/// The continuous viewpoints' errors of the samples whose true camera elevation lies in one
/// band.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BandAccuracy {
    /// The band's lower edge, degrees.
    pub from_deg: f64,
    /// Its upper edge, degrees (exclusive but for the last band).
    pub to_deg: f64,
    /// Samples whose true direction lies in it.
    pub samples: usize,
    /// Their errors.
    pub viewpoint: ViewpointAccuracy,
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
    /// The continuous viewpoints' errors; `None` when the model has no viewpoint heads.
    pub viewpoint: Option<ViewpointAccuracy>,
    /// Per level.
    pub per_level: Vec<LevelAccuracy>,
    /// Per ring (elevation) of cameras.
    pub per_ring: Vec<RingAccuracy>,
    /// The continuous viewpoints' errors per band of true elevation ([`ELEVATION_BANDS_DEG`];
    /// the bands with samples), where a mean over a ring hides a pull toward its middle (a
    /// regression answers near the elevations it was trained on: cameras at a ring's edges
    /// are read toward its centre); empty when the model has no viewpoint heads.
    pub per_elevation_band: Vec<BandAccuracy>,
    /// Per camera.
    pub per_camera: Vec<CameraAccuracy>,
    /// `confusion[t][p]`: samples of true label `t + 1` predicted as `p + 1` (0-based
    /// [`CameraLabel::index`] on both axes).
    pub confusion: Vec<Vec<usize>>,
}

/// Localizes every sample of `dataset` (using its missing-landmark masks) and compares with
/// the true labels, and, when the model has viewpoint heads, the continuous viewpoints with
/// the true camera directions.
///
/// # Errors
/// [`CamlocError::Dataset`] for a sample whose label is not a camera of the dataset or whose
/// clip index is out of range; [`CamlocError::Inconsistent`] when the dataset's cameras differ
/// from the model's, or it is empty; descriptor or prediction errors naming the sample.
pub fn evaluate(localizer: &CameraLocalizer, dataset: &Dataset) -> Result<Evaluation, CamlocError> {
    evaluate_with(localizer, dataset, None)
}

/// [`evaluate`] of the samples as `camloc localize` localizes them
/// ([`CameraLocalizer::localize_filled`]): a sample with missing landmarks, or with a landmark
/// far off the others, has them filled in by `filler` instead of its descriptor's missing
/// values replaced by their training means (on a simulated reviewer's 1,118 views with
/// landmarks missing, 85.9% right and a median viewpoint error of 10.0 deg, against 76.3% and
/// 22.6 deg). Other samples get [`evaluate`]'s answers; a filled one costs a few tenths of a
/// millisecond (more with more cameras: 52,736 views of a 32-camera sphere, 22 s on 2
/// cores).
///
/// # Errors
/// As [`evaluate`]; the fill's errors naming the sample.
pub fn evaluate_filled(
    localizer: &CameraLocalizer,
    dataset: &Dataset,
    filler: &Reconstructor,
) -> Result<Evaluation, CamlocError> {
    evaluate_with(localizer, dataset, Some(filler))
}

/// [`evaluate`], with the missing landmarks filled in by `filler` if given.
fn evaluate_with(
    localizer: &CameraLocalizer,
    dataset: &Dataset,
    filler: Option<&Reconstructor>,
) -> Result<Evaluation, CamlocError> {
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
    let answered = answers(localizer, dataset, &poses, filler)?;
    let k = cameras.len();
    let mut confusion = vec![vec![0usize; k]; k];
    // Each true camera's samples' viewpoint errors (none without viewpoint heads).
    let mut by_camera: Vec<Vec<ViewpointError>> = vec![Vec::new(); k];
    let mut folded = 0;
    for (s, (p, error)) in dataset.samples.iter().zip(answered) {
        let t = usize::from(s.label) - 1;
        confusion[t][p.index()] += 1;
        by_camera[t].extend(error);
        folded +=
            usize::from(cameras.fold_back_to_front(s.label) == cameras.fold_back_to_front(p.get()));
    }
    let n = dataset.samples.len();
    let correct: usize = (0..k).map(|t| confusion[t][t]).sum();
    let views = cameras.viewpoints();
    // The viewpoint errors of the samples whose true camera `keep` accepts.
    let viewpoint_of = |keep: &dyn Fn(usize) -> bool| {
        let group: Vec<ViewpointError> = (by_camera.iter().enumerate())
            .filter(|&(t, _)| keep(t))
            .flat_map(|(_, errors)| errors.iter().copied())
            .collect();
        ViewpointAccuracy::of(&group)
    };
    // Samples, exact hits and hits of a camera `same` accepts, of the true cameras `keep`
    // accepts.
    let tally = |keep: &dyn Fn(usize) -> bool, same: &dyn Fn(usize) -> bool| {
        let (mut total, mut exact, mut close) = (0, 0, 0);
        for t in (0..k).filter(|&t| keep(t)) {
            for (p, &c) in confusion[t].iter().enumerate() {
                total += c;
                exact += if p == t { c } else { 0 };
                close += if same(p) { c } else { 0 };
            }
        }
        (total, share(exact, total), share(close, total))
    };
    let per_camera = views
        .iter()
        .map(|v| {
            let label = cameras.label(v.label)?;
            let (samples, accuracy, _) = tally(&|t| t == label.index(), &|_| false);
            Ok(CameraAccuracy {
                label,
                name: format!("{} {}", v.level.name(), v.side.name()),
                azimuth_deg: v.azimuth_deg,
                elevation_deg: v.elevation_deg,
                samples,
                accuracy: (samples > 0).then_some(accuracy),
                viewpoint: viewpoint_of(&|t| t == label.index()),
            })
        })
        .collect::<Result<_, CamlocError>>()?;
    let per_level = [Level::Lower, Level::Middle, Level::Upper]
        .into_iter()
        .filter_map(|level| {
            let of_level = |c: usize| views[c].level == level;
            let (samples, accuracy, level_accuracy) = tally(&of_level, &of_level);
            (samples > 0).then(|| LevelAccuracy {
                level,
                samples,
                accuracy,
                level_accuracy,
                viewpoint: viewpoint_of(&of_level),
            })
        })
        .collect();
    let per_ring = cameras
        .elevations_deg()
        .iter()
        .filter_map(|&elevation_deg| {
            let of_ring = |c: usize| views[c].elevation_deg == elevation_deg;
            let (samples, accuracy, ring_accuracy) = tally(&of_ring, &of_ring);
            (samples > 0).then(|| RingAccuracy {
                elevation_deg,
                level: Level::nearest(elevation_deg),
                samples,
                accuracy,
                ring_accuracy,
                viewpoint: viewpoint_of(&of_ring),
            })
        })
        .collect();
    let last = ELEVATION_BANDS_DEG.len() - 1;
    let per_elevation_band = (ELEVATION_BANDS_DEG.iter().enumerate())
        .filter_map(|(b, &(from_deg, to_deg))| {
            let band: Vec<ViewpointError> = (by_camera.iter().flatten())
                .filter(|e| {
                    let t = e.true_elevation_deg;
                    t >= from_deg && (t < to_deg || (b == last && t <= to_deg))
                })
                .copied()
                .collect();
            Some(BandAccuracy {
                from_deg,
                to_deg,
                samples: band.len(),
                viewpoint: ViewpointAccuracy::of(&band)?,
            })
        })
        .collect();
    Ok(Evaluation {
        samples: n,
        accuracy: share(correct, n),
        accuracy_folded: share(folded, n),
        viewpoint: viewpoint_of(&|_| true),
        per_level,
        per_ring,
        per_elevation_band,
        per_camera,
        confusion,
    })
}

/// `hits / total`, 0 for no samples.
fn share(hits: usize, total: usize) -> f64 {
    if total == 0 {
        0.0
    } else {
        hits as f64 / total as f64
    }
}

/// One sample's continuous-viewpoint error.
#[derive(Clone, Copy, Debug)]
struct ViewpointError {
    /// Angle between the answered viewpoint and the true direction, degrees.
    angle_deg: f64,
    /// Answered minus true elevation, degrees.
    elevation_deg: f64,
    /// The true elevation, degrees.
    true_elevation_deg: f64,
    /// Whether the angle is within the answered uncertainty.
    within_uncertainty: bool,
}

impl ViewpointAccuracy {
    /// The summary of `errors`; `None` for none.
    fn of(errors: &[ViewpointError]) -> Option<ViewpointAccuracy> {
        let n = errors.len();
        let mut angles: Vec<f64> = errors.iter().map(|e| e.angle_deg).collect();
        let median = median(&mut angles)?;
        let count = |f: &dyn Fn(&ViewpointError) -> bool| errors.iter().filter(|e| f(e)).count();
        Some(ViewpointAccuracy {
            median_error_deg: median,
            beyond_45: share(count(&|e| e.angle_deg > 45.0), n),
            mean_elevation_error_deg: errors.iter().map(|e| e.elevation_deg).sum::<f64>()
                / n as f64,
            within_uncertainty: share(count(&|e| e.within_uncertainty), n),
        })
    }
}

/// The label of every pose of `dataset` and, when the localizer has viewpoint heads, the
/// error of its continuous viewpoint (by the sample's true camera direction), in parallel;
/// poses with missing landmarks filled in by `filler` if given.
///
/// # Errors
/// Descriptor and fill errors naming the sample; prediction errors.
fn answers(
    localizer: &CameraLocalizer,
    dataset: &Dataset,
    poses: &[PartialPose2],
    filler: Option<&Reconstructor>,
) -> Result<Vec<(CameraLabel, Option<ViewpointError>)>, CamlocError> {
    if localizer.viewpoint_heads().is_none() && filler.is_none() {
        let labels = localizer.predict_labels(poses)?;
        return Ok(labels.into_iter().map(|label| (label, None)).collect());
    }
    poses
        .par_iter()
        .zip(&dataset.samples)
        .enumerate()
        .map(|(i, (pose, sample))| {
            // Every sample through the fill, as `localize`: a landmark far off the others is
            // missing there too, and a complete pose costs what `localize_partial` costs.
            let l = match filler {
                Some(filler) => localizer.localize_filled(pose, filler).map_err(|e| {
                    CamlocError::Inconsistent {
                        what: "dataset",
                        detail: format!("sample {i}: {e}"),
                    }
                })?,
                None => localizer.localize_tempered(pose, 1.0, || format!("sample {i}"))?,
            };
            let error = match (l.azimuth_deg, l.elevation_deg, l.uncertainty_deg) {
                (Some(azimuth), Some(elevation), Some(uncertainty)) => {
                    Some(viewpoint_error(sample, azimuth, elevation, uncertainty))
                }
                _ => None,
            };
            Ok((l.label, error))
        })
        .collect()
}

/// The error of answering the viewpoint `(azimuth, elevation)` with `uncertainty` (degrees)
/// for `sample`.
fn viewpoint_error(
    sample: &Sample,
    azimuth: f64,
    elevation: f64,
    uncertainty: f64,
) -> ViewpointError {
    let truth = camera_direction_deg(&sample.rotation);
    let angle_deg = angle_between_deg((azimuth, elevation), truth);
    ViewpointError {
        angle_deg,
        elevation_deg: elevation - truth.1,
        true_elevation_deg: truth.1,
        within_uncertainty: angle_deg <= uncertainty,
    }
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
