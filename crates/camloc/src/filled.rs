//! Localization of a pose with missing landmarks (also one whose torso is incomplete: a hip
//! and so the pelvis, or a shoulder and so the neck, occluded): they are filled in from the
//! pose basis seen by hypothesised cameras, the camera is the one the filled-in pose agrees
//! with, and its probabilities are tempered for what was filled in (docs/conventions.md
//! section 6, "Filled-in poses").

use camloc_features::FeatureError;
use camloc_geometry::{Matrix3, Vector3};
use camloc_reconstruct::{ReconstructError, Reconstructor};
use camloc_skeleton::{Landmark, PartialPose2, Pose2};

use crate::{CameraLocalizer, CamlocError, Localization};

/// Fewest landmarks present for [`CameraLocalizer::localize_filled`] to fill in a missing
/// torso: with fewer, the fill is mostly the basis's mean pose and the camera a guess.
pub const MIN_PRESENT_FOR_FILL: usize = 8;

/// Camera hypotheses refilled to convergence (those whose fills the classifier agrees with
/// most).
const STARTS: usize = 3;

/// The misfit of the basis seen from a converged viewpoint ([`Reconstructor::impute_with_misfit`])
/// that weighs as much as a factor `e` of its probability when the hypotheses are compared.
/// Chosen on the validation subjects 07, 13, 14, 75 and 114 among 0.003, 0.01 and the misfit
/// alone (docs/measured.md).
const MISFIT_SCALE: f64 = 0.01;

/// Most refills of a pose from its latest localization's continuous viewpoint.
const MAX_REFILLS: usize = 8;

/// The refills stop when the viewpoint moves less than this, degrees.
const REFILL_TOLERANCE_DEG: f64 = 0.1;

/// How much the temperature of a filled-in pose's probabilities rises per missing landmark
/// (the pelvis and the neck not counted: they follow from the hips and the shoulders): the
/// filled-in pose looks as certain as a complete one, its answer is not (held-out subjects,
/// `jittered`, 4 to 7 landmarks filled in at random: 86 to 70% right at a mean probability of
/// 0.89 to 0.92, the temperatures of least log loss about 1.5 to 2.7; a simulated user's
/// self-occluded joints, 2 or 3 missing: 74-78% right at 0.84-0.90; docs/measured.md).
pub const FILL_TEMPERATURE_STEP: f64 = 0.25;

/// The temperature of the probabilities of a pose whose `missing` landmarks were filled in:
/// 1 plus [`FILL_TEMPERATURE_STEP`] per landmark other than the pelvis and the neck.
pub fn fill_temperature(missing: &[Landmark]) -> f64 {
    let counted = missing.iter().filter(|l| !is_derivable(**l)).count();
    1.0 + FILL_TEMPERATURE_STEP * counted as f64
}

/// Whether `landmark` is the pelvis or the neck, which the hips and the shoulders give.
fn is_derivable(landmark: Landmark) -> bool {
    matches!(landmark, Landmark::Pelvis | Landmark::Neck)
}

