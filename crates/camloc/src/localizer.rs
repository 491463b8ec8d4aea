//! [`CameraLocalizer`]: descriptor + classifier + camera set, saved and used together; the
//! localization of one pose or many. Training is in `train.rs`.

use camloc_dataset::PostureGroup;
use camloc_features::Descriptor;
use camloc_geometry::{CameraLabel, CameraSet, Level, Matrix3, Side, look_at_origin, sphere_point};
use camloc_learning::{DirectionHeads, LogisticModel, QuadraticExpansion, softmax_in_place};
use camloc_reconstruct::Intrinsics;
use camloc_skeleton::{Landmark, PartialPose2, Pose2};
use camloc_store::{FileKind, Persist, Validate};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::rows::{extract_rows, impute_rows};
use crate::{CameraHeight, CamlocError, TrainingInfo};

/// Where the camera stood, as localized from one 2D pose.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Localization {
    /// Most probable camera (Table 1 numbering for the default cameras).
    pub label: CameraLabel,
    /// Its height class.
    pub level: Level,
    /// Its side of the body.
    pub side: Side,
    /// Its rotation (rows: camera x, y, z axes in the canonical body frame).
    pub rotation: Matrix3,
    /// Probability of `label`.
    pub probability: f64,
    /// Probability of every camera, index [`CameraLabel::index`].
    pub probabilities: Vec<f64>,
    /// `label` after mirror folding (back -> front of the same level, paper section 8.1).
    pub folded_label: CameraLabel,
    /// Landmarks that were missing in the input (their descriptor values were imputed).
    pub missing: Vec<Landmark>,
    /// Continuous camera azimuth in degrees, `[0, 360)`, in the person's canonical frame
    /// (docs/conventions.md section 2: 180 = in front, 270 = the person's left, 0 = behind,
    /// 90 = the person's right); `None` when the model has no viewpoint heads.
    pub azimuth_deg: Option<f64>,
    /// Continuous camera elevation in degrees, `[-90, 90]`, positive above the person (under
    /// [`CameraHeight::Shares`] with an input's middle-camera elevation, a middle-ring camera's
    /// is moved toward it: [`HeightShares::elevations_deg`](crate::HeightShares::elevations_deg));
    /// `None` when the model has no viewpoint heads.
    pub elevation_deg: Option<f64>,
    /// Angular radius in degrees around (`azimuth_deg`, `elevation_deg`) that held about
    /// 68% of the true directions of the calibration samples with a class probability like
    /// this one's; `None` when the model has no viewpoint heads.
    pub uncertainty_deg: Option<f64>,
}

impl Localization {
    /// The rotation (rows: camera x, y, z axes in the canonical body frame) of a camera
    /// that looks at the body from the continuous viewpoint (`azimuth_deg`, `elevation_deg`),
    /// without roll (docs/conventions.md section 2, "Looking at the body"); the class's
    /// `rotation` when the model has no viewpoint heads or the viewpoint is straight above or
    /// below. The camera `camloc reconstruct`'s `hybrid` starts from: a few degrees from the
    /// truth where the class's centre may be 45 away.
    pub fn viewpoint_rotation(&self) -> Matrix3 {
        match (self.azimuth_deg, self.elevation_deg) {
            (Some(azimuth), Some(elevation)) => {
                look_at_origin(sphere_point(azimuth, elevation, 1.0)).unwrap_or(self.rotation)
            }
            _ => self.rotation,
        }
    }
}

