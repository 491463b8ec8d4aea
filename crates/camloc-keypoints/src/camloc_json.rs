//! camloc JSON: the project's own keypoint format (see the crate documentation).

use camloc_skeleton::{Landmark, NUM_LANDMARKS, PartialPose2};

use std::fmt;

use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};

use crate::ReadOptions;
use crate::error::{KeypointError, Location};
use crate::json::{
    self, Json, SkipVisitor, Skipped, check_keys, get, index_path, key_path, number_array,
    wrong_type,
};
use crate::record::{KeypointRecord, finish};

/// The value of the `format` key.
pub const CAMLOC_FORMAT_TAG: &str = "camloc-keypoints";
/// The format version this crate reads and writes.
pub const CAMLOC_FORMAT_VERSION: u64 = 1;

/// Landmark names in index order: the keys of a `landmarks` object.
const LANDMARK_NAMES: [&str; NUM_LANDMARKS] = {
    let mut names = [""; NUM_LANDMARKS];
    let mut i = 0;
    while i < NUM_LANDMARKS {
        names[i] = Landmark::ALL[i].name();
        i += 1;
    }
    names
};

/// Keys of the top-level document object.
const DOCUMENT_KEYS: [&str; 3] = ["format", "version", "poses"];
/// Keys of a pose object.
const POSE_KEYS: [&str; 2] = ["id", "landmarks"];

/// What a top-level object that is not a document must be.
const EXPECTED: &str = "an object with \"poses\" (a document) or \"landmarks\" (one pose)";

/// Top-level keys whose value (first occurrence) is kept while streaming: the document's
/// `format` and `version`, and the keys of a bare pose. Other values are parsed and dropped.
const KEPT_KEYS: [&str; 4] = ["format", "version", "id", "landmarks"];

/// Reads camloc JSON text (BOM already removed, known not to be blank).
pub(crate) fn parse(
    text: &str,
    file: &str,
    options: &ReadOptions,
) -> Result<Vec<KeypointRecord>, KeypointError> {
    let root: Json = json::parse(text, file)?;
    let Json::Object(fields) = &root else {
        return Err(wrong_type(file, "", EXPECTED, &root));
    };
    if is_bare_pose(fields) {
        return Ok(vec![pose(&root, "", 0, file, options)?]);
    }
    document_poses(fields, file)?
        .iter()
        .enumerate()
        .map(|(i, value)| pose(value, &index_path("poses", i), i, file, options))
        .collect()
}

/// `true` for a top level that is one pose: `landmarks` and no `poses`.
fn is_bare_pose(fields: &[(String, Json)]) -> bool {
    get(fields, "poses").is_none() && get(fields, "landmarks").is_some()
}

/// Checks the top-level keys of a document (known keys, each once; the format tag; the
/// version; `poses` an array) in this order, and returns the poses.
fn document_poses<'a>(
    fields: &'a [(String, Json)],
    file: &str,
) -> Result<&'a [Json], KeypointError> {
    check_keys(fields, &DOCUMENT_KEYS, file, "")?;
    let wrong_tag = |tag: &&Json| !matches!(tag, Json::String(s) if s == CAMLOC_FORMAT_TAG);
    if let Some(tag) = get(fields, "format").filter(wrong_tag) {
        return Err(KeypointError::InvalidValue {
            file: file.to_owned(),
            at: Location::Path("format".to_owned()),
            field: "format",
            text: json_text(tag),
            expected: "\"camloc-keypoints\"",
        });
    }
    let wrong_version = |version: &&Json| !matches!(version, Json::Number(n) if n.as_u64() == Some(CAMLOC_FORMAT_VERSION));
    if let Some(version) = get(fields, "version").filter(wrong_version) {
        return Err(KeypointError::UnsupportedVersion {
            file: file.to_owned(),
            at: Location::Path("version".to_owned()),
            found: json_text(version),
        });
    }
    match get(fields, "poses") {
        Some(Json::Array(poses)) => Ok(poses),
        Some(other) => Err(wrong_type(file, "poses", "an array of poses", other)),
        None => Err(KeypointError::MissingKey {
            file: file.to_owned(),
            at: Location::Path(String::new()),
            key: "poses",
        }),
    }
}

/// Why [`stream`] stopped before the end of the input.
pub(crate) enum Stop {
    /// The input is invalid.
    Invalid(KeypointError),
    /// Reading failed (an I/O error of the reader, e.g. its size limit).
    Io(std::io::Error),
    /// `emit` returned `false`: nobody wants more records.
    Closed,
}

