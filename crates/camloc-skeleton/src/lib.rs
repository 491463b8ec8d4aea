//! Skeleton conventions shared by every camloc crate (docs/conventions.md section 3): landmarks,
//! limbs and pose types. The motion-capture readers that produce [`Pose3`] sequences are in the
//! `camloc-mocap` crate.
//!
//! * [`Landmark`] names the 15 landmarks in their fixed order, [`LIMBS`] lists the 14 limbs
//!   (the torso, pelvis to neck, is the reference length in 2D).
//! * [`Pose2`] holds 2D landmarks in image coordinates (any unit, `v` grows downwards);
//!   [`Pose3`] holds 3D landmarks in metres in the z-up world frame of docs/conventions.md section
//! 1.

pub mod data;
mod pose;
mod spread;

pub use pose::{
    LIMB_NAMES, LIMBS, Landmark, NECK_HEAD_LIMB, NUM_LANDMARKS, NUM_LIMBS, PartialPose2, Pose2,
    Pose3, SAFE_EXPONENT, TORSO_LIMB, mean_limb_lengths, mirror_landmark_index,
};
pub use spread::{centroid, rms_radius, rms_radius_about};
