//! Projected matching pursuit (Ramakrishna, Kanade & Sheikh, ECCV 2012; the paper's eqs. 5-6)
//! with the camera modes of docs/conventions.md section 6.
//!
//! Layers, each using only those above it: `config` and `mode` (the public options),
//! `observation` (the normalised 2D input), `camera_update` (how the camera is re-fitted),
//! `reconstructor` (the [`Reconstructor`] and its precomputed constraint), `greedy` (the
//! pursuit loop), `reflection` (the depth-reflected start), `hypotheses` (the solves of a
//! mode, the priors and the ranking), `refined` (each hypothesis refined with the person's
//! own bone lengths, [`crate::refine`]), `sequence` (the frames of one person: depths
//! chosen over time, one refinement with shared lengths), `impute` (missing landmarks
//! filled in from the basis seen by a given rotation) and `level` (a reconstruction turned
//! so that its camera stands at a given elevation).

mod camera_update;
mod coefficients;
mod config;
mod greedy;
mod hypotheses;
mod impute;
mod level;
mod mode;
mod observation;
mod reconstructor;
mod refined;
mod reflection;
mod sequence;
mod size;
#[cfg(test)]
mod tests;

pub use config::{DEFAULT_COEFFICIENT_PRIOR, EQUAL_FIT_TOLERANCE, LengthTarget, ReconstructConfig};
pub use hypotheses::Reconstruction;
pub use level::LEVEL_AZIMUTH_AGREEMENT_DEG;
pub use mode::{CameraMode, ModeKind};
pub use reconstructor::Reconstructor;
pub use refined::{LiftedDepths, depths_along_axis};
pub use sequence::SequenceReconstruction;
