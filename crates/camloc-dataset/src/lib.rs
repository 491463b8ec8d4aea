//! camloc datasets: 2D projections of real 3D poses, labelled with the camera that saw them.
//!
//! A [`Dataset`] is what `cargo xtask gen-dataset` writes and what training, evaluation and
//! reconstruction read. Each [`Sample`] holds the 15 projected landmarks, the camera's class
//! label and exact rotation, the subject, clip and frame it came from, and the canonical 3D pose
//! (metres, pelvis at the origin, facing -x). The [`DatasetHeader`] records the protocol, camera
//! set, seed and versions, so a file says how it was made.
//!
//! [`generate`] builds a dataset from canonical 3D poses under a [`Protocol`]
//! (docs/conventions.md section 7); `Dataset` implements [`camloc_store::Persist`] (save, load with validation) as a
//! versioned, checksummed file ([`camloc_store`]). Splits are by subject ([`Dataset::split_by_subjects`])
//! or by motion category ([`Dataset::split_by_category`], leave-one-category-out).
//!
//! Frames are chosen by pose ([`select_by_pose`]: a frame is kept when its maximum per-joint
//! distance to every frame kept before it in its clip exceeds a threshold in mm), so static
//! stretches, repeated cycles and frame rates do not decide what a model sees. Each clip
//! carries a [`MotionCategory`] read from the CMU index text ([`MocapIndex`],
//! [`assign_categories`]). The `sphere` protocol draws camera directions anywhere in the band
//! the Table-1 cameras cover and labels each with the camera of its elevation ring and
//! azimuth quadrant ([`by_ring_and_side`](camloc_geometry::CameraSet::by_ring_and_side)),
//! recording whether it lies in that camera's class box; [`Augmentation`] varies bone lengths
//! and the neck, pelvis and head placements of photo annotations.

mod augment;
mod dataset;
mod error;
mod from_mocap;
mod generate;
mod posture;
mod protocol;
mod rig;
mod select;
#[cfg(test)]
mod test_poses;

pub use augment::{
    Augmentation, angle_between_deg, annotated, camera_direction_deg, direction_vector,
    in_class_box,
};
pub use camloc_mocap::{CATEGORY_RULES, CategorySource, MocapIndex, MotionCategory};
pub use dataset::{
    CameraCount, ClipInfo, Dataset, DatasetHeader, MAX_CLIPS, Sample, default_test_subjects,
};
pub use error::DatasetError;
pub use from_mocap::{MocapSummary, assign_categories, load_mocap_folders};
pub use generate::{GenerateConfig, PoseSequence, generate};
pub use posture::{
    BodyAngles, FLOOR_CLEARANCE_M, LIMIT_COVERAGE, LOW_PELVIS_SHARE, PostureGroup, PostureKind,
    PostureLimits, body_angles, is_low_posture, make_posture, pelvis_height_m,
};
pub use protocol::{Jitter, Protocol, SPHERE_BAND_DEG};
pub use rig::{DetectorNoise, Rig, RigView};
pub use select::{DEFAULT_MIN_POSE_DISTANCE_MM, max_joint_distance_mm, select_by_pose};
