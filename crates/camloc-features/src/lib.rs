//! 2D pose descriptors: fixed-length feature vectors that describe how a pose looks in the image.
//!
//! Every descriptor is computed relative to a body origin and in units of a 2D torso length
//! (pelvis and neck for `paper` and `landmarks`, mid-hip and mid-shoulder for `joints`), so it
//! is invariant to 2D translation and scale of the input. Image axes are kept (u right, v
//! down): the in-image orientation of the body is what tells the viewpoint.
//!
//! * [`Descriptor::Paper`]: the paper's Algorithm 1 (docs/conventions.md section 4): the 13
//!   non-torso limb lengths relative to the torso through `exp(-rl^2 / (2 sigma^2))`, then a
//!   log-polar shape context histogram of the 14 other landmarks centred on the pelvis.
//! * [`Descriptor::Landmarks`]: keeps which landmark is where: torso-normalised coordinates of
//!   the 14 landmarks, the unit direction of each limb, and the raw relative limb lengths.
//! * [`Descriptor::Joints`] (the default): the same kind of values built only on the 12 limb
//!   joints, in a frame from the mid-hip point to the mid-shoulder point. Mocap skeletons and
//!   photo annotations place the pelvis and neck differently (CMU's neck sits below the
//!   shoulder line, a photo annotator's above it); the limb joints they place alike, so this
//!   descriptor transfers to real keypoints.
//!
//! More capacity than a linear model of a descriptor comes from a learned expansion of it
//! (`camloc_learning::QuadraticExpansion`), not from a descriptor of its own.
//!
//! Every descriptor except the joints descriptor uses the torso (pelvis to neck) as unit and
//! the pelvis as origin (docs/conventions.md section 3); the joints descriptor departs from that on purpose,
//! for the reason above.

mod descriptor;
mod error;
mod shape_context;

pub use descriptor::{Descriptor, PaperConfig};
pub use error::FeatureError;
pub use shape_context::{MAX_SHAPE_CONTEXT_CELLS, ShapeContextBins};
