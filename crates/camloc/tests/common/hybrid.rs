//! The reconstructor of `camloc reconstruct`, for the tests that reconstruct as it does.

use camloc::{CameraLocalizer, DepthLifter, ModeKind, PoseReconstructor, default_basis};

/// The embedded basis, model and lifter, `hybrid` (the command line's default).
pub fn hybrid_reconstructor() -> PoseReconstructor {
    PoseReconstructor::new(default_basis().unwrap())
        .unwrap()
        .with_localizer(CameraLocalizer::default_model().unwrap())
        .with_lifter(DepthLifter::default_lifter().unwrap())
        .with_mode(ModeKind::Hybrid)
        .unwrap()
}