/// Reads a camloc JSON object from `reader` (BOM already removed, starting with `{` after
/// white space) and gives its records to `emit` one at a time, each as soon as its pose is
/// parsed: memory is that of one pose, whatever the number of poses.
///
/// Errors are those of [`parse`], found in input order: a document-level problem (unknown or
/// repeated key, format tag, version, `poses` not an array) in the keys before `poses` stops
/// before any pose (reported as [`parse`] does, after reading the rest); one in the keys after
/// `poses` is reported after the poses. A bare pose is emitted at the end of the object.
pub(crate) fn stream<R: std::io::Read>(
    reader: R,
    file: &str,
    options: &ReadOptions,
    emit: &mut dyn FnMut(KeypointRecord) -> bool,
) -> Result<(), Stop> {
    let mut sink = Sink {
        file,
        options,
        emit,
        stop: None,
    };
    let mut deserializer = serde_json::Deserializer::from_reader(reader);
    let parsed = deserializer
        .deserialize_map(DocumentVisitor(&mut sink))
        .and_then(|()| deserializer.end());
    match parsed {
        Ok(()) => Ok(()),
        Err(e) => Err(match sink.stop {
            Some(stop) => stop,
            None if e.is_io() => Stop::Io(e.into()),
            None => Stop::Invalid(json::syntax_error(&e, file)),
        }),
    }
}

/// Where streamed records go, and why streaming stopped.
struct Sink<'a> {
    file: &'a str,
    options: &'a ReadOptions,
    emit: &'a mut dyn FnMut(KeypointRecord) -> bool,
    stop: Option<Stop>,
}

impl Sink<'_> {
    /// Gives a record to `emit`, or records why not and returns an error that ends parsing.
    fn send<E: de::Error>(
        &mut self,
        record: Result<KeypointRecord, KeypointError>,
    ) -> Result<(), E> {
        let stop = match record {
            Ok(record) => {
                if (self.emit)(record) {
                    return Ok(());
                }
                Stop::Closed
            }
            Err(e) => Stop::Invalid(e),
        };
        self.stop = Some(stop);
        Err(E::custom("streaming stopped"))
    }
}

/// The top-level object of a streamed input.
struct DocumentVisitor<'s, 'a>(&'s mut Sink<'a>);

impl<'de> Visitor<'de> for DocumentVisitor<'_, '_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(EXPECTED)
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let sink = self.0;
        let mut fields: Vec<(String, Json)> = Vec::new();
        while let Some(key) = map.next_key::<String>()? {
            let first = get(&fields, &key).is_none();
            let value = if key == "poses" && first && {
                // Stream the poses only if the keys so far pass the document checks.
                fields.push((key.clone(), Json::Array(Vec::new())));
                let ok = document_poses(&fields, sink.file).is_ok();
                fields.pop();
                ok
            } {
                map.next_value_seed(PosesSeed(&mut *sink))?
            } else if first && KEPT_KEYS.contains(&key.as_str()) {
                map.next_value::<Json>()?
            } else {
                map.next_value::<Skipped>()?.0
            };
            fields.push((key, value));
        }
        if is_bare_pose(&fields) {
            let root = Json::Object(fields);
            let record = pose(&root, "", 0, sink.file, sink.options);
            return sink.send(record);
        }
        match document_poses(&fields, sink.file) {
            Ok(_) => Ok(()),
            Err(e) => sink.send(Err(e)),
        }
    }
}

/// The value of `poses`: an array is streamed pose by pose (its placeholder is an empty
/// array), another value skipped (its placeholder has its type).
struct PosesSeed<'s, 'a>(&'s mut Sink<'a>);

