//! COCO-17 keypoints: a COCO dataset file (`{"annotations": [...]}`) or a results list
//! (`[{"image_id": .., "keypoints": [..], "score": ..}]`).
//!
//! The top level and the annotations are streamed: only `image_id`, `id`, `track_id`,
//! `keypoints`, `iscrowd` and `num_keypoints` of each annotation are kept (a crowd's region or
//! a person without a labelled keypoint, whose keypoints are all unlabelled, is skipped), so
//! that segmentation polygons and image lists of large dataset files are skipped rather than
//! held in memory. An integer `image_id` is the record's frame and an integer `track_id` (a
//! tracker's person id) its person, so that the poses of a video's detections are ordered
//! and kept apart by person.

use std::fmt;

use serde::de::{self, Deserialize, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};

use crate::emit::{self, ListReader, Sink, TopLevel};

use crate::ReadOptions;
use crate::error::{KeypointError, Location};
use crate::json::{self, Json, index_path, key_path, number_array, wrong_type};
use crate::layout::{COCO17, keeps};
use crate::record::{KeypointRecord, from_joints};

/// The 17 COCO keypoints in file order. The first five (nose, eyes, ears) become the camloc head;
/// the other twelve have camloc landmarks of the same name.
pub const COCO_KEYPOINTS: [&str; 17] = {
    let mut names = [""; 17];
    let mut i = 0;
    while i < 17 {
        names[i] = COCO17[i].0;
        i += 1;
    }
    names
};

/// The fields of one annotation (or result) this reader uses; the rest are skipped.
#[derive(Default)]
struct Annotation {
    image_id: Option<Json>,
    id: Option<Json>,
    track_id: Option<Json>,
    keypoints: Option<Json>,
    /// A dataset's `iscrowd` (1: a crowd's region, without keypoints).
    iscrowd: Option<Json>,
    /// A dataset's `num_keypoints` (0: a person without a labelled keypoint).
    num_keypoints: Option<Json>,
}

impl Annotation {
    /// A dataset's annotation that is no pose: a crowd's region (`iscrowd` 1, `true` or
    /// `"1"`) or a person without a labelled keypoint (`num_keypoints` 0), whose keypoints
    /// are indeed all unlabelled (absent, or every flag 0): skipped (a COCO dataset file has
    /// thousands). One that says so but has labelled keypoints is read.
    fn without_keypoints(&self) -> bool {
        let crowd = match &self.iscrowd {
            Some(Json::Number(v)) => v.as_f64() == Some(1.0),
            Some(Json::Bool(crowd)) => *crowd,
            Some(Json::String(text)) => text == "1" || text.eq_ignore_ascii_case("true"),
            _ => false,
        };
        let none_labelled =
            matches!(&self.num_keypoints, Some(Json::Number(v)) if v.as_f64() == Some(0.0));
        let unlabelled = match &self.keypoints {
            None => true,
            Some(Json::Array(values)) => values
                .iter()
                .skip(2)
                .step_by(3)
                .all(|v| matches!(v, Json::Number(n) if n.as_f64() == Some(0.0))),
            Some(_) => false,
        };
        (crowd || none_labelled) && unlabelled
    }
}

impl<'de> Deserialize<'de> for Annotation {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_map(AnnotationVisitor)
    }
}

struct AnnotationVisitor;

impl<'de> Visitor<'de> for AnnotationVisitor {
    type Value = Annotation;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a COCO annotation object")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Annotation, A::Error> {
        let mut annotation = Annotation::default();
        while let Some(key) = map.next_key::<String>()? {
            let (slot, name) = match key.as_str() {
                "image_id" => (&mut annotation.image_id, "image_id"),
                "id" => (&mut annotation.id, "id"),
                "track_id" => (&mut annotation.track_id, "track_id"),
                "keypoints" => (&mut annotation.keypoints, "keypoints"),
                "iscrowd" => (&mut annotation.iscrowd, "iscrowd"),
                "num_keypoints" => (&mut annotation.num_keypoints, "num_keypoints"),
                _ => {
                    map.next_value::<IgnoredAny>()?;
                    continue;
                }
            };
            if slot.is_some() {
                return Err(de::Error::duplicate_field(name));
            }
            *slot = Some(map.next_value()?);
        }
        Ok(annotation)
    }
}

/// COCO keypoints: a results list, or a dataset object whose `annotations` are read one at a
/// time (other keys skipped).
pub(crate) struct Input;

impl TopLevel for Input {
    const EXPECTED: &'static str = "a COCO dataset object or a list of COCO results";

    fn list<'de, A: SeqAccess<'de>>(self, seq: A, sink: &mut Sink) -> Result<(), A::Error> {
        Annotations("").read(seq, sink)
    }

    fn object<'de, A: MapAccess<'de>>(self, map: A, sink: &mut Sink) -> Result<(), A::Error> {
        const KEY: &str = "annotations";
        emit::object_with_list(map, sink, KEY, "a list of annotations", Annotations(KEY))
    }
}

