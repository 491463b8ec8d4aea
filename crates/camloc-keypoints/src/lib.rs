//! Readers that turn the 2D keypoint files users bring into camloc's 15 landmarks
//! ([`PartialPose2`], image coordinates, `v` growing downwards), and a writer for the project's
//! own JSON format.
//!
//! ```no_run
//! use camloc_keypoints::{ReadOptions, read_keypoints};
//!
//! let records = read_keypoints("poses.json", None, &ReadOptions::default())?;
//! for record in &records {
//!     record.require_torso()?; // the localiser needs pelvis and neck
//!     println!("{} from {}: derived {:?}", record.id, record.source, record.derived);
//! }
//! # Ok::<(), camloc_keypoints::KeypointError>(())
//! ```
//!
//! Every reader returns one [`KeypointRecord`] per pose: an id, the pose, the landmarks that were
//! *derived* rather than read, where the pose is in the file, and its frame and person for
//! inputs that have them. Coordinates are kept in the file's units (pixels, except MediaPipe's
//! normalised coordinates, which are scaled by [`ReadOptions::image_size`]); camloc's
//! descriptors are invariant to 2D translation and scale.
//!
//! # Formats
//!
//! [`KeypointFormat`] lists the nine formats: camloc JSON, LSP-14 CSV and COCO-17 JSON (below),
//! and OpenPose JSON (BODY_25, COCO-18), MMPose predictions, MediaPipe Pose, NumPy `.npy` arrays
//! in a [`Layout`], MPII JSON annotations and Ultralytics YOLO pose text, whose joint mappings
//! are tabled in docs/keypoints.md. [`KeypointFormat::from_extension_and_content`] picks the
//! format when none is given. [`read_keypoints`] reads a file, [`open_keypoints`] and
//! [`open_keypoints_reader`] (standard input) stream its records (`.npy` arrays one pose at a
//! time), [`read_folder`] reads a folder file by file, each with its own result;
//! [`pose_from_array`] maps one raw (J, 2) or (J, 3) pose; [`write_npy`] and [`NpyPoseWriter`]
//! write (N, 15, 2) and (N, 15, 3) arrays.
//!
//! ## camloc JSON (version 1)
//!
//! ```json
//! {
//!   "format": "camloc-keypoints",
//!   "version": 1,
//!   "poses": [
//!     {
//!       "id": "frame-0001",
//!       "landmarks": {
//!         "pelvis": [320.0, 250.0],
//!         "left_hip": [337.5, 260.5],
//!         "head": null
//!       }
//!     }
//!   ]
//! }
//! ```
//!
//! * `landmarks` maps [`Landmark::name`] keys (`pelvis`, `left_hip`, `left_knee`, `left_ankle`,
//!   `right_hip`, `right_knee`, `right_ankle`, `neck`, `head`, `left_shoulder`, `left_elbow`,
//!   `left_wrist`, `right_shoulder`, `right_elbow`, `right_wrist`) to `[u, v]` image coordinates
//!   (`u` to the right, `v` down, any unit). A missing key or `null` is a missing landmark; an
//!   unknown key or a key given twice is an error.
//! * `id` (a string) is optional: a pose without one is called `pose-{index}` (0-based).
//! * `frame` and `person` (integers of at least 0) are optional: the pose's video frame and its
//!   person in that frame ([`KeypointRecord::frame`], [`KeypointRecord::person`]); the writer
//!   writes them for records that have them.
//! * `format` and `version` are optional when reading and checked when present; the writer
//!   ([`to_camloc_json`]) always writes them, and every landmark key.
//! * For convenience a file may also hold one bare pose: `{"id": "..", "landmarks": {..}}`.
//! * Record sources are JSON paths: `file.json: poses[3]` (`file.json: top level` for a bare pose).
//!
//! ## LSP-14 CSV
//!
//! A header naming the columns `image,joint,x,y,visible` (any order, any ASCII case), then one
//! row per joint; fields are separated by commas (no quoting), blank lines are skipped. Rows are
//! grouped by `image` in order of first appearance (an image's rows need not be contiguous); a
//! record's id is the image name and its source the line of the image's first row. Joints map by
//! name (see [`LSP_JOINTS`]), except that `head_top` becomes the head (the crown sits higher than
//! camloc's head landmark, the upper end of the neck). `visible` must be `0` or `1`:
//! by default a `0` marks the landmark as missing; [`Invisible::Use`] keeps the annotated
//! coordinates of invisible joints, except placeholders (a coordinate `<= 0`: no position). An
//! image that lacks some joint rows simply has those
//! landmarks missing.
//!
//! ## COCO-17 JSON
//!
//! Either a dataset file (`{"annotations": [{"image_id": .., "id": .., "keypoints": [..]}], ..}`;
//! other keys and other annotation fields are skipped) or a results list
//! (`[{"image_id": .., "keypoints": [..], "score": ..}]`). `keypoints` holds 51 numbers, `x, y, v`
//! for each of [`COCO_KEYPOINTS`]; a keypoint is present when `v` (visibility flag in dataset
//! files, confidence in results) is above 0 and at least [`ReadOptions::min_score`] (0 by
//! default), so `v == 0` is missing. Shoulders, elbows, wrists, hips, knees and ankles map by name; the head is the
//! mean of the present face points (nose, eyes, ears) and is recorded as derived. That point
//! lies between nose and eye level, and in front of the neck axis in side views; CMU's head
//! landmark (the end of the `upperneck` bone) lies about two thirds of the way from the neck to
//! the crown, so the COCO head is *lower* than CMU's and the neck-head limb of COCO input shorter
//! than in the training data (LSP's `head_top`, the crown, is higher). The id of a record is
//! `"{image_id}/{id}"`, or `"{image_id}/{index}"` (0-based position in the list) when the entry
//! has no `id` (results lists).
//!
//! # Derivation (docs/conventions.md section 3)
//!
//! With [`ReadOptions::derive_torso`] (the default), in every format, a missing pelvis becomes
//! the midpoint of the hips when both are present, and a missing neck the midpoint of the
//! shoulders when both are present ([`derive_torso`]). LSP never has a pelvis and COCO has
//! neither, so these are derived there; derived landmarks are listed in
//! [`KeypointRecord::derived`]. A pose whose pelvis or neck stays missing is not an error at
//! read time: [`KeypointRecord::require_torso`] lets the caller reject it.
//!
//! # Errors
//!
//! Nothing in this crate panics on any input. [`KeypointError`] says what is wrong and where:
//! the file, then a line (CSV), a JSON path such as `poses[2].landmarks.left_knee`, a JSON
//! line and column for syntax errors, or an array element `[pose, joint, channel]`. Messages
//! quote at most [`MAX_QUOTED_CHARS`] characters of any piece of input. Text inputs longer than
//! [`ReadOptions::max_bytes`] (one OpenPose frame: [`OPENPOSE_FRAME_MAX_BYTES`]) are refused
//! (files before they are read, pipes at the limit). JSON inputs are parsed entry by entry, each
//! entry at most [`MAX_ENTRY_VALUES`] values. `.npy` arrays, and JSON and LSP inputs longer
//! than [`STREAM_PEEK_BYTES`], are streamed by [`open_keypoints`]: their records come one at a
//! time, memory independent of their number, and an error ends the stream after the records
//! before it.