impl CameraLocalizer {
    /// Localizes `pose` with its missing landmarks filled in (a complete pose, or one missing
    /// only the pelvis or the neck beside the hips and shoulders that stand in for them, as
    /// [`CameraLocalizer::localize_partial`] does). Provided at least [`MIN_PRESENT_FOR_FILL`]
    /// landmarks are present, a pose's missing landmarks are filled in by `filler`
    /// ([`Reconstructor::impute`]: the basis pose that fits the present landmarks, seen by a
    /// given camera rotation) under each camera class's rotation in turn (each fill averaged
    /// with the mirror image of the mirrored pose's, so that mirror-image poses get
    /// mirror-image fills). The three classes whose filled-in poses the classifier gives the
    /// highest probability of that same class are each refined: the pose is filled in again
    /// from the latest localization's continuous viewpoint
    /// ([`Localization::viewpoint_rotation`]) until the viewpoint moves less than 0.1 deg (at
    /// most 8 times). Of the three final localizations the answer is the one whose
    /// probability is highest after a penalty for the misfit of the basis seen from its
    /// viewpoint (`ln p - misfit / 0.01`: a viewpoint from which no basis pose looks like the
    /// present landmarks loses), its probabilities tempered by [`fill_temperature`]; its
    /// `missing` names the landmarks the input lacked. This also localizes a pose whose
    /// torso the descriptor cannot make (the pelvis or the neck missing with a hip or a
    /// shoulder beside it, as when a detector or an annotator misses one hip). A pose with a
    /// torso and fewer landmarks, or whose fill fails, is localized as `localize_partial`
    /// does (the descriptor values of missing landmarks at their training means), which is
    /// less often right (docs/RESULTS.md, "Missing landmarks": held-out subjects with 1 to 6
    /// random landmarks of the limbs and head missing, both ways).
    ///
    /// Costs 15 to 39 fills (two basis fits each) and 12 to 36 localizations for a pose with
    /// missing landmarks (docs/RESULTS.md, "Missing landmarks": a few tenths of a millisecond
    /// of wall time per pose on two cores); a complete pose costs what `localize_partial`
    /// costs.
    ///
    /// # Errors
    /// As [`CameraLocalizer::localize_partial`]; [`CamlocError::NothingDetected`] for a pose
    /// without a single landmark; a pose without a torso and with fewer than
    /// [`MIN_PRESENT_FOR_FILL`] landmarks present keeps its [`FeatureError::MissingTorso`]
    /// (the context says how many are present);
    /// [`CamlocError::Reconstruct`] when the fill of a pose without a torso fails
    /// (non-finite or coinciding landmarks).
    pub fn localize_filled(
        &self,
        pose: &PartialPose2,
        filler: &Reconstructor,
    ) -> Result<Localization, CamlocError> {
        let partial = match self.localize_partial(pose) {
            Err(
                e @ CamlocError::Feature {
                    source: FeatureError::MissingTorso { .. },
                    ..
                },
            ) => Err(e),
            // The descriptor does not read the pelvis and the neck: a pose missing only
            // those is localized as it is.
            Ok(found) if found.missing.iter().any(|l| !is_derivable(*l)) => Ok(found),
            found => return found,
        };
        // The landmarks far off the others are missing here too, and filled in: a shoulder
        // misplaced by 2,000 px took the neck derived from it along, and the fill of the
        // pose as given kept both, so that it failed for "the neck is missing" (a simulated
        // user's COCO-17 pose, which the same pose with the shoulder's score 0 was not).
        let (cleaned, _) = crate::without_far_off_landmarks(pose);
        let pose = &cleaned;
        let present = pose.points.iter().flatten().count();
        if present == 0 {
            return Err(CamlocError::NothingDetected);
        }
        let missing_torso = match partial {
            Ok(found) if present < MIN_PRESENT_FOR_FILL => return Ok(found),
            Ok(found) => {
                // A fill that fails keeps the answer of the missing landmarks' means.
                return Ok(self.best_fill(pose, filler).ok().flatten().unwrap_or(found));
            }
            Err(e) => e,
        };
        if present < MIN_PRESENT_FOR_FILL {
            return Err(match missing_torso {
                CamlocError::Feature { context, source } => CamlocError::Feature {
                    context: format!(
                        "{context} ({present} landmark{} present, {MIN_PRESENT_FOR_FILL} needed \
                         to fill in a torso; a format without a pelvis or neck derives it from \
                         both hips or both shoulders)",
                        if present == 1 { "" } else { "s" }
                    ),
                    source,
                },
                other => other,
            });
        }
        self.best_fill(pose, filler)?.ok_or(missing_torso)
    }

