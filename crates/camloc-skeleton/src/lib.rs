//! Skeleton conventions shared by every camloc crate (SPEC.md section 3) and readers that turn
//! CMU motion capture (ASF/AMC and BVH) into 3D landmark positions.
//!
//! * [`Landmark`] names the 15 landmarks in their fixed order, [`LIMBS`] lists the 14 limbs
//!   (the torso, pelvis to neck, is the reference length in 2D).
//! * [`mocap`] reads CMU BVH and ASF/AMC files into [`Pose3`] sequences and canonicalises
//!   them (pelvis at the origin, facing -x).
//! * [`Pose2`] holds 2D landmarks in image coordinates (any unit, `v` grows downwards);
//!   [`Pose3`] holds 3D landmarks in metres in the z-up world frame of SPEC.md section 1.

pub mod mocap;
mod pose;

pub use pose::{
    LIMB_NAMES, LIMBS, Landmark, NUM_LANDMARKS, NUM_LIMBS, PartialPose2, Pose2, Pose3,
    SAFE_EXPONENT, TORSO_LIMB, mirror_landmark_index,
};
