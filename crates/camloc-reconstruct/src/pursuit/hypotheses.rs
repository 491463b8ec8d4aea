//! One reconstruction: the solves a [`CameraMode`] asks for, each with its depth-reflected
//! hypothesis and the priors, ranked.

use camloc_geometry::{Matrix3, WeakPerspective, check_rotation};
use camloc_skeleton::{NUM_LANDMARKS, Pose2, Pose3};

use super::camera_update::CameraUpdate;
use super::config::EQUAL_FIT_TOLERANCE;
use super::greedy::Fit;
use super::mode::CameraMode;
use super::observation::Observation;
use super::reconstructor::Reconstructor;
use crate::prior::symmetrise;
use crate::{Given, PerspectiveCamera, ReconstructError};

/// Tolerance of the rotation check applied to rotations given in a [`CameraMode`].
const ROTATION_TOLERANCE: f64 = 1e-6;

/// A reconstructed 3D pose and the camera that projects it onto the input.
#[derive(Clone, Debug, PartialEq)]
pub struct Reconstruction {
    /// The 3D pose, metres, in the basis's canonical body frame (pelvis at the origin; the
    /// frame in which the training poses face -x). The camera rotation maps this frame to the
    /// camera; with a fixed class rotation the pose is therefore oriented as a canonical pose
    /// seen from that class, with Procrustes modes its facing is whatever the estimated
    /// camera implies. With the refinement ([`ReconstructConfig::refinement`]) it has the
    /// given bone lengths, or the estimated ones (proportions from the 2D and the length
    /// prior, size from the prior: a size cannot be told from one camera); without it, the
    /// pursuit's `mu + B w` at the training-average size.
    ///
    /// [`ReconstructConfig::refinement`]: crate::ReconstructConfig::refinement
    pub pose: Pose3,
    /// Weak-perspective camera in the input's image units: `L = s [I2 0] R X + t`. After a
    /// refinement with a perspective camera (given intrinsics, or an estimated distance:
    /// [`Refinement::distance`](crate::Refinement::distance)), that camera's approximation at
    /// the pelvis.
    pub camera: WeakPerspective,
    /// Eq. 6 at the solution: the Euclidean norm of the reprojection residuals (2 per
    /// landmark), in the input's image units, of the camera the solution was fitted with
    /// (after a refinement, its perspective camera when it had one, and over the landmarks not
    /// imputed).
    pub projection_error: f64,
    /// Indices of the pursuit's selected basis components, in order of selection (at most
    /// [`ReconstructConfig::max_basis`]).
    ///
    /// [`ReconstructConfig::max_basis`]: crate::ReconstructConfig::max_basis
    pub selected: Vec<usize>,
    /// Coefficients of the selected components, parallel to `selected` (metres), before the
    /// refinement.
    pub coefficients: Vec<f64>,
    /// Coefficient/camera alternations performed, over every hypothesis tried (both depth
    /// hypotheses; for [`CameraMode::Hybrid`], both solves).
    pub iterations: usize,
    /// `true` when this is the depth-reflected hypothesis: the pursuit's found pose mirrored
    /// in depth, or, when the refinement started from lifted depths, those depths mirrored
    /// (the lifter's reading is `false`, in every frame of a sequence too).
    pub reflected: bool,
    /// How far the pursuit's pose lay outside the learned joint-angle limits, before the
    /// prior's projection: the sum over the 8 limb bones of the angle beyond the limits,
    /// radians (0: within them).
    pub limit_violation_rad: f64,
    /// How far this pose (the one returned, after the refinement) lies outside the learned
    /// joint-angle limits, measured as [`limit_violation_rad`](Self::limit_violation_rad):
    /// a pose that the 2D bends beyond them (a knee seen bent backwards) has it above 0;
    /// check such poses before using them.
    pub outside_limits_rad: f64,
    /// The full perspective camera of the final refinement (`camera` is then its
    /// weak-perspective approximation at the pelvis): with known intrinsics
    /// ([`Given::intrinsics`]) theirs; without them, when the refinement estimated the
    /// camera's distance ([`Refinement::distance`](crate::Refinement::distance)) as finite,
    /// the camera at that distance with the pelvis on its optical axis (the principal point
    /// is the pelvis's image point, the focal length the scale times the distance; one view
    /// tells the distance poorly, so a single frame's is mostly the prior's). `None` under
    /// weak perspective.
    pub perspective: Option<PerspectiveCamera>,
}