mod array_pose;
mod camloc_json;
mod coco;
mod emit;
mod error;
mod folder;
mod format;
mod json;
mod layout;
mod layout_check;
mod lsp;
mod mediapipe;
mod mmpose;
mod mpii;
mod normalised;
mod npy;
mod openpose;
mod peek;
mod record;
mod sample;
mod stream;
mod torso;
mod weak;
mod yolo;

use std::fmt;
use std::io::{self, Read};
use std::path::Path;
use std::str::FromStr;

pub use camloc_json::{CAMLOC_FORMAT_TAG, CAMLOC_FORMAT_VERSION, to_camloc_json};

/// The largest frame or person number a record carries (2^63 - 1): they are written to
/// NumPy's and Python's signed 64-bit integers.
pub const MAX_FRAME_NUMBER: u64 = i64::MAX as u64;

/// The largest score of a format whose scores are not range-checked (COCO flags go up to 2,
/// MMPose's heatmap maxima a little over 1) that a `min_score` in (0, 1] accepts: a larger one
/// is on another scale (0-100) and refused ([`KeypointError::ScoreScale`]).
pub const SCORE_SCALE_LIMIT: f64 = 2.0;
pub use array_pose::{ArrayPoseError, pose_from_array};
pub use camloc_skeleton::{Landmark, PartialPose2, Pose3};
pub use coco::COCO_KEYPOINTS;
pub use error::{
    KeypointError, Location, MAX_QUOTED_CHARS, MAX_QUOTED_ITEMS, MAX_QUOTED_PATH_CHARS, PosePlace,
};
pub use folder::{FolderRecords, has_subfolders, keypoint_files, open_folder_file, read_folder};
pub use format::{KeypointFormat, UnknownFormatName};
pub use json::MAX_ENTRY_VALUES;
pub use layout::{Layout, MappedPose, UnknownLayoutName};
pub use layout_check::{
    COCO_FACE_SPREAD_MAX, H36M_HIPS_SPREAD_MIN, LAYOUT_CHECK_MIN_SCORE, contradicted,
};
pub use lsp::LSP_JOINTS;
pub use npy::{NPY_MAX_HEADER_BYTES, NpyPose, NpyPoseWriter, NpyPoses, read_npy_poses3, write_npy};
pub use openpose::{OPENPOSE_FRAME_MAX_BYTES, frame_index};
pub use peek::STREAM_PEEK_BYTES;
pub use record::KeypointRecord;
pub use sample::{SAMPLE_MAX_BYTES, sample_records};
pub use torso::derive_torso;
pub use weak::WeakScores;

