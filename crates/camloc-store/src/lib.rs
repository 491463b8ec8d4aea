//! Versioned, checksummed binary files and safe writing.
//!
//! Every file camloc writes (datasets, models, reconstruction bases) is an *envelope*:
//!
//! | bytes | content |
//! |---|---|
//! | 8 | magic, says what kind of file it is (e.g. `CAMLOCDS`) |
//! | 4 | format version, little-endian `u32` |
//! | 8 | payload length, little-endian `u64` |
//! | 8 | FNV-1a 64-bit checksum of the payload, little-endian |
//! | n | payload: the value, bincode 2 (`config::standard()`) through serde |
//!
//! [`decode`] refuses another kind of file, another version, a truncated file and any flipped
//! byte with a typed [`StoreError`]. [`write_new`] writes to a temporary file beside the target
//! and renames it into place, so a crash never leaves a half-written output, and it refuses to
//! replace an existing file unless asked to.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use serde::Serialize;
use serde::de::DeserializeOwned;

/// Length of the envelope header in bytes.
pub const HEADER_LEN: usize = 28;

/// What can go wrong reading or writing a camloc file.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// Operating-system error on `path`.
    #[error("{path}: {source}")]
    Io {
        /// File concerned.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// The output exists and overwriting was not requested.
    #[error("{path}: already exists (pass --force to overwrite it)")]
    Exists {
        /// File that exists.
        path: PathBuf,
    },
    /// The bytes are not a file of the expected kind.
    #[error("not a camloc {what} file (magic bytes {found:?})")]
    WrongKind {
        /// Expected kind, e.g. "model".
        what: &'static str,
        /// The first bytes found, lossily decoded.
        found: String,
    },
    /// The file is of the right kind but another format version.
    #[error(
        "camloc {what} file has format version {found}, this build reads version {expected}; regenerate it with this version of camloc"
    )]
    Version {
        /// Kind of file.
        what: &'static str,
        /// Version in the file.
        found: u32,
        /// Version this build reads.
        expected: u32,
    },
    /// The file is damaged: truncated, checksum mismatch, or undecodable payload.
    #[error("camloc {what} file is corrupt: {detail}")]
    Corrupt {
        /// Kind of file.
        what: &'static str,
        /// What is wrong.
        detail: String,
    },
    /// The value could not be encoded.
    #[error("could not encode {what}: {detail}")]
    Encode {
        /// Kind of file.
        what: &'static str,
        /// Encoder message.
        detail: String,
    },
}

/// Identifies one kind of camloc file: its magic bytes, current version and a human name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FileKind {
    /// Eight magic bytes at the start of the file.
    pub magic: [u8; 8],
    /// Format version written by this build (and the only one it reads).
    pub version: u32,
    /// Name used in messages ("dataset", "model", ...).
    pub what: &'static str,
}

/// FNV-1a 64-bit hash, the envelope checksum.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Encodes `value` into an envelope of `kind`.
///
/// # Errors
/// [`StoreError::Encode`] if serde/bincode refuses the value.
pub fn encode<T: Serialize>(kind: FileKind, value: &T) -> Result<Vec<u8>, StoreError> {
    let payload =
        bincode::serde::encode_to_vec(value, bincode::config::standard()).map_err(|e| {
            StoreError::Encode {
                what: kind.what,
                detail: e.to_string(),
            }
        })?;
    let mut out = Vec::with_capacity(HEADER_LEN + payload.len());
    out.extend_from_slice(&kind.magic);
    out.extend_from_slice(&kind.version.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&fnv1a64(&payload).to_le_bytes());
    out.extend_from_slice(&payload);
    Ok(out)
}

/// Decodes an envelope of `kind` back into a value.
///
/// # Errors
/// [`StoreError::WrongKind`], [`StoreError::Version`] or [`StoreError::Corrupt`] (truncated,
/// trailing bytes, checksum mismatch, undecodable payload).
pub fn decode<T: DeserializeOwned>(kind: FileKind, bytes: &[u8]) -> Result<T, StoreError> {
    let corrupt = |detail: String| StoreError::Corrupt {
        what: kind.what,
        detail,
    };
    if bytes.len() < 8 || bytes[..8] != kind.magic {
        return Err(StoreError::WrongKind {
            what: kind.what,
            found: String::from_utf8_lossy(&bytes[..bytes.len().min(8)]).into_owned(),
        });
    }
    if bytes.len() < HEADER_LEN {
        return Err(corrupt(format!(
            "truncated header ({} of {HEADER_LEN} bytes)",
            bytes.len()
        )));
    }
    let le_u32 = |r: std::ops::Range<usize>| {
        let mut a = [0u8; 4];
        a.copy_from_slice(&bytes[r]);
        u32::from_le_bytes(a)
    };
    let le_u64 = |r: std::ops::Range<usize>| {
        let mut a = [0u8; 8];
        a.copy_from_slice(&bytes[r]);
        u64::from_le_bytes(a)
    };
    let version = le_u32(8..12);
    if version != kind.version {
        return Err(StoreError::Version {
            what: kind.what,
            found: version,
            expected: kind.version,
        });
    }
    let len = le_u64(12..20);
    let checksum = le_u64(20..28);
    let payload = &bytes[HEADER_LEN..];
    if payload.len() as u64 != len {
        return Err(corrupt(format!(
            "payload is {} bytes, header says {len} (truncated or padded file)",
            payload.len()
        )));
    }
    if fnv1a64(payload) != checksum {
        return Err(corrupt(
            "checksum mismatch (the file was modified or damaged)".into(),
        ));
    }
    let (value, used) = bincode::serde::decode_from_slice(payload, bincode::config::standard())
        .map_err(|e| corrupt(format!("undecodable payload: {e}")))?;
    if used != payload.len() {
        return Err(corrupt(format!(
            "{} trailing bytes after the payload",
            payload.len() - used
        )));
    }
    Ok(value)
}

