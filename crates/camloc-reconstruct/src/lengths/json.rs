//! The JSON form of [`BoneLengths`] (see there): reading, writing, serde.

use std::fmt;
use std::io::Read;
use std::path::Path;

use serde::de::{self, MapAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use camloc_store::quoted;

use super::{BONE_KEYS, BoneLengthError, BoneLengths};

/// The `"format"` of a bone lengths document.
pub const BONE_LENGTHS_FORMAT: &str = "camloc-bone-lengths";

/// The `"version"` of a bone lengths document.
pub const BONE_LENGTHS_VERSION: u32 = 1;

/// The largest bone lengths file [`BoneLengths::read_json`] reads, bytes (a document is a few
/// hundred bytes).
pub const MAX_BONE_LENGTHS_FILE_BYTES: u64 = 64 * 1024;

/// The `"lengths"` object: one number per limb by its [`BONE_KEYS`] name, every one required,
/// no other key, none twice (a list is refused: its order would be a guess).
struct Named([f64; 14]);

impl Serialize for Named {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(BONE_KEYS.len()))?;
        for (key, value) in BONE_KEYS.iter().zip(&self.0) {
            map.serialize_entry(key, value)?;
        }
        map.end()
    }
}

impl<'de> Deserialize<'de> for Named {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_map(NamedVisitor)
    }
}

/// Reads [`Named`], naming every key that is missing, unknown or repeated.
struct NamedVisitor;

impl<'de> Visitor<'de> for NamedVisitor {
    type Value = Named;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(
            f,
            "an object of the 14 limbs' lengths by name ({})",
            BONE_KEYS.join(", ")
        )
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Named, A::Error> {
        let mut values = [None; 14];
        while let Some(key) = map.next_key::<String>()? {
            let Some(i) = BONE_KEYS.iter().position(|k| *k == key) else {
                return Err(de::Error::custom(format!(
                    "unknown limb \"{}\" (the limbs: {})",
                    quoted(&key),
                    BONE_KEYS.join(", ")
                )));
            };
            if values[i].is_some() {
                return Err(de::Error::custom(format!("limb {key:?} given twice")));
            }
            values[i] = Some(map.next_value::<f64>()?);
        }
        let missing: Vec<String> = BONE_KEYS
            .iter()
            .zip(&values)
            .filter(|(_, v)| v.is_none())
            .map(|(k, _)| format!("{k:?}"))
            .collect();
        if !missing.is_empty() {
            return Err(de::Error::custom(format!(
                "missing limb(s) {} (all 14 are needed)",
                missing.join(", ")
            )));
        }
        Ok(Named(values.map(|v| v.unwrap_or_default())))
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
    /// Whose lengths these are (written by `--bone-lengths-out`; not read).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    person: Option<String>,
    lengths: Named,
}

impl BoneLengths {
    /// Reads the JSON form (see [`BoneLengths`]).
    ///
    /// # Errors
    /// [`BoneLengthError::Json`] for malformed JSON, a missing, unknown or repeated key (the
    /// message names it, with line and column); [`BoneLengthError::Header`] for another
    /// `format`, `version` or `unit`, or a document that is a list; as
    /// [`BoneLengths::given`] for the values.
    pub fn from_json_str(text: &str) -> Result<BoneLengths, BoneLengthError> {
        // (serde would read a list as the document's fields in order.)
        if text.trim_start().starts_with('[') {
            return Err(BoneLengthError::Header(
                "the document is a list; it is an object whose \"lengths\" names the 14 limbs"
                    .into(),
            ));
        }
        let document: Document = serde_json::from_str(text)?;
        let header = |what: &str, found: String, expected: String| {
            BoneLengthError::Header(format!("{what} is {found}, expected {expected}"))
        };
        if let Some(format) = document.format.filter(|f| f != BONE_LENGTHS_FORMAT) {
            return Err(header(
                "\"format\"",
                format!("\"{}\"", quoted(&format)),
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
            return Err(header(
                "\"unit\"",
                format!("\"{}\"", quoted(&unit)),
                "\"m\"".into(),
            ));
        }
        BoneLengths::given(document.lengths.0)
    }

    /// The JSON form (see [`BoneLengths`]), with `format`, `version` and `unit`, one length a
    /// line, ending with a newline. Numbers are written in the shortest form that reads back
    /// to the same value.
    pub fn to_json_string(&self) -> String {
        self.to_json_string_of(None)
    }

    /// [`to_json_string`](Self::to_json_string) with `person`, the name of whose lengths these
    /// are (`person 3 of clip.npy`), after `unit` when given: a folder of videos' numbered files
    /// each say whose they are. Reading takes any `person` string and leaves it aside.
    pub fn to_json_string_of(&self, person: Option<&str>) -> String {
        let document = Document {
            format: Some(BONE_LENGTHS_FORMAT.into()),
            version: Some(BONE_LENGTHS_VERSION),
            unit: Some("m".into()),
            person: person.map(str::to_owned),
            lengths: Named(self.0),
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
        // (A byte-order mark, as some editors write, is not part of the document.)
        let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
        BoneLengths::from_json_str(text).map_err(|e| file_error(e.to_string()))
    }

    /// The JSON key of limb `limb` ([`BONE_KEYS`]); `None` for an index of 14 or more.
    pub fn key(limb: usize) -> Option<&'static str> {
        BONE_KEYS.get(limb).copied()
    }
}

/// Serialises as the `"lengths"` object of the JSON form.
impl Serialize for BoneLengths {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        Named(self.0).serialize(serializer)
    }
}

/// Reads the `"lengths"` object of the JSON form, validated.
impl<'de> Deserialize<'de> for BoneLengths {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let named = Named::deserialize(deserializer)?;
        BoneLengths::from_array(named.0).map_err(de::Error::custom)
    }
}
