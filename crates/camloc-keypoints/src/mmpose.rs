//! MMPose predictions: instances with `keypoints` as `[[x, y], ...]` and `keypoint_scores`.
//!
//! Accepted shapes: a list of instances (`MMPoseInferencer` per image), a list of frames
//! `{"frame_id": n, "instances": [...]}` (video), or either under `"instance_info"` of an object
//! (`--save-predictions` of the demos; `meta_info` and other keys are skipped).

use serde::de::{MapAccess, SeqAccess};

use crate::ReadOptions;
use crate::array_pose::ArrayPoseError;
use crate::emit::{self, ListReader, Sink, TopLevel};
use crate::error::{KeypointError, Location, PosePlace};
use crate::json::{
    self, Json, array, index_path, key_path, number_array, numbers, object, optional, required,
};
use crate::layout::{Layout, keeps, resolve_layout};
use crate::layout_check::contradicted;
use crate::record::{KeypointRecord, from_joints};
use crate::stream::Item;

/// MMPose predictions: a list of instances or frames, or an object with `instance_info` (other
/// keys skipped); the list is read one entry at a time.
pub(crate) struct Predictions;

impl TopLevel for Predictions {
    const EXPECTED: &'static str =
        "a list of instances or frames, or an object with \"instance_info\"";

    fn list<'de, A: SeqAccess<'de>>(self, seq: A, sink: &mut Sink) -> Result<(), A::Error> {
        Entries("").read(seq, sink)
    }

    fn object<'de, A: MapAccess<'de>>(self, map: A, sink: &mut Sink) -> Result<(), A::Error> {
        const KEY: &str = "instance_info";
        emit::object_with_list(
            map,
            sink,
            KEY,
            "a list of instances or frames",
            Entries(KEY),
        )
    }
}

/// The list of instances or frames at the given JSON path, one entry at a time.
struct Entries(&'static str);

impl ListReader for Entries {
    fn read<'de, A: SeqAccess<'de>>(self, seq: A, sink: &mut Sink) -> Result<(), A::Error> {
        let (file, options) = (sink.file, sink.options);
        emit::entries(seq, sink, |entry, i| {
            entry_records(&entry, &index_path(self.0, i), i, file, options)
        })
    }
}

/// The records of entry `i` at `path`: an instance, or a frame `{"frame_id", "instances"}`;
/// each instance's record or error (a refused instance is its own error: the frame's other
/// instances and the next entries are still read, [`Sink::send`](crate::emit::Sink::send)).
fn entry_records(
    entry: &Json,
    path: &str,
    i: usize,
    file: &str,
    options: &ReadOptions,
) -> Result<Vec<Item>, KeypointError> {
    let fields = object(entry, "an instance or frame object", file, path)?;
    let Some(instances) = optional(fields, "instances", file, path)? else {
        let record = instance_record(entry, path, i.to_string(), file, options);
        return Ok(vec![placed(record, None, i)]);
    };
    let frame_path = key_path(path, "frame_id");
    let frame = match optional(fields, "frame_id", file, path)? {
        Some(value) => json::count_number(value, "frame_id", file, &frame_path)?,
        None => i as u64,
    };
    let instances_path = key_path(path, "instances");
    let instances = array(instances, "a list of instances", file, &instances_path)?;
    Ok(instances
        .iter()
        .enumerate()
        .map(|(n, instance)| {
            let record = instance_record(
                instance,
                &index_path(&instances_path, n),
                format!("{frame}/{n}"),
                file,
                options,
            );
            placed(record, Some(frame), n)
        })
        .collect())
}

/// An instance's record, or the error of its pose, with the frame `frame` (when the entry
/// is a frame) and, without a `track_id`, the person `n` (its position).
fn placed(item: Item, frame: Option<u64>, n: usize) -> Item {
    match item {
        Ok(record) => Ok(KeypointRecord {
            frame: frame.or(record.frame),
            person: record.person.or(Some(n as u64)),
            person_is_position: record.person.is_none(),
            ..record
        }),
        Err(mut e) => {
            if let Some(place) = e.refused_place_mut() {
                place.frame = frame.or(place.frame);
                place.person = place.person.or(Some(n as u64));
            }
            Err(e)
        }
    }
}

/// One instance at `path`; its person is the instance's `track_id` (a tracker's person id)
/// when that is a number [`json::tracking_number`] takes, else `None`.
fn instance_record(
    instance: &Json,
    path: &str,
    id: String,
    file: &str,
    options: &ReadOptions,
) -> Result<KeypointRecord, KeypointError> {
    let fields = object(instance, "an instance object", file, path)?;
    let kp_path = key_path(path, "keypoints");
    let keypoints = array(
        required(fields, "keypoints", file, path)?,
        "a list of [x, y]",
        file,
        &kp_path,
    )?;
    let layout =
        resolve_layout(options.layout, keypoints.len(), Some(Layout::Coco17)).map_err(|what| {
            KeypointError::JointCount {
                file: file.to_owned(),
                at: Location::Path(kp_path.clone()),
                found: keypoints.len() as u64,
                what,
            }
        })?;
    let scores = match optional(fields, "keypoint_scores", file, path)? {
        Some(value) => {
            let scores_path = key_path(path, "keypoint_scores");
            let scores = numbers(value, "a list of numbers", file, &scores_path)?;
            if scores.len() != keypoints.len() {
                return Err(KeypointError::WrongLength {
                    file: file.to_owned(),
                    at: Location::Path(scores_path),
                    expected: keypoints.len(),
                    found: scores.len(),
                    items: "numbers",
                    what: "one score per keypoint",
                });
            }
            for (k, &score) in scores.iter().enumerate() {
                json::score_on_threshold_scale(score, options, file, &index_path(&scores_path, k))?;
            }
            Some(scores)
        }
        None => None,
    };
    let mut points = Vec::with_capacity(keypoints.len());
    for (k, point) in keypoints.iter().enumerate() {
        let xy = number_array::<2>(point, "[x, y]", file, &index_path(&kp_path, k))?;
        let kept = scores.as_ref().is_none_or(|s| keeps(s[k], options));
        points.push(kept.then_some(xy));
    }
    let person = optional(fields, "track_id", file, path)?.and_then(json::tracking_number);
    if let Some((likely, spread)) = contradicted(layout, &points, scores.as_deref()) {
        return Err(KeypointError::LayoutMismatch {
            place: Box::new(PosePlace {
                id,
                source: format!("{file}: {}", Location::Path(path.to_owned())),
                frame: None,
                person,
            }),
            file: file.to_owned(),
            at: Location::Path(kp_path),
            source: ArrayPoseError::LayoutMismatch {
                layout,
                likely,
                spread,
            },
        });
    }
    let record = from_joints(layout.joints(), points, id, file, path, options);
    Ok(KeypointRecord { person, ..record })
}
