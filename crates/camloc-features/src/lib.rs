//! 2D pose descriptors: fixed-length feature vectors that describe how a pose looks in the image.
//!
//! Every descriptor is computed relative to the pelvis and in units of the 2D torso length
//! (pelvis to neck), so it is invariant to 2D translation and scale of the input. Image axes are
//! kept (u right, v down): the in-image orientation of the body is what tells the viewpoint.
//!
//! * [`Descriptor::Paper`]: the paper's Algorithm 1 (SPEC.md section 4): the 13 non-torso limb
//!   lengths relative to the torso through `exp(-rl^2 / (2 sigma^2))`, then a log-polar shape
//!   context histogram of the 14 other landmarks centred on the pelvis.
//! * [`Descriptor::Landmarks`] (the default): keeps which landmark is where: torso-normalised
//!   coordinates of the 14 landmarks, the unit direction of each limb, and the raw relative
//!   limb lengths.

mod descriptor;
mod shape_context;

pub use descriptor::{Descriptor, FeatureError, PaperConfig};
pub use shape_context::ShapeContextBins;
