//! Errors of the motion-capture readers and of [`canonicalise`](super::canonicalise).

use std::path::{Path, PathBuf};

use thiserror::Error;

use camloc_skeleton::Landmark;
use camloc_store::{quoted, quoted_path};

/// Why a motion-capture file or folder could not be turned into poses.
///
/// Every variant names the file; syntax errors also carry the 1-based line number, so that the
/// message reads like a compiler diagnostic: `walk.bvh:12: expected a number for channel
/// Zrotation of joint LeftKnee, found 'abc'`.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum MocapError {
    /// Reading a file or listing a folder failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The operating-system error.
        #[source]
        source: std::io::Error,
    },
    /// A file larger than [`MAX_MOCAP_FILE_BYTES`](crate::MAX_MOCAP_FILE_BYTES) (or endless,
    /// as `/dev/zero`), refused after reading that much.
    #[error(
        "{}: larger than {} MiB, more than a motion-capture file holds; not read",
        path.display(),
        limit >> 20
    )]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// The limit, bytes.
        limit: u64,
    },
    /// The content of a file is malformed at `line`.
    #[error("{}:{line}: {problem}", quoted_path(Path::new(file)))]
    Parse {
        /// The file (its path, or the source name given to a `parse_*` function).
        file: String,
        /// 1-based line number where the problem was found.
        line: usize,
        /// What was expected and what was found.
        problem: ParseProblem,
    },
    /// The skeleton has no joint (BVH) or bone (ASF) for one of the 15 landmarks.
    #[error("{}: no {} for landmark {}", quoted_path(Path::new(file)), quoted(expected), landmark.name())]
    MissingLandmark {
        /// The file.
        file: String,
        /// The landmark that cannot be located.
        landmark: Landmark,
        /// The joint or bone that was looked for, e.g. `joint 'LeftKnee'`.
        expected: String,
    },
    /// An `.amc` motion has no skeleton: CMU names motions `SS_CC.amc` and expects the
    /// skeleton `SS.asf` in the same folder.
    #[error("{}: no skeleton file {} for this motion", amc.display(), asf.display())]
    MissingSkeleton {
        /// The motion file.
        amc: PathBuf,
        /// The skeleton file that was looked for.
        asf: PathBuf,
    },
}

/// The specific syntax or content problem of a [`MocapError::Parse`].
#[derive(Clone, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum ParseProblem {
    /// The file has no content at all (or only whitespace).
    #[error("the file is empty")]
    Empty,
    /// The bytes are not valid UTF-8 text, or hold a NUL byte (not text).
    #[error("the file is not UTF-8 text (an invalid byte or a NUL)")]
    NotUtf8,
    /// A different token was expected.
    #[error("expected {}, found '{}'", quoted(expected), quoted(found))]
    Expected {
        /// What the grammar requires here.
        expected: String,
        /// The token that was found.
        found: String,
    },
    /// A line ends where a value is required.
    #[error("missing {}", quoted(expected))]
    Missing {
        /// What the line lacks, e.g. `a bone name`.
        expected: String,
    },
    /// The file ends where more content is required.
    #[error("expected {}, found the end of the file", quoted(expected))]
    UnexpectedEnd {
        /// What the grammar requires here.
        expected: String,
    },
    /// A token that should be a number is not one.
    #[error("expected a number for {}, found '{}'", quoted(what), quoted(found))]
    NotANumber {
        /// The quantity, e.g. `channel Zrotation of joint LeftKnee`.
        what: String,
        /// The token that was found.
        found: String,
    },
    /// A number is infinite or NaN.
    #[error("{} is not finite: '{}'", quoted(what), quoted(found))]
    NotFinite {
        /// The quantity.
        what: String,
        /// The token that was found.
        found: String,
    },
    /// A line holds the wrong number of values.
    #[error("{} has {found} values, expected {expected}", quoted(what))]
    ValueCount {
        /// The line's content, e.g. `frame 3`.
        what: String,
        /// The number of values required.
        expected: usize,
        /// The number of values found.
        found: usize,
    },
    /// A BVH file has fewer frame lines than its `Frames:` header declares.
    #[error("the file ends after {found} frames but `Frames:` declares {declared}")]
    Truncated {
        /// The count in the `Frames:` header.
        declared: usize,
        /// The number of frame lines present.
        found: usize,
    },
    /// A BVH file has more frame lines than its `Frames:` header declares.
    #[error("more frame lines than the {declared} declared by `Frames:`")]
    ExtraFrames {
        /// The count in the `Frames:` header.
        declared: usize,
    },
    /// A name is defined or listed twice where it must be unique.
    #[error("{} appears twice", quoted(what))]
    Duplicate {
        /// The duplicated item, e.g. `joint 'LeftKnee'`.
        what: String,
    },
    /// A name does not refer to anything known.
    #[error("unknown {}", quoted(what))]
    Unknown {
        /// The unknown item, e.g. `bone 'lfemr'`.
        what: String,
    },
    /// A value is syntactically fine but not acceptable.
    #[error("invalid {}: {reason}", quoted(what))]
    Invalid {
        /// The value.
        what: String,
        /// Why it is rejected.
        reason: String,
    },
}

impl MocapError {
    /// The 1-based line number of a [`MocapError::Parse`], `None` for the other variants.
    pub fn line(&self) -> Option<usize> {
        match self {
            MocapError::Parse { line, .. } => Some(*line),
            _ => None,
        }
    }

    /// The problem of a [`MocapError::Parse`], `None` for the other variants.
    pub fn problem(&self) -> Option<&ParseProblem> {
        match self {
            MocapError::Parse { problem, .. } => Some(problem),
            _ => None,
        }
    }
}

/// Why [`canonicalise`](super::canonicalise) cannot bring a pose into the canonical frame.
#[derive(Clone, Copy, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum CanonicaliseError {
    /// A coordinate of the pose is infinite or NaN.
    #[error("cannot canonicalise a pose with non-finite coordinates")]
    NotFinite,
    /// The horizontal part of `(right_hip - left_hip) + (right_shoulder - left_shoulder)` is
    /// zero relative to the pose's size, so the facing direction is undefined.
    #[error(
        "cannot canonicalise the pose: the hips and shoulders give no horizontal left-right \
         direction (horizontal length {horizontal_m} m)"
    )]
    NoLateralDirection {
        /// Length of the horizontal left-right vector, in metres.
        horizontal_m: f64,
    },
}
