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
//! One mechanism reads and writes them all: a type implements [`Validate`] (the invariants a
//! decoded value must satisfy) and [`Persist`] (its [`FileKind`]), and gets
//! [`Persist::to_bytes`], [`Persist::from_bytes`], [`Persist::save`] and [`Persist::load`].
//!
//! Reading is bounded: the 28-byte header is read first, the magic and version are checked,
//! the declared payload length is capped by the kind's [`FileKind::max_payload`] and by the
//! actual file length, exactly that many bytes are read, and bincode decodes under a byte
//! limit. A wrong kind, another version, a truncated or padded file, any flipped byte
//! (checksum) and a decoded value that breaks its invariants ([`Validate`]) are refused with
//! a typed [`StoreError`] that names the file.
//!
//! Writing goes through [`write_new`] (one file) or [`StagedFiles`] (several, all or nothing):
//! temporary files in the targets' folders, renamed into place, never replacing an existing
//! file unless asked to, under one rule for links and special files ([`check_target`]). The
//! temporaries still in the making are on one list, which an interrupted program removes with
//! [`remove_unfinished`].

use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};

use serde::Serialize;
use serde::de::DeserializeOwned;

mod quote;
mod unfinished;
mod write;

pub use quote::{
    MAX_QUOTED_CHARS, MAX_QUOTED_PATH_CHARS, escaped, markup_escaped, quoted, quoted_path,
};
pub use unfinished::{Unfinished, remove_unfinished};
pub use write::{StagedFiles, check_target, file_type_name, scratch_beside, write_new};

/// Length of the envelope header in bytes.
pub const HEADER_LEN: usize = 28;

/// Largest number of bytes bincode may consume while decoding one payload (the largest
/// [`FileKind::max_payload`] of the kinds below); a second bound besides the payload length.
const DECODE_LIMIT: usize = 1 << 31;

/// The most bytes reserved up front for the payload of a stream whose length is unknown (a
/// pipe): its header's declared length is not trusted with memory before the bytes arrive.
const UNKNOWN_LENGTH_RESERVE: u64 = 1 << 20;

/// Origin named in errors for values decoded from memory rather than from a file.
pub const MEMORY_ORIGIN: &str = "<memory>";

/// What can go wrong reading or writing a camloc file. Every variant names the file (or the
/// origin of the bytes, e.g. `<memory>`).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StoreError {
    /// Operating-system error on `path`.
    #[error("{}: {source}", crate::quoted_path(.path))]
    Io {
        /// File concerned.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// The output exists and overwriting was not requested.
    #[error("{}: already exists (pass --force to overwrite it)", crate::quoted_path(.path))]
    Exists {
        /// File that exists.
        path: PathBuf,
    },
    /// The output path is a symbolic link and overwriting was not requested; camloc never
    /// writes through a link.
    #[error(
        "{}: already exists as a symbolic link, which camloc never writes through (--force replaces the link itself by a new file, not its target)",
        crate::quoted_path(.path)
    )]
    Symlink {
        /// The link.
        path: PathBuf,
    },
    /// The output path is neither a regular file nor a symbolic link (a directory, device,
    /// FIFO or socket); refused even with `--force`.
    #[error(
        "{}: is a {kind}, not a regular file: camloc writes only regular files and never replaces a {kind}, even with --force",
        crate::quoted_path(.path)
    )]
    NotRegular {
        /// The path.
        path: PathBuf,
        /// What it is ("directory", "character device", "FIFO", ...).
        kind: &'static str,
    },
    /// The bytes are not a file of the expected kind.
    #[error("{}: not a camloc {what} file (magic bytes \"{found}\"{})", crate::quoted_path(std::path::Path::new(.origin)),
        .other.map_or(String::new(), |o| format!(": this is a {o}")))]
    WrongKind {
        /// File (or origin) read.
        origin: String,
        /// Expected kind, e.g. "model".
        what: &'static str,
        /// The first (up to 8) bytes found, ASCII-escaped.
        found: String,
        /// The kind of camloc file these magic bytes belong to, if any.
        other: Option<&'static str>,
    },
    /// The file is of the right kind but another format version.
    #[error(
        "{}: camloc {what} file has format version {found}, this build reads version {expected}; regenerate it with this version of camloc", crate::quoted_path(std::path::Path::new(.origin))
    )]
    Version {
        /// File (or origin) read.
        origin: String,
        /// Kind of file.
        what: &'static str,
        /// Version in the file.
        found: u32,
        /// Version this build reads.
        expected: u32,
    },
    /// The header declares a payload larger than any valid file of this kind.
    #[error(
        "{}: camloc {what} file declares a payload of {declared} bytes, more than the {max} bytes a {what} file may hold", crate::quoted_path(std::path::Path::new(.origin))
    )]
    TooLarge {
        /// File (or origin) read.
        origin: String,
        /// Kind of file.
        what: &'static str,
        /// Payload length in the header.
        declared: u64,
        /// [`FileKind::max_payload`].
        max: u64,
    },
    /// The file is damaged: truncated, padded, checksum mismatch, or undecodable payload.
    #[error("{}: camloc {what} file is corrupt: {detail}", crate::quoted_path(std::path::Path::new(.origin)))]
    Corrupt {
        /// File (or origin) read.
        origin: String,
        /// Kind of file.
        what: &'static str,
        /// What is wrong.
        detail: String,
    },
    /// The file decoded but its content breaks the invariants of the value
    /// ([`Validate::validate`]).
    #[error("{}: invalid camloc {what} file: {source}", crate::quoted_path(std::path::Path::new(.origin)))]
    Invalid {
        /// File (or origin) read.
        origin: String,
        /// Kind of file.
        what: &'static str,
        /// The violated invariant (the type's own validation error).
        source: Box<dyn std::error::Error + Send + Sync>,
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

/// Identifies one kind of camloc file: its magic bytes, current version, a human name and
/// the largest payload a file of that kind may declare.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FileKind {
    /// Eight magic bytes at the start of the file.
    pub magic: [u8; 8],
    /// Format version written by this build (and the only one it reads).
    pub version: u32,
    /// Name used in messages ("dataset", "model", ...).
    pub what: &'static str,
    /// Largest payload length in bytes accepted in a header (bounds the memory a hostile
    /// header can make a reader allocate).
    pub max_payload: u64,
}

