//! Localization of a pose whose torso is incomplete (a hip and so the pelvis, or a shoulder
//! and so the neck, occluded): its missing landmarks are filled in from the pose basis seen
//! by hypothesised cameras, and the camera is the one the filled-in pose agrees with
//! (docs/conventions.md section 6, "Missing landmarks").

use camloc_features::FeatureError;
use camloc_geometry::{Matrix3, Vector3};
use camloc_reconstruct::{ReconstructError, Reconstructor};
use camloc_skeleton::{PartialPose2, Pose2};

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

impl CameraLocalizer {
    /// Localizes `pose` as [`CameraLocalizer::localize_partial`] does, and also a pose whose
    /// torso the descriptor cannot make (the pelvis or the neck missing with a hip or a
    /// shoulder beside it, as when a detector or an annotator misses one hip), provided at
    /// least [`MIN_PRESENT_FOR_FILL`] landmarks are present. Such a pose's missing landmarks
    /// are filled in by `filler` ([`Reconstructor::impute`]: the basis pose that fits the
    /// present landmarks, seen by a given camera rotation) under each camera class's rotation
    /// in turn (each fill averaged with the mirror image of the mirrored pose's, so that
    /// mirror-image poses get mirror-image fills). The three classes whose filled-in poses the
    /// classifier gives the highest probability of that same class are each refined: the pose
    /// is filled in again from the latest localization's continuous viewpoint
    /// ([`Localization::viewpoint_rotation`]) until the viewpoint moves less than 0.1 deg (at
    /// most 8 times). Of the three final localizations the answer is the one whose
    /// probability is highest after a penalty for the misfit of the basis seen from its
    /// viewpoint (`ln p - misfit / 0.01`: a viewpoint from which no basis pose looks like the
    /// present landmarks loses); its `missing` names the landmarks the input lacked.
    ///
    /// Costs 15 to 39 fills (two basis fits each) and 12 to 36 localizations for such a pose
    /// (docs/RESULTS.md, "Missing landmarks": 0.11-0.12 ms of wall time per pose on two
    /// cores); other poses cost what `localize_partial` costs.
    ///
    /// # Errors
    /// As [`CameraLocalizer::localize_partial`]; [`CamlocError::NothingDetected`] for a pose
    /// without a single landmark; a pose without a torso and with fewer than
    /// [`MIN_PRESENT_FOR_FILL`] landmarks present keeps its [`FeatureError::MissingTorso`]
    /// (the context says how many are present);
    /// [`CamlocError::Reconstruct`] when the fill fails (non-finite or coinciding landmarks).
    pub fn localize_filled(
        &self,
        pose: &PartialPose2,
        filler: &Reconstructor,
    ) -> Result<Localization, CamlocError> {
        let missing_torso = match self.localize_partial(pose) {
            Err(
                e @ CamlocError::Feature {
                    source: FeatureError::MissingTorso { .. },
                    ..
                },
            ) => e,
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
        let missing = pose.missing().collect::<Vec<_>>();
        let fill = |rotation: &Matrix3| {
            mirror_symmetric_fill(filler, pose, rotation).map_err(|source| {
                CamlocError::Reconstruct {
                    context: "input pose (filling in its missing landmarks)".into(),
                    source,
                }
            })
        };
        let localize = |filled: &Pose2| -> Result<Localization, CamlocError> {
            let mut found = self.localize(filled)?;
            found.missing.clone_from(&missing);
            Ok(found)
        };
        let mut hypotheses: Vec<(f64, Localization)> = Vec::new();
        for (c, view) in self.cameras().viewpoints().iter().enumerate() {
            let found = localize(&fill(&view.rotation)?.0)?;
            let agreement = found.probabilities.get(c).copied().unwrap_or(0.0);
            hypotheses.push((agreement, found));
        }
        hypotheses.sort_by(|a, b| b.0.total_cmp(&a.0));
        let mut best: Option<(f64, Localization)> = None;
        for (_, mut found) in hypotheses.into_iter().take(STARTS) {
            for _ in 0..MAX_REFILLS {
                let rotation = found.viewpoint_rotation();
                let next = localize(&fill(&rotation)?.0)?;
                let axis = |r: &Matrix3| r.row(2).transpose();
                let moved_deg = axis(&rotation)
                    .dot(&axis(&next.viewpoint_rotation()))
                    .clamp(-1.0, 1.0)
                    .acos()
                    .to_degrees();
                found = next;
                if moved_deg < REFILL_TOLERANCE_DEG {
                    break;
                }
            }
            let (_, misfit) = fill(&found.viewpoint_rotation())?;
            let score = found.probability.ln() - misfit / MISFIT_SCALE;
            if best.as_ref().is_none_or(|(b, _)| score > *b) {
                best = Some((score, found));
            }
        }
        let Some((_, found)) = best else {
            return Err(missing_torso);
        };
        Ok(found)
    }
}

/// `pose` filled in by `filler` seen by `rotation` ([`Reconstructor::impute_with_misfit`]),
/// each filled-in landmark the mean of that fill and of the mirror image of the mirrored
/// pose's fill seen by the mirrored camera, and the mean of the two fits' misfits: a pose and
/// its mirror image get mirror-image fills (the basis, fitted to people as recorded, is not
/// mirror-symmetric), so that the mirror-symmetric classifier sees them from mirror-image
/// cameras.
fn mirror_symmetric_fill(
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
