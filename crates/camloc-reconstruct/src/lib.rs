//! 3D human pose from 2D landmarks (docs/conventions.md; the paper's eqs. 5-6 and 12; Ramakrishna,
//! Kanade & Sheikh, "Reconstructing 3D Human Pose from 2D Image Landmarks", ECCV 2012).
//!
//! * [`PoseBasis`]: mean pose and PCA components of scale-normalised canonical 3D poses
//!   (metres, pelvis at the origin, facing -x) and, for a dictionary ([`BasisKind`]), k-means
//!   cluster centres beside them; the anthropometric target (the training poses' common sum
//!   of squared limb lengths) and the learned [`JointLimits`]; stored as a versioned,
//!   checksummed file ([`camloc_store::Persist`], validated after every decode).
//! * [`Reconstructor::reconstruct`]: projected matching pursuit. The pose `mu + B w` (at most
//!   `k` components) and a weak-perspective camera minimise the reprojection error (eq. 6)
//!   subject to the anthropometric constraint, solved exactly per step by
//!   [`constrained_least_squares`]. The camera comes from a [`CameraMode`]: Procrustes
//!   (`opt`), a fixed rotation (`classified`, `oracle`) or a fixed start refined by
//!   Procrustes (`hybrid`). The depth-reflected solution is tried as a second hypothesis;
//!   [`Reconstructor::reconstruct_hypotheses`] returns them ranked. Priors
//!   ([`ReconstructConfig`]): a Gaussian on the coefficients, left/right limb symmetry
//!   ([`symmetrise`]) and the joint-angle limits.
//! * Metrics: [`mpjpe_after_similarity`] (millimetres, reflection excluded),
//!   [`projection_error_eq12`] and its bounding-box variant, [`rms_error_in_torsos`].
//! * [`evaluate`]: compares modes over samples with known truth, in parallel.
//!
//! # Example
//!
//! ```no_run
//! use camloc_geometry::CameraSet;
//! use camloc_reconstruct::{BasisConfig, CameraMode, PoseBasis, ReconstructConfig, Reconstructor};
//! use camloc_store::Persist; // save / load
//! # fn training_poses() -> Vec<camloc_skeleton::Pose3> { unimplemented!() }
//! # fn landmarks() -> camloc_skeleton::Pose2 { unimplemented!() }
//!
//! let basis = PoseBasis::fit(&training_poses(), &BasisConfig::default())?;
//! basis.save("basis.bin".as_ref(), false)?;
//! let reconstructor = Reconstructor::new(basis, ReconstructConfig::default())?;
//! // Camera 05 (middle level, front), e.g. from the viewpoint classifier.
//! let table = CameraSet::table1();
//! let Some(front) = table.get(5) else { unreachable!("Table 1 has camera 05") };
//! let recon = reconstructor.reconstruct(&landmarks(), &CameraMode::Hybrid(front.rotation))?;
//! println!("{} basis poses, eq. 6 error {:.2} px", recon.selected.len(), recon.projection_error);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Frames and units
//!
//! 3D poses are in metres in the basis's canonical body frame (pelvis at the origin, z up, the
//! training poses facing -x). A reconstruction has the training-average body size, so compare
//! it with a truth only after a similarity alignment ([`mpjpe_after_similarity`]). 2D input is
//! in any image units (`v` down); the returned camera maps the 3D pose into those units.
//!
//! # Choosing a camera mode
//!
//! `opt` needs nothing but the 2D pose, is the fastest, and is the default of the `camloc`
//! facade and tool. With the default basis and priors, `hybrid` (which starts from the class
//! rotation and lets Procrustes move away from it, limiting the cost of a wrong or approximate
//! class) gave the lowest 3D error on held-out CMU subjects under both protocols, at about
//! twice the time of `opt` (`cargo bench -p camloc --bench reconstruct`); a fixed class
//! rotation (`classified`) helps only when the true camera is close to it, as under the
//! `canonical` protocol. The measurements behind this, per protocol and mode, are in
//! `docs/RESULTS.md` (`cargo xtask report` and the `compare_modes` example).

mod basis;
mod dense;
mod error;
mod eval;
mod frame_rate;
mod length_prior;
mod lengths;
mod lsq;
mod metrics;
mod prior;
mod pursuit;
mod refine;
mod viterbi;
mod world;

pub use basis::{
    BasisConfig, BasisKind, DEFAULT_ATOMS, MAX_ATOMS, POSE_DIM, PoseBasis, sum_squared_limb_lengths,
};
pub use error::ReconstructError;
pub use eval::{
    EvalReport, EvalSample, ModeReport, Pipeline, PipelineReport, evaluate, evaluate_with_pipeline,
};
pub use frame_rate::{FrameRate, MOST_WINDOW_RATE_HZ, REFERENCE_FRAME_RATE_HZ};
pub use length_prior::{IMPLAUSIBLE_LENGTHS_D2, LengthPrior, LengthWidening};
pub use lengths::{
    BONE_KEYS, BONE_LENGTHS_FORMAT, BONE_LENGTHS_VERSION, BoneLengthError, BoneLengths,
    LEGS_SHARE_OF_HEIGHT, MAX_BONE_LENGTH_M, MAX_BONE_LENGTHS_FILE_BYTES, MAX_HEIGHT_M,
    MIN_BONE_LENGTH_M, MIN_HEIGHT_M,
};
pub use lsq::{ConstrainedSolution, QuadraticConstraint, constrained_least_squares};
pub use metrics::{
    BBOX_FLOOR_IN_TORSOS, align_similarity, bounding_box, median, mpjpe_after_scale,
    mpjpe_after_similarity, projection_error_eq12, projection_error_eq12_bbox, rms_error_in_torsos,
};
pub use prior::{JointLimits, symmetrise};
pub use pursuit::{
    CameraMode, DEFAULT_COEFFICIENT_PRIOR, EQUAL_FIT_TOLERANCE, LEVEL_AZIMUTH_AGREEMENT_DEG,
    LengthTarget, LiftedDepths, ModeKind, ReconstructConfig, Reconstruction, Reconstructor,
    SequenceReconstruction, depths_along_axis,
};
pub use refine::{
    DistancePrior, Given, Intrinsics, MAX_POSE_REACH_PER_FOCAL, MIN_FOCAL_PX,
    MIN_POSE_SPREAD_PER_FOCAL, PerspectiveCamera, Refinement,
};
pub use world::{SMOOTHING_FRAMES, world_poses};

/// `x > 0`, false for NaN (reads better than a negated comparison at the call sites).
pub(crate) fn is_positive(x: f64) -> bool {
    x > 0.0
}

/// `x > 0` and finite.
pub(crate) fn is_positive_finite(x: f64) -> bool {
    x.is_finite() && x > 0.0
}

/// The first landmark of `pose` with a non-finite coordinate, as an error.
pub(crate) fn check_finite_landmarks(
    pose: &camloc_skeleton::Pose2,
) -> Result<(), ReconstructError> {
    match camloc_skeleton::Landmark::ALL
        .into_iter()
        .find(|l| !pose.get(*l).iter().all(|c| c.is_finite()))
    {
        Some(landmark) => Err(ReconstructError::NonFiniteInput {
            landmark: landmark.index(),
            name: landmark.name(),
        }),
        None => Ok(()),
    }
}
