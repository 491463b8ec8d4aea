//! camloc JSON: the project's own keypoint format (see the crate documentation).

use std::collections::HashSet;

use camloc_skeleton::{Landmark, NUM_LANDMARKS, PartialPose2};

use serde::de::{MapAccess, SeqAccess};

use crate::ReadOptions;
use crate::emit::{self, ListReader, ListSeed, Sink, TopLevel};
use crate::error::{KeypointError, Location};
use crate::json::{
    Json, Skipped, check_keys, count_number, get, index_path, key_path, number_array, wrong_type,
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
const POSE_KEYS: [&str; 4] = ["id", "frame", "person", "landmarks"];

/// What a top-level object that is not a document must be.
const EXPECTED: &str = "an object with \"poses\" (a document) or \"landmarks\" (one pose)";

/// Top-level keys whose value (first occurrence) is kept while streaming: the document's
/// `format` and `version`, and the keys of a bare pose. Other values are parsed and dropped.
const KEPT_KEYS: [&str; 6] = ["format", "version", "id", "frame", "person", "landmarks"];

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
        let found = match version {
            Json::String(text) => format!("\"{}\" (a string)", camloc_store::quoted(text)),
            other => json_text(other),
        };
        return Err(KeypointError::UnsupportedVersion {
            file: file.to_owned(),
            at: Location::Path("version".to_owned()),
            found,
        });
    }
    match get(fields, "poses") {
        Some(Json::Array(poses)) => Ok(poses),
        Some(other) => Err(wrong_type(file, "poses", "an array of poses", other)),
        None => Err(KeypointError::MissingKey {
            file: file.to_owned(),
            at: Location::Path(String::new()),
            key: "poses",
            read_as_coco: false,
        }),
    }
}

/// camloc JSON: a document, whose poses are read one at a time, or one bare pose.
///
/// Errors come in input order: a document-level problem (unknown or repeated key, format tag,
/// version, `poses` not an array) in the keys before `poses` stops before any pose (after
/// reading the rest, for the full list of unknown keys); one in the keys after `poses` is
/// reported after the poses. A bare pose is read at the end of the object.
pub(crate) struct Document;

impl TopLevel for Document {
    const EXPECTED: &'static str = EXPECTED;

    fn object<'de, A: MapAccess<'de>>(self, mut map: A, sink: &mut Sink) -> Result<(), A::Error> {
        let mut fields: Vec<(String, Json)> = Vec::new();
        // The keys so far (a document of a million unknown keys is read in linear time).
        let mut seen: HashSet<String> = HashSet::new();
        while let Some(key) = map.next_key::<String>()? {
            let first = seen.insert(key.clone());
            let value = if key == "poses" && first && {
                // Stream the poses only if the keys so far pass the document checks.
                fields.push((key.clone(), Json::Array(Vec::new())));
                let ok = document_poses(&fields, sink.file).is_ok();
                fields.pop();
                ok
            } {
                map.next_value_seed(ListSeed(Poses, &mut *sink))?
            } else if first && KEPT_KEYS.contains(&key.as_str()) {
                map.next_value::<Json>()?
            } else {
                map.next_value::<Skipped>()?.0
            };
            fields.push((key, value));
        }
        if is_bare_pose(&fields) {
            let record = pose(Json::Object(fields), "", 0, sink.file, sink.options);
            return sink.send(record);
        }
        match document_poses(&fields, sink.file) {
            Ok(_) => Ok(()),
            Err(e) => Err(sink.fail(e)),
        }
    }
}

/// The value of `poses`, read pose by pose.
struct Poses;

impl ListReader for Poses {
    fn read<'de, A: SeqAccess<'de>>(self, seq: A, sink: &mut Sink) -> Result<(), A::Error> {
        let (file, options) = (sink.file, sink.options);
        emit::entries(seq, sink, |value, index| {
            pose(value, &index_path("poses", index), index, file, options).map(Some)
        })
    }
}

/// The pose object `value` at JSON path `path`, the `index`-th of the input (taken: its id
/// is moved into the record, not copied, whatever its length).
fn pose(
    value: Json,
    path: &str,
    index: usize,
    file: &str,
    options: &ReadOptions,
) -> Result<KeypointRecord, KeypointError> {
    let Json::Object(mut fields) = value else {
        return Err(wrong_type(file, path, "a pose object", &value));
    };
    check_keys(&fields, &POSE_KEYS, file, path)?;
    let id = match fields.iter().position(|(key, _)| key == "id") {
        Some(at) => match fields.swap_remove(at).1 {
            Json::String(id) => id,
            other => return Err(wrong_type(file, &key_path(path, "id"), "a string", &other)),
        },
        None => format!("pose-{index}"),
    };
    let fields = &fields;
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
                read_as_coco: false,
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
    let number = |key: &'static str| {
        get(fields, key)
            .map(|v| count_number(v, key, file, &key_path(path, key)))
            .transpose()
    };
    let (frame, person) = (number("frame")?, number("person")?);
    let source = format!("{file}: {}", Location::Path(path.to_owned()));
    Ok(KeypointRecord {
        frame,
        person,
        ..finish(id, pose, Vec::new(), source, options)
    })
}

