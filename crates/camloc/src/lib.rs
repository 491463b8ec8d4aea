//! # camloc
//!
//! Camera localization from the 2D landmarks of a human pose: which viewpoint on a sphere
//! around the person the image was taken from (by default the 12 cameras of Table 1 of the
//! paper), with its probability, and 3D reconstruction of the pose with that camera.
//!
//! ```
//! use camloc::keypoints::{ReadOptions, read_keypoints};
//! use camloc::{PartialPose2, PoseReconstructor};
//! # fn main() -> Result<(), camloc::CamlocError> {
//! # let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/keypoints/example.json");
//! // Three 2D poses (15 landmarks in image coordinates, v down) made by this project.
//! let records = read_keypoints(path, None, &ReadOptions::default())?;
//! let poses: Vec<PartialPose2> = records.iter().map(|r| r.pose).collect();
//! // `camloc reconstruct`'s defaults: the embedded basis, model and depth lifter, camera
//! // mode hybrid, the prior over camera heights estimated from the poses.
//! let reconstructor = PoseReconstructor::default_reconstructor()?
//!     .with_camera_height_from(&poses);
//! for (record, pose) in records.iter().zip(&poses) {
//!     let where_ = reconstructor.localize(pose)?; // as `camloc localize`
//!     println!("{}: camera {} ({} {}), p = {:.2}", record.id, where_.label,
//!              where_.level.name(), where_.side.name(), where_.probability);
//!     let pose3 = reconstructor.reconstruct(pose)?.reconstruction.pose;
//!     assert!(pose3.is_finite()); // metres, canonical body frame (docs/conventions.md)
//! }
//! # Ok(()) }
//! ```
//!
//! [`CameraLocalizer::train`] fits a localizer on a [`dataset::Dataset`], [`evaluate`]
//! measures one, [`PoseReconstructor`] reconstructs 3D poses with a chosen [`ModeKind`].
//! Cameras are named by [`CameraLabel`] (Table 1 numbering). The layers below are
//! re-exported: [`geometry`] (camera sphere, projection, Procrustes), [`skeleton`]
//! (landmarks, limbs, pose types), [`mocap`] (BVH and ASF/AMC readers, the BVH writer),
//! [`dataset`], [`features`], [`learning`], [`keypoints`] and
//! [`reconstruct`](mod@reconstruct).

mod aim;
mod below_floor;
mod beyond_limits;
mod camera_height;
mod continuations;
mod conventions;
mod defaults;
mod dropout;
mod error;
mod evaluate;
mod far_off;
mod filled;
mod follow;
mod follow_report;
mod fps_range;
mod height_shares;
mod identity;
mod image_size_check;
mod input_elevation;
mod lean;
mod lengths_fit;
mod lifter;
mod localizer;
mod often_filled;
mod placeholders;
mod reconstruction;
mod rows;
mod select;
mod sequence;
mod sides;
mod spread;
mod stretch_check;
mod torso_placement;
mod train;
mod train_options;
mod upside_down;
mod videos;
mod view_weights;
mod viewpoint_smoothing;
mod world;

pub use camloc_dataset as dataset;
pub use camloc_features as features;
pub use camloc_geometry as geometry;
pub use camloc_keypoints as keypoints;
pub use camloc_learning as learning;
pub use camloc_mocap as mocap;
pub use camloc_reconstruct as reconstruct;
pub use camloc_skeleton as skeleton;
pub use camloc_store as store;