/// A list of annotations at the given JSON path, read one at a time.
struct Annotations(&'static str);

impl ListReader for Annotations {
    fn read<'de, A: SeqAccess<'de>>(self, mut seq: A, sink: &mut Sink) -> Result<(), A::Error> {
        let mut index = 0;
        while let Some(annotation) = seq.next_element::<Annotation>()? {
            let path = index_path(self.0, index);
            index += 1;
            if annotation.without_keypoints() {
                continue;
            }
            let record = record(&annotation, &path, index - 1, sink.file, sink.options);
            sink.send(record)?;
        }
        Ok(())
    }
}

/// One annotation at JSON path `path` (the `index`-th of its list) as a record.
fn record<'a>(
    annotation: &'a Annotation,
    path: &str,
    index: usize,
    file: &str,
    options: &ReadOptions,
) -> Result<KeypointRecord, KeypointError> {
    let required = |value: Option<&'a Json>, key: &'static str| {
        value.ok_or_else(|| KeypointError::MissingKey {
            file: file.to_owned(),
            at: Location::Path(path.to_owned()),
            key,
            read_as_coco: true,
        })
    };
    let image_id = required(annotation.image_id.as_ref(), "image_id")?;
    let image = id_text(image_id, file, &key_path(path, "image_id"))?;
    let suffix = match &annotation.id {
        Some(id) => id_text(id, file, &key_path(path, "id"))?,
        None => index.to_string(),
    };
    let values = number_array::<{ 3 * COCO_KEYPOINTS.len() }>(
        required(annotation.keypoints.as_ref(), "keypoints")?,
        "17 COCO keypoints as x, y, v",
        file,
        &key_path(path, "keypoints"),
    )?;

    let keypoints_path = key_path(path, "keypoints");
    for (k, xyv) in values.chunks_exact(3).enumerate() {
        json::score_on_threshold_scale(
            xyv[2],
            options,
            file,
            &index_path(&keypoints_path, 3 * k + 2),
        )?;
    }
    let points = values
        .chunks_exact(3)
        .map(|xyv| keeps(xyv[2], options).then_some([xyv[0], xyv[1]]));
    let record = from_joints(
        &COCO17,
        points,
        format!("{image}/{suffix}"),
        file,
        path,
        options,
    );
    Ok(KeypointRecord {
        frame: json::frame_number(image_id),
        person: annotation.track_id.as_ref().and_then(json::tracking_number),
        ..record
    })
}

/// An image or annotation id (a number or a string) as text.
fn id_text(value: &Json, file: &str, path: &str) -> Result<String, KeypointError> {
    match value {
        Json::Number(n) => Ok(n.to_string()),
        Json::String(s) => Ok(s.clone()),
        other => Err(wrong_type(file, path, "a number or a string", other)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use camloc_skeleton::Landmark;

    #[test]
    fn skips_other_keys_and_rejects_a_repeated_annotation_key() {
        let mut kp = vec![0.0; 51];
        kp[3 * 5..3 * 5 + 3].copy_from_slice(&[7.0, 8.0, 2.0]);
        let kp = serde_json::to_string(&kp).unwrap();
        let ok = format!(
            r#"{{"images": [{{"id": 1}}], "annotations": [{{"segmentation": [[1,2,3]], "image_id": 1, "keypoints": {kp}}}]}}"#
        );
        let parse = |text: &str| {
            let options = ReadOptions::default();
            crate::parse_keypoints(text, "c.json", Some(crate::KeypointFormat::Coco), &options)
        };
        let records = parse(&ok).unwrap();
        assert_eq!(records[0].id, "1/0");
        assert_eq!(
            records[0].pose.points[Landmark::LeftShoulder.index()],
            Some([7.0, 8.0])
        );
        assert_eq!((records[0].frame, records[0].person), (Some(1), None));
        let tracked = format!(
            r#"[{{"image_id": 4, "track_id": 2, "keypoints": {kp}}}, {{"image_id": "a.jpg", "track_id": -1, "keypoints": {kp}}}]"#
        );
        let keys: Vec<_> = parse(&tracked)
            .unwrap()
            .iter()
            .map(|r| (r.frame, r.person))
            .collect();
        assert_eq!(keys, [(Some(4), Some(2)), (None, None)]);
        // Numbers as scripts and tools write them: floats, digit strings, image file names.
        let written = format!(
            r#"[{{"image_id": 12.0, "track_id": "3", "keypoints": {kp}}},
                {{"image_id": "frames/cam2_frame_000013.jpg", "track_id": 4.0, "keypoints": {kp}}},
                {{"image_id": "0014", "track_id": "walker", "keypoints": {kp}}},
                {{"image_id": "000015_cam2.jpg", "keypoints": {kp}}},
                {{"image_id": 1.5, "track_id": -2.0, "keypoints": {kp}}}]"#
        );
        let keys: Vec<_> = parse(&written)
            .unwrap()
            .iter()
            .map(|r| (r.frame, r.person))
            .collect();
        assert_eq!(
            keys,
            [
                (Some(12), Some(3)),
                (Some(13), Some(4)),
                (Some(14), None),
                (Some(15), None),
                (None, None)
            ]
        );
        let twice = format!(r#"[{{"image_id": 1, "keypoints": {kp}, "keypoints": {kp}}}]"#);
        let err = parse(&twice).unwrap_err();
        assert!(matches!(err, KeypointError::Json { .. }), "{err:?}");
    }
}
