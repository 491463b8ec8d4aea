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
//! *derived* rather than read, and where the pose is in the file. Coordinates are kept in the
//! file's units (pixels for the three formats below); camloc's descriptors are invariant to 2D
//! translation and scale.
//!
//! # Formats
//!
//! [`KeypointFormat::from_extension_and_content`] picks the format when none is given: `.csv` is
//! LSP, `.json` is camloc JSON if it has a `"poses"` or `"landmarks"` key and COCO if it has
//! `"annotations"` or `"keypoints"` or is a top-level list.
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
//! coordinates of invisible joints. An image that lacks some joint rows simply has those
//! landmarks missing.
//!
//! ## COCO-17 JSON
//!
//! Either a dataset file (`{"annotations": [{"image_id": .., "id": .., "keypoints": [..]}], ..}`;
//! other keys and other annotation fields are skipped) or a results list
//! (`[{"image_id": .., "keypoints": [..], "score": ..}]`). `keypoints` holds 51 numbers, `x, y, v`
//! for each of [`COCO_KEYPOINTS`]; a keypoint is present when `v` (visibility flag in dataset
//! files, confidence in results) is above [`CocoOptions::min_score`], 0 by default, so `v == 0`
//! is missing. Shoulders, elbows, wrists, hips, knees and ankles map by name; the head is the
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
//! the file, then a line (CSV), a JSON path such as `poses[2].landmarks.left_knee`, or a JSON
//! line and column for syntax errors. Inputs longer than [`ReadOptions::max_bytes`] are refused
//! before they are parsed.

#![warn(missing_docs)]

mod camloc_json;
mod coco;
mod error;
mod format;
mod json;
mod lsp;
mod record;

use std::io::Read;
use std::path::Path;

pub use camloc_json::{CAMLOC_FORMAT_TAG, CAMLOC_FORMAT_VERSION, to_camloc_json};
pub use camloc_skeleton::{Landmark, PartialPose2};
pub use coco::COCO_KEYPOINTS;
pub use error::{KeypointError, Location};
pub use format::{KeypointFormat, UnknownFormatName};
pub use lsp::LSP_JOINTS;
pub use record::{KeypointRecord, derive_torso};

/// What to do with LSP joints marked `visible = 0`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Invisible {
    /// The landmark is missing (the default).
    #[default]
    Missing,
    /// Keep the annotated coordinates (LSP annotates occluded joints where they are guessed to
    /// be; joints outside the image may have coordinates outside it).
    Use,
}

/// Options of the LSP CSV reader.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct LspOptions {
    /// Treatment of joints with `visible = 0`.
    pub invisible: Invisible,
}

/// Options of the COCO reader.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CocoOptions {
    /// A keypoint is present when its third value (visibility flag or confidence) is strictly
    /// greater than this. Default 0: only `v == 0` (or below) is missing.
    pub min_score: f64,
}

/// Options shared by all readers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReadOptions {
    /// Derive a missing pelvis/neck from the hips/shoulders ([`derive_torso`]). Default `true`.
    pub derive_torso: bool,
    /// LSP CSV options.
    pub lsp: LspOptions,
    /// COCO options.
    pub coco: CocoOptions,
    /// Largest input accepted, in bytes; longer inputs give [`KeypointError::TooLarge`].
    /// Default [`ReadOptions::DEFAULT_MAX_BYTES`] (1 GiB).
    pub max_bytes: u64,
}

impl ReadOptions {
    /// The default input size limit: 1 GiB, room for the largest COCO keypoint files.
    pub const DEFAULT_MAX_BYTES: u64 = 1 << 30;
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            derive_torso: true,
            lsp: LspOptions::default(),
            coco: CocoOptions::default(),
            max_bytes: ReadOptions::DEFAULT_MAX_BYTES,
        }
    }
}

/// Reads a keypoint file. `format: None` detects it from the extension and content
/// ([`KeypointFormat::from_extension_and_content`]). Record sources and error messages name the
/// file as `path` displays.
pub fn read_keypoints(
    path: impl AsRef<Path>,
    format: Option<KeypointFormat>,
    options: &ReadOptions,
) -> Result<Vec<KeypointRecord>, KeypointError> {
    let path = path.as_ref();
    let name = path.display().to_string();
    let io = |source| KeypointError::Io {
        file: name.clone(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let too_large = |bytes| KeypointError::TooLarge {
        file: name.clone(),
        bytes,
        limit: options.max_bytes,
    };
    // Refuse known-large files before reading; `take` also bounds pipes and special files.
    let size = file.metadata().map_err(io)?.len();
    if size > options.max_bytes {
        return Err(too_large(size));
    }
    let mut bytes = Vec::new();
    file.take(options.max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > options.max_bytes {
        return Err(too_large(bytes.len() as u64));
    }
    parse_keypoints_bytes(&bytes, &name, format, options)
}

/// Parses keypoint bytes, which must be UTF-8 ([`KeypointError::NotUtf8`] otherwise); see
/// [`parse_keypoints`].
pub fn parse_keypoints_bytes(
    bytes: &[u8],
    source_name: &str,
    format: Option<KeypointFormat>,
    options: &ReadOptions,
) -> Result<Vec<KeypointRecord>, KeypointError> {
    match std::str::from_utf8(bytes) {
        Ok(text) => parse_keypoints(text, source_name, format, options),
        Err(e) => {
            let offset = e.valid_up_to();
            let line = 1 + bytes[..offset].iter().filter(|&&b| b == b'\n').count();
            Err(KeypointError::NotUtf8 {
                file: source_name.to_owned(),
                line,
                offset,
            })
        }
    }
}

/// Parses keypoint text. `source_name` names the input in record sources and errors, and its
/// extension (if any) helps detection when `format` is `None`. A leading byte-order mark is
/// ignored.
pub fn parse_keypoints(
    text: &str,
    source_name: &str,
    format: Option<KeypointFormat>,
    options: &ReadOptions,
) -> Result<Vec<KeypointRecord>, KeypointError> {
    let file = source_name;
    if text.len() as u64 > options.max_bytes {
        return Err(KeypointError::TooLarge {
            file: file.to_owned(),
            bytes: text.len() as u64,
            limit: options.max_bytes,
        });
    }
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim().is_empty() {
        return Err(KeypointError::Empty {
            file: file.to_owned(),
        });
    }
    let extension = Path::new(source_name).extension().and_then(|e| e.to_str());
    let format = match format {
        Some(format) => format,
        None => KeypointFormat::from_extension_and_content(extension, text).ok_or_else(|| {
            KeypointError::UnknownFormat {
                file: file.to_owned(),
                reason: match extension {
                    Some(ext) => format!("extension \".{ext}\" and content match none"),
                    None => "no extension, and the content matches none".to_owned(),
                },
            }
        })?,
    };
    match format {
        KeypointFormat::Camloc => camloc_json::parse(text, file, options),
        KeypointFormat::Lsp => lsp::parse(text, file, options),
        KeypointFormat::Coco => coco::parse(text, file, options),
    }
}