/// What to do with LSP joints marked `visible = 0`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Invisible {
    /// The landmark is missing (the default).
    #[default]
    Missing,
    /// Keep the annotated coordinates (some LSP-style files place occluded joints where they
    /// are guessed to be). A coordinate `<= 0` (at or beyond the image's top or left edge) is
    /// the placeholder of a joint that was not annotated: that joint stays missing.
    Use,
}

/// Options of the LSP CSV reader.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct LspOptions {
    /// Treatment of joints with `visible = 0`.
    pub invisible: Invisible,
}

/// The size of the images that normalised coordinates (MediaPipe) are relative to, in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageSize {
    /// Width in pixels (multiplies normalised `x`).
    pub width: f64,
    /// Height in pixels (multiplies normalised `y`).
    pub height: f64,
}

/// An image size that is not `W,H` (or `WxH`) with two positive finite numbers.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "image size \"{}\" is not W,H with two positive numbers of pixels (e.g. 1920,1080)",
    error::clip(.0)
)]
pub struct InvalidImageSize(pub String);

impl FromStr for ImageSize {
    type Err = InvalidImageSize;

    /// Parses `W,H` or `WxH` (e.g. `1920,1080`); both must be positive and finite.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let invalid = || InvalidImageSize(s.to_owned());
        let (w, h) = s
            .split_once(',')
            .or_else(|| s.split_once(['x', 'X']))
            .ok_or_else(invalid)?;
        let number = |t: &str| {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v > 0.0)
                .ok_or_else(invalid)
        };
        Ok(ImageSize {
            width: number(w)?,
            height: number(h)?,
        })
    }
}

impl fmt::Display for ImageSize {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{}", self.width, self.height)
    }
}

/// Options shared by all readers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReadOptions {
    /// Derive a missing pelvis/neck from the hips/shoulders ([`derive_torso`]). Default `true`.
    pub derive_torso: bool,
    /// LSP CSV options.
    pub lsp: LspOptions,
    /// Joints whose score is below this are missing, in every format with scores: COCO
    /// (visibility flag or confidence), OpenPose (confidence), MMPose (`keypoint_scores`),
    /// MediaPipe (`visibility`), `.npy` (N, J, 3). A score of 0 always means missing. Default 0;
    /// finite and at least 0 (COCO dataset flags go up to 2): the readers refuse another
    /// value with [`KeypointError::InvalidMinScore`].
    pub min_score: f64,
    /// The image size that normalised coordinates are scaled by (MediaPipe needs it; other
    /// formats ignore it). Default `None`.
    pub image_size: Option<ImageSize>,
    /// The joint layout of `.npy` arrays and MMPose keypoints. `None` (the default): told from
    /// the joint count, with 17 meaning COCO-17 for MMPose and needing a name for `.npy`.
    pub layout: Option<Layout>,
    /// Largest text input accepted, in bytes; longer inputs give [`KeypointError::TooLarge`]
    /// (a streamed input after the records before the limit).
    /// Default [`ReadOptions::DEFAULT_MAX_BYTES`] (1 GiB). One OpenPose frame is also limited
    /// to [`OPENPOSE_FRAME_MAX_BYTES`]; `.npy` arrays are streamed and not limited.
    pub max_bytes: u64,
}

