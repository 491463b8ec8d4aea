//! The pursuit's hypotheses refined into the person's own proportions
//! ([`Reconstructor::reconstruct_with`]) and turned into [`Reconstruction`]s.

use camloc_geometry::{Matrix3, WeakPerspective};
use camloc_skeleton::{Landmark, NUM_LANDMARKS, Pose2, Pose3};
use nalgebra::Vector3;

use super::hypotheses::{Candidate, Ranked, Reconstruction};
use super::mode::CameraMode;
use super::observation::Observation;
use super::reconstructor::Reconstructor;
use crate::length_prior::{IMPLAUSIBLE_LENGTHS_D2, LimbVector};
use crate::refine::{LengthInput, RefineFrame, RefinedFrame, refine};
use crate::{BoneLengths, Given, PerspectiveCamera, ReconstructError};

impl Reconstructor {
    /// Reconstructs the 3D pose seen in `pose` like
    /// [`reconstruct_hypotheses`](Self::reconstruct_hypotheses), with what is `given` of the
    /// person and the camera: each of the (up to `max`) hypotheses is refined
    /// ([`ReconstructConfig::refinement`](crate::ReconstructConfig::refinement)) with the
    /// given bone lengths or, without them, with the lengths as unknowns under the length
    /// prior; with given intrinsics, under full perspective. The hypotheses keep the
    /// pursuit's order.
    ///
    /// # Errors
    /// As [`reconstruct_hypotheses`](Self::reconstruct_hypotheses);
    /// [`ReconstructError::InvalidConfig`] for intrinsics that are not finite or a focal
    /// length that is not positive; [`ReconstructError::Numerical`] when the estimated
    /// lengths leave the plausible range.
    pub fn reconstruct_with(
        &self,
        pose: &Pose2,
        mode: &CameraMode,
        max: usize,
        given: &Given,
    ) -> Result<Vec<Reconstruction>, ReconstructError> {
        self.reconstruct_lifted(pose, mode, max, given, None)
    }

    /// [`reconstruct_with`](Self::reconstruct_with), the refinement of the first hypothesis
    /// started from the landmarks' `depths` along the camera's optical axis when they are
    /// given (a [`LiftedDepths`], for instance `camloc::DepthLifter`'s) instead of the
    /// pursuit's pose: the pose whose landmarks are the 2D ones at those depths, turned into
    /// the body frame by the hypothesis' camera; its bone directions are then the ones the
    /// refinement holds the pose near. The first hypothesis of the other depth reflection
    /// starts from those depths mirrored (the lifted pose's depth mirror), any further one
    /// from its pursuit pose.
    ///
    /// # Errors
    /// As [`reconstruct_with`](Self::reconstruct_with).
    pub fn reconstruct_lifted(
        &self,
        pose: &Pose2,
        mode: &CameraMode,
        max: usize,
        given: &Given,
        depths: Option<&LiftedDepths>,
    ) -> Result<Vec<Reconstruction>, ReconstructError> {
        self.reconstruct_imputed(pose, 0, mode, max, given, depths)
    }

    /// [`reconstruct_lifted`](Self::reconstruct_lifted) of a pose whose landmarks with bit
    /// `i` set in `imputed` were filled in (for instance by [`impute`](Self::impute)), not
    /// observed: the pursuit fits them like the others, the refinement leaves them out of
    /// its reprojection error (the bone directions' prior holds their bones where the
    /// pursuit or the lifter put them).
    ///
    /// # Errors
    /// As [`reconstruct_with`](Self::reconstruct_with).
    pub fn reconstruct_imputed(
        &self,
        pose: &Pose2,
        imputed: u16,
        mode: &CameraMode,
        max: usize,
        given: &Given,
        depths: Option<&LiftedDepths>,
    ) -> Result<Vec<Reconstruction>, ReconstructError> {
        if let Some(intrinsics) = &given.intrinsics {
            intrinsics.check()?;
            intrinsics.check_pose(pose)?;
        }
        let Ranked {
            obs,
            mut candidates,
            iterations,
        } = self.ranked(pose, mode)?;
        let starts = lifted_starts(&mut candidates, max.max(1), depths);
        candidates
            .into_iter()
            .zip(starts)
            .map(|(c, start)| {
                let refined = if self.refines(given) {
                    self.refine_candidate(&obs, &c, given, start.as_ref(), imputed)?
                } else {
                    None
                };
                Ok(self.reconstruction(&obs, c, refined, given, iterations))
            })
            .collect()
    }