/// Reads and decodes the envelope file at `path`.
///
/// # Errors
/// [`StoreError::Io`] if the file cannot be read, then as [`decode`].
pub fn load<T: DeserializeOwned>(kind: FileKind, path: &Path) -> Result<T, StoreError> {
    let bytes = fs::read(path).map_err(|source| StoreError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    decode(kind, &bytes)
}

/// Encodes `value` and writes it to `path` with [`write_new`].
///
/// # Errors
/// As [`encode`] and [`write_new`].
pub fn save<T: Serialize>(
    kind: FileKind,
    value: &T,
    path: &Path,
    overwrite: bool,
) -> Result<(), StoreError> {
    write_new(path, &encode(kind, value)?, overwrite)
}

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename, so that
/// `path` is either untouched or complete. Refuses to replace an existing `path` unless
/// `overwrite` is `true`.
///
/// # Errors
/// [`StoreError::Exists`] if `path` exists and `overwrite` is false, [`StoreError::Io`] for
/// operating-system failures (the temporary file is removed).
pub fn write_new(path: &Path, bytes: &[u8], overwrite: bool) -> Result<(), StoreError> {
    let io = |source| StoreError::Io {
        path: path.to_path_buf(),
        source,
    };
    if !overwrite && path.exists() {
        return Err(StoreError::Exists {
            path: path.to_path_buf(),
        });
    }
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".into());
    let tmp = dir.join(format!(".{name}.tmp-{}", std::process::id()));
    let result = (|| {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        drop(f);
        if !overwrite && path.exists() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::AlreadyExists,
                "appeared while writing",
            ));
        }
        fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result.map_err(|e| {
        if e.kind() == std::io::ErrorKind::AlreadyExists {
            StoreError::Exists {
                path: path.to_path_buf(),
            }
        } else {
            io(e)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const KIND: FileKind = FileKind {
        magic: *b"CAMLOCTS",
        version: 3,
        what: "test",
    };

    #[derive(Debug, PartialEq, serde::Serialize, serde::Deserialize)]
    struct Thing {
        name: String,
        values: Vec<f64>,
    }

    proptest! {
        #[test]
        fn round_trip_is_exact(name in ".{0,20}", values in proptest::collection::vec(proptest::num::f64::ANY, 0..50)) {
            let t = Thing { name, values };
            let bytes = encode(KIND, &t).unwrap();
            let back: Thing = decode(KIND, &bytes).unwrap();
            prop_assert_eq!(encode(KIND, &back).unwrap(), bytes);
        }

        #[test]
        fn any_flipped_byte_is_refused(pos in 0usize..200, bit in 0u8..8) {
            let t = Thing { name: "abc".into(), values: vec![1.5, -2.0, 3.25, 1e300] };
            let mut bytes = encode(KIND, &t).unwrap();
            let pos = pos % bytes.len();
            bytes[pos] ^= 1 << bit;
            prop_assert!(decode::<Thing>(KIND, &bytes).is_err());
        }
    }

    #[test]
    fn kind_version_and_truncation_errors() {
        let bytes = encode(KIND, &vec![1u32, 2, 3]).unwrap();
        let other = FileKind { version: 4, ..KIND };
        assert!(matches!(
            decode::<Vec<u32>>(other, &bytes),
            Err(StoreError::Version {
                found: 3,
                expected: 4,
                ..
            })
        ));
        let wrong = FileKind {
            magic: *b"CAMLOCXX",
            ..KIND
        };
        assert!(matches!(
            decode::<Vec<u32>>(wrong, &bytes),
            Err(StoreError::WrongKind { .. })
        ));
        assert!(matches!(
            decode::<Vec<u32>>(KIND, &bytes[..bytes.len() - 1]),
            Err(StoreError::Corrupt { .. })
        ));
        assert!(matches!(
            decode::<Vec<u32>>(KIND, &bytes[..10]),
            Err(StoreError::Corrupt { .. })
        ));
        assert!(matches!(
            decode::<Vec<u32>>(KIND, b""),
            Err(StoreError::WrongKind { .. })
        ));
    }

    #[test]
    fn write_new_refuses_to_overwrite_and_leaves_no_temporary() {
        let dir = std::env::temp_dir().join(format!("camloc-store-test-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let path = dir.join("out.bin");
        let _ = fs::remove_file(&path);
        write_new(&path, b"first", false).unwrap();
        assert!(matches!(
            write_new(&path, b"second", false),
            Err(StoreError::Exists { .. })
        ));
        assert_eq!(fs::read(&path).unwrap(), b"first");
        write_new(&path, b"third", true).unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"third");
        let leftovers: Vec<_> = fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().contains(".tmp-"))
            .collect();
        assert!(leftovers.is_empty());
        assert!(matches!(
            write_new(&dir.join("missing-dir").join("x.bin"), b"x", false),
            Err(StoreError::Io { .. })
        ));
        fs::remove_dir_all(&dir).unwrap();
    }
}