/// Datasets (`camloc_dataset::Dataset`): up to 2 GiB of payload (about 3 million samples of
/// about 700 bytes). Version 3 added the structural augmentation settings to the header,
/// version 4 the posture categories of clips (sit, squat, kneel, crawl), version 5 the head
/// reach range of photo landmark placements.
pub const DATASET_KIND: FileKind = FileKind {
    magic: *b"CAMLOCDS",
    version: 5,
    what: "dataset",
    max_payload: 1 << 31,
};

/// Camera localizer models (`camloc::CameraLocalizer`): up to 64 MiB (a descriptor of
/// 10,000 values for 64 cameras, with viewpoint heads, would still fit; the default model is
/// under 1 MiB). Version 2 added the continuous-viewpoint heads, version 3 the quadratic
/// feature expansion, version 4 the posture groups of (posture, camera) classes, version 5
/// the viewpoint heads' own expansion and the clamped components of quadratic expansions,
/// version 6 the model's own camera priors (`TrainingInfo::camera_priors`), version 7 the
/// viewpoint heads' elevation fits (`camloc_learning::ElevationFit`).
pub const MODEL_KIND: FileKind = FileKind {
    magic: *b"CAMLOCMD",
    version: 7,
    what: "model",
    max_payload: 64 << 20,
};

/// PCA pose bases (`camloc_reconstruct::PoseBasis`): up to 1 MiB (a full 45 x 45 basis is
/// about 17 KiB; a dictionary of the most atoms allowed, 1024, about 370 KiB). Version 2
/// added the dictionary atoms and the joint-angle limits, version 3 the prior on limb
/// lengths.
pub const POSE_BASIS_KIND: FileKind = FileKind {
    magic: *b"CAMLOCPB",
    version: 3,
    what: "pose basis",
    max_payload: 1 << 20,
};

/// Depth lifters (`camloc::DepthLifter`): up to 64 MiB (each of the default two, 12 classes
/// of 15 depths, is about 850 KiB). Version 2 added the lifter of poses
/// whose pelvis and neck sit at the hip and shoulder midpoints.
pub const LIFTER_KIND: FileKind = FileKind {
    magic: *b"CAMLOCDL",
    version: 2,
    what: "depth lifter",
    max_payload: 64 << 20,
};

/// Every kind of file camloc writes (used to say what a file of the wrong kind is).
pub const KINDS: [FileKind; 4] = [DATASET_KIND, MODEL_KIND, POSE_BASIS_KIND, LIFTER_KIND];

/// The invariants a decoded value must satisfy before it is used: run by [`Persist`] after
/// every decode, and by containers on the values nested in them.
pub trait Validate {
    /// The error describing the first violated invariant.
    type Invalid: std::error::Error + Send + Sync + 'static;

    /// Checks every invariant (sizes against each other, finite numbers, ...), so that no
    /// method of a validated value can panic or silently compute garbage.
    ///
    /// # Errors
    /// The first violated invariant.
    fn validate(&self) -> Result<(), Self::Invalid>;
}

