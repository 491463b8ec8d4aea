//! How the camera is obtained: [`CameraMode`] and its rotation-free [`ModeKind`].

use camloc_geometry::Matrix3;
use serde::{Deserialize, Serialize};

/// How the camera is obtained during reconstruction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CameraMode {
    /// `opt`: the orthogonal Procrustes camera (eq. 3), first from the mean pose, then
    /// re-estimated after every coefficient update. The baseline of the paper.
    Opt,
    /// `classified`: rotation fixed to the classified viewpoint's rotation (e.g. a Table-1
    /// camera); only scale and translation are estimated (the paper's section 8.2).
    Classified(Matrix3),
    /// `oracle`: rotation fixed to the true camera rotation (evaluation only); otherwise as
    /// [`CameraMode::Classified`].
    Oracle(Matrix3),
    /// `hybrid`: the given rotation (typically the classified one) as a start, refined by
    /// Procrustes. Two hypotheses are solved and the one with the lower reprojection error is
    /// kept: (1) the pursuit as [`CameraMode::Classified`], then the camera refined by
    /// Procrustes (eq. 3), alternating with the coefficients of the selected components while
    /// the error falls; (2) the pursuit as [`CameraMode::Opt`] but started from the given
    /// rotation instead of the mean pose's Procrustes camera. Either alone measured worse (see
    /// "Choosing a camera mode" in the crate documentation).
    Hybrid(Matrix3),
}

impl CameraMode {
    /// The mode without its rotation.
    pub fn kind(&self) -> ModeKind {
        match self {
            CameraMode::Opt => ModeKind::Opt,
            CameraMode::Classified(_) => ModeKind::Classified,
            CameraMode::Oracle(_) => ModeKind::Oracle,
            CameraMode::Hybrid(_) => ModeKind::Hybrid,
        }
    }

    /// Short lower-case name (`opt`, `classified`, `oracle`, `hybrid`).
    pub fn name(&self) -> &'static str {
        self.kind().name()
    }
}

/// A camera mode to evaluate, resolved per sample into a [`CameraMode`]. Serialised by its
/// lower-case [`name`](ModeKind::name), as the command line names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ModeKind {
    /// [`CameraMode::Opt`].
    Opt,
    /// [`CameraMode::Classified`] with the sample's classified rotation.
    Classified,
    /// [`CameraMode::Oracle`] with the sample's true rotation.
    Oracle,
    /// [`CameraMode::Hybrid`] with the sample's classified rotation.
    Hybrid,
}

impl ModeKind {
    /// Every mode, baseline first.
    pub const ALL: [ModeKind; 4] = [
        ModeKind::Opt,
        ModeKind::Classified,
        ModeKind::Oracle,
        ModeKind::Hybrid,
    ];

    /// Lower-case name (`opt`, `classified`, `oracle`, `hybrid`).
    pub fn name(self) -> &'static str {
        match self {
            ModeKind::Opt => "opt",
            ModeKind::Classified => "classified",
            ModeKind::Oracle => "oracle",
            ModeKind::Hybrid => "hybrid",
        }
    }
}
