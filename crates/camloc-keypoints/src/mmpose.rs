//! MMPose predictions: instances with `keypoints` as `[[x, y], ...]` and `keypoint_scores`.
//!
//! Accepted shapes: a list of instances (`MMPoseInferencer` per image), a list of frames
//! `{"frame_id": n, "instances": [...]}` (video), or either under `"instance_info"` of an object
//! (`--save-predictions` of the demos; `meta_info` and other keys are skipped).

use crate::ReadOptions;
use crate::error::{KeypointError, Location};
use crate::json::{
    self, Json, array, get, index_path, key_path, number_array, numbers, object, required,
};
use crate::layout::{Layout, keeps, resolve_layout};
use crate::record::{KeypointRecord, from_joints};

/// Reads MMPose predictions (BOM already removed, known not to be blank).
pub(crate) fn parse(
    text: &str,
    file: &str,
    options: &ReadOptions,
) -> Result<Vec<KeypointRecord>, KeypointError> {
    const EXPECTED: &str = "a list of instances or frames, or an object with \"instance_info\"";
    let root: Json = json::parse(text, file)?;
    let (list, list_path) = match &root {
        Json::Array(items) => (&items[..], String::new()),
        Json::Object(fields) => (
            array(
                required(fields, "instance_info", file, "")?,
                "a list of instances or frames",
                file,
                "instance_info",
            )?,
            "instance_info".to_owned(),
        ),
        other => return Err(json::wrong_type(file, "", EXPECTED, other)),
    };
    let mut records = Vec::new();
    for (i, entry) in list.iter().enumerate() {
        let path = index_path(&list_path, i);
        let fields = object(entry, "an instance or frame object", file, &path)?;
        match get(fields, "instances") {
            Some(instances) => {
                let frame_id = match get(fields, "frame_id") {
                    Some(Json::Number(n)) => Some(n.clone()),
                    Some(other) => {
                        return Err(json::wrong_type(
                            file,
                            &key_path(&path, "frame_id"),
                            "an integer",
                            other,
                        ));
                    }
                    None => None,
                };
                let frame = frame_id.as_ref().and_then(serde_json::Number::as_u64);
                let frame_name = frame_id.map_or_else(|| i.to_string(), |n| n.to_string());
                let instances_path = key_path(&path, "instances");
                let instances = array(instances, "a list of instances", file, &instances_path)?;
                for (n, instance) in instances.iter().enumerate() {
                    let record = instance_record(
                        instance,
                        &index_path(&instances_path, n),
                        format!("{frame_name}/{n}"),
                        file,
                        options,
                    )?;
                    records.push(KeypointRecord {
                        frame: frame.or(Some(i as u64)),
                        person: Some(n as u64),
                        ..record
                    });
                }
            }
            None => {
                let record = instance_record(entry, &path, i.to_string(), file, options)?;
                records.push(KeypointRecord {
                    person: Some(i as u64),
                    ..record
                });
            }
        }
    }
    Ok(records)
}

/// One instance at `path`.
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
    let scores = match get(fields, "keypoint_scores") {
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
    Ok(from_joints(
        layout.joints(),
        points,
        id,
        file,
        path,
        options,
    ))
}