/// A value stored in its own kind of envelope file. Implementors give the [`FileKind`]; the
/// methods are provided and are the only way camloc reads and writes these files.
pub trait Persist: Validate + Serialize + DeserializeOwned {
    /// Magic, version, name and size cap of the file kind.
    const KIND: FileKind;

    /// Encodes the value as an envelope. Deterministic: equal values give equal bytes.
    ///
    /// # Errors
    /// [`StoreError::Encode`] if serde/bincode refuses the value.
    fn to_bytes(&self) -> Result<Vec<u8>, StoreError> {
        encode(Self::KIND, self)
    }

    /// Decodes and validates an envelope held in memory; errors name `origin` (e.g.
    /// [`MEMORY_ORIGIN`] or "embedded default model").
    ///
    /// # Errors
    /// As [`decode`], plus [`StoreError::Invalid`] when [`Validate::validate`] refuses it.
    fn from_bytes_named(bytes: &[u8], origin: &str) -> Result<Self, StoreError> {
        validated(decode(Self::KIND, bytes, origin)?, Self::KIND, origin)
    }

    /// [`from_bytes_named`](Self::from_bytes_named) with origin [`MEMORY_ORIGIN`].
    ///
    /// # Errors
    /// As [`from_bytes_named`](Self::from_bytes_named).
    fn from_bytes(bytes: &[u8]) -> Result<Self, StoreError> {
        Self::from_bytes_named(bytes, MEMORY_ORIGIN)
    }

    /// Reads, decodes and validates the file at `path`, with bounded reading (see the crate
    /// documentation): `/dev/zero` or a forged length fail after reading the header.
    ///
    /// # Errors
    /// [`StoreError::Io`] if it cannot be opened or read, otherwise as
    /// [`from_bytes_named`](Self::from_bytes_named) (naming `path`).
    fn load(path: &Path) -> Result<Self, StoreError> {
        let origin = path.display().to_string();
        validated(read_file(Self::KIND, path)?, Self::KIND, &origin)
    }

    /// Encodes the value and writes it to `path` with [`write_new`] (never replacing an
    /// existing file unless `overwrite`).
    ///
    /// # Errors
    /// As [`encode`] and [`write_new`].
    fn save(&self, path: &Path, overwrite: bool) -> Result<(), StoreError> {
        write_new(path, &self.to_bytes()?, overwrite)
    }
}

/// Runs the validation hook on a freshly decoded value.
fn validated<T: Validate>(value: T, kind: FileKind, origin: &str) -> Result<T, StoreError> {
    value.validate().map_err(|e| StoreError::Invalid {
        origin: origin.to_string(),
        what: kind.what,
        source: Box::new(e),
    })?;
    Ok(value)
}