impl ReadOptions {
    /// The default input size limit: 1 GiB, room for the largest COCO keypoint files.
    pub const DEFAULT_MAX_BYTES: u64 = 1 << 30;

    /// [`KeypointError::InvalidMinScore`] (naming the input `file`) unless `min_score` is
    /// finite and at least 0.
    pub(crate) fn check_min_score(&self, file: &str) -> Result<(), KeypointError> {
        if self.min_score.is_finite() && self.min_score >= 0.0 {
            Ok(())
        } else {
            Err(KeypointError::InvalidMinScore {
                file: file.to_owned(),
                value: self.min_score,
            })
        }
    }

    /// The size limit for an input of `format` (`None`: not known yet).
    fn byte_limit(&self, format: Option<KeypointFormat>) -> (u64, &'static str) {
        match format {
            Some(KeypointFormat::OpenPose) if OPENPOSE_FRAME_MAX_BYTES < self.max_bytes => (
                OPENPOSE_FRAME_MAX_BYTES,
                "OPENPOSE_FRAME_MAX_BYTES, one frame",
            ),
            _ => (
                self.max_bytes,
                "--max-input-bytes; Python max_input_bytes=; Rust ReadOptions::max_bytes",
            ),
        }
    }
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            derive_torso: true,
            lsp: LspOptions::default(),
            min_score: 0.0,
            image_size: None,
            layout: None,
            max_bytes: ReadOptions::DEFAULT_MAX_BYTES,
        }
    }
}

/// The records of one input, produced as they are read: `.npy` arrays pose by pose, long JSON
/// and LSP inputs on a reader thread (memory independent of N), short inputs from the parsed
/// text. Returned by [`open_keypoints`] and [`open_keypoints_reader`].
pub struct KeypointStream {
    inner: StreamInner,
}

/// Where a [`KeypointStream`]'s records come from.
enum StreamInner {
    /// Read whole (short inputs): the records, and the errors of poses refused on their own.
    Parsed(std::vec::IntoIter<stream::Item>),
    Npy(Box<NpyPoses<Box<dyn Read + Send>>>),
    /// Parsed on a producer thread (JSON and LSP longer than [`STREAM_PEEK_BYTES`]).
    Channel(stream::Received),
}

impl Iterator for KeypointStream {
    type Item = Result<KeypointRecord, KeypointError>;

    fn next(&mut self) -> Option<Self::Item> {
        match &mut self.inner {
            StreamInner::Parsed(items) => items.next(),
            StreamInner::Npy(poses) => poses.next(),
            StreamInner::Channel(received) => received.next_item(),
        }
    }

    /// Exact for text inputs read whole; for `.npy` the poses left (fewer if an error stops
    /// the stream); unknown for streamed JSON and LSP.
    fn size_hint(&self) -> (usize, Option<usize>) {
        match &self.inner {
            StreamInner::Parsed(items) => items.size_hint(),
            StreamInner::Npy(poses) => (0, usize::try_from(poses.len()).ok()),
            StreamInner::Channel(_) => (0, None),
        }
    }
}

/// Reads a keypoint file. `format: None` detects it from the extension and content
/// ([`KeypointFormat::from_extension_and_content`]). Record sources and error messages name the
/// file as `path` displays. See [`open_keypoints`] to get the records one at a time.
pub fn read_keypoints(
    path: impl AsRef<Path>,
    format: Option<KeypointFormat>,
    options: &ReadOptions,
) -> Result<Vec<KeypointRecord>, KeypointError> {
    open_keypoints(path, format, options)?.collect()
}

