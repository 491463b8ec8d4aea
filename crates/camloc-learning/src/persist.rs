//! Binary model files: the versioned, checksummed envelope of [`camloc_store`] (magic
//! `CAMLOCLR`, format version [`FORMAT_VERSION`], payload length, FNV-1a 64 checksum) around
//! the bincode 2 (serde, standard configuration) encoding of a [`LogisticModel`].
//!
//! The checksum detects every single changed byte of the payload, so a damaged file is
//! reported as [`LearningError::Corrupt`] instead of silently giving different probabilities.

use std::path::Path;

use camloc_store::{FileKind, StoreError};

use crate::{LearningError, LogisticModel};

/// First bytes of every model file.
pub const MAGIC: [u8; 8] = *b"CAMLOCLR";
/// Version of the model format written by this build (the only one it reads).
pub const FORMAT_VERSION: u32 = 1;

const MODEL_FILE: FileKind = FileKind {
    magic: MAGIC,
    version: FORMAT_VERSION,
    what: "logistic model",
};

impl From<StoreError> for LearningError {
    fn from(e: StoreError) -> Self {
        match e {
            StoreError::Io { path, source } => LearningError::Io { path, source },
            StoreError::Version {
                found, expected, ..
            } => LearningError::Version { found, expected },
            StoreError::Encode { detail, .. } => LearningError::Encode(detail),
            other => LearningError::Corrupt(other.to_string()),
        }
    }
}

impl LogisticModel {
    /// Serialises the model: header (magic, version, length, checksum) then the bincode
    /// payload. Deterministic: the same model always gives the same bytes, and
    /// `from_bytes(to_bytes(m))` gives back `m` whose `to_bytes` is byte-identical.
    ///
    /// # Errors
    /// [`LearningError::Encode`] if bincode fails (not expected for a valid model).
    pub fn to_bytes(&self) -> Result<Vec<u8>, LearningError> {
        Ok(camloc_store::encode(MODEL_FILE, self)?)
    }

    /// Parses bytes written by [`to_bytes`](Self::to_bytes). Never panics on any input.
    ///
    /// # Errors
    /// [`LearningError::Version`] if the header carries another format version;
    /// [`LearningError::Corrupt`] for a bad magic, a truncated or over-long buffer, a
    /// checksum mismatch, an undecodable payload or a decoded model that violates its
    /// invariants.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, LearningError> {
        let model: LogisticModel = camloc_store::decode(MODEL_FILE, bytes)?;
        model
            .validate()
            .map_err(|e| LearningError::Corrupt(format!("invalid model: {e}")))?;
        Ok(model)
    }

    /// Writes [`to_bytes`](Self::to_bytes) to `path` atomically (temporary file in the same
    /// directory, flushed, then renamed over `path`), replacing an existing file.
    ///
    /// # Errors
    /// [`LearningError::Io`] naming the file that could not be written or renamed.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), LearningError> {
        Ok(camloc_store::write_new(
            path.as_ref(),
            &self.to_bytes()?,
            true,
        )?)
    }

    /// Reads a model written by [`save`](Self::save).
    ///
    /// # Errors
    /// [`LearningError::Io`] if the file cannot be read, otherwise as
    /// [`from_bytes`](Self::from_bytes).
    pub fn load(path: impl AsRef<Path>) -> Result<Self, LearningError> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|source| LearningError::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::from_bytes(&bytes)
    }
}
