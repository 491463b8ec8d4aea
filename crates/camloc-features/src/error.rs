//! [`FeatureError`]: why a descriptor could not be computed.

/// Why a descriptor could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FeatureError {
    /// A landmark coordinate is NaN or infinite.
    #[error("landmark {landmark} has a non-finite coordinate")]
    NonFinite {
        /// Name of the landmark.
        landmark: &'static str,
    },
    /// The two ends of the torso segment that gives the descriptor its unit of length
    /// coincide (or nearly so): there is no unit of scale.
    #[error(
        "degenerate torso: {top} and {origin} are {} apart (relative to the pose size), so the pose has no scale",
        relative(*.length)
    )]
    DegenerateTorso {
        /// Torso length relative to the pose's extent.
        length: f64,
        /// Lower end of the torso segment: "the pelvis" or, for
        /// [`Descriptor::Joints`](crate::Descriptor::Joints), "the hip midpoint".
        origin: &'static str,
        /// Upper end: "the neck" or, for [`Descriptor::Joints`](crate::Descriptor::Joints), "the
        /// shoulder midpoint".
        top: &'static str,
    },
    /// The output buffer has the wrong length.
    #[error("descriptor buffer has length {got}, expected {expected}")]
    BufferSize {
        /// Required length.
        expected: usize,
        /// Given length.
        got: usize,
    },
    /// Invalid descriptor settings.
    #[error("invalid descriptor settings: {0}")]
    InvalidConfig(String),
    /// The pelvis or the neck is missing: without the torso there is no origin or scale.
    #[error("landmark {landmark} is missing; the torso (pelvis and neck) is required")]
    MissingTorso {
        /// Name of the missing landmark.
        landmark: &'static str,
    },
    /// Unknown descriptor name.
    #[error("unknown descriptor '{0}' (expected 'landmarks', 'joints' or 'paper')")]
    UnknownName(String),
}

/// A relative length for a message: `0` when it is zero, three decimals from 0.001 up, else
/// in scientific notation with two significant digits (`1.2e-9`).
fn relative(length: f64) -> String {
    if length == 0.0 {
        "0".to_owned()
    } else if length.abs() >= 1e-3 {
        format!("{length:.3}")
    } else {
        format!("{length:.1e}")
    }
}