/// Opens a keypoint file and returns its records as a stream: a `.npy` array is read one pose
/// at a time, a JSON input longer than [`STREAM_PEEK_BYTES`] is parsed entry by entry on a
/// reader thread (from memory, after reading it whole, when only the whole text tells its
/// format), a longer LSP file read whole and parsed there, shorter inputs read whole (within
/// their size limit) and parsed. `format: None` detects the format as
/// [`read_keypoints`] does.
pub fn open_keypoints(
    path: impl AsRef<Path>,
    format: Option<KeypointFormat>,
    options: &ReadOptions,
) -> Result<KeypointStream, KeypointError> {
    open_path(path.as_ref(), format, options, true)
}

/// [`open_keypoints`], telling the reader the file's size when `sized` (a file beyond
/// [`ReadOptions::max_bytes`] is then refused before it is read) or not (its records before
/// the limit are read).
pub(crate) fn open_path(
    path: &Path,
    format: Option<KeypointFormat>,
    options: &ReadOptions,
    sized: bool,
) -> Result<KeypointStream, KeypointError> {
    let name = path.display().to_string();
    let io_error = |source| KeypointError::Io {
        file: name.clone(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io_error)?;
    let metadata = file.metadata().map_err(io_error)?;
    let size = (sized && metadata.is_file()).then_some(metadata.len());
    let extension = path.extension().and_then(|e| e.to_str());
    let format = format.or_else(|| {
        extension
            .filter(|e| e.eq_ignore_ascii_case("npy"))
            .map(|_| KeypointFormat::Npy)
    });
    open_keypoints_reader(io::BufReader::new(file), &name, size, format, options)
}

/// Reads keypoints from any reader, e.g. standard input: `name` names it in records and errors
/// (its extension, if any, helps detection), `size` is its length in bytes when known. A `.npy`
/// array (named by `format`, or recognised by its magic bytes) and a JSON or LSP input longer
/// than [`STREAM_PEEK_BYTES`] are streamed (at most [`ReadOptions::max_bytes`] of it: past that,
/// the stream ends with [`KeypointError::TooLarge`]); shorter inputs are read and parsed. The
/// start of the input is looked at first (its blank lead skipped): content that is not UTF-8,
/// or that no format matches, is refused there.
pub fn open_keypoints_reader(
    mut reader: impl Read + Send + 'static,
    name: &str,
    size: Option<u64>,
    format: Option<KeypointFormat>,
    options: &ReadOptions,
) -> Result<KeypointStream, KeypointError> {
    options.check_min_score(name)?;
    let io_error = |source| KeypointError::Io {
        file: name.to_owned(),
        source,
    };
    // Peek at the first bytes for the NumPy magic.
    let mut start = Vec::with_capacity(format::NPY_MAGIC.len());
    (&mut reader)
        .take(format::NPY_MAGIC.len() as u64)
        .read_to_end(&mut start)
        .map_err(io_error)?;
    let npy = match format {
        Some(format) => format == KeypointFormat::Npy,
        None => start.starts_with(format::NPY_MAGIC),
    };
    let reader = io::Cursor::new(start).chain(reader);
    if npy {
        let reader: Box<dyn Read + Send> = Box::new(reader);
        let poses = NpyPoses::new(reader, name, size, options)?;
        return Ok(KeypointStream {
            inner: StreamInner::Npy(Box::new(poses)),
        });
    }
    let (limit, rule) = options.byte_limit(format);
    let too_large = |bytes, (limit, rule): (u64, &'static str)| KeypointError::TooLarge {
        file: name.to_owned(),
        bytes,
        limit,
        rule,
    };
    // Refuse a file of known size beyond `bound` before reading it.
    let refuse_known = |bound: (u64, &'static str)| match size.filter(|&size| size > bound.0) {
        Some(size) => Err(too_large(size, bound)),
        None => Ok(()),
    };
    // Known-large files are refused before reading; `take` also bounds pipes and special
    // files.
    refuse_known((limit, rule))?;
    // Peek at the start (past a blank lead): input that is not text, or whose format nothing
    // can match, is refused at once; an input that ends within it is parsed whole, a longer
    // JSON document is streamed.
    let mut reader = reader;
    let start = peek::read_start(&mut reader, limit, size, format).map_err(io_error)?;
    if start.len() > limit {
        return Err(too_large(start.len(), (limit, rule)));
    }
    if let Some(e) = format::not_keypoints(&start.content, name) {
        return Err(e);
    }
    if let Some(e) = start.utf8_error(name) {
        return Err(e);
    }
    // Nothing but white space (its lead only counted, not held): empty, or a YOLO frame
    // without people.
    if start.content.is_empty() && start.ended {
        let items = parse_items_bytes(b"", name, format, options)?;
        return Ok(KeypointStream {
            inner: StreamInner::Parsed(items.into_iter()),
        });
    }
    let extension = Path::new(name).extension().and_then(|e| e.to_str());
    let text = start.text();
    let detected = format.or_else(|| KeypointFormat::from_extension_and_content(extension, text));
    if detected.is_none() && !text.starts_with(['{', '[']) && !text.is_empty() {
        return Err(unknown_format(name, extension));
    }
    // A format found from the content may have a lower limit (one OpenPose frame): a file
    // known to be beyond it is refused before more is read.
    refuse_known(options.byte_limit(detected))?;
    if detected == Some(KeypointFormat::Lsp) && !start.ended {
        lsp::check_header_of_start(text, start.newlines, name)?;
    }
    let json = detected.filter(|f| f.is_json());
    // A short document after a long blank lead is streamed too: read whole, its lead would
    // be held in memory.
    let long_lead = start.lead_len() > STREAM_PEEK_BYTES;
    if let (Some(json), true) = (json, !start.ended || long_lead) {
        let (lead, content) = (start.lead(false), start.content);
        return stream_json(
            lead.chain(io::Cursor::new(content)).chain(reader),
            name,
            json,
            options.byte_limit(Some(json)),
            options,
        );
    }
    let mut bytes = Vec::new();
    start.lead(true).read_to_end(&mut bytes).map_err(io_error)?;
    bytes.extend_from_slice(&start.content);
    reader
        .take((limit.saturating_add(1)).saturating_sub(bytes.len() as u64))
        .read_to_end(&mut bytes)
        .map_err(io_error)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64, (limit, rule)));
    }
    if !start.ended {
        return stream_text(bytes, name, detected, options);
    }
    let items = parse_items_bytes(&bytes, name, format, options)?;
    Ok(KeypointStream {
        inner: StreamInner::Parsed(items.into_iter()),
    })
}

