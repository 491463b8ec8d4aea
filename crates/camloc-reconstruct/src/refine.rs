//! The skeleton refinement: the pursuit's pose rebuilt with a person's own bone lengths and
//! fitted again to the 2D (docs/conventions.md section 6).
//!
//! The pose is a skeleton of 14 bones from the pelvis, each a unit direction times a length.
//! Starting from the pursuit's pose (its bone directions) and camera, Levenberg-Marquardt
//! minimises the robust reprojection error (Huber) plus, as priors, each bone direction's
//! distance from the pursuit's (which keeps the pursuit's choice of depths and its learned
//! pose where the 2D says nothing) and, when the lengths are unknowns, a Gaussian on the log
//! lengths ([`LengthPrior`](crate::LengthPrior), widened by [`LengthWidening`]). Over the
//! frames of one person (a sequence) the lengths are shared and each bone's direction in the
//! camera's orientation is held near the mean of its neighbouring frames' (unknown lengths
//! are estimated by a first pass without that term, `Reconstructor::reconstruct_sequence`).
//! With known intrinsics the camera is a full perspective one; without them, by default, a
//! perspective camera at an unknown distance ([`Refinement::distance`]) shared by the frames.
//!
//! Layers: `kinematics` (bones to landmarks), `problem` (one frame's cost and normal
//! equations), `solve` (the steps over all frames), `run` (from pursuit results to refined
//! poses).

mod kinematics;
mod problem;
mod run;
mod solve;

use camloc_geometry::Matrix3;
use camloc_skeleton::Pose2;
use serde::{Deserialize, Serialize};

use crate::length_prior::LengthWidening;
use crate::{BoneLengths, FrameRate, ReconstructError};
use camloc_skeleton::rms_radius;

pub(crate) use run::{LengthInput, RefineFrame, RefinedFrame, refine};

