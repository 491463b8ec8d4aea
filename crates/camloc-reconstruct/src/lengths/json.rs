//! The JSON form of [`BoneLengths`] (see there): reading, writing, serde.

use std::io::Read;
use std::path::Path;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::{BONE_KEYS, BoneLengthError, BoneLengths};

/// The `"format"` of a bone lengths document.
pub const BONE_LENGTHS_FORMAT: &str = "camloc-bone-lengths";

/// The `"version"` of a bone lengths document.
pub const BONE_LENGTHS_VERSION: u32 = 1;

/// The largest bone lengths file [`BoneLengths::read_json`] reads, bytes (a document is a few
/// hundred bytes).
pub const MAX_BONE_LENGTHS_FILE_BYTES: u64 = 64 * 1024;

/// The `"lengths"` object: one field per limb, every one required, no other key, none twice
/// (serde's derive refuses duplicates and, with `deny_unknown_fields`, unknown keys).
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Named {
    left_pelvis_hip: f64,
    left_thigh: f64,
    left_shin: f64,
    right_pelvis_hip: f64,
    right_thigh: f64,
    right_shin: f64,
    torso: f64,
    neck_head: f64,
    left_collar: f64,
    left_upper_arm: f64,
    left_forearm: f64,
    right_collar: f64,
    right_upper_arm: f64,
    right_forearm: f64,
}

impl Named {
    fn from_array(a: [f64; 14]) -> Named {
        let [
            left_pelvis_hip,
            left_thigh,
            left_shin,
            right_pelvis_hip,
            right_thigh,
            right_shin,
            torso,
            neck_head,
            left_collar,
            left_upper_arm,
            left_forearm,
            right_collar,
            right_upper_arm,
            right_forearm,
        ] = a;
        Named {
            left_pelvis_hip,
            left_thigh,
            left_shin,
            right_pelvis_hip,
            right_thigh,
            right_shin,
            torso,
            neck_head,
            left_collar,
            left_upper_arm,
            left_forearm,
            right_collar,
            right_upper_arm,
            right_forearm,
        }
    }

    fn to_array(&self) -> [f64; 14] {
        [
            self.left_pelvis_hip,
            self.left_thigh,
            self.left_shin,
            self.right_pelvis_hip,
            self.right_thigh,
            self.right_shin,
            self.torso,
            self.neck_head,
            self.left_collar,
            self.left_upper_arm,
            self.left_forearm,
            self.right_collar,
            self.right_upper_arm,
            self.right_forearm,
        ]
    }
}

/// The whole document.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Document {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    format: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    version: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    unit: Option<String>,
    lengths: Named,
}

impl BoneLengths {
    /// Reads the JSON form (see [`BoneLengths`]).
    ///
    /// # Errors
    /// [`BoneLengthError::Json`] for malformed JSON, a missing, unknown or repeated key (the
    /// message names it, with line and column); [`BoneLengthError::Header`] for another
    /// `format`, `version` or `unit`; as [`BoneLengths::from_array`] for the values.
    pub fn from_json_str(text: &str) -> Result<BoneLengths, BoneLengthError> {
        let document: Document = serde_json::from_str(text)?;
        let header = |what: &str, found: String, expected: String| {
            BoneLengthError::Header(format!("{what} is {found}, expected {expected}"))
        };
        if let Some(format) = document.format.filter(|f| f != BONE_LENGTHS_FORMAT) {
            return Err(header(
                "\"format\"",
                format!("{format:?}"),
                format!("{BONE_LENGTHS_FORMAT:?}"),
            ));
        }
        if let Some(version) = document.version.filter(|v| *v != BONE_LENGTHS_VERSION) {
            return Err(header(
                "\"version\"",
                version.to_string(),
                BONE_LENGTHS_VERSION.to_string(),
            ));
        }
        if let Some(unit) = document.unit.filter(|u| u != "m") {
            return Err(header("\"unit\"", format!("{unit:?}"), "\"m\"".into()));
        }
        BoneLengths::from_array(document.lengths.to_array())
    }

    /// The JSON form (see [`BoneLengths`]), with `format`, `version` and `unit`, one length a
    /// line, ending with a newline. Numbers are written in the shortest form that reads back
    /// to the same value.
    pub fn to_json_string(&self) -> String {
        let document = Document {
            format: Some(BONE_LENGTHS_FORMAT.into()),
            version: Some(BONE_LENGTHS_VERSION),
            unit: Some("m".into()),
            lengths: Named::from_array(self.0),
        };
        // A struct of strings and finite numbers always serialises.
        let mut text = serde_json::to_string_pretty(&document).unwrap_or_default();
        text.push('\n');
        text
    }

    /// Reads a bone lengths file (the JSON form), refusing files over
    /// [`MAX_BONE_LENGTHS_FILE_BYTES`].
    ///
    /// # Errors
    /// [`BoneLengthError::File`] naming the file when it cannot be read, is too large or is
    /// not UTF-8, with the reason of [`BoneLengths::from_json_str`] when its content is
    /// refused.
    pub fn read_json(path: &Path) -> Result<BoneLengths, BoneLengthError> {
        let name = camloc_store::quoted_path(path);
        let file_error = |detail: String| BoneLengthError::File {
            path: name.clone(),
            detail,
        };
        let file = std::fs::File::open(path).map_err(|e| file_error(e.to_string()))?;
        let mut bytes = Vec::new();
        file.take(MAX_BONE_LENGTHS_FILE_BYTES + 1)
            .read_to_end(&mut bytes)
            .map_err(|e| file_error(e.to_string()))?;
        if bytes.len() as u64 > MAX_BONE_LENGTHS_FILE_BYTES {
            return Err(file_error(format!(
                "larger than {MAX_BONE_LENGTHS_FILE_BYTES} bytes: not a bone lengths document"
            )));
        }
        let text = String::from_utf8(bytes).map_err(|_| file_error("not UTF-8 text".into()))?;
        BoneLengths::from_json_str(&text).map_err(|e| file_error(e.to_string()))
    }

    /// The JSON key of limb `limb` ([`BONE_KEYS`]); `None` for an index of 14 or more.
    pub fn key(limb: usize) -> Option<&'static str> {
        BONE_KEYS.get(limb).copied()
    }
}

/// Serialises as the `"lengths"` object of the JSON form.
impl Serialize for BoneLengths {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        Named::from_array(self.0).serialize(serializer)
    }
}

/// Reads the `"lengths"` object of the JSON form, validated.
impl<'de> Deserialize<'de> for BoneLengths {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let named = Named::deserialize(deserializer)?;
        BoneLengths::from_array(named.to_array()).map_err(serde::de::Error::custom)
    }
}