/// [`KeypointError::UnknownFormat`] for input `file` with `extension`.
fn unknown_format(file: &str, extension: Option<&str>) -> KeypointError {
    KeypointError::UnknownFormat {
        file: file.to_owned(),
        reason: match extension {
            Some(ext) => format!("extension \".{ext}\" and content match none"),
            None => "no extension, and the content matches none".to_owned(),
        },
    }
}

/// Streams the JSON document `reader` (BOM removed) in `format` on a producer thread, at most
/// `limit` bytes of it (`rule` names the limit in the error).
fn stream_json(
    reader: impl Read + Send + 'static,
    name: &str,
    format: KeypointFormat,
    (limit, rule): (u64, &'static str),
    options: &ReadOptions,
) -> Result<KeypointStream, KeypointError> {
    layout_check::layout_applies(format, options, name)?;
    let file = name.to_owned();
    let options = *options;
    let received = stream::spawn(name, move |sender| {
        let reader = sender.buffered(reader, limit);
        let read = serde_json::de::IoRead::new(reader);
        let outcome = json_records(format, read, &file, &options, &mut |item| sender.send(item));
        let error = match outcome {
            Some(Ok(()) | Err(emit::Stop::Closed)) => return,
            Some(Err(emit::Stop::Invalid(e))) => e,
            Some(Err(emit::Stop::Io(e))) => {
                match e
                    .get_ref()
                    .and_then(|e| e.downcast_ref::<stream::OverLimit>())
                {
                    Some(over) => KeypointError::TooLarge {
                        file: file.clone(),
                        bytes: over.read,
                        limit: over.limit,
                        rule,
                    },
                    None => KeypointError::Io {
                        file: file.clone(),
                        source: e,
                    },
                }
            }
            // Not a JSON format: not streamed (see `streamable_start`).
            None => return,
        };
        sender.send(Err(error));
    })?;
    Ok(KeypointStream {
        inner: StreamInner::Channel(received),
    })
}

/// Streams a long text input that was read whole (LSP CSV, or JSON whose format its first
/// 64 KiB did not tell) from a reader thread, so that the text is held but not its records.
fn stream_text(
    mut bytes: Vec<u8>,
    name: &str,
    format: Option<KeypointFormat>,
    options: &ReadOptions,
) -> Result<KeypointStream, KeypointError> {
    let text = utf8_text(&bytes, name)?;
    let bom = if text.starts_with('\u{feff}') {
        '\u{feff}'.len_utf8()
    } else {
        0
    };
    let extension = Path::new(name).extension().and_then(|e| e.to_str());
    let format = match format {
        Some(format) => format,
        None => KeypointFormat::from_extension_and_content(extension, &text[bom..])
            .ok_or_else(|| unknown_format(name, extension))?,
    };
    match format {
        KeypointFormat::Lsp => stream_lsp(bytes, name, options),
        KeypointFormat::Npy | KeypointFormat::Yolo => Ok(KeypointStream {
            inner: StreamInner::Parsed(
                parse_items_bytes(&bytes, name, Some(format), options)?.into_iter(),
            ),
        }),
        json => {
            bytes.drain(..bom);
            let limit = options.byte_limit(Some(json));
            stream_json(io::Cursor::new(bytes), name, json, limit, options)
        }
    }
}

/// Reads the LSP CSV text `bytes` on a producer thread and streams its records (the text and
/// about 24 bytes per row are held, not the records).
fn stream_lsp(
    bytes: Vec<u8>,
    name: &str,
    options: &ReadOptions,
) -> Result<KeypointStream, KeypointError> {
    layout_check::layout_applies(KeypointFormat::Lsp, options, name)?;
    let file = name.to_owned();
    let options = *options;
    let received = stream::spawn(name, move |sender| {
        let outcome = utf8_text(&bytes, &file).and_then(|text| {
            let text = text.strip_prefix('\u{feff}').unwrap_or(text);
            lsp::read(text, &file, &options, &mut |record| sender.send(Ok(record)))
        });
        if let Err(e) = outcome {
            sender.send(Err(e));
        }
    })?;
    Ok(KeypointStream {
        inner: StreamInner::Channel(received),
    })
}

/// `bytes` as UTF-8 text, or [`KeypointError::NotUtf8`] naming the first invalid byte.
fn utf8_text<'a>(bytes: &'a [u8], file: &str) -> Result<&'a str, KeypointError> {
    std::str::from_utf8(bytes).map_err(|e| {
        let offset = e.valid_up_to();
        let line = 1 + bytes[..offset].iter().filter(|&&b| b == b'\n').count();
        KeypointError::NotUtf8 {
            file: file.to_owned(),
            line,
            offset,
        }
    })
}

