//! What `camloc localize` and `camloc reconstruct` do by default, as library calls (Python's
//! `Localizer()` and `reconstruct` too): [`PoseReconstructor::default_reconstructor`] (the
//! embedded basis, model and depth lifter, camera mode `hybrid`), the camera heights' prior
//! estimated from the input ([`CameraLocalizer::with_camera_height_from`],
//! [`PoseReconstructor::with_camera_height_from`], `--camera-height from-input`) and a
//! localization that fills in a missing torso ([`PoseReconstructor::localize`]).

use camloc_reconstruct::ModeKind;
use camloc_skeleton::PartialPose2;

use crate::{
    CameraLocalizer, CamlocError, DepthLifter, Localization, PoseReconstructor, default_basis,
};

impl CameraLocalizer {
    /// This localizer under the shares of the camera heights among `poses` (the first
    /// [`HEIGHT_SHARE_MAX_POSES`](crate::HEIGHT_SHARE_MAX_POSES) of them, in input order:
    /// [`CameraLocalizer::estimate_height_shares`]), as `camloc localize` and `camloc
    /// reconstruct` localize by default (`--camera-height from-input`). Without a pose that
    /// can be localized each pose is on its own ([`CameraHeight::Any`](crate::CameraHeight::Any)).
    pub fn with_camera_height_from(self, poses: &[PartialPose2]) -> CameraLocalizer {
        let estimate = self.estimate_height_shares(poses);
        self.with_camera_height(estimate.camera_height())
    }
}

impl PoseReconstructor {
    /// The reconstructor of `camloc reconstruct`'s defaults: the embedded pose basis, the
    /// embedded default model as its localizer (camera height
    /// [`CameraHeight::Any`](crate::CameraHeight::Any) until
    /// [`with_camera_height_from`](Self::with_camera_height_from)), the embedded depth lifter
    /// and the camera mode [`ModeKind::Hybrid`]. With the camera heights estimated from the
    /// same poses, its reconstructions are those of `camloc reconstruct` to the last bit, and
    /// [`localize`](Self::localize) gives `camloc localize`'s localizations.
    ///
    /// # Errors
    /// [`CamlocError::NoDefault`] when this build embedded no basis, model or lifter;
    /// decoding errors otherwise.
    pub fn default_reconstructor() -> Result<PoseReconstructor, CamlocError> {
        PoseReconstructor::new(default_basis()?)?
            .with_localizer(CameraLocalizer::default_model()?)
            .with_lifter(DepthLifter::default_lifter()?)
            .with_mode(ModeKind::Hybrid)
    }

    /// This reconstructor with its localizer under the shares of the camera heights among
    /// `poses` ([`CameraLocalizer::with_camera_height_from`]); unchanged without a localizer.
    pub fn with_camera_height_from(self, poses: &[PartialPose2]) -> PoseReconstructor {
        match self.localizer().cloned() {
            Some(localizer) => self.with_localizer(localizer.with_camera_height_from(poses)),
            None => self,
        }
    }

    /// Localizes `pose` with this reconstructor's localizer as `camloc localize` does: a pose
    /// whose torso is incomplete is filled in from this reconstructor's basis
    /// ([`CameraLocalizer::localize_filled`]; [`CameraLocalizer::localize_partial`] refuses
    /// it).
    ///
    /// # Errors
    /// [`CamlocError::InvalidOption`] without a localizer; otherwise as
    /// [`CameraLocalizer::localize_filled`].
    pub fn localize(&self, pose: &PartialPose2) -> Result<Localization, CamlocError> {
        let localizer = self.localizer().ok_or(CamlocError::InvalidOption {
            name: "localizer",
            detail: "this reconstructor has none; give it one with with_localizer".to_owned(),
        })?;
        localizer.localize_filled(pose, self.reconstructor())
    }
}
