//! camloc datasets: 2D projections of real 3D poses, labelled with the camera that saw them.
//!
//! A [`Dataset`] is what `cargo xtask gen-dataset` writes and what training, evaluation and
//! reconstruction read. Each [`Sample`] holds the 15 projected landmarks, the camera's class
//! label and exact rotation, the subject, clip and frame it came from, and the canonical 3D pose
//! (metres, pelvis at the origin, facing -x). The [`DatasetHeader`] records the protocol, camera
//! set, seed and versions, so a file says how it was made.
//!
//! [`generate`] builds a dataset from canonical 3D poses under a [`Protocol`]
//! (SPEC.md section 7); [`Dataset::save`]/[`Dataset::load`] store it as a versioned,
//! checksummed file ([`camloc_store`]). Splits are by subject ([`Dataset::split_by_subjects`]).

mod augment;
mod category;
mod dataset;
mod from_mocap;
mod generate;
mod select;

pub use augment::{
    Augmentation, angle_between_deg, camera_direction_deg, direction_vector, in_class_box,
    nearest_by_direction,
};
pub use category::{CATEGORY_RULES, CategorySource, MocapIndex, MotionCategory, assign_categories};
pub use dataset::{
    CameraCount, ClipInfo, DATASET_FILE, Dataset, DatasetError, DatasetHeader, Sample,
    default_test_subjects,
};
pub use from_mocap::{MocapSummary, default_cmu_folder, load_mocap_folders};
pub use generate::{GenerateConfig, Jitter, PoseSequence, Protocol, SPHERE_BAND_DEG, generate};
pub use select::{DEFAULT_MIN_POSE_DISTANCE_MM, max_joint_distance_mm, select_by_pose};