/// Reads the JSON document `read` in `format` and gives its records to `emit` (see
/// [`emit::drive`]); `None` for the formats that are not JSON.
fn json_records<'de, R: serde_json::de::Read<'de>>(
    format: KeypointFormat,
    read: R,
    file: &str,
    options: &ReadOptions,
    emit: &mut dyn FnMut(stream::Item) -> bool,
) -> Option<Result<(), emit::Stop>> {
    Some(match format {
        KeypointFormat::Camloc => emit::drive(read, file, options, emit, camloc_json::Document),
        KeypointFormat::Coco => emit::drive(read, file, options, emit, coco::Input),
        KeypointFormat::OpenPose => emit::drive(read, file, options, emit, openpose::Frame),
        KeypointFormat::MmPose => emit::drive(read, file, options, emit, mmpose::Predictions),
        KeypointFormat::MediaPipe => emit::drive(read, file, options, emit, mediapipe::Frames),
        KeypointFormat::Mpii => emit::drive(read, file, options, emit, mpii::Annotations),
        KeypointFormat::Lsp | KeypointFormat::Npy | KeypointFormat::Yolo => return None,
    })
}

/// Parses keypoint bytes: a `.npy` array (named by `format` or recognised by its magic), or
/// UTF-8 text ([`KeypointError::NotUtf8`] otherwise) as [`parse_keypoints`] does.
pub fn parse_keypoints_bytes(
    bytes: &[u8],
    source_name: &str,
    format: Option<KeypointFormat>,
    options: &ReadOptions,
) -> Result<Vec<KeypointRecord>, KeypointError> {
    parse_items_bytes(bytes, source_name, format, options)?
        .into_iter()
        .collect()
}