/// A trained camera localizer: descriptor, classifier and the camera set it predicts.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CameraLocalizer {
    pub(crate) descriptor: Descriptor,
    pub(crate) cameras: CameraSet,
    /// The feature expansion between descriptor and classifier ([`Capacity::Quadratic`]);
    /// `None`: the classifier sees the descriptor.
    ///
    /// [`Capacity::Quadratic`]: crate::Capacity::Quadratic
    pub(crate) expansion: Option<QuadraticExpansion>,
    /// The classifier: `cameras.len() * posture_groups` classes, class `g * cameras + c` being
    /// camera `c` (0-based) seen on a body of posture group `g`.
    pub(crate) model: LogisticModel,
    /// Posture groups the classifier's classes are split into: those present in the
    /// training data (1: none; see
    /// [`TrainOptions::posture_classes`](crate::TrainOptions::posture_classes)).
    pub(crate) posture_groups: usize,
    /// Per descriptor value, the training mean used in place of undefined values.
    pub(crate) imputation: Vec<f64>,
    pub(crate) info: TrainingInfo,
    /// Continuous-viewpoint heads refining the class to a direction (`None`: not fitted).
    pub(crate) viewpoint: Option<DirectionHeads>,
    /// What the viewpoint heads see: `None`, the classifier's features; else the descriptor
    /// expanded by this quadratic expansion of their own
    /// ([`CameraLocalizer::fit_viewpoint_with_capacity`]).
    pub(crate) viewpoint_expansion: Option<QuadraticExpansion>,
    /// The prior over the camera's height this localizer applies (not saved with the model:
    /// [`CameraLocalizer::with_camera_height`]).
    #[serde(skip)]
    pub(crate) camera_height: CameraHeight,
    /// The camera's intrinsics, when known: each pose is localized as a camera aimed at it
    /// would see it (not saved with the model: [`CameraLocalizer::with_intrinsics`]).
    #[serde(skip)]
    pub(crate) intrinsics: Option<Intrinsics>,
}

/// [`Intrinsics::check`] as a [`CamlocError::InvalidOption`] (the localizer's and the
/// reconstructor's `with_intrinsics`).
pub(crate) fn check_intrinsics(intrinsics: &Intrinsics) -> Result<(), CamlocError> {
    intrinsics.check().map_err(|e| CamlocError::InvalidOption {
        name: "intrinsics",
        detail: e.to_string(),
    })
}

impl CameraLocalizer {
    /// The descriptor rows of `poses` (row-major), in parallel, undefined values imputed.
    /// Errors name a pose by `first` plus its index in `poses`.
    pub(crate) fn descriptor_rows(
        &self,
        poses: &[PartialPose2],
        first: usize,
    ) -> Result<Vec<f64>, CamlocError> {
        let (mut x, undefined) = extract_rows(&self.descriptor, poses, first)?;
        impute_rows(&mut x, &undefined, &self.imputation);
        Ok(x)
    }

    /// The number of features the viewpoint heads see.
    pub(crate) fn head_width(&self) -> usize {
        self.viewpoint_expansion
            .as_ref()
            .map_or(self.feature_width(), QuadraticExpansion::n_outputs)
    }

    /// The quadratic expansion of the descriptor the viewpoint heads see, if they have their
    /// own (else they see the classifier's features).
    pub fn viewpoint_expansion(&self) -> Option<&QuadraticExpansion> {
        self.viewpoint_expansion.as_ref()
    }

    /// The number of features the classifier sees: the descriptor's, or the expansion's
    /// outputs.
    pub(crate) fn feature_width(&self) -> usize {
        self.expansion
            .as_ref()
            .map_or(self.descriptor.len(), QuadraticExpansion::n_outputs)
    }

    /// The probability of every camera for the feature row `x` into `out` (one per
    /// camera) under the model's own priors: the classifier's class probabilities (into
    /// `classes`, one per class) summed over the posture groups.
    pub(crate) fn model_camera_probabilities_into(
        &self,
        x: &[f64],
        classes: &mut [f64],
        out: &mut [f64],
    ) -> Result<(), CamlocError> {
        self.model.predict_proba_into(x, classes)?;
        out.fill(0.0);
        for group in classes.chunks_exact(out.len()) {
            for (o, p) in out.iter_mut().zip(group) {
                *o += p;
            }
        }
        Ok(())
    }

    /// [`model_camera_probabilities_into`](Self::model_camera_probabilities_into) weighed by
    /// the localizer's [`CameraHeight`] prior: what its localizations report.
    pub(crate) fn camera_probabilities_into(
        &self,
        x: &[f64],
        classes: &mut [f64],
        out: &mut [f64],
    ) -> Result<(), CamlocError> {
        self.model_camera_probabilities_into(x, classes, out)?;
        self.camera_height
            .reweigh(&self.cameras, &self.info.camera_priors, out);
        Ok(())
    }

    /// This localizer with the prior `height` over the camera's height (replacing any set
    /// before): every localization, label and evaluation it makes from now on weighs the
    /// cameras by it ([`CameraHeight`]). The model file is unchanged; a loaded model starts
    /// with [`CameraHeight::Any`].
    #[must_use]
    pub fn with_camera_height(mut self, height: CameraHeight) -> Self {
        self.camera_height = height;
        self
    }

