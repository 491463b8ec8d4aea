//! Errors of the reconstruction crate.

use camloc_geometry::GeometryError;

/// What can go wrong building a basis, reconstructing a pose or validating a stored basis
/// (reading and writing basis files fail with [`camloc_store::StoreError`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReconstructError {
    /// [`crate::PoseBasis::fit`] was given no training poses.
    #[error("pose basis: the training set is empty")]
    EmptyTrainingSet,
    /// A training pose holds NaN or infinity.
    #[error("pose basis: training pose {index} has a non-finite coordinate")]
    NonFiniteTrainingPose {
        /// Index of the pose in the training slice.
        index: usize,
    },
    /// A training pose has all limbs of zero length, so its scale cannot be normalised.
    #[error("pose basis: training pose {index} has zero total limb length (all joints coincide)")]
    DegenerateTrainingPose {
        /// Index of the pose in the training slice.
        index: usize,
    },
    /// More PCA components were requested than the training poses support.
    #[error(
        "pose basis: {requested} components requested but the {training} training poses span only {available} directions with non-zero variance"
    )]
    TooManyComponents {
        /// `BasisConfig::n_components`.
        requested: usize,
        /// Number of components with variance above the numerical floor.
        available: usize,
        /// Number of training poses.
        training: usize,
    },
    /// A configuration value is out of its valid range.
    #[error("invalid configuration: {field} = {value}: {reason}")]
    InvalidConfig {
        /// Name of the field, e.g. `ReconstructConfig::max_basis`.
        field: &'static str,
        /// The offending value, formatted.
        value: String,
        /// Why it is refused.
        reason: &'static str,
    },
    /// A stored basis decoded but its content is inconsistent (the file's name is added by
    /// [`camloc_store::StoreError::Invalid`] around this error).
    #[error("pose basis content is inconsistent: {reason}")]
    InvalidBasis {
        /// What is inconsistent.
        reason: String,
    },
    /// The 2D input holds NaN or infinity.
    #[error("2D pose: landmark {landmark} ({name}) has a non-finite coordinate")]
    NonFiniteInput {
        /// Landmark index (0..15).
        landmark: usize,
        /// Landmark name.
        name: &'static str,
    },
    /// Too few landmarks of the 2D input are present to fill in the others: the 3D pose
    /// would be mostly the basis's guess.
    #[error(
        "{present} landmark{} present, {needed} needed to fill in the missing ones and reconstruct the pose",
        if *.present == 1 { "" } else { "s" }
    )]
    TooFewLandmarks {
        /// Landmarks present.
        present: usize,
        /// The fewest accepted.
        needed: usize,
    },
    /// A 2D pose far smaller than the focal length says a person can be: keypoints in other
    /// units than the focal length (normalised 0-1 coordinates with a focal length in pixels).
    #[error(
        "2D pose spans {spread:.3} (root mean square radius) at a focal length of {focal:?}, under \
         1/{} of it: a person hundreds of metres away; give the keypoints in the focal \
         length's units (pixels)",
        crate::MIN_POSE_SPREAD_PER_FOCAL.recip()
    )]
    ScaleMismatch {
        /// The pose's root mean square radius about its centroid (input units).
        spread: f64,
        /// The focal length given (pixels).
        focal: f64,
    },
    /// A 2D pose spread over, or lying off the optical axis by, more focal lengths than a
    /// camera sees ([`crate::MAX_POSE_REACH_PER_FOCAL`]): a focal length or principal point
    /// wrong by orders of magnitude.
    #[error(
        "2D pose reaches {reach:.3e} focal lengths (focal length {focal:.3e}) from its centroid \
         or the principal point, beyond a camera's view ({}); check the focal length and \
         principal point (pixels)",
        crate::MAX_POSE_REACH_PER_FOCAL
    )]
    OutsideView {
        /// The larger of the pose's root mean square radius and its centroid's distance from
        /// the principal point, in focal lengths.
        reach: f64,
        /// The focal length given (pixels).
        focal: f64,
    },
    /// A 2D pose that spans 90 deg or more of the view under a focal length: turned to aim at
    /// its pelvis, a landmark lies behind the camera (a focal length far too short).
    #[error(
        "2D pose spans 90 deg or more of the view at a focal length of {focal:?} (aimed at its \
         pelvis, a landmark lies behind the camera); check the focal length and principal \
         point (pixels)"
    )]
    BeyondView {
        /// The focal length given (pixels).
        focal: f64,
    },
    /// The camera fitted to a 2D pose sees some of its landmarks behind it: a landmark lies
    /// far from where the others put it (a detection misplaced by most of the image), or a
    /// very close wide-angle view (a simulated user's: 5 of 658 views at 0.45-0.75 m with a
    /// focal length of 500 px, 39 of 779 at 300 px; none of 4,481 from 0.9 m on).
    #[error(
        "the camera fitted to the 2D pose has landmarks behind it: a landmark is likely \
         misplaced far from the others (give it as missing), or the camera is closer and wider \
         than the fit follows"
    )]
    BehindFittedCamera,
    /// The 2D input cannot be reconstructed (zero torso, all points coinciding).
    #[error("2D pose is degenerate: {0}")]
    DegenerateInput(&'static str),
    /// A camera rotation given in a [`crate::CameraMode`] is not a proper rotation.
    #[error("camera mode {mode}: the given matrix is not a proper rotation: {source}")]
    InvalidRotation {
        /// Name of the mode.
        mode: &'static str,
        /// The rotation check that failed.
        source: GeometryError,
    },
    /// A constrained least-squares problem has no feasible point (the constraint's quadric is
    /// empty).
    #[error(
        "constrained least squares: the constraint set is empty (radius^2 = {radius_sq:.3e} < 0)"
    )]
    InfeasibleConstraint {
        /// `c^T Q^-1 c - e`, which must be non-negative.
        radius_sq: f64,
    },
    /// The constraint matrix `Q` is not symmetric positive definite.
    #[error("constrained least squares: Q is not symmetric positive definite")]
    NotPositiveDefinite,
    /// Matrix or vector sizes of a least-squares problem do not agree.
    #[error("constrained least squares: {what}: expected {expected}, got {got}")]
    DimensionMismatch {
        /// Which operand.
        what: &'static str,
        /// Expected size.
        expected: usize,
        /// Given size.
        got: usize,
    },
    /// A numerical step failed (non-finite intermediate, failed eigen-decomposition).
    #[error("numerical failure: {0}")]
    Numerical(&'static str),
    /// A camera estimate failed.
    #[error("camera estimation failed: {0}")]
    Geometry(#[from] GeometryError),
    /// Bone lengths were refused.
    #[error(transparent)]
    BoneLengths(#[from] crate::BoneLengthError),
}