    /// The refinement of candidate `c` of one pose from `start` (lifted depths), or from its
    /// pursuit pose without one. A lifted start whose refined bone lengths lie beyond
    /// [`IMPLAUSIBLE_LENGTHS_D2`] under the widened length prior, or whose refinement fails,
    /// is refined again from the pursuit's pose, which is kept when its lengths are the more
    /// plausible: a lifter that reads a pose far from anything it was fitted on (an upside-down
    /// gymnast of LSP's photos) drew torsos of 1.3 and 1.9 m. Given lengths are never
    /// implausible.
    fn refine_candidate(
        &self,
        obs: &Observation,
        c: &Candidate,
        given: &Given,
        start: Option<&LiftedDepths>,
        imputed: u16,
    ) -> Result<Option<RefinedFrame>, ReconstructError> {
        let frame = self.refine_frame(obs, c, given, start, imputed);
        let lifted = self.refine_within_limits(frame, given);
        if start.is_none() || given.lengths.is_some() {
            return lifted;
        }
        let distance = match &lifted {
            Ok(Some(r)) => self.length_distance(&r.pose),
            Ok(None) => return lifted,
            Err(_) => f64::INFINITY,
        };
        if distance <= IMPLAUSIBLE_LENGTHS_D2 {
            return lifted;
        }
        let frame = self.refine_frame(obs, c, given, None, imputed);
        match self.refine_within_limits(frame, given) {
            Ok(Some(r)) if self.length_distance(&r.pose) < distance => Ok(Some(r)),
            _ => lifted,
        }
    }

    /// The squared Mahalanobis distance of the limb lengths of `pose` (metres) from the mean
    /// of the widened length prior the refinement estimates lengths under: about 14 (the
    /// limbs) for a typical body, beyond [`IMPLAUSIBLE_LENGTHS_D2`] for one in a thousand of
    /// the prior's own draws.
    fn length_distance(&self, pose: &Pose3) -> f64 {
        let mean = self.basis.length_prior().mean_log();
        let off = LimbVector::from_fn(|limb, _| pose.limb_length(limb).ln() - mean[limb]);
        (self.whitening * off).norm_squared()
    }

    /// The refinement of one `frame`, refined again from a flip of its limbs' depths into the
    /// joint-angle limits where that helps
    /// ([`refine_again_within_limits`](Self::refine_again_within_limits)).
    fn refine_within_limits(
        &self,
        frame: RefineFrame,
        given: &Given,
    ) -> Result<Option<RefinedFrame>, ReconstructError> {
        let settings = &self.config.refinement;
        let (first, _) = refine(
            std::slice::from_ref(&frame),
            self.length_input(given),
            settings,
            false,
        )?;
        let mut out =
            self.refine_again_within_limits(vec![frame], first, self.length_input(given), false)?;
        Ok(out.pop())
    }

    /// The refined frames `refined` of `inputs` (one pose, or one person's frames with
    /// `sequence`), refined again with `lengths` where the joint-angle limits are on and a
    /// frame's refined pose has a limb that a flip of its bones' depths takes into them
    /// ([`JointLimits::flip_depths`](crate::JointLimits::flip_depths): the 2D fits both, the
    /// direction prior held it near the start's reading): those frames restart from their
    /// flips, the others as they first started, and the second refinement is kept when the
    /// frames end further within the limits, summed over the frames.
    pub(super) fn refine_again_within_limits(
        &self,
        inputs: Vec<RefineFrame>,
        refined: Vec<RefinedFrame>,
        lengths: LengthInput,
        sequence: bool,
    ) -> Result<Vec<RefinedFrame>, ReconstructError> {
        if !self.config.joint_limits {
            return Ok(refined);
        }
        let limits = self.basis.joint_limits();
        let mut flipped_any = false;
        let again: Vec<RefineFrame> = (inputs.into_iter().zip(&refined))
            .map(|(input, first)| {
                let flipped =
                    limits.flip_depths(&first.pose, &first.camera.rotation, input.imputed);
                if flipped == first.pose {
                    return input;
                }
                flipped_any = true;
                RefineFrame {
                    pose: flipped,
                    camera: first.camera,
                    ..input
                }
            })
            .collect();
        if !flipped_any {
            return Ok(refined);
        }
        let (second, _) = refine(&again, lengths, &self.config.refinement, sequence)?;
        let outside = |frames: &[RefinedFrame]| -> f64 {
            frames.iter().map(|f| limits.violation(&f.pose)).sum()
        };
        Ok(if outside(&second) < outside(&refined) {
            second
        } else {
            refined
        })
    }