/// Settings of the skeleton refinement ([`ReconstructConfig::refinement`]).
///
/// [`ReconstructConfig::refinement`]: crate::ReconstructConfig::refinement
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Refinement {
    /// Without given lengths: refine with the lengths as unknowns under the length prior
    /// (`true`), or keep the pursuit's pose with the training-average proportions (`false`,
    /// no refinement). Given lengths or intrinsics are always refined with.
    pub estimate_lengths: bool,
    /// Deviation of the 2D landmarks, in units of the input's RMS radius about its centroid
    /// (the 2D input is normalised so; a torso is about 1.1 of them); > 0.
    pub image_sigma: f64,
    /// Huber threshold of a landmark's reprojection error, in `image_sigma`s; > 0.
    pub huber: f64,
    /// Deviation of each bone's unit direction from the one the refinement starts from (the
    /// pursuit's pose, or the lifted one in sequences and under full perspective); > 0.
    pub direction_sigma: f64,
    /// Single frames started from a lifted pose without intrinsics: the
    /// same deviation, from the lifted directions; > 0. The lifted pose is the better
    /// anchor there, so it is held tighter; in sequences and under full perspective (the
    /// lifted pose is an orthographic reading of the 2D) `direction_sigma` measured better
    /// (docs/RESULTS.md).
    pub lifted_direction_sigma: f64,
    /// Single frames started from a lifted pose with known intrinsics: from this distance of
    /// the camera (metres, the focal length over the pursuit's scale) on, the frame takes
    /// [`lifted_direction_sigma`](Self::lifted_direction_sigma) as under weak perspective:
    /// there a body's depth changes its image by a few percent, and the lifted pose (an
    /// orthographic reading) is as good an anchor; `f64::INFINITY` for never; > 0.
    pub weak_perspective_from_m: f64,
    /// The length prior's widening for other skeletons and detectors.
    pub widening: LengthWidening,
    /// Without intrinsics: the camera's distance from the pelvis is an unknown under this
    /// prior (one for all the frames of a sequence) and the camera a perspective one with the
    /// pelvis on its optical axis (the reported `camera` is its weak-perspective
    /// approximation at the pelvis); `None` keeps weak perspective (a camera far away).
    pub distance: Option<DistancePrior>,
    /// Most Levenberg-Marquardt steps (at least 1).
    pub iterations: usize,
    /// Sequences: deviation of each bone's unit direction in the camera's orientation from
    /// the mean of the frames before and after it; 0 turns the smoothness off. At frame
    /// rates above [`REFERENCE_FRAME_RATE_HZ`](crate::REFERENCE_FRAME_RATE_HZ) the frames
    /// within 1/30 s on each side and the deviation times
    /// [`FrameRate::deviation_factor`] ([`frame_rate`](Self::frame_rate)).
    pub smoothness: f64,
    /// Sequences: the smoothness of a bone whose end landmark was imputed (filled in from the
    /// pose basis, not seen) is
    /// this many times as strong (its deviation divided by it; >= 1): nothing in the image
    /// holds such a bone, and each frame's guess had made hidden limbs swing and jump (on
    /// held-out windows with landmarks missing over 5 to 40 frames and filled in from the
    /// basis, 4 brought them 1-8 mm closer, `jittered` and `rig`; 10 and 25 no closer).
    pub hidden_smoothness: f64,
    /// Sequences: their frames a second, which scales [`smoothness`](Self::smoothness)
    /// ([`FrameRate`]; the reference rate, 30, by default).
    pub frame_rate: FrameRate,
    /// Sequences with unknown lengths: the length prior's deviations are divided by
    /// `min(sequence_prior, sqrt(frames))` (a one-frame sequence keeps the single frame's
    /// prior); >= 1. The frames of one video share their errors (a camera elevation misjudged
    /// over a window draws every frame's depths alike), which the per-frame reprojection
    /// terms count as independent evidence: without it the lengths follow those shared
    /// errors.
    pub sequence_prior: f64,
    /// Sequences with unknown lengths, beyond this many frames: the length prior's weight
    /// grows with the frames as their reprojection terms' does (its deviations divided by
    /// `sequence_prior * sqrt(frames / length_evidence_frames)` when that is larger), so that
    /// a long video weighs the errors its frames share against the prior as a window of this
    /// many frames does; >= 1. Without it the lengths of a long video follow those shared
    /// errors to implausible values (a person seen from one side for 10,000 frames: the
    /// collar bones, along the depth, shrank to 1 cm).
    pub length_evidence_frames: f64,
    /// Sequences: choose each frame's depth hypothesis by the Viterbi path that fits the 2D
    /// and moves least between frames (`true`), or take each frame's preferred one.
    pub consistent_depth: bool,
    /// Sequences: deviation of the camera-oriented landmarks between consecutive frames in
    /// the Viterbi path's cost (metres, at the training-average size); > 0.
    pub motion_m: f64,
    /// The head's limit: the angle (radians) between the neck-to-head bone and the
    /// pelvis-to-neck one beyond which a prior holds the head back (the CMU motion capture's
    /// heads lie within 47 deg of it, 99.5% within 36 deg; a head bowed or thrown back
    /// further than the limit is taken for a 2D head point that the depth cannot explain,
    /// such as one annotated below the neck); > 0, `f64::INFINITY` for none.
    pub head_tilt_limit_rad: f64,
    /// Deviation (radians) of the head's angle beyond [`head_tilt_limit_rad`]; > 0.
    ///
    /// [`head_tilt_limit_rad`]: Self::head_tilt_limit_rad
    pub head_tilt_sigma_rad: f64,
}