impl<'de> DeserializeSeed<'de> for PosesSeed<'_, '_> {
    type Value = Json;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<Json, D::Error> {
        deserializer.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for PosesSeed<'_, '_> {
    type Value = Json;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("an array of poses")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Json, A::Error> {
        let sink = self.0;
        let mut index = 0;
        while let Some(value) = seq.next_element::<Json>()? {
            let path = index_path("poses", index);
            let record = pose(&value, &path, index, sink.file, sink.options);
            sink.send(record)?;
            index += 1;
        }
        Ok(Json::Array(Vec::new()))
    }

    // Any other value is skipped; its placeholder has its type.
    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Json, A::Error> {
        SkipVisitor.visit_map(map)
    }

    fn visit_unit<E: de::Error>(self) -> Result<Json, E> {
        SkipVisitor.visit_unit()
    }

    fn visit_bool<E: de::Error>(self, v: bool) -> Result<Json, E> {
        SkipVisitor.visit_bool(v)
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Json, E> {
        SkipVisitor.visit_i64(v)
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Json, E> {
        SkipVisitor.visit_u64(v)
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Json, E> {
        SkipVisitor.visit_f64(v)
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Json, E> {
        SkipVisitor.visit_str(v)
    }
}

/// The pose object `value` at JSON path `path`, the `index`-th of the input.
fn pose(
    value: &Json,
    path: &str,
    index: usize,
    file: &str,
    options: &ReadOptions,
) -> Result<KeypointRecord, KeypointError> {
    let Json::Object(fields) = value else {
        return Err(wrong_type(file, path, "a pose object", value));
    };
    check_keys(fields, &POSE_KEYS, file, path)?;
    let id = match get(fields, "id") {
        Some(Json::String(id)) => id.clone(),
        Some(other) => return Err(wrong_type(file, &key_path(path, "id"), "a string", other)),
        None => format!("pose-{index}"),
    };
    let landmarks_path = key_path(path, "landmarks");
    let landmarks = match get(fields, "landmarks") {
        Some(Json::Object(landmarks)) => landmarks,
        Some(other) => {
            return Err(wrong_type(
                file,
                &landmarks_path,
                "an object of landmarks",
                other,
            ));
        }
        None => {
            return Err(KeypointError::MissingKey {
                file: file.to_owned(),
                at: Location::Path(path.to_owned()),
                key: "landmarks",
            });
        }
    };
    check_keys(landmarks, &LANDMARK_NAMES, file, &landmarks_path)?;
    let mut pose = PartialPose2::empty();
    for (landmark, point) in Landmark::ALL.iter().zip(&mut pose.points) {
        *point = match get(landmarks, landmark.name()) {
            None | Some(Json::Null) => None,
            Some(value) => {
                let path = key_path(&landmarks_path, landmark.name());
                Some(number_array::<2>(value, "[u, v] or null", file, &path)?)
            }
        };
    }
    let source = format!("{file}: {}", Location::Path(path.to_owned()));
    Ok(finish(id, pose, Vec::new(), source, options))
}

/// A short rendering of a JSON value for error messages.
fn json_text(value: &Json) -> String {
    match value {
        Json::String(s) => s.clone(),
        Json::Number(n) => n.to_string(),
        other => other.kind().to_owned(),
    }
}

/// Writes poses as a camloc JSON document (format version 1), pretty-printed with one landmark
/// per line, every landmark key present and missing ones as `null`.
///
/// Coordinates are written in the shortest form that reads back to the same `f64`, so
/// [`parse_keypoints`](crate::parse_keypoints) with `derive_torso: false` returns exactly the
/// given ids and poses. A non-finite coordinate cannot be written in JSON: such a landmark is
/// written as `null`, i.e. missing.
pub fn to_camloc_json<S: AsRef<str>>(poses: &[(S, PartialPose2)]) -> String {
    let mut out = format!(
        "{{\n  \"format\": {},\n  \"version\": {CAMLOC_FORMAT_VERSION},\n  \"poses\": [",
        string(CAMLOC_FORMAT_TAG)
    );
    for (i, (id, pose)) in poses.iter().enumerate() {
        out.push_str(if i == 0 { "\n" } else { ",\n" });
        out.push_str(&format!(
            "    {{\n      \"id\": {},\n      \"landmarks\": {{\n",
            string(id.as_ref())
        ));
        let lines: Vec<String> = Landmark::ALL
            .iter()
            .zip(&pose.points)
            .map(|(landmark, point)| {
                format!("        \"{}\": {}", landmark.name(), point_text(*point))
            })
            .collect();
        out.push_str(&lines.join(",\n"));
        out.push_str("\n      }\n    }");
    }
    out.push_str(if poses.is_empty() {
        "]\n}\n"
    } else {
        "\n  ]\n}\n"
    });
    out
}

/// A JSON string literal.
fn string(s: &str) -> String {
    serde_json::Value::from(s).to_string()
}

/// `[u, v]`, or `null` for a missing or non-finite point.
fn point_text(point: Option<[f64; 2]>) -> String {
    let number = serde_json::Number::from_f64;
    match point.and_then(|[u, v]| number(u).zip(number(v))) {
        Some((u, v)) => format!("[{u}, {v}]"),
        None => "null".to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_all_keys_in_landmark_order_with_null_for_missing() {
        let mut pose = PartialPose2::empty();
        pose.points[Landmark::Neck.index()] = Some([1.5, -2.0]);
        pose.points[Landmark::Head.index()] = Some([f64::NAN, 0.0]);
        let text = to_camloc_json(&[("a \"quoted\" id", pose)]);
        assert!(text.contains("\"id\": \"a \\\"quoted\\\" id\""), "{text}");
        assert!(text.contains("\"neck\": [1.5, -2.0],"), "{text}");
        assert!(text.contains("\"head\": null,"), "{text}");
        let mut previous = 0;
        for name in LANDMARK_NAMES {
            let at = text.find(&format!("\"{name}\":")).unwrap();
            assert!(at > previous, "{name} out of order");
            previous = at;
        }
    }

    #[test]
    fn empty_list_is_a_valid_document() {
        let text = to_camloc_json::<&str>(&[]);
        let root: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(root["poses"], serde_json::json!([]));
        assert!(
            parse(&text, "e.json", &ReadOptions::default())
                .unwrap()
                .is_empty()
        );
    }
}