    /// Whether the refinement runs: lengths or intrinsics given, or lengths to estimate.
    pub(super) fn refines(&self, given: &Given) -> bool {
        self.config.refinement.estimate_lengths
            || given.lengths.is_some()
            || given.intrinsics.is_some()
    }

    /// The refinement's lengths: the given ones, else unknowns under the length prior.
    pub(super) fn length_input(&self, given: &Given) -> LengthInput<'_> {
        match given.lengths {
            Some(lengths) => LengthInput::Given(lengths),
            None => LengthInput::Estimated {
                whitening: &self.whitening,
                mean_log: self.basis.length_prior().mean_log(),
            },
        }
    }

    /// The lengths a reconstruction has without the refinement: the given ones, else those
    /// of the pursuit's `poses` on average.
    pub(super) fn unrefined_lengths(
        &self,
        given: &Given,
        poses: &[Pose3],
    ) -> Result<BoneLengths, ReconstructError> {
        match given.lengths {
            Some(lengths) => Ok(lengths),
            None if poses.is_empty() => self.template_lengths(),
            None => Ok(BoneLengths::mean_of(poses)?),
        }
    }

    /// What the refinement starts `candidate` from: its pose, or with (finite) `depths` the
    /// lifted pose ([`reconstruct_lifted`](Self::reconstruct_lifted)); `imputed` marks the
    /// landmarks that were filled in.
    pub(super) fn refine_frame(
        &self,
        obs: &Observation,
        candidate: &Candidate,
        given: &Given,
        depths: Option<&LiftedDepths>,
        imputed: u16,
    ) -> RefineFrame {
        let camera = candidate.fit.camera;
        let (points, lifted) = match depths {
            Some(z) if z.iter().all(|v| v.is_finite()) => {
                let points = lifted_points(obs, z, &camera);
                // The lifter is not held to the joint-angle limits: a limb it bends the
                // wrong way in depth (a knee backwards) is flipped in depth where that
                // takes it into them, the 2D unchanged; the refinement's direction prior
                // then holds that reading.
                let points = if self.config.joint_limits {
                    let limits = self.basis.joint_limits();
                    limits
                        .flip_depths(&Pose3 { points }, &camera.rotation, imputed)
                        .points
                } else {
                    points
                };
                (points, true)
            }
            _ => (candidate.fit.points, false),
        };
        RefineFrame {
            observed: obs.points,
            pose: Pose3 { points },
            camera,
            intrinsics: given
                .intrinsics
                .map(|i| obs.normalise_intrinsics(&i, imputed)),
            lifted,
            imputed,
        }
    }

    /// The reconstruction of `candidate`, `refined` or as the pursuit left it, in the input's
    /// image units.
    pub(super) fn reconstruction(
        &self,
        obs: &Observation,
        candidate: Candidate,
        refined: Option<RefinedFrame>,
        given: &Given,
        iterations: usize,
    ) -> Reconstruction {
        let (pose, camera, error, perspective) = match refined {
            Some(r) => {
                let perspective = r.perspective.map(|(focal, t, c)| PerspectiveCamera {
                    rotation: r.camera.rotation,
                    translation: t,
                    // A given focal length exactly as given.
                    focal_px: given.intrinsics.map_or(focal * obs.scale, |i| i.focal_px),
                    principal_point: obs.denormalise_point(c),
                });
                (r.pose, r.camera, r.squared_error, perspective)
            }
            None => (
                Pose3 {
                    points: candidate.fit.points,
                },
                candidate.fit.camera,
                candidate.fit.error,
                None,
            ),
        };
        Reconstruction {
            pose,
            camera: obs.denormalise(&camera),
            projection_error: error.sqrt() * obs.scale,
            selected: candidate.fit.selected,
            coefficients: candidate.fit.coefficients,
            iterations,
            reflected: candidate.reflected,
            limit_violation_rad: candidate.violation,
            outside_limits_rad: self.basis.joint_limits().violation(&pose),
            perspective,
        }
    }
}