pub use aim::aimed_at_pelvis;
pub use below_floor::{BELOW_FLOOR_CAUSES, BELOW_FLOOR_M, BelowFloor, below_floor};
pub use beyond_limits::{
    BEYOND_LIMITS_MIN_POSES, BEYOND_LIMITS_RAD, BEYOND_LIMITS_SHARE, LimitCount,
};
pub use camera_height::{CameraHeight, EYE_LEVEL_WEIGHT};
pub use camloc_features::Descriptor;
pub use camloc_geometry::CameraLabel;
pub use camloc_geometry::{CameraSet, Level, Side};
pub use camloc_reconstruct::ModeKind;
pub use camloc_skeleton::{Landmark, PartialPose2, Pose2, Pose3};
pub use continuations::{Continuation, continuations};
pub use conventions::InputConventions;
pub use error::CamlocError;
pub use evaluate::{
    BandAccuracy, CameraAccuracy, ELEVATION_BANDS_DEG, Evaluation, LevelAccuracy, RingAccuracy,
    ViewpointAccuracy, evaluate, evaluate_filled,
};
pub use far_off::{FAR_OFF_RATIO, without_far_off_landmarks};
pub use filled::{FILL_TEMPERATURE_STEP, MIN_PRESENT_FOR_FILL, fill_temperature};
pub use follow::{
    DUPLICATE_SIZE_RATIO, DUPLICATE_TORSOS, FOLLOW_GAP_STEPS, LOST_REACH_FACTOR,
    MAX_FOLLOWED_PER_FRAME, follow_people, follow_records, follow_untracked,
};
pub use follow_report::{BRIEF_PERSON_STEPS, FollowReport};
pub use fps_range::frame_rate_problem;
pub use height_shares::{
    HEIGHT_SHARE_MAX_POSES, HEIGHT_SHARE_PSEUDO_VIEWS, HeightEstimate, HeightShares,
    eye_level_shares,
};
pub use identity::{
    IDENTITY_JUMP_TORSOS, IDENTITY_SIZE_RATIO, LeftOut, OUTLIER_END_GAP_FRAMES, OUTLIER_RUN_FRAMES,
    PERSON_STEP_TORSOS, TorsoAnchor, identity_jumps, left_out_of_sequence, outlier_frames,
};
pub use image_size_check::{
    IMAGE_SIZE_CHECK_MIN_POSES, IMAGE_SIZE_CHECK_POSES, IMAGE_SIZE_SWAP_RATIO, ImageSizeCheck,
    SIDE_VIEW_MIN_SINE, WIDER_READING_RATIO,
};
pub use input_elevation::ELEVATION_PSEUDO_VIEWS;
pub use lengths_fit::{LengthsFit, POOR_LENGTHS_FIT_RATIO};
pub use often_filled::{
    FILLED_RUN_GAP_FRAMES, FILLED_RUN_S, FilledCount, FilledLandmark, OFTEN_FILLED_SHARE,
    OftenFilled, often_filled, often_filled_frames,
};
pub use reconstruction::{
    GAP_FILL_S, LANDMARK_SMOOTHING_S, PoseReconstruction, PoseReconstructor,
    PoseSequenceReconstruction, SEQUENCE_BREAK_FRAMES, default_basis, evaluation_samples,
    fill_short_gaps, hybrid_camera, person_height_problem, smooth_landmarks,
};
pub use select::{DescriptorCv, cross_validate};
pub use sequence::{
    DEFAULT_SWITCH_PROBABILITY, NEIGHBOUR_SHARE, OUTLIER_SHARE, SequenceModel, SmoothedFrame,
    frame_slots, sequences, timeline_slots,
};
pub use sides::{
    SIDE_SWAP_GAP_FRAMES, SIDE_SWAP_JOIN_RATIO, SIDE_SWAP_MOTION_FACTOR, SIDE_SWAP_PENALTY,
    SIDE_SWAP_RUN_FRAMES, SideChain, SwappedPart, swap_sides_back, swapped_sides,
    with_part_swapped, with_sides_swapped,
};
pub use stretch_check::{STRETCH_CHECK_MIN_POSES, StretchCheck, VIDEO_STRETCH};

pub use lean::{
    LeanHistogram, TILT_MIN_AGREEMENT, TILT_MIN_POSES, TILT_NEAR_DEG, TILT_SHIN_DEG,
    TILT_WARNING_DEG, orientation_warning, shin_leans_deg, torso_lean_deg,
};
pub use lifter::{DEFAULT_LIFTER_LAMBDA, DepthLifter, depth_targets};
pub use localizer::{CameraLocalizer, Localization};
pub use placeholders::{has_origin_placeholders, origin_placeholder_warning};
pub use torso_placement::{
    MIDPOINT_PLACEMENT, OWN_PLACEMENT, SEQUENCE_PLACEMENT_QUANTILE, own_placement_weight,
    sequence_own_placement_weight,
};
pub use train_options::{
    Capacity, DEFAULT_LAMBDA, DEFAULT_PRECONDITIONER_ROWS, DEFAULT_PRODUCT_ROWS,
    DEFAULT_QUADRATIC_COMPONENTS, DEFAULT_QUADRATIC_LAMBDA, DEFAULT_VIEWPOINT_LAMBDA,
    LandmarkDropout, MAX_DROPOUT_COPIES, QUADRATIC_GRADIENT_TOLERANCE, TrainOptions, TrainingInfo,
};
pub use upside_down::head_below_ankles;
pub use videos::videos_of;
pub use view_weights::NEW_VIEW_SIZES;
pub use viewpoint_smoothing::{
    VIEWPOINT_CUT_DEG, VIEWPOINT_HALF_WINDOW, Viewpoint, smooth_viewpoints, viewpoint_half_window,
};