impl Default for Refinement {
    /// Lengths estimated; image deviation 0.04 (about 4% of a torso), Huber at 2.5
    /// deviations, direction deviation 0.15 (0.10 from a single frame's lifted pose, with
    /// known intrinsics from 15 m), the
    /// default widening, the camera's distance estimated under [`DistancePrior::default`], 10
    /// steps; in sequences smoothness 0.07 (0.1 before; docs/RESULTS.md) at 30 frames a
    /// second, 4 times as strong for bones ending in a filled-in landmark, the length prior's
    /// deviations halved (`sequence_prior` 2) and made to keep pace with the frames beyond 60
    /// (`length_evidence_frames`), the Viterbi choice of depths with motion deviation 0.1 m;
    /// the head held back beyond 75 deg from the torso's line with a deviation of 0.05 rad.
    fn default() -> Self {
        Refinement {
            estimate_lengths: true,
            image_sigma: 0.04,
            huber: 2.5,
            direction_sigma: 0.15,
            lifted_direction_sigma: 0.10,
            weak_perspective_from_m: 15.0,
            widening: LengthWidening::default(),
            distance: Some(DistancePrior::default()),
            iterations: 10,
            smoothness: 0.07,
            hidden_smoothness: 4.0,
            frame_rate: FrameRate::default(),
            sequence_prior: 2.0,
            length_evidence_frames: 60.0,
            consistent_depth: true,
            motion_m: 0.1,
            head_tilt_limit_rad: 75f64.to_radians(),
            head_tilt_sigma_rad: 0.05,
        }
    }
}

impl Refinement {
    /// An error naming the first setting out of range.
    pub(crate) fn check(&self) -> Result<(), ReconstructError> {
        let invalid = |field, value: f64, reason| ReconstructError::InvalidConfig {
            field,
            value: format!("{value:?}"),
            reason,
        };
        for (field, value) in [
            ("Refinement::image_sigma", self.image_sigma),
            ("Refinement::huber", self.huber),
            ("Refinement::direction_sigma", self.direction_sigma),
            (
                "Refinement::lifted_direction_sigma",
                self.lifted_direction_sigma,
            ),
            ("Refinement::motion_m", self.motion_m),
            ("Refinement::head_tilt_sigma_rad", self.head_tilt_sigma_rad),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(invalid(field, value, "must be finite and > 0"));
            }
        }
        if !(self.smoothness.is_finite() && self.smoothness >= 0.0) {
            return Err(invalid(
                "Refinement::smoothness",
                self.smoothness,
                "must be finite and >= 0",
            ));
        }
        FrameRate::new(self.frame_rate.hz())?;
        if !(self.hidden_smoothness.is_finite() && self.hidden_smoothness >= 1.0) {
            return Err(invalid(
                "Refinement::hidden_smoothness",
                self.hidden_smoothness,
                "must be finite and >= 1",
            ));
        }
        if !(self.sequence_prior.is_finite() && self.sequence_prior >= 1.0) {
            return Err(invalid(
                "Refinement::sequence_prior",
                self.sequence_prior,
                "must be finite and >= 1",
            ));
        }
        if !(self.length_evidence_frames.is_finite() && self.length_evidence_frames >= 1.0) {
            return Err(invalid(
                "Refinement::length_evidence_frames",
                self.length_evidence_frames,
                "must be finite and >= 1",
            ));
        }
        if !(self.head_tilt_limit_rad > 0.0) {
            return Err(invalid(
                "Refinement::head_tilt_limit_rad",
                self.head_tilt_limit_rad,
                "must be > 0 (infinite for no limit)",
            ));
        }
        if !(self.weak_perspective_from_m > 0.0) {
            return Err(invalid(
                "Refinement::weak_perspective_from_m",
                self.weak_perspective_from_m,
                "must be > 0 (infinite for never)",
            ));
        }
        if self.iterations == 0 {
            return Err(invalid(
                "Refinement::iterations",
                0.0,
                "at least one step is needed",
            ));
        }
        if let Some(distance) = &self.distance {
            if !(distance.mean_per_m.is_finite() && distance.mean_per_m >= 0.0) {
                return Err(invalid(
                    "DistancePrior::mean_per_m",
                    distance.mean_per_m,
                    "must be finite and >= 0",
                ));
            }
            if !(distance.sigma_per_m.is_finite() && distance.sigma_per_m > 0.0) {
                return Err(invalid(
                    "DistancePrior::sigma_per_m",
                    distance.sigma_per_m,
                    "must be finite and > 0",
                ));
            }
        }
        self.widening.check()
    }
}