impl Reconstruction {
    /// A reconstruction of `pose` seen by `camera` as the pursuit would leave it without
    /// selections or errors (for tests of what is done with reconstructions).
    #[cfg(test)]
    pub(crate) fn seen_by(pose: Pose3, camera: WeakPerspective) -> Reconstruction {
        Reconstruction {
            pose,
            camera,
            projection_error: 0.0,
            selected: Vec::new(),
            coefficients: Vec::new(),
            iterations: 0,
            reflected: false,
            limit_violation_rad: 0.0,
            outside_limits_rad: 0.0,
            perspective: None,
        }
    }

    /// The pose's landmarks as the camera it was fitted with sees them, in the input's image
    /// units: by [`perspective`](Self::perspective) when there is one (and every landmark is
    /// in front of it), else by [`camera`](Self::camera).
    pub fn reprojection(&self) -> [[f64; 2]; NUM_LANDMARKS] {
        self.reprojection_scaled(1.0)
    }

    /// [`reprojection`](Self::reprojection) in image units multiplied by `factor` (the
    /// camera's image-side quantities scaled alike; exact for a power of two).
    pub(crate) fn reprojection_scaled(&self, factor: f64) -> [[f64; 2]; NUM_LANDMARKS] {
        let points = &self.pose.points;
        self.perspective
            .as_ref()
            .and_then(|p| {
                PerspectiveCamera {
                    focal_px: p.focal_px * factor,
                    principal_point: p.principal_point.map(|c| c * factor),
                    ..*p
                }
                .project(points)
            })
            .unwrap_or_else(|| {
                WeakPerspective {
                    scale: self.camera.scale * factor,
                    translation: self.camera.translation.map(|t| t * factor),
                    ..self.camera
                }
                .project(points)
            })
    }
}

/// One hypothesis of [`Reconstructor::solve`], after the priors.
pub(super) struct Candidate {
    pub(super) fit: Fit,
    pub(super) reflected: bool,
    /// [`Reconstruction::limit_violation_rad`].
    pub(super) violation: f64,
}

/// The hypotheses of one pose, preferred first ([`Reconstructor::ranked`]).
pub(super) struct Ranked {
    /// The normalised 2D input.
    pub(super) obs: Observation,
    /// The hypotheses after the priors, preferred first.
    pub(super) candidates: Vec<Candidate>,
    /// Alternations performed over all of them.
    pub(super) iterations: usize,
}

impl Reconstructor {
    /// Reconstructs the 3D pose seen in `pose` (any image units, `v` down) under `mode`: the
    /// first of [`reconstruct_hypotheses`](Self::reconstruct_hypotheses).
    ///
    /// # Errors
    /// As [`reconstruct_hypotheses`](Self::reconstruct_hypotheses).
    pub fn reconstruct(
        &self,
        pose: &Pose2,
        mode: &CameraMode,
    ) -> Result<Reconstruction, ReconstructError> {
        let mut all = self.reconstruct_hypotheses(pose, mode, 1)?;
        all.pop()
            .ok_or(ReconstructError::Numerical("no hypothesis was solved"))
    }

