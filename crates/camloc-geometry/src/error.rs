//! Errors of the geometry crate.

/// What can go wrong in camera geometry.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum GeometryError {
    /// The eq. 4 look-at is undefined for a camera on the z axis (straight above or below).
    #[error(
        "camera position ({x}, {y}, {z}) is on the z axis (a pole): the eq. 4 look-at rotation is undefined"
    )]
    Pole {
        /// Camera x, metres.
        x: f64,
        /// Camera y, metres.
        y: f64,
        /// Camera z, metres.
        z: f64,
    },
    /// A camera at the origin cannot look at the origin.
    #[error("camera position is at the origin (or not finite): no viewing direction")]
    DegeneratePosition,
    /// A matrix that should be a rotation is not.
    #[error(
        "matrix is not a rotation: orthonormality error {orthonormality_error:.3e}, determinant {determinant:.6}"
    )]
    NotARotation {
        /// max |R R^T - I| entry.
        orthonormality_error: f64,
        /// det(R), which must be +1.
        determinant: f64,
    },
    /// A point is behind (or on) the image plane of a perspective camera.
    #[error("point {index} is behind the perspective camera (depth {depth:.4} m)")]
    BehindCamera {
        /// Index of the offending point.
        index: usize,
        /// Its depth along the optical axis, metres.
        depth: f64,
    },
    /// Inputs of mismatched or too small size.
    #[error("{what}: expected {expected}, got {got}")]
    Size {
        /// Which input.
        what: &'static str,
        /// What was expected.
        expected: String,
        /// What was given.
        got: usize,
    },
    /// Non-finite numbers in the input.
    #[error("{what} contains a non-finite number")]
    NonFinite {
        /// Which input.
        what: &'static str,
    },
    /// Degenerate point configuration (all points coincide, or are collinear in a way that
    /// leaves the rotation undetermined).
    #[error("degenerate point configuration: {0}")]
    Degenerate(&'static str),
    /// A camera label that names no camera: 0, or beyond the camera set.
    #[error("invalid camera label {label}{}", match cameras {
        Some(n) => format!(": the camera set has labels 1 to {n}"),
        None => ": labels start at 1".to_string(),
    })]
    InvalidLabel {
        /// The label given.
        label: u16,
        /// Number of cameras in the set it was checked against, if any.
        cameras: Option<usize>,
    },
    /// A sphere definition that makes no sense (no azimuths, elevation at a pole, ...).
    #[error("invalid camera sphere: {0}")]
    InvalidSphere(String),
}
