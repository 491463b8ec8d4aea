//! [`DatasetError`]: what can go wrong reading, checking or generating a dataset.

use camloc_geometry::GeometryError;
use camloc_store::StoreError;

/// Errors of dataset handling.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DatasetError {
    /// Reading or writing the file failed (missing, exists, wrong kind/version, corrupt).
    #[error(transparent)]
    Store(#[from] StoreError),
    /// A sample refers to a clip the header does not list.
    #[error("sample {sample} refers to clip {clip}, but the header lists {clips} clips")]
    BadClipIndex {
        /// Index of the sample.
        sample: usize,
        /// Clip index in the sample.
        clip: u32,
        /// Number of clips in the header.
        clips: usize,
    },
    /// A sample's label is not a camera of the header's camera set.
    #[error("sample {sample} has camera label {label}, but the camera set has {cameras} cameras")]
    BadLabel {
        /// Index of the sample.
        sample: usize,
        /// Its label.
        label: u16,
        /// Cameras in the set.
        cameras: usize,
    },
    /// A sample's missing-landmark mask has bits beyond the 15 landmarks.
    #[error(
        "sample {sample} has missing-landmark mask {mask:#06x}, which names landmarks beyond the 15"
    )]
    BadMissingMask {
        /// Index of the sample.
        sample: usize,
        /// The mask.
        mask: u16,
    },
    /// A sample holds NaN or an infinity.
    #[error("sample {sample}: {what} holds a non-finite number")]
    NonFinite {
        /// Index of the sample.
        sample: usize,
        /// Which part ("2D landmarks", "rotation", "3D pose").
        what: &'static str,
    },
    /// The header's camera set is not a valid sphere of cameras.
    #[error("dataset camera set: {0}")]
    Cameras(#[source] GeometryError),
    /// A header field is out of its domain.
    #[error("dataset header: {field} = {value}: {reason}")]
    BadHeader {
        /// Field name.
        field: &'static str,
        /// Its value, as text.
        value: String,
        /// The valid domain.
        reason: &'static str,
    },
    /// Invalid generation settings or input poses.
    #[error("invalid dataset generation input: {0}")]
    Invalid(String),
    /// Two datasets that cannot be joined ([`crate::Dataset::append`]): what differs.
    #[error("datasets that cannot be joined: {0}")]
    Incompatible(String),
}