    /// Reconstructs the 3D pose seen in `pose` (any image units, `v` down) under `mode`, and
    /// returns up to `max` hypotheses, the preferred one first.
    ///
    /// Algorithm (projected matching pursuit): start from `mu` and the mode's initial camera;
    /// repeatedly add the component whose projection has the largest normalised correlation
    /// with the current residual, then alternate an exact constrained least-squares solve of
    /// the selected coefficients (translation eliminated) with a camera update (Procrustes, or
    /// scale and translation for a fixed rotation), keeping whichever camera gives the lower
    /// error; stop when a new component lowers the error by less than
    /// [`ReconstructConfig::min_relative_decrease`] (it is then discarded) or `max_basis` is
    /// reached.
    ///
    /// Depth reflection (when [`ReconstructConfig::try_depth_reflection`]): the solution `X`
    /// is reflected in the plane through the pelvis orthogonal to the camera's optical axis
    /// `r3`, `X' = (I - 2 r3 r3^T) X`. The same camera sees `X'` exactly as it sees `X` (the
    /// reflection only negates depth), and the camera stays a proper rotation; only the pose
    /// changes handedness, so `X'` is generally not in the basis span. `X'` is therefore
    /// projected onto the basis (the same number of components, those whose unit columns
    /// correlate most with `X'` minus the mean — for a PCA basis the largest coefficients of
    /// the orthogonal projection; dictionary atoms are not orthogonal, so for them it is only
    /// a correlation — then the constrained 3D least-squares fit on those components)
    /// and the pursuit continues from there with the same camera update (for fixed-rotation
    /// modes: the reflected pose seen by the same rotation).
    ///
    /// Priors ([`ReconstructConfig::symmetry`], [`ReconstructConfig::joint_limits`]) then
    /// adjust each hypothesis and its camera is refitted. The hypotheses are ranked by
    /// reprojection error, except that of two whose RMS errors are within
    /// [`EQUAL_FIT_TOLERANCE`] of each other the one with the smaller joint-limit violation
    /// comes first (with the joint-limit prior on).
    ///
    /// [`CameraMode::Hybrid`] runs two such solves (see there), and their hypotheses are
    /// ranked together.
    ///
    /// # Errors
    /// [`ReconstructError::NonFiniteInput`], [`ReconstructError::DegenerateInput`] (zero torso,
    /// coincident landmarks), [`ReconstructError::InvalidRotation`] for a mode rotation that
    /// is not proper, [`ReconstructError::Geometry`] when a camera cannot be estimated (e.g.
    /// collinear 2D landmarks under Procrustes).
    ///
    /// [`ReconstructConfig::min_relative_decrease`]: crate::ReconstructConfig::min_relative_decrease
    /// [`ReconstructConfig::try_depth_reflection`]: crate::ReconstructConfig::try_depth_reflection
    /// [`ReconstructConfig::symmetry`]: crate::ReconstructConfig::symmetry
    /// [`ReconstructConfig::joint_limits`]: crate::ReconstructConfig::joint_limits
    pub fn reconstruct_hypotheses(
        &self,
        pose: &Pose2,
        mode: &CameraMode,
        max: usize,
    ) -> Result<Vec<Reconstruction>, ReconstructError> {
        self.reconstruct_with(pose, mode, max, &Given::default())
    }

    /// The pursuit's hypotheses for `pose` under `mode` after the priors, preferred first
    /// (see [`reconstruct_hypotheses`](Self::reconstruct_hypotheses)), with the normalised
    /// input and the alternations performed over all of them.
    pub(super) fn ranked(
        &self,
        pose: &Pose2,
        mode: &CameraMode,
    ) -> Result<Ranked, ReconstructError> {
        let obs = Observation::new(pose)?;
        let checked = |r: &Matrix3| {
            check_rotation(r, ROTATION_TOLERANCE)
                .map(|()| CameraUpdate::Fixed(*r))
                .map_err(|source| ReconstructError::InvalidRotation {
                    mode: mode.name(),
                    source,
                })
        };
        let mut candidates = match mode {
            CameraMode::Opt => self.solve(
                &obs,
                CameraUpdate::Procrustes,
                CameraUpdate::Procrustes,
                false,
            )?,
            CameraMode::Classified(r) | CameraMode::Oracle(r) => {
                let fixed = checked(r)?;
                self.solve(&obs, fixed, fixed, false)?
            }
            CameraMode::Hybrid(r) => {
                let fixed = checked(r)?;
                let mut all = self.solve(&obs, fixed, fixed, true)?;
                all.extend(self.solve(&obs, fixed, CameraUpdate::Procrustes, false)?);
                all
            }
        };
        let iterations = candidates.iter().map(|c| c.fit.iterations).sum();
        candidates.sort_by(|a, b| self.preference(a, b));
        Ok(Ranked {
            obs,
            candidates,
            iterations,
        })
    }