/// A short rendering of a JSON value for error messages.
fn json_text(value: &Json) -> String {
    match value {
        Json::String(s) => camloc_store::quoted(s),
        Json::Number(n) => n.to_string(),
        other => other.kind().to_owned(),
    }
}

/// Writes records as a camloc JSON document (format version 1), pretty-printed with one
/// landmark per line, every landmark key present and missing ones as `null`; each pose's
/// `id`, and its `frame` and `person` numbers when it has them (poses of a video), so that
/// `camloc localize --sequence` groups the written poses as it grouped the read ones.
///
/// Coordinates are written in the shortest form that reads back to the same `f64`, so
/// [`parse_keypoints`](crate::parse_keypoints) with `derive_torso: false` returns exactly the
/// given ids, poses, frames and persons (not their `source` or `derived`). A non-finite
/// coordinate cannot be written in JSON: such a landmark is written as `null`, i.e. missing.
pub fn to_camloc_json(records: &[KeypointRecord]) -> String {
    let mut out = format!(
        "{{\n  \"format\": {},\n  \"version\": {CAMLOC_FORMAT_VERSION},\n  \"poses\": [",
        string(CAMLOC_FORMAT_TAG)
    );
    for (i, record) in records.iter().enumerate() {
        out.push_str(if i == 0 { "\n" } else { ",\n" });
        out.push_str(&format!("    {{\n      \"id\": {},\n", string(&record.id)));
        for (key, number) in [("frame", record.frame), ("person", record.person)] {
            if let Some(n) = number {
                out.push_str(&format!("      \"{key}\": {n},\n"));
            }
        }
        out.push_str("      \"landmarks\": {\n");
        let lines: Vec<String> = Landmark::ALL
            .iter()
            .zip(&record.pose.points)
            .map(|(landmark, point)| {
                format!("        \"{}\": {}", landmark.name(), point_text(*point))
            })
            .collect();
        out.push_str(&lines.join(",\n"));
        out.push_str("\n      }\n    }");
    }
    out.push_str(if records.is_empty() {
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

    /// A record as the writer takes it (its source and derived landmarks are not written).
    fn record(
        id: &str,
        pose: PartialPose2,
        frame: Option<u64>,
        person: Option<u64>,
    ) -> KeypointRecord {
        KeypointRecord {
            id: id.to_owned(),
            pose,
            derived: Vec::new(),
            source: String::new(),
            frame,
            person,
            person_is_position: false,
        }
    }

    #[test]
    fn writes_all_keys_in_landmark_order_with_null_for_missing() {
        let mut pose = PartialPose2::empty();
        pose.points[Landmark::Neck.index()] = Some([1.5, -2.0]);
        pose.points[Landmark::Head.index()] = Some([f64::NAN, 0.0]);
        let text = to_camloc_json(&[record("a \"quoted\" id", pose, None, None)]);
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
        let text = to_camloc_json(&[]);
        let root: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(root["poses"], serde_json::json!([]));
        assert!(
            crate::parse_keypoints(&text, "e.json", None, &ReadOptions::default())
                .unwrap()
                .is_empty()
        );
    }

    #[test]
    fn frames_and_persons_are_written_and_read_back_and_checked() {
        let mut pose = PartialPose2::empty();
        pose.points[Landmark::Pelvis.index()] = Some([1.0, 2.0]);
        let records = [
            record("12/1", pose, Some(12), Some(1)),
            record("still", pose, None, None),
        ];
        let text = to_camloc_json(&records);
        assert!(
            !text
                .split("\"still\"")
                .nth(1)
                .unwrap()
                .contains("\"frame\""),
            "{text}"
        );
        let options = ReadOptions {
            derive_torso: false,
            ..ReadOptions::default()
        };
        let read = crate::parse_keypoints(&text, "f.json", None, &options).unwrap();
        let keys: Vec<_> = read.iter().map(|r| (r.frame, r.person)).collect();
        assert_eq!(keys, [(Some(12), Some(1)), (None, None)]);
        for (bad, key) in [
            ("-1", "frame"),
            ("1.5", "frame"),
            ("\"3\"", "person"),
            ("9223372036854775808", "person"),
        ] {
            let doc = format!(r#"{{"poses": [{{"{key}": {bad}, "landmarks": {{}}}}]}}"#);
            let err = crate::parse_keypoints(&doc, "b.json", None, &options).unwrap_err();
            assert!(
                err.to_string().contains(&format!("poses[0].{key}")),
                "{err}"
            );
        }
    }
}