/// The lifted depths each of the first `max` `candidates` starts its refinement from, so
/// that with a lifter the hypotheses stay distinct readings of the 2D: the first candidate
/// the lifted `depths`; the first candidate of the other depth reflection the same depths
/// mirrored (negated: the lifted pose's own depth mirror); any further candidate none (its
/// pursuit pose). Started from the same lifted pose, every hypothesis of a pose ended within
/// a few centimetres of the first. With depths, each candidate's `reflected` is made relative
/// to the first's (the lifter's reading): a candidate started from the lifted depths is
/// `reflected` when they are the mirrored ones, whichever of the pursuit's two depth readings
/// it came from.
fn lifted_starts(
    candidates: &mut [Candidate],
    max: usize,
    depths: Option<&LiftedDepths>,
) -> Vec<Option<LiftedDepths>> {
    let Some(depths) = depths else {
        return vec![None; candidates.len().min(max)];
    };
    let first = candidates.first().is_some_and(|c| c.reflected);
    let mut used = [false; 2];
    candidates
        .iter_mut()
        .take(max)
        .map(|c| {
            let mirrored = c.reflected != first;
            c.reflected = mirrored;
            if std::mem::replace(&mut used[usize::from(mirrored)], true) {
                None
            } else if mirrored {
                Some(depths.map(|z| -z))
            } else {
                Some(*depths)
            }
        })
        .collect()
}

/// The landmarks' depths along a camera's optical axis, about the centroid of the 3D
/// landmarks, in the units of the 2D pose centred on its centroid and divided by its RMS
/// radius (positive away from the camera; `camloc::DepthLifter` predicts them).
pub type LiftedDepths = [f64; NUM_LANDMARKS];

/// The true [`LiftedDepths`] of `pose` (metres, body frame) seen by a camera with `rotation`
/// (body frame to camera frame): each landmark's coordinate along the optical axis (row 3)
/// about the centroid of the landmarks, divided by the RMS radius of their coordinates
/// across it (rows 1 and 2), the unit of the normalised 2D pose of an orthographic view.
pub fn depths_along_axis(pose: &Pose3, rotation: &Matrix3) -> LiftedDepths {
    let n = NUM_LANDMARKS as f64;
    let points = &pose.points;
    let centroid: [f64; 3] = std::array::from_fn(|a| points.iter().map(|p| p[a]).sum::<f64>() / n);
    let seen = points.map(|p| {
        let d = Vector3::new(p[0] - centroid[0], p[1] - centroid[1], p[2] - centroid[2]);
        rotation * d
    });
    let radius = (seen.iter().map(|q| q.x * q.x + q.y * q.y).sum::<f64>() / n).sqrt();
    seen.map(|q| q.z / radius)
}

/// The body-frame pose (metres, pelvis at the origin) whose landmarks `camera` sees at the
/// normalised 2D points of `obs` with `depths`: `X = R^T (p - p_pelvis) / s`.
fn lifted_points(
    obs: &Observation,
    depths: &LiftedDepths,
    camera: &WeakPerspective,
) -> [[f64; 3]; NUM_LANDMARKS] {
    let seen: [Vector3<f64>; NUM_LANDMARKS] =
        std::array::from_fn(|j| Vector3::new(obs.points[j][0], obs.points[j][1], depths[j]));
    let pelvis = seen[Landmark::Pelvis.index()];
    let inverse = camera.rotation.transpose() / camera.scale;
    seen.map(|p| (inverse * (p - pelvis)).into())
}
