//! # camloc
//!
//! Camera localization from the 2D landmarks of a human pose: which viewpoint on a sphere
//! around the person the image was taken from (by default the 12 cameras of Table 1 of the
//! paper), with its probability, and 3D reconstruction of the pose with that camera.
//!
//! ```no_run
//! use camloc::{CameraLocalizer, Pose2};
//! # fn main() -> Result<(), camloc::CamlocError> {
//! let localizer = CameraLocalizer::default_model()?;
//! let pose = Pose2::new([[0.0; 2]; 15]); // 15 landmarks in image coordinates (v down)
//! let where_ = localizer.localize(&pose)?;
//! println!("camera {:02} ({} {}), p = {:.2}", where_.label, where_.level.name(),
//!          where_.side.name(), where_.probability);
//! # Ok(()) }
//! ```
//!
//! The layers below are re-exported: [`geometry`] (camera sphere, projection, Procrustes),
//! [`skeleton`] (landmarks, limbs, mocap readers), [`dataset`], [`features`], [`learning`],
//! [`keypoints`] and [`reconstruct`](mod@reconstruct).

mod error;
mod evaluate;
mod localizer;
mod reconstruction;
mod select;
pub mod svg;

pub use camloc_dataset as dataset;
pub use camloc_features as features;
pub use camloc_geometry as geometry;
pub use camloc_keypoints as keypoints;
pub use camloc_learning as learning;
pub use camloc_reconstruct as reconstruct;
pub use camloc_skeleton as skeleton;
pub use camloc_store as store;

pub use camloc_features::Descriptor;
pub use camloc_geometry::{CameraSet, Level, Side};
pub use camloc_skeleton::{Landmark, PartialPose2, Pose2, Pose3};
pub use error::CamlocError;
pub use evaluate::{CameraAccuracy, Evaluation, LevelAccuracy, evaluate};
pub use reconstruction::{
    CameraChoice, PoseReconstruction, default_basis, evaluate_reconstruction, reconstruct,
    reconstructor,
};
pub use select::{DescriptorCv, cross_validate};
/// The error for an output file that exists and may not be overwritten.
pub fn store_exists(path: &std::path::Path) -> CamlocError {
    CamlocError::Store(camloc_store::StoreError::Exists {
        path: path.to_path_buf(),
    })
}

pub use localizer::{
    CameraLocalizer, DEFAULT_LAMBDA, LandmarkDropout, Localization, TrainOptions, TrainingInfo,
};