/// What is wrong with a payload that does not decode, in words (bincode's own messages are
/// its Rust debug text: `UnexpectedEnd { additional: 59936 }`).
fn decode_problem(e: &bincode::error::DecodeError) -> String {
    use bincode::error::DecodeError as E;
    match e {
        E::UnexpectedEnd { additional } => format!("it ends {additional} bytes too early"),
        E::LimitExceeded => "a length beyond what any file of this kind holds".into(),
        E::Utf8 { .. } => "a text that is not UTF-8".into(),
        E::OutsideUsizeRange(n) => format!("a length of {n}, beyond this machine's"),
        _ => "values that are not this kind of file's (a damaged or forged file)".into(),
    }
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
pub fn encode<T: Serialize + ?Sized>(kind: FileKind, value: &T) -> Result<Vec<u8>, StoreError> {
    let payload =
        bincode::serde::encode_to_vec(value, bincode::config::standard()).map_err(|e| {
            StoreError::Encode {
                what: kind.what,
                detail: e.to_string(),
            }
        })?;
    Ok(envelope(kind, &payload))
}

/// Wraps an already encoded payload in the envelope header of `kind` (magic, version, length,
/// checksum). Useful to build test files whose checksum is valid.
pub fn envelope(kind: FileKind, payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(HEADER_LEN + payload.len());
    out.extend_from_slice(&kind.magic);
    out.extend_from_slice(&kind.version.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&fnv1a64(payload).to_le_bytes());
    out.extend_from_slice(payload);
    out
}

/// Decodes an envelope of `kind` held in memory (no validation: see [`Persist`]); errors name
/// `origin`.
///
/// # Errors
/// [`StoreError::WrongKind`], [`StoreError::Version`], [`StoreError::TooLarge`] or
/// [`StoreError::Corrupt`] (truncated, trailing bytes, checksum mismatch, undecodable
/// payload).
pub fn decode<T: DeserializeOwned>(
    kind: FileKind,
    bytes: &[u8],
    origin: &str,
) -> Result<T, StoreError> {
    let mut reader = bytes;
    read_envelope(kind, &mut reader, Some(bytes.len() as u64), origin)
}

/// Opens `path` and decodes the envelope it holds with bounded reading.
fn read_file<T: DeserializeOwned>(kind: FileKind, path: &Path) -> Result<T, StoreError> {
    let io = |source| StoreError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = fs::File::open(path).map_err(io)?;
    let meta = file.metadata().map_err(io)?;
    if meta.is_dir() {
        return Err(io(std::io::Error::new(
            std::io::ErrorKind::IsADirectory,
            "is a directory",
        )));
    }
    // Only a regular file has a trustworthy length; devices and pipes are read as streams
    // (still bounded by the header's length and the kind's cap).
    let known_len = meta.is_file().then_some(meta.len());
    let mut reader = std::io::BufReader::new(file);
    read_envelope(kind, &mut reader, known_len, &path.display().to_string())
}

/// Reads up to `buf.len()` bytes, stopping early only at the end of the input.
fn read_full(reader: &mut impl Read, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut filled = 0;
    while filled < buf.len() {
        match reader.read(&mut buf[filled..]) {
            Ok(0) => break,
            Ok(n) => filled += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(filled)
}

/// The envelope reader behind [`decode`] and [`Persist::load`]: header first, then exactly
/// the declared payload (capped by the kind and by `known_len`, the input's total length when
/// known), then a check that nothing follows.
fn read_envelope<T: DeserializeOwned>(
    kind: FileKind,
    reader: &mut impl Read,
    known_len: Option<u64>,
    origin: &str,
) -> Result<T, StoreError> {
    let corrupt = |detail: String| StoreError::Corrupt {
        origin: origin.to_string(),
        what: kind.what,
        detail,
    };
    let io = |e: std::io::Error| StoreError::Io {
        path: PathBuf::from(origin),
        source: e,
    };
    let mut header = [0u8; HEADER_LEN];
    let got = read_full(reader, &mut header).map_err(io)?;
    if got < 8 || header[..8] != kind.magic {
        let magic = &header[..got.min(8)];
        return Err(StoreError::WrongKind {
            origin: origin.to_string(),
            what: kind.what,
            found: magic.escape_ascii().to_string(),
            other: KINDS.iter().find(|k| k.magic == magic).map(|k| k.what),
        });
    }
    if got < HEADER_LEN {
        return Err(corrupt(format!(
            "truncated header ({got} of {HEADER_LEN} bytes)"
        )));
    }
    let version = u32::from_le_bytes([header[8], header[9], header[10], header[11]]);
    if version != kind.version {
        return Err(StoreError::Version {
            origin: origin.to_string(),
            what: kind.what,
            found: version,
            expected: kind.version,
        });
    }
    let mut word = [0u8; 8];
    word.copy_from_slice(&header[12..20]);
    let len = u64::from_le_bytes(word);
    word.copy_from_slice(&header[20..28]);
    let checksum = u64::from_le_bytes(word);
    if len > kind.max_payload {
        return Err(StoreError::TooLarge {
            origin: origin.to_string(),
            what: kind.what,
            declared: len,
            max: kind.max_payload,
        });
    }
    if let Some(total) = known_len {
        let actual = total.saturating_sub(HEADER_LEN as u64);
        if actual != len {
            return Err(corrupt(format!(
                "payload is {actual} bytes, header says {len} (truncated or padded file)"
            )));
        }
    }
    // A file's length is known: reserve it. A pipe's header may lie (a 31-byte stream
    // declaring 2 GiB): reserve a little and let the bytes that come grow it.
    let reserve = match known_len {
        Some(_) => len,
        None => len.min(UNKNOWN_LENGTH_RESERVE),
    };
    let mut payload = Vec::with_capacity(usize::try_from(reserve).unwrap_or(0));
    reader.take(len).read_to_end(&mut payload).map_err(io)?;
    if (payload.len() as u64) < len {
        return Err(corrupt(format!(
            "payload is {} bytes, header says {len} (truncated file)",
            payload.len()
        )));
    }
    if read_full(reader, &mut [0u8; 1]).map_err(io)? != 0 {
        return Err(corrupt(format!(
            "bytes after the {len}-byte payload (padded file)"
        )));
    }
    if fnv1a64(&payload) != checksum {
        return Err(corrupt(
            "checksum mismatch (the file was modified or damaged)".into(),
        ));
    }
    let config = bincode::config::standard().with_limit::<DECODE_LIMIT>();
    let (value, used) = bincode::serde::decode_from_slice(&payload, config)
        .map_err(|e| corrupt(format!("undecodable payload: {}", decode_problem(&e))))?;
    if used != payload.len() {
        return Err(corrupt(format!(
            "{} trailing bytes after the payload",
            payload.len() - used
        )));
    }
    Ok(value)
}

#[cfg(test)]
mod tests;