    /// The prior over the camera's height this localizer applies.
    pub fn camera_height(&self) -> CameraHeight {
        self.camera_height
    }

    /// This localizer for poses seen by a camera of known `intrinsics` (pixels; `None`:
    /// unknown): each pose is localized as the camera turned about its centre to aim at the
    /// pelvis would see it ([`aimed_at_pelvis`](crate::aimed_at_pelvis)), the views the model
    /// was trained on; the viewpoint (where the camera stands) is the same. A person near the
    /// edge of a wide-angle image is otherwise drawn out by the perspective (a simulated
    /// user's views at f = 500 px, the pelvis 500 px off-centre: 58% against 77% centred).
    /// Without a principal point nothing changes. The model file is unchanged.
    ///
    /// # Errors
    /// [`CamlocError::InvalidOption`] for a focal length that is not finite and positive or a
    /// principal point that is not finite.
    pub fn with_intrinsics(mut self, intrinsics: Option<Intrinsics>) -> Result<Self, CamlocError> {
        if let Some(k) = &intrinsics {
            check_intrinsics(k)?;
        }
        self.intrinsics = intrinsics;
        Ok(self)
    }

    /// The camera's intrinsics this localizer aims the poses with, if given.
    pub fn intrinsics(&self) -> Option<Intrinsics> {
        self.intrinsics
    }

    /// Posture groups the classifier's classes are split into (1 unless trained with
    /// [`TrainOptions::posture_classes`](crate::TrainOptions::posture_classes)).
    pub fn posture_groups(&self) -> usize {
        self.posture_groups
    }

    /// The continuous-viewpoint heads, if the model has them.
    pub fn viewpoint_heads(&self) -> Option<&DirectionHeads> {
        self.viewpoint.as_ref()
    }

    /// The descriptor the model was trained with.
    pub fn descriptor(&self) -> &Descriptor {
        &self.descriptor
    }

    /// The camera classes.
    pub fn cameras(&self) -> &CameraSet {
        &self.cameras
    }

    /// The feature expansion between descriptor and classifier, if the model has one
    /// ([`Capacity::Quadratic`]).
    ///
    /// [`Capacity::Quadratic`]: crate::Capacity::Quadratic
    pub fn expansion(&self) -> Option<&QuadraticExpansion> {
        self.expansion.as_ref()
    }

    /// The fitted classifier (on the expanded features when the model has an expansion).
    pub fn model(&self) -> &LogisticModel {
        &self.model
    }

    /// What the model was trained on.
    pub fn training_info(&self) -> &TrainingInfo {
        &self.info
    }

    /// Per descriptor value, the training mean used in place of values that depend on a
    /// missing landmark.
    pub fn imputation(&self) -> &[f64] {
        &self.imputation
    }

    /// Localizes the camera of a complete 2D pose (image coordinates, any units).
    ///
    /// # Errors
    /// [`CamlocError::Feature`] for non-finite landmarks or a degenerate torso.
    pub fn localize(&self, pose: &Pose2) -> Result<Localization, CamlocError> {
        self.localize_partial(&PartialPose2::from(*pose))
    }

    /// Localizes the camera of a 2D pose with possibly missing landmarks; values of the
    /// descriptor that depend on a missing landmark are replaced by their training mean. A
    /// landmark far off the others ([`crate::without_far_off_landmarks`]) is missing too.
    ///
    /// # Errors
    /// [`CamlocError::Feature`] when the pelvis or neck is missing, for non-finite landmarks
    /// or a degenerate torso.
    pub fn localize_partial(&self, pose: &PartialPose2) -> Result<Localization, CamlocError> {
        self.localize_tempered(pose, 1.0, || "input pose".into())
    }