    /// The order of two hypotheses: by error, unless they fit about equally and the
    /// joint-limit prior is on, then by violation.
    fn preference(&self, a: &Candidate, b: &Candidate) -> std::cmp::Ordering {
        let (ea, eb) = (a.fit.error.sqrt(), b.fit.error.sqrt());
        let close = (ea - eb).abs() <= EQUAL_FIT_TOLERANCE * ea.max(eb);
        if self.config.joint_limits && close && a.violation != b.violation {
            a.violation.total_cmp(&b.violation)
        } else {
            a.fit.error.total_cmp(&b.fit.error)
        }
    }

    /// Applies the configured priors to `fit`'s pose, refits its camera with `update` and
    /// returns the pose's joint-limit violation before the priors.
    fn apply_priors(
        &self,
        obs: &Observation,
        fit: &mut Fit,
        update: CameraUpdate,
    ) -> Result<f64, ReconstructError> {
        let limits = self.basis.joint_limits();
        let mut pose = Pose3 { points: fit.points };
        let violation = limits.violation(&pose);
        if !(self.config.symmetry || self.config.joint_limits) {
            return Ok(violation);
        }
        if self.config.symmetry {
            pose = symmetrise(&pose);
        }
        if self.config.joint_limits {
            pose = limits.project(&pose);
        }
        let camera = update.fit_or_keep(&fit.camera, &pose.points, &obs.points);
        fit.error = camera.squared_error(&pose.points, &obs.points)?;
        fit.camera = camera;
        fit.points = pose.points;
        Ok(violation)
    }

    /// One full solve: the camera `start` fitted to the mean pose, the pursuit with camera
    /// `update`, the depth-reflected hypothesis if configured, and, if `refine`, a Procrustes
    /// refinement of each hypothesis; then the priors. Returns the hypotheses (the direct one
    /// first).
    fn solve(
        &self,
        obs: &Observation,
        start: CameraUpdate,
        update: CameraUpdate,
        refine: bool,
    ) -> Result<Vec<Candidate>, ReconstructError> {
        let mean = self.points(&[], &[]);
        let camera = start.start(&mean, &obs.points)?;
        let initial = Fit {
            selected: Vec::new(),
            coefficients: Vec::new(),
            points: mean,
            error: camera.squared_error(&mean, &obs.points)?,
            camera,
            iterations: 0,
            multiplier: None,
        };
        let primary = self.pursue(obs, initial, update)?;
        let other = if self.config.try_depth_reflection {
            let mut other = self.reflected_start(obs, &primary, update)?;
            self.alternate(obs, &mut other, update)?;
            Some(self.pursue(obs, other, update)?)
        } else {
            None
        };
        // The refinement never raises the error.
        let last = if refine {
            CameraUpdate::Procrustes
        } else {
            update
        };
        let finish = |mut fit: Fit, reflected: bool| -> Result<Candidate, ReconstructError> {
            if refine {
                self.alternate(obs, &mut fit, CameraUpdate::Procrustes)?;
            }
            let violation = self.apply_priors(obs, &mut fit, last)?;
            Ok(Candidate {
                fit,
                reflected,
                violation,
            })
        };
        let mut out = vec![finish(primary, false)?];
        if let Some(other) = other {
            out.push(finish(other, true)?);
        }
        Ok(out)
    }
}
