//! Binary model files: a fixed header then a bincode 2 (serde, standard configuration)
//! payload.
//!
//! Layout (little-endian):
//!
//! | offset | size | content |
//! |---|---|---|
//! | 0 | 8 | magic `CAMLOCLR` |
//! | 8 | 4 | format version ([`FORMAT_VERSION`]) |
//! | 12 | 8 | payload length in bytes |
//! | 20 | 8 | FNV-1a 64 checksum of the payload |
//! | 28 | .. | payload: the [`LogisticModel`] encoded by `bincode::serde::encode_to_vec` |
//!
//! The checksum detects every single changed byte of the payload (FNV-1a's per-byte step
//! is a bijection of the state), so a damaged file is reported as
//! [`LearningError::Corrupt`] instead of silently giving different probabilities.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::{LearningError, LogisticModel};

/// First bytes of every model file.
pub const MAGIC: [u8; 8] = *b"CAMLOCLR";
/// Version of the model format written by this build (the only one it reads).
pub const FORMAT_VERSION: u32 = 1;
/// Header length in bytes: magic, version, payload length, checksum.
const HEADER_LEN: usize = 28;

/// FNV-1a, 64-bit.
fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Reads `N` bytes at `offset`, or reports which header field is truncated.
fn header_field<const N: usize>(
    bytes: &[u8],
    offset: usize,
    field: &str,
) -> Result<[u8; N], LearningError> {
    bytes
        .get(offset..offset + N)
        .and_then(|s| <[u8; N]>::try_from(s).ok())
        .ok_or_else(|| {
            LearningError::Corrupt(format!(
                "truncated header: {} bytes, the {field} field needs bytes {offset}..{}",
                bytes.len(),
                offset + N
            ))
        })
}

impl LogisticModel {
    /// Serialises the model: header (magic, version, length, checksum) then the bincode
    /// payload. Deterministic: the same model always gives the same bytes, and
    /// `from_bytes(to_bytes(m))` gives back `m` whose `to_bytes` is byte-identical.
    ///
    /// # Errors
    /// [`LearningError::Encode`] if bincode fails (not expected for a valid model).
    pub fn to_bytes(&self) -> Result<Vec<u8>, LearningError> {
        let payload = bincode::serde::encode_to_vec(self, bincode::config::standard())
            .map_err(|e| LearningError::Encode(e.to_string()))?;
        let mut out = Vec::with_capacity(HEADER_LEN + payload.len());
        out.extend_from_slice(&MAGIC);
        out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
        out.extend_from_slice(&fnv1a64(&payload).to_le_bytes());
        out.extend_from_slice(&payload);
        Ok(out)
    }

    /// Parses bytes written by [`to_bytes`](Self::to_bytes). Never panics on any input.
    ///
    /// # Errors
    /// [`LearningError::Version`] if the header carries another format version;
    /// [`LearningError::Corrupt`] for a bad magic, a truncated or over-long buffer, a
    /// checksum mismatch, an undecodable payload or a decoded model that violates its
    /// invariants.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, LearningError> {
        let magic: [u8; 8] = header_field(bytes, 0, "magic")?;
        if magic != MAGIC {
            return Err(LearningError::Corrupt(
                "bad magic: not a camloc logistic model".to_owned(),
            ));
        }
        let found = u32::from_le_bytes(header_field(bytes, 8, "version")?);
        if found != FORMAT_VERSION {
            return Err(LearningError::Version {
                found,
                expected: FORMAT_VERSION,
            });
        }
        let length = u64::from_le_bytes(header_field(bytes, 12, "payload length")?);
        let checksum = u64::from_le_bytes(header_field(bytes, 20, "checksum")?);
        let payload = bytes.get(HEADER_LEN..).unwrap_or_default();
        if length != payload.len() as u64 {
            return Err(LearningError::Corrupt(format!(
                "payload is {} bytes but the header says {length} (truncated or extended)",
                payload.len()
            )));
        }
        let actual = fnv1a64(payload);
        if actual != checksum {
            return Err(LearningError::Corrupt(format!(
                "checksum mismatch: header {checksum:#018x}, payload {actual:#018x}"
            )));
        }
        let (model, read): (LogisticModel, usize) =
            bincode::serde::decode_from_slice(payload, bincode::config::standard())
                .map_err(|e| LearningError::Corrupt(format!("cannot decode payload: {e}")))?;
        if read != payload.len() {
            return Err(LearningError::Corrupt(format!(
                "{} trailing bytes after the model",
                payload.len() - read
            )));
        }
        model
            .validate()
            .map_err(|e| LearningError::Corrupt(format!("invalid model: {e}")))?;
        Ok(model)
    }

    /// Writes [`to_bytes`](Self::to_bytes) to `path` atomically: to a temporary file in the
    /// same directory, flushed to disk, then renamed over `path`.
    ///
    /// # Errors
    /// [`LearningError::Io`] naming the file that could not be written or renamed.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), LearningError> {
        let path = path.as_ref();
        let bytes = self.to_bytes()?;
        let file_name = path
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "model".to_owned());
        let temp = path.with_file_name(format!(".{file_name}.tmp-{}", std::process::id()));
        let io = |p: &Path| {
            let p: PathBuf = p.to_owned();
            move |source| LearningError::Io { path: p, source }
        };
        let written = fs::File::create(&temp)
            .and_then(|mut f| f.write_all(&bytes).and_then(|()| f.sync_all()))
            .map_err(io(&temp))
            .and_then(|()| fs::rename(&temp, path).map_err(io(path)));
        if written.is_err() {
            // Best effort: do not leave a partial temporary file behind.
            let _ = fs::remove_file(&temp);
        }
        written
    }

    /// Reads a model written by [`save`](Self::save).
    ///
    /// # Errors
    /// [`LearningError::Io`] if the file cannot be read, otherwise as
    /// [`from_bytes`](Self::from_bytes).
    pub fn load(path: impl AsRef<Path>) -> Result<Self, LearningError> {
        let path = path.as_ref();
        let bytes = fs::read(path).map_err(|source| LearningError::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::from_bytes(&bytes)
    }
}