    /// [`localize_partial`](Self::localize_partial) with the model's own probabilities
    /// tempered (`p^(1 / temperature)`, normalised; 1 leaves them as they are) before the
    /// camera-height prior weighs them: the answer of a pose whose missing landmarks were
    /// filled in is less certain than the filled-in pose looks (docs/conventions.md section 6).
    /// A descriptor error is given `context()` (which names the pose).
    pub(crate) fn localize_tempered(
        &self,
        pose: &PartialPose2,
        temperature: f64,
        context: impl FnOnce() -> String,
    ) -> Result<Localization, CamlocError> {
        // A landmark far off the others is read as missing (and so listed).
        let (cleaned, _) = crate::without_far_off_landmarks(pose);
        let pose = &cleaned;
        self.with_clean_pose_rows(pose, context, |rows| {
            let mut probabilities = vec![0.0; self.cameras.len()];
            self.model_camera_probabilities_into(
                rows.classifier,
                rows.classes,
                &mut probabilities,
            )?;
            if temperature != 1.0 {
                temper(&mut probabilities, temperature);
            }
            // The uncertainty is calibrated on the model's own probabilities (kept when
            // a prior over the height changes them).
            let own = (self.camera_height != CameraHeight::Any).then(|| probabilities.clone());
            self.camera_height
                .reweigh(&self.cameras, &self.info.camera_priors, &mut probabilities);
            let heads_x: &[f64] = match &self.viewpoint_expansion {
                Some(e) => {
                    rows.head_row.resize(e.n_outputs(), 0.0);
                    e.expand_into(rows.descriptor, rows.head_row)?;
                    rows.head_row
                }
                None => rows.classifier,
            };
            self.localization_from(heads_x, probabilities, pose.missing().collect(), own)
        })
    }

