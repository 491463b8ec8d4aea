//! The facade's error type.

use camloc_dataset::DatasetError;
use camloc_features::FeatureError;
use camloc_geometry::GeometryError;
use camloc_keypoints::KeypointError;
use camloc_learning::LearningError;
use camloc_reconstruct::ReconstructError;
use camloc_store::StoreError;

/// Everything that can go wrong in camloc, with what and where.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CamlocError {
    /// A descriptor could not be computed for a pose.
    #[error("{context}: {source}")]
    Feature {
        /// Which pose (sample index, record id, ...).
        context: String,
        /// Why.
        source: FeatureError,
    },
    /// A camera label or camera geometry problem (e.g. a label that names no camera).
    #[error(transparent)]
    Geometry(#[from] GeometryError),
    /// Training or prediction failed in the classifier.
    #[error(transparent)]
    Learning(#[from] LearningError),
    /// A file could not be read or written (missing, exists, wrong kind or version, corrupt).
    #[error(transparent)]
    Store(#[from] StoreError),
    /// A dataset problem.
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    /// A keypoint file problem.
    #[error(transparent)]
    Keypoints(#[from] KeypointError),
    /// A motion-capture file could not be read.
    #[error(transparent)]
    Mocap(#[from] camloc_mocap::MocapError),
    /// A BVH file could not be written from the poses given.
    #[error(transparent)]
    Bvh(#[from] camloc_mocap::BvhWriteError),
    /// A reconstruction problem.
    #[error("{context}: {source}")]
    Reconstruct {
        /// Which pose.
        context: String,
        /// Why.
        source: ReconstructError,
    },
    /// A model or basis whose parts do not fit together (e.g. built for another descriptor).
    #[error("inconsistent {what}: {detail}")]
    Inconsistent {
        /// What is inconsistent ("model", "dataset", ...).
        what: &'static str,
        /// Details.
        detail: String,
    },
    /// A pose without a single landmark: nothing was detected (a row of NaN, a detection
    /// whose every score is 0).
    #[error("the pose has no landmarks (nothing detected)")]
    NothingDetected,
    /// No default model (or basis) was embedded at build time.
    #[error(
        "no default {0} is embedded in this build; pass one explicitly or run `cargo xtask train-default`"
    )]
    NoDefault(&'static str),
    /// An invalid option value.
    #[error("invalid {name}: {detail}")]
    InvalidOption {
        /// Option name.
        name: &'static str,
        /// What is wrong.
        detail: String,
    },
}