/// The prior on the distance of a camera whose intrinsics are not given
/// ([`Refinement::distance`]): a Gaussian on the inverse of the distance from the camera to
/// the pelvis.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct DistancePrior {
    /// Mean inverse distance, 1/m; finite and >= 0 (0: a camera far away).
    pub mean_per_m: f64,
    /// Deviation of the inverse distance, 1/m; finite and > 0.
    pub sigma_per_m: f64,
}

impl Default for DistancePrior {
    /// Mean 0.1/m (a camera 10 m away), deviation 0.1/m.
    fn default() -> Self {
        DistancePrior {
            mean_per_m: 0.1,
            sigma_per_m: 0.1,
        }
    }
}

/// The shortest focal length, pixels, that [`Intrinsics::check`] accepts: an image a few
/// pixels wide would see the whole half-space in front of the camera.
pub const MIN_FOCAL_PX: f64 = 1.0;

/// A pinhole camera's intrinsics, in the input's image units (pixels).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Intrinsics {
    /// Focal length, pixels; finite and at least [`MIN_FOCAL_PX`].
    pub focal_px: f64,
    /// Principal point `(u, v)`, pixels (`u` right, `v` down, as the input); `None`: the
    /// centre of each pose's 2D bounding box (the person taken to be near the image centre).
    pub principal_point: Option<[f64; 2]>,
}

impl Intrinsics {
    /// Checks the intrinsics.
    ///
    /// # Errors
    /// [`ReconstructError::InvalidConfig`] when the focal length is not finite and at least
    /// [`MIN_FOCAL_PX`] or the principal point is not finite.
    pub fn check(&self) -> Result<(), ReconstructError> {
        if !(self.focal_px.is_finite() && self.focal_px >= MIN_FOCAL_PX) {
            return Err(ReconstructError::InvalidConfig {
                field: "the focal length (pixels)",
                value: format!("{:?}", self.focal_px),
                reason: "it must be finite and at least 1 pixel",
            });
        }
        if let Some(point) = self
            .principal_point
            .filter(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(ReconstructError::InvalidConfig {
                field: "the principal point (pixels)",
                value: format!("{:?}, {:?}", point[0], point[1]),
                reason: "it must be finite",
            });
        }
        Ok(())
    }
}

/// The smallest root mean square radius of a 2D pose, as a share of the focal length, that
/// [`Intrinsics::check_pose`] accepts: a person's landmarks lie about 0.4 m from their centroid,
/// so a smaller pose would be more than about 400 m away.
pub const MIN_POSE_SPREAD_PER_FOCAL: f64 = 1e-3;

/// The largest root mean square radius of a 2D pose, and the largest distance of its centroid
/// from the principal point, in focal lengths, that [`Intrinsics::check_pose`] accepts: a
/// centroid 10 focal lengths off the axis lies 84 deg from it (a wide lens's corner is about
/// 1 to 2 focal lengths off), and a person's landmarks 0.4 m from their centroid spread over
/// 10 focal lengths 4 cm from the lens. A re-test found 100 too wide: a focal length of 5
/// px gave confident labels.
pub const MAX_POSE_REACH_PER_FOCAL: f64 = 10.0;