    /// Runs `f` on the rows of `pose` made in this thread's [`RowBuffers`]: its descriptor
    /// (undefined values imputed) and the classifier's features (expanded if the model has
    /// an expansion). A descriptor error is given `context()` (which names the pose).
    pub(crate) fn with_pose_rows<R>(
        &self,
        pose: &PartialPose2,
        context: impl FnOnce() -> String,
        f: impl FnOnce(PoseRows<'_>) -> Result<R, CamlocError>,
    ) -> Result<R, CamlocError> {
        // A landmark far off the others is read as missing.
        let (cleaned, _) = crate::without_far_off_landmarks(pose);
        self.with_clean_pose_rows(&cleaned, context, f)
    }

    /// [`with_pose_rows`](Self::with_pose_rows) of a pose whose landmarks far off the others
    /// were already taken out ([`crate::without_far_off_landmarks`]).
    fn with_clean_pose_rows<R>(
        &self,
        pose: &PartialPose2,
        context: impl FnOnce() -> String,
        f: impl FnOnce(PoseRows<'_>) -> Result<R, CamlocError>,
    ) -> Result<R, CamlocError> {
        ROW_BUFFERS.with_borrow_mut(|buffers| {
            let RowBuffers {
                descriptor,
                undefined,
                expanded,
                head_row,
                classes,
            } = buffers;
            let d = self.descriptor.len();
            descriptor.resize(d, 0.0);
            undefined.resize(d, false);
            let aimed = match self
                .intrinsics
                .map(|k| crate::aimed_at_pelvis(pose, &k))
                .transpose()
            {
                Ok(aimed) => aimed,
                Err(source) => {
                    return Err(CamlocError::Reconstruct {
                        context: context(),
                        source,
                    });
                }
            };
            self.descriptor
                .extract_partial_into(aimed.as_ref().unwrap_or(pose), descriptor, undefined)
                .map_err(|source| CamlocError::Feature {
                    context: context(),
                    source,
                })?;
            impute_rows(descriptor, undefined, &self.imputation);
            let classifier: &[f64] = match &self.expansion {
                Some(e) => {
                    expanded.resize(e.n_outputs(), 0.0);
                    e.expand_into(descriptor, expanded)?;
                    expanded
                }
                None => descriptor,
            };
            classes.resize(self.model.n_classes(), 0.0);
            f(PoseRows {
                descriptor,
                classifier,
                head_row,
                classes,
            })
        })
    }

    /// Localizes many poses in parallel; one result per pose, in order.
    pub fn localize_batch(&self, poses: &[PartialPose2]) -> Vec<Result<Localization, CamlocError>> {
        poses.par_iter().map(|p| self.localize_partial(p)).collect()
    }

    /// The localization of a pose whose camera probabilities are `probabilities` (under the
    /// localizer's [`CameraHeight`]; `own`: the model's own, when they differ) and whose
    /// viewpoint heads' features are `heads_x`. The uncertainty is looked up by the model's own
    /// probability of the chosen camera, the probability it was calibrated on: under
    /// `--camera-height from-input` the reweighted one held the errors of 65% of the `rig`
    /// views of validation subjects, the model's own 79% (calibrated to hold about 68%;
    /// docs/RESULTS.md).
    fn localization_from(
        &self,
        heads_x: &[f64],
        probabilities: Vec<f64>,
        missing: Vec<Landmark>,
        own: Option<Vec<f64>>,
    ) -> Result<Localization, CamlocError> {
        let (best, probability) = most_probable(&probabilities);
        let (mut azimuth_deg, mut elevation_deg, mut uncertainty_deg) = (None, None, None);
        if let Some(heads) = &self.viewpoint {
            let u = heads.predict(best, heads_x)?;
            // (`% 360`: a tiny negative angle rounds to 360 under `rem_euclid`.)
            azimuth_deg = Some(u[1].atan2(u[0]).to_degrees().rem_euclid(360.0) % 360.0);
            let read = u[2].clamp(-1.0, 1.0).asin().to_degrees();
            elevation_deg = Some((read + self.input_elevation_shift_deg(best)).clamp(-90.0, 90.0));
            uncertainty_deg =
                Some(heads.uncertainty_deg(own.as_ref().map_or(probability, |o| o[best])));
        }
        let label = CameraLabel::from_index(best)?;
        let view = self.cameras.get(label.get());
        let folded = self.cameras.fold_back_to_front(label.get());
        Ok(Localization {
            label,
            level: view.map_or(Level::Middle, |v| v.level),
            side: view.map_or(Side::Front, |v| v.side),
            rotation: view.map_or_else(Matrix3::identity, |v| v.rotation),
            probability,
            probabilities,
            folded_label: CameraLabel::new(folded).unwrap_or(label),
            missing,
            azimuth_deg,
            elevation_deg,
            uncertainty_deg,
        })
    }

    /// The default model embedded in this build (trained by `cargo xtask train-default` on
    /// the CMU data under the `jittered` protocol, with landmark dropout).
    ///
    /// # Errors
    /// [`CamlocError::NoDefault`] when the build embedded none; decoding errors otherwise.
    pub fn default_model() -> Result<CameraLocalizer, CamlocError> {
        let bytes = include_bytes!(concat!(env!("OUT_DIR"), "/default-model.bin"));
        if bytes.is_empty() {
            return Err(CamlocError::NoDefault("model"));
        }
        Self::from_bytes_named(bytes, "embedded default model").map_err(CamlocError::from)
    }
}

/// Tempers `probabilities` in place: each `p^(1 / temperature)`, normalised to sum 1 (the
/// softmax of `ln p / temperature`, so that tiny probabilities do not underflow first).
fn temper(probabilities: &mut [f64], temperature: f64) {
    for p in probabilities.iter_mut() {
        *p = p.ln() / temperature;
    }
    softmax_in_place(probabilities);
}

/// The localizer's invariants, run after every decode of a model file: a valid descriptor
/// and camera set, the classifier's own [`LogisticModel::validate`] (shapes against its class
/// count and feature count, finite numbers, positive scales), and descriptor, classifier,
/// imputation and cameras agreeing in size.
impl Validate for CameraLocalizer {
    type Invalid = CamlocError;

    fn validate(&self) -> Result<(), CamlocError> {
        let inconsistent = |detail: String| CamlocError::Inconsistent {
            what: "model",
            detail,
        };
        self.descriptor
            .validate()
            .map_err(|e| inconsistent(e.to_string()))?;
        self.cameras
            .validate()
            .map_err(|e| inconsistent(format!("camera set: {e}")))?;
        self.model.validate()?;
        let d = self.descriptor.len();
        if let Some(e) = &self.expansion {
            e.validate()
                .map_err(|e| inconsistent(format!("feature expansion: {e}")))?;
            if e.n_inputs() != d {
                return Err(inconsistent(format!(
                    "descriptor '{}' has {d} values, the feature expansion expects {}",
                    self.descriptor.name(),
                    e.n_inputs()
                )));
            }
        }
        let width = self.feature_width();
        if self.model.n_features() != width || self.imputation.len() != d {
            return Err(inconsistent(format!(
                "descriptor '{}' has {d} values ({width} features), classifier expects {} and imputation has {}",
                self.descriptor.name(),
                self.model.n_features(),
                self.imputation.len()
            )));
        }
        if !(1..=PostureGroup::ALL.len()).contains(&self.posture_groups)
            || self.model.n_classes() != self.cameras.len() * self.posture_groups
        {
            return Err(inconsistent(format!(
                "classifier has {} classes for {} cameras in {} posture groups",
                self.model.n_classes(),
                self.cameras.len(),
                self.posture_groups
            )));
        }
        let priors = &self.info.camera_priors;
        let total: f64 = priors.iter().sum();
        if priors.len() != self.cameras.len()
            || !priors.iter().all(|p| p.is_finite() && *p >= 0.0)
            || (total - 1.0).abs() > 1e-6
        {
            return Err(inconsistent(format!(
                "{} camera priors (summing to {total}) for {} cameras; expected non-negative \
                 priors summing to 1",
                priors.len(),
                self.cameras.len()
            )));
        }
        if !self.imputation.iter().all(|v| v.is_finite()) {
            return Err(inconsistent("non-finite imputation value".into()));
        }
        if let Some(e) = &self.viewpoint_expansion {
            e.validate()
                .map_err(|e| inconsistent(format!("viewpoint feature expansion: {e}")))?;
            if e.n_inputs() != d {
                return Err(inconsistent(format!(
                    "descriptor '{}' has {d} values, the viewpoint feature expansion expects {}",
                    self.descriptor.name(),
                    e.n_inputs()
                )));
            }
        }
        if let Some(heads) = &self.viewpoint {
            heads
                .validate(self.cameras.len(), self.head_width())
                .map_err(|e| inconsistent(format!("viewpoint heads: {e}")))?;
        }
        Ok(())
    }
}

/// Model files: [`camloc_store::MODEL_KIND`] (magic `CAMLOCMD`); load with
/// [`Persist::load`], write with [`Persist::save`] (no overwrite unless asked).
impl Persist for CameraLocalizer {
    const KIND: FileKind = camloc_store::MODEL_KIND;
}

/// The most probable class and its probability (the first on ties).
pub(crate) fn most_probable(probabilities: &[f64]) -> (usize, f64) {
    probabilities
        .iter()
        .copied()
        .enumerate()
        .fold(
            (0, f64::NEG_INFINITY),
            |a, (i, p)| if p > a.1 { (i, p) } else { a },
        )
}

/// The rows of one pose, made by [`CameraLocalizer::with_pose_rows`] in this thread's
/// [`RowBuffers`].
pub(crate) struct PoseRows<'a> {
    /// The descriptor, undefined values imputed.
    pub(crate) descriptor: &'a [f64],
    /// The classifier's features: the descriptor, or its expansion.
    pub(crate) classifier: &'a [f64],
    /// Room for the viewpoint heads' own expanded row (any length; the user sizes it).
    pub(crate) head_row: &'a mut Vec<f64>,
    /// Room for the classifier's class probabilities, one per class.
    pub(crate) classes: &'a mut [f64],
}

/// The rows of one pose that [`CameraLocalizer::with_pose_rows`] fills: kept per thread and
/// reused, so that localizing or labelling a pose allocates only its result. Every call
/// sizes and overwrites them.
#[derive(Default)]
struct RowBuffers {
    /// The descriptor, then imputed.
    descriptor: Vec<f64>,
    /// Which descriptor values depend on a missing landmark.
    undefined: Vec<bool>,
    /// The expanded row, for a model with an expansion.
    expanded: Vec<f64>,
    /// The viewpoint heads' expanded row, for heads with their own expansion.
    head_row: Vec<f64>,
    /// The classifier's class probabilities, before they are summed over postures.
    classes: Vec<f64>,
}

thread_local! {
    static ROW_BUFFERS: std::cell::RefCell<RowBuffers> = std::cell::RefCell::default();
}

#[cfg(test)]
mod tests {
    use super::temper;

    #[test]
    fn tempering_keeps_the_order_and_the_sum_and_flattens() {
        let given = [0.7, 0.2, 0.1, 0.0];
        let mut same = given;
        temper(&mut same, 1.0);
        for (a, b) in same.iter().zip(&given) {
            assert!((a - b).abs() < 1e-15);
        }
        let mut flat = given;
        temper(&mut flat, 2.0);
        assert!((flat.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        assert!(flat[0] < given[0] && flat[0] > flat[1] && flat[1] > flat[2]);
        assert_eq!(flat[3], 0.0);
        // sqrt(0.7) / (sqrt(0.7) + sqrt(0.2) + sqrt(0.1)).
        let want = 0.7f64.sqrt() / (0.7f64.sqrt() + 0.2f64.sqrt() + 0.1f64.sqrt());
        assert!((flat[0] - want).abs() < 1e-12);
    }
}