    /// The localization of `pose` (its far-off landmarks taken out) with its missing
    /// landmarks filled in by `filler` as [`localize_filled`](Self::localize_filled)
    /// describes, `None` when no hypothesis could be localized.
    fn best_fill(
        &self,
        pose: &PartialPose2,
        filler: &Reconstructor,
    ) -> Result<Option<Localization>, CamlocError> {
        let missing = pose.missing().collect::<Vec<_>>();
        let fill = |rotation: &Matrix3| {
            mirror_symmetric_fill(filler, pose, rotation).map_err(|source| {
                CamlocError::Reconstruct {
                    context: "input pose (filling in its missing landmarks)".into(),
                    source,
                }
            })
        };
        let localize = |rotation: &Matrix3| -> Result<(Localization, Pose2), CamlocError> {
            let (filled, _) = fill(rotation)?;
            Ok((self.localize(&filled)?, filled))
        };
        let mut hypotheses: Vec<(f64, (Localization, Pose2))> = Vec::new();
        for (c, view) in self.cameras().viewpoints().iter().enumerate() {
            let found = localize(&view.rotation)?;
            let agreement = found.0.probabilities.get(c).copied().unwrap_or(0.0);
            hypotheses.push((agreement, found));
        }
        hypotheses.sort_by(|a, b| b.0.total_cmp(&a.0));
        let mut best: Option<(f64, (Localization, Pose2))> = None;
        for (_, mut found) in hypotheses.into_iter().take(STARTS) {
            for _ in 0..MAX_REFILLS {
                let rotation = found.0.viewpoint_rotation();
                let next = localize(&rotation)?;
                let axis = |r: &Matrix3| r.row(2).transpose();
                let moved_deg = axis(&rotation)
                    .dot(&axis(&next.0.viewpoint_rotation()))
                    .clamp(-1.0, 1.0)
                    .acos()
                    .to_degrees();
                found = next;
                if moved_deg < REFILL_TOLERANCE_DEG {
                    break;
                }
            }
            let (_, misfit) = fill(&found.0.viewpoint_rotation())?;
            let score = found.0.probability.ln() - misfit / MISFIT_SCALE;
            if best.as_ref().is_none_or(|(b, _)| score > *b) {
                best = Some((score, found));
            }
        }
        let Some((_, (found, filled))) = best else {
            return Ok(None);
        };
        let temperature = fill_temperature(&missing);
        let mut found = if temperature > 1.0 {
            self.localize_tempered(&PartialPose2::from(filled), temperature, || {
                "input pose".into()
            })?
        } else {
            found
        };
        found.missing = missing;
        Ok(Some(found))
    }
}

/// `pose` filled in by `filler` seen by `rotation` ([`Reconstructor::impute_with_misfit`]),
/// each filled-in landmark the mean of that fill and of the mirror image of the mirrored
/// pose's fill seen by the mirrored camera, and the mean of the two fits' misfits: a pose and
/// its mirror image get mirror-image fills (the basis, fitted to people as recorded, is not
/// mirror-symmetric), so that the mirror-symmetric classifier sees them from mirror-image
/// cameras.
pub(crate) fn mirror_symmetric_fill(
    filler: &Reconstructor,
    pose: &PartialPose2,
    rotation: &Matrix3,
) -> Result<(Pose2, f64), ReconstructError> {
    // The mirror image: u -> -u in the camera frame and the body reflected through its
    // sagittal plane (y -> -y in the canonical frame, docs/conventions.md section 1).
    let image_flip = Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, 1.0));
    let body_flip = Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, 1.0));
    let (direct, direct_misfit) = filler.impute_with_misfit(pose, rotation)?;
    let (mirrored, mirrored_misfit) =
        filler.impute_with_misfit(&pose.mirrored(), &(image_flip * rotation * body_flip))?;
    let mirrored = mirrored.mirrored();
    let mut points = direct.points;
    for (i, point) in points.iter_mut().enumerate() {
        if pose.points[i].is_none() {
            let other = mirrored.points[i];
            *point = [0.5 * (point[0] + other[0]), 0.5 * (point[1] + other[1])];
        }
    }
    Ok((Pose2::new(points), 0.5 * (direct_misfit + mirrored_misfit)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_temperature_rises_with_missing_limbs_and_ignores_pelvis_and_neck() {
        use Landmark::*;
        assert_eq!(fill_temperature(&[]), 1.0);
        assert_eq!(fill_temperature(&[Pelvis, Neck]), 1.0);
        let three = [LeftWrist, RightWrist, LeftAnkle];
        assert_eq!(fill_temperature(&three), 1.0 + 3.0 * FILL_TEMPERATURE_STEP);
        let with_torso = [Pelvis, Neck, LeftWrist, RightWrist, LeftAnkle];
        assert_eq!(fill_temperature(&with_torso), fill_temperature(&three));
    }
}