impl Intrinsics {
    /// Checks that `pose` is in the units of the focal length and in the camera's view: its
    /// root mean square radius about its centroid is at least [`MIN_POSE_SPREAD_PER_FOCAL`]
    /// of the focal length, and neither that radius nor the centroid's distance from the
    /// principal point (when given) exceeds [`MAX_POSE_REACH_PER_FOCAL`] focal lengths.
    ///
    /// # Errors
    /// [`ReconstructError::ScaleMismatch`] for a smaller pose (normalised coordinates with a
    /// focal length in pixels); [`ReconstructError::OutsideView`] for a pose a camera of this
    /// focal length and principal point cannot see (a focal length or principal point wrong
    /// by orders of magnitude).
    pub fn check_pose(&self, pose: &Pose2) -> Result<(), ReconstructError> {
        self.check_points(&pose.points)
    }

    /// [`check_pose`](Self::check_pose) on the landmarks `points` of a pose (those present
    /// of a partial one; none: nothing to check).
    ///
    /// # Errors
    /// As [`check_pose`](Self::check_pose).
    pub fn check_points(&self, points: &[[f64; 2]]) -> Result<(), ReconstructError> {
        if points.is_empty() {
            return Ok(());
        }
        let spread = rms_radius(points);
        if spread < MIN_POSE_SPREAD_PER_FOCAL * self.focal_px {
            return Err(ReconstructError::ScaleMismatch {
                spread,
                focal: self.focal_px,
            });
        }
        let n = points.len() as f64;
        let centroid = [0, 1].map(|k| points.iter().map(|p| p[k]).sum::<f64>() / n);
        let off_axis = self
            .principal_point
            .map_or(0.0, |c| (centroid[0] - c[0]).hypot(centroid[1] - c[1]));
        let reach = spread.max(off_axis) / self.focal_px;
        if !(reach <= MAX_POSE_REACH_PER_FOCAL) {
            return Err(ReconstructError::OutsideView {
                reach,
                focal: self.focal_px,
            });
        }
        Ok(())
    }
}

/// A full perspective camera fitted with known [`Intrinsics`], or at an estimated distance
/// ([`Refinement::distance`]): a body-frame point `X`
/// (metres, the reconstruction's frame) is at `Y = R X + T` in the camera frame and seen at
/// `u = f Y_x / Y_z + c_u`, `v = f Y_y / Y_z + c_v` (pixels).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PerspectiveCamera {
    /// `R`: rows are the camera's axes in the body frame (row 3 the optical axis).
    pub rotation: Matrix3,
    /// `T`: the pelvis in the camera frame, metres (`T_z` its depth). Absolute only when the
    /// bone lengths were given or the reconstruction was resized to the person's height
    /// ([`Reconstruction::resize_to_height`](crate::Reconstruction::resize_to_height)): with
    /// estimated lengths the size, hence the depth, is the length prior's.
    pub translation: [f64; 3],
    /// The focal length `f`, pixels (the given one, or the estimated one).
    pub focal_px: f64,
    /// The principal point `(c_u, c_v)` used, pixels.
    pub principal_point: [f64; 2],
}

impl PerspectiveCamera {
    /// The image points of `points` (body frame, metres); `None` when one is not in front
    /// of the camera.
    pub fn project<const N: usize>(&self, points: &[[f64; 3]; N]) -> Option<[[f64; 2]; N]> {
        let mut out = [[0.0; 2]; N];
        for (o, x) in out.iter_mut().zip(points) {
            let y = self.rotation * camloc_geometry::Vector3::from(*x);
            let z = y.z + self.translation[2];
            if !(z > 0.0) {
                return None;
            }
            let f = self.focal_px / z;
            *o = [
                f * (y.x + self.translation[0]) + self.principal_point[0],
                f * (y.y + self.translation[1]) + self.principal_point[1],
            ];
        }
        Some(out)
    }
}

/// What is known of the person and the camera besides the 2D: the person's bone lengths and
/// the camera's intrinsics, each optional.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Given {
    /// The person's bone lengths: the reconstruction has exactly these (metres).
    pub lengths: Option<BoneLengths>,
    /// The camera's intrinsics: a final full perspective refinement.
    pub intrinsics: Option<Intrinsics>,
}