/// [`parse_keypoints_bytes`] with the errors of poses refused on their own
/// ([`KeypointError::is_pose_error`]) kept in their places; another error is the result.
fn parse_items_bytes(
    bytes: &[u8],
    source_name: &str,
    format: Option<KeypointFormat>,
    options: &ReadOptions,
) -> Result<Vec<stream::Item>, KeypointError> {
    options.check_min_score(source_name)?;
    let npy = match format {
        Some(format) => format == KeypointFormat::Npy,
        None => bytes.starts_with(format::NPY_MAGIC),
    };
    if npy {
        let size = Some(bytes.len() as u64);
        return until_fatal(NpyPoses::new(bytes, source_name, size, options)?);
    }
    if let Some(e) = format::not_keypoints(bytes, source_name) {
        return Err(e);
    }
    parse_items(utf8_text(bytes, source_name)?, source_name, format, options)
}

/// The items of `items` up to the first error that is not a pose's own, which is returned
/// instead.
fn until_fatal(
    items: impl IntoIterator<Item = stream::Item>,
) -> Result<Vec<stream::Item>, KeypointError> {
    items
        .into_iter()
        .map(|item| match item {
            Err(e) if !e.is_pose_error() => Err(e),
            item => Ok(item),
        })
        .collect()
}

/// Parses keypoint text. `source_name` names the input in record sources and errors, and its
/// extension (if any) helps detection when `format` is `None`. A leading byte-order mark is
/// ignored. `.npy` arrays are binary: see [`parse_keypoints_bytes`].
pub fn parse_keypoints(
    text: &str,
    source_name: &str,
    format: Option<KeypointFormat>,
    options: &ReadOptions,
) -> Result<Vec<KeypointRecord>, KeypointError> {
    parse_items(text, source_name, format, options)?
        .into_iter()
        .collect()
}

/// [`parse_keypoints`] with the errors of poses refused on their own
/// ([`KeypointError::is_pose_error`]) kept in their places; another error is the result.
fn parse_items(
    text: &str,
    source_name: &str,
    format: Option<KeypointFormat>,
    options: &ReadOptions,
) -> Result<Vec<stream::Item>, KeypointError> {
    options.check_min_score(source_name)?;
    let file = source_name;
    let too_large = |(limit, rule)| KeypointError::TooLarge {
        file: file.to_owned(),
        bytes: text.len() as u64,
        limit,
        rule,
    };
    let (limit, rule) = options.byte_limit(format);
    if text.len() as u64 > limit {
        return Err(too_large((limit, rule)));
    }
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let extension = Path::new(source_name).extension().and_then(|e| e.to_str());
    if text.trim().is_empty() {
        // A YOLO frame where nobody was detected is an empty file.
        let detected = format.or_else(|| KeypointFormat::from_extension_and_content(extension, ""));
        return match detected {
            Some(KeypointFormat::Yolo) => Ok(Vec::new()),
            _ => Err(KeypointError::Empty {
                file: file.to_owned(),
            }),
        };
    }
    let format = match format {
        Some(format) => format,
        None => KeypointFormat::from_extension_and_content(extension, text)
            .ok_or_else(|| unknown_format(file, extension))?,
    };
    let (limit, rule) = options.byte_limit(Some(format));
    if text.len() as u64 > limit {
        return Err(too_large((limit, rule)));
    }
    layout_check::layout_applies(format, options, file)?;
    match format {
        KeypointFormat::Lsp => Ok(lsp::parse(text, file, options)?
            .into_iter()
            .map(Ok)
            .collect()),
        KeypointFormat::Yolo => Ok(yolo::parse(text, file, options)?
            .into_iter()
            .map(Ok)
            .collect()),
        KeypointFormat::Npy => {
            let size = Some(text.len() as u64);
            until_fatal(NpyPoses::new(text.as_bytes(), file, size, options)?)
        }
        json => emit::collect(file, |emit| {
            let read = serde_json::de::StrRead::new(text);
            json_records(json, read, file, options, emit).unwrap_or(Ok(()))
        }),
    }
}
