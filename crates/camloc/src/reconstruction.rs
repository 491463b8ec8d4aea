//! 3D reconstruction with the localized camera (paper section 8.2).

use camloc_dataset::Dataset;
use camloc_reconstruct::{
    CameraMode, EvalReport, EvalSample, ModeKind, PoseBasis, ReconstructConfig, Reconstruction,
    Reconstructor,
};
use camloc_skeleton::PartialPose2;
use camloc_store::Persist;
use serde::Serialize;

use crate::localizer::sample_pose;
use crate::{CameraLocalizer, CamlocError, Localization};

/// Which camera the reconstruction uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum CameraChoice {
    /// Orthogonal Procrustes re-estimated at every step (Ramakrishna et al.'s baseline). The
    /// default: lowest 3D error on held-out subjects under the realistic `jittered` protocol
    /// (docs/RESULTS.md), where real cameras stand up to 30 deg away from the class centres.
    Opt,
    /// The rotation of the classified camera, fixed; only scale and translation are fitted
    /// (the paper's section 8.2). Best when the camera really is one of the set's viewpoints
    /// (the `canonical` protocol).
    Classified,
    /// The classified rotation as the start, refined by Procrustes; keeps the better of
    /// that and the Procrustes pursuit started from it.
    Hybrid,
}

impl CameraChoice {
    /// Lower-case name (`opt`, `classified`, `hybrid`).
    pub fn name(self) -> &'static str {
        match self {
            CameraChoice::Opt => "opt",
            CameraChoice::Classified => "classified",
            CameraChoice::Hybrid => "hybrid",
        }
    }
}

/// A reconstructed pose and the camera localization it used (none for `opt`).
#[derive(Clone, Debug)]
pub struct PoseReconstruction {
    /// The reconstruction: 3D pose (metres, canonical body frame), weak-perspective camera,
    /// reprojection error.
    pub reconstruction: Reconstruction,
    /// The camera localization, when the mode used one.
    pub localization: Option<Localization>,
}

/// The default basis embedded in this build (PCA of all CMU poses, `cargo xtask
/// train-default`).
///
/// # Errors
/// [`CamlocError::NoDefault`] when the build embedded none; decoding errors otherwise.
pub fn default_basis() -> Result<PoseBasis, CamlocError> {
    let bytes = include_bytes!(concat!(env!("OUT_DIR"), "/default-basis.bin"));
    if bytes.is_empty() {
        return Err(CamlocError::NoDefault("basis"));
    }
    Ok(PoseBasis::from_bytes_named(
        bytes,
        "embedded default basis",
    )?)
}

/// Builds a reconstructor with the default settings on `basis`.
///
/// # Errors
/// [`CamlocError::Reconstruct`] if the basis is unusable.
pub fn reconstructor(basis: PoseBasis) -> Result<Reconstructor, CamlocError> {
    Reconstructor::new(basis, ReconstructConfig::default()).map_err(|source| {
        CamlocError::Reconstruct {
            context: "basis".into(),
            source,
        }
    })
}

/// Reconstructs one 2D pose (all 15 landmarks needed) with the chosen camera.
///
/// # Errors
/// [`CamlocError::Reconstruct`] when landmarks are missing or the pose is degenerate;
/// localization errors for `classified` and `hybrid`.
pub fn reconstruct(
    reconstructor: &Reconstructor,
    localizer: &CameraLocalizer,
    pose: &PartialPose2,
    choice: CameraChoice,
) -> Result<PoseReconstruction, CamlocError> {
    let Some(complete) = pose.complete() else {
        let missing: Vec<&str> = pose.missing().map(|l| l.name()).collect();
        return Err(CamlocError::InvalidOption {
            name: "input pose",
            detail: format!(
                "reconstruction needs all 15 landmarks; missing: {}",
                missing.join(", ")
            ),
        });
    };
    let localization = match choice {
        CameraChoice::Opt => None,
        _ => Some(localizer.localize(&complete)?),
    };
    let mode = match (&localization, choice) {
        (Some(l), CameraChoice::Classified) => CameraMode::Classified(l.rotation),
        (Some(l), _) => CameraMode::Hybrid(l.rotation),
        (None, _) => CameraMode::Opt,
    };
    let reconstruction = reconstructor
        .reconstruct(&complete, &mode)
        .map_err(|source| CamlocError::Reconstruct {
            context: "input pose".into(),
            source,
        })?;
    Ok(PoseReconstruction {
        reconstruction,
        localization,
    })
}

/// Reconstructs every complete sample of `dataset` with every camera mode (`opt`,
/// `classified` with `localizer`'s prediction, `oracle` with the true rotation, `hybrid`) and
/// reports 3D error after similarity alignment and projection error per mode.
///
/// # Errors
/// Localization errors naming the sample.
pub fn evaluate_reconstruction(
    reconstructor: &Reconstructor,
    localizer: &CameraLocalizer,
    dataset: &Dataset,
) -> Result<EvalReport, CamlocError> {
    let poses: Vec<PartialPose2> = dataset.samples.iter().map(sample_pose).collect();
    let labels = localizer.predict_labels(&poses)?;
    let samples: Vec<EvalSample> = dataset
        .samples
        .iter()
        .zip(&labels)
        .filter(|(s, _)| s.missing_mask == 0)
        .map(|(s, label)| EvalSample {
            pose2: s.landmarks,
            truth: s.pose3,
            true_rotation: s.rotation,
            classified_rotation: localizer.cameras().get(*label).map(|v| v.rotation),
        })
        .collect();
    Ok(camloc_reconstruct::evaluate(
        &samples,
        reconstructor,
        &ModeKind::ALL,
    ))
}
